"""One progress line on stderr for long runs, silent otherwise.

:class:`Progress` shows nothing for the first ``delay`` seconds (short runs stay silent),
then one line rewritten in place (``\\r``) at most every ``interval`` seconds, cleared when
the run ends. It writes only when the stream is a terminal and ``quiet`` is false, so
pipes, files, tests and ``--quiet`` runs see nothing. Every long loop of mechcont (continuation
steps, simulated seconds of a sweep, animation frames, the paper's sections) reports
through it::

    with Progress("sweep", total=350.0, unit="s simulated", quiet=quiet) as bar:
        sweep(..., progress=bar.set)
"""

from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["Progress"]


class Progress:
    """A progress line: ``label: 12/54 frames (22 %) 3.1 s``.

    Parameters
    ----------
    label:
        What is running (``"animation"``, ``"[nose_gear] Fig. 11"``).
    total:
        The value at the end (frames, steps, seconds simulated); ``None`` when unknown
        (then the count and the elapsed time are shown).
    unit:
        Word after the count (``"frames"``, ``"steps"``, ``"s simulated"``).
    quiet:
        Never write.
    stream:
        Where to write (default ``sys.stderr``); nothing is written unless it is a terminal.
    delay, interval:
        Seconds before the first line, and between redraws.
    """

    def __init__(self, label: str, total: float | None = None, unit: str = "", *, quiet: bool = False,
                 stream: TextIO | None = None, delay: float = 2.0, interval: float = 0.25):
        self.label, self.total, self.unit = label, total, unit
        self.stream = sys.stderr if stream is None else stream
        isatty = getattr(self.stream, "isatty", None)
        self.enabled = not quiet and bool(isatty and isatty())
        self.delay, self.interval = float(delay), float(interval)
        self.value = 0.0
        self.t0 = time.monotonic()
        self._last = -1e300
        self._width = 0

    # -- reporting --------------------------------------------------------------------------
    def update(self, n: float = 1) -> None:
        """Advance by ``n`` (e.g. one accepted continuation step)."""
        self.set(self.value + n)

    def set(self, value: float) -> None:
        """Set the current value (e.g. the simulated time of a sweep)."""
        self.value = float(value)
        if not self.enabled:
            return
        now = time.monotonic()
        if now - self.t0 < self.delay or now - self._last < self.interval:
            return
        self._last = now
        self._write(self.line(now - self.t0))

    def __call__(self, *args: float) -> None:
        """As a callback: ``progress(n)`` advances by ``n``; ``progress()`` by one."""
        self.update(args[0] if args else 1)

    def line(self, elapsed: float) -> str:
        """The text shown after ``elapsed`` seconds."""
        count = f"{self.value:.0f}" if self.total is None or self.total >= 20 else f"{self.value:.3g}"
        if self.total:
            frac = min(max(self.value / self.total, 0.0), 1.0)
            total = f"{self.total:.0f}" if self.total >= 20 else f"{self.total:.3g}"
            body = f"{count}/{total} {self.unit} ({100 * frac:.0f} %)".replace("  ", " ")
        else:
            body = f"{count} {self.unit}".strip()
        return f"{self.label}: {body}, {elapsed:.1f} s"

    def _write(self, text: str) -> None:
        pad = max(self._width - len(text), 0)
        self.stream.write("\r" + text + " " * pad)
        self.stream.flush()
        self._width = len(text)

    def close(self) -> None:
        """Clear the line (if one was written)."""
        if self.enabled and self._width:
            self.stream.write("\r" + " " * self._width + "\r")
            self.stream.flush()
            self._width = 0

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
