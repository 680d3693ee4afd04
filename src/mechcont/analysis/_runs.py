"""Which continuation runs an analysis rests on stopped short, where, and why (one line each)."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..continuation import Branch

__all__ = ["early_stops"]


def early_stops(branch: Branch | None, what: str, show: Iterable[str] = ()) -> list[str]:
    """One line per end of ``branch`` that is not a bound or a requested stop.

    A direction that failed (``status`` not ``"completed"``, e.g. a step-size underflow) or
    that used up ``max_steps`` before reaching its bounds is named with ``what`` (e.g.
    ``"downlock branch in l_sp1"``), the values of the continuation parameter and of the
    names in ``show`` where it stopped, and the engine's reason. Returns ``[]`` when every
    direction ended normally.
    """
    if branch is None:
        return []
    out = []
    names = [branch.vary, *(n for n in show if n != branch.vary)]
    for p in branch.special("EP"):
        reason = p.reason
        if not reason:
            continue  # a bound (or a limit): the run ended where it was asked to
        vals = p.values
        where = ", ".join(f"{n} = {vals[n]:.6g}" for n in names if n in vals)
        why = ("it used up max_steps before reaching its bounds (raise max_steps, --max-steps)" if reason == "max_steps"
               else reason)
        out.append(f"{what} stopped early at {where}: {why}")
    if not out and (not branch.success or "max_steps" in branch.message):
        out.append(f"{what} stopped early ({branch.status}): {branch.message}")
    return out
