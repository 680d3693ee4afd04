"""Signals that must stop a run even when a library swallows the exception they raise.

The ``mechcont`` command turns SIGTERM and SIGHUP (the terminal closed) into :class:`Terminated`
and Ctrl-C into ``KeyboardInterrupt`` (:func:`install`), so every ``finally`` block and
:func:`mechcont._io.atomic_write` clean up and the exit status is 128 + the signal's number.
Some libraries catch exceptions raised inside their callbacks
(Matplotlib's event callbacks do), so a signal that arrives there would be lost and the run
would finish as if nothing happened. Each handler therefore also records the signal here;
:func:`raise_pending` re-raises it at the next safe point (before an output file is moved into
place, and when the command returns).
"""

from __future__ import annotations

import contextlib
import os
import signal
from collections.abc import Callable, Iterator
from types import FrameType
from typing import NoReturn

__all__ = ["Terminated", "record", "raise_pending", "clear", "pending", "install", "process_state", "TERMINATING",
           "stop_gracefully", "stopping", "raise_held"]

_PENDING: list[int] = []
#: Signals that ended a computation gracefully (:func:`stop_gracefully`): raised when the command returns.
_HELD: list[int] = []
_GRACEFUL: list[bool] = []
#: The signals that end a run as :class:`Terminated`: SIGTERM, and SIGHUP where the platform has it.
TERMINATING: tuple[int, ...] = tuple(getattr(signal, n) for n in ("SIGTERM", "SIGHUP") if hasattr(signal, n))


class Terminated(BaseException):
    """Raised by the SIGTERM and SIGHUP handlers of the ``mechcont`` command: unwinds like Ctrl-C
    (``finally`` blocks and :func:`mechcont._io.atomic_write` clean up). ``signum`` is the signal."""

    def __init__(self, signum: int = signal.SIGTERM):
        super().__init__(signum)
        self.signum = signum


def record(signum: int) -> None:
    """Remember that signal ``signum`` arrived."""
    _PENDING.append(signum)


def clear() -> None:
    """Forget recorded signals (at the start of a command)."""
    _PENDING.clear()
    _HELD.clear()


def pending() -> int | None:
    """The first signal recorded since :func:`clear`, or None."""
    return _PENDING[0] if _PENDING else None


def raise_pending() -> None:
    """Raise :class:`Terminated` or ``KeyboardInterrupt`` if a signal arrived and was swallowed."""
    if _PENDING:
        signum = _PENDING[0]
        _PENDING.clear()
        raise Terminated(signum) if signum in TERMINATING else KeyboardInterrupt()


def _terminate(signum: int, frame: FrameType | None) -> None:
    """The SIGTERM/SIGHUP handler: records the signal; raises :class:`Terminated` unless inside :func:`stop_gracefully`."""
    record(signum)
    if not _GRACEFUL:
        raise Terminated(signum)


@contextlib.contextmanager
def stop_gracefully() -> Iterator[None]:
    """Within the block, SIGTERM and SIGHUP are only recorded: a long loop that asks :func:`stopping`
    ends itself, so that what it computed can be written. On leaving, a signal that arrived is held:
    writing the results goes on (a second signal then stops it at once, as usual) and
    :func:`raise_held` raises it when the command returns (exit status 128 + the signal)."""
    _GRACEFUL.append(True)
    try:
        yield
    finally:
        _GRACEFUL.pop()
        if not _GRACEFUL:
            caught = [s for s in _PENDING if s in TERMINATING]
            if caught:
                _HELD.append(caught[0])
                _PENDING[:] = [s for s in _PENDING if s not in TERMINATING]


def stopping() -> int | None:
    """The terminating signal a loop inside :func:`stop_gracefully` should stop for, or None."""
    return next((s for s in _PENDING if s in TERMINATING), None) if _GRACEFUL else None


def raise_held() -> None:
    """Raise :class:`Terminated` for a signal that :func:`stop_gracefully` held (once the results are written)."""
    if _HELD:
        signum = _HELD[0]
        _HELD.clear()
        raise Terminated(signum)


def _interrupt(signum: int, frame: FrameType | None) -> NoReturn:
    """The SIGINT handler: records the signal and raises ``KeyboardInterrupt``."""
    record(signum)
    raise KeyboardInterrupt()


def install() -> Callable[[], None]:
    """Handle SIGTERM and SIGHUP as :class:`Terminated` and SIGINT as ``KeyboardInterrupt`` (each also
    recorded); returns a function that puts the previous handlers back."""
    previous = {s: signal.signal(s, _terminate) for s in TERMINATING}
    previous[signal.SIGINT] = signal.signal(signal.SIGINT, _interrupt)

    def restore() -> None:
        for s, handler in previous.items():
            signal.signal(s, handler)

    return restore


def process_state(pid: int) -> str | None:
    """What process ``pid`` is doing, as far as it matters to a lock or a temporary file it left:
    ``"stopped"`` (state T or t in ``/proc/PID/stat``: Ctrl-Z, SIGSTOP), ``"gone"`` (no such process,
    or one that has ended: a zombie, Z or X), or None (running, sleeping, or not known: no ``/proc``)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            text = f.read()
    except FileNotFoundError:
        return "gone" if os.path.isdir("/proc/self") else None
    except OSError:
        return None
    state = text[text.rfind(b")") + 2:][:1]  # the name in parentheses may hold spaces and ')'
    return "stopped" if state in (b"T", b"t") else "gone" if state in (b"Z", b"X") else None
