"""Signals that must stop a run even when a library swallows the exception they raise.

The ``mechcont`` command turns SIGTERM into :class:`Terminated` and Ctrl-C into
``KeyboardInterrupt``. Some libraries catch exceptions raised inside their callbacks
(Matplotlib's event callbacks do), so a signal that arrives there would be lost and the run
would finish as if nothing happened. Each handler therefore also records the signal here;
:func:`raise_pending` re-raises it at the next safe point (before an output file is moved into
place, and when the command returns).
"""

from __future__ import annotations

import signal

__all__ = ["Terminated", "record", "raise_pending", "clear", "pending"]

_PENDING: list[int] = []


class Terminated(BaseException):
    """Raised by the SIGTERM handler of the ``mechcont`` command: unwinds like Ctrl-C
    (``finally`` blocks and :func:`mechcont._io.atomic_write` clean up)."""


def record(signum: int) -> None:
    """Remember that signal ``signum`` arrived."""
    _PENDING.append(signum)


def clear() -> None:
    """Forget recorded signals (at the start of a command)."""
    _PENDING.clear()


def pending() -> int | None:
    """The first signal recorded since :func:`clear`, or None."""
    return _PENDING[0] if _PENDING else None


def raise_pending() -> None:
    """Raise :class:`Terminated` or ``KeyboardInterrupt`` if a signal arrived and was swallowed."""
    if _PENDING:
        signum = _PENDING[0]
        _PENDING.clear()
        raise Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()
