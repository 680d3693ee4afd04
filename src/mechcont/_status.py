"""One status vocabulary for every result: branches, special points, simulations, freefalls, studies, rejected steps.

A :class:`Status` is a ``str`` (its value is the word tables, JSON files and messages have
always shown: ``"completed"``, ``"located"``...), so ``branch.status == "completed"`` holds and
files written before the enum read back; :attr:`Status.message` explains it (scipy's
``OdeResult.status``/``message`` and diffrax's ``RESULTS`` are the models).
"""

from __future__ import annotations

from collections.abc import Iterable
from enum import StrEnum

from .errors import InputError

__all__ = ["Status"]


class Status(StrEnum):
    """How a computation ended, or how well a point is known.

    Branches (and fold curves): :attr:`COMPLETED`, :attr:`STEP_UNDERFLOW`, :attr:`FAILED` (which
    :class:`~mechcont.continuation.Termination` of a direction gives which: its ``status``).
    Special points: :attr:`LOCATED`, :attr:`APPROXIMATE`. Time simulations: :attr:`FINISHED`,
    :attr:`EVENT`, :attr:`FAILED`. Freefall outcomes: :attr:`LOCKED`, :attr:`AT_REST`,
    :attr:`STILL_MOVING`, :attr:`FAILED`. Study samples: :attr:`CONVERGED`, :attr:`FAILED`; a
    study's release run also :attr:`STOPPED_EARLY`. A corrector's rejected step (its reason, in
    a branch's message when the step size underflows): :attr:`NOT_FINITE`, :attr:`SINGULAR`,
    :attr:`TOO_SLOW`, :attr:`SINGULAR_TANGENT` (too many iterations says how many, in its own words).
    """

    COMPLETED = "completed"
    STEP_UNDERFLOW = "step size underflow"
    LOCATED = "located"
    APPROXIMATE = "approximate"
    FINISHED = "finished"
    EVENT = "event"
    CONVERGED = "converged"
    STOPPED_EARLY = "stopped early"
    LOCKED = "locked"
    AT_REST = "at rest"
    STILL_MOVING = "still moving"
    NOT_FINITE = "residual not finite (outside the model's domain)"
    SINGULAR = "singular bordered Jacobian"
    TOO_SLOW = "corrector converging too slowly"
    SINGULAR_TANGENT = "singular tangent system"
    FAILED = "failed"

    # equal to its word, so it must hash like it too (sets and dict keys of old strings)
    __hash__ = str.__hash__

    @property
    def message(self) -> str:
        """A readable sentence saying what the status means."""
        return _MESSAGES[self]

    @property
    def success(self) -> bool:
        """True for a normal end or a point solved to the tolerances."""
        return self in _SUCCESS

    @classmethod
    def of(cls, value: str | Status) -> Status:
        """The status written as ``value`` (its word, e.g. ``"completed"``; a member is returned as is).
        Raises :class:`~mechcont.errors.InputError` naming the valid words for any other text."""
        if isinstance(value, cls):
            return value
        try:
            return cls(str(value).strip())
        except ValueError:
            raise InputError("status", f"unknown status '{value}'; valid: {', '.join(m.value for m in cls)}") from None

    @classmethod
    def first_failure(cls, statuses: Iterable[Status | str]) -> Status:
        """The status of a result made of parts (a branch's two directions): :attr:`COMPLETED`
        when every part completed, else the first part's that did not."""
        return next((s for s in map(cls.of, statuses) if s is not cls.COMPLETED), cls.COMPLETED)


_MESSAGES = {
    Status.COMPLETED: "Every direction ended normally (a bound, a stop event or max_steps).",
    Status.STEP_UNDERFLOW: "The step size fell below dsmin (or two branches were too close to separate).",
    Status.LOCATED: "Solved to the tolerances (a fold polished on its augmented system, an event's zero found).",
    Status.APPROXIMATE: "Detected by a sign change but not located.",
    Status.FINISHED: "The end of the time span was reached.",
    Status.EVENT: "A terminal event occurred.",
    Status.CONVERGED: "Every analysis of the sample converged.",
    Status.STOPPED_EARLY: "The run stopped before its end (see its notes).",
    Status.LOCKED: "The freefall ended with the gear locked.",
    Status.AT_REST: "The freefall came to rest short of locking.",
    Status.STILL_MOVING: "The freefall was still moving at its end time (it may have struck the lock and left it).",
    Status.NOT_FINITE: "A corrector step was rejected: the residual is not finite (outside the model's domain).",
    Status.SINGULAR: "A corrector step was rejected: the bordered Jacobian is singular.",
    Status.TOO_SLOW: "A corrector step was rejected: its corrections did not contract (another branch near?).",
    Status.SINGULAR_TANGENT: "A step was rejected: the tangent system is singular.",
    Status.FAILED: "The computation failed; its own message says where and why.",
}
_SUCCESS = frozenset({Status.COMPLETED, Status.LOCATED, Status.FINISHED, Status.EVENT, Status.CONVERGED, Status.LOCKED,
                      Status.AT_REST, Status.STILL_MOVING})
