"""Which parameters a continuation branch was continued at other values of than a sweep drawn on it."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

import numpy as np

from ..equations import Model
from ._compare import branch_differences

if TYPE_CHECKING:
    from ..continuation import Branch

__all__ = ["held_branch_differences"]


def held_branch_differences(system: Model, branch: Branch, ramped: Iterable[str] = ()) -> list[tuple[str, float, float]]:
    """:func:`~mechcont.dynamics.branch_differences` for a sweep drawn on ``branch``: the parameters held along the
    whole branch (not ``ramped``, not a stop's reaction, not one that moves along the branch: those are solved for
    there, not values it was continued at) whose value on ``branch`` differs from the system's and changes the
    equilibrium equations: ``(name, on branch, system's)``, SI units."""
    solved = {s.reaction for s in system.stops}
    solved |= {n for n in system.parameter_names if np.ptp(np.asarray(branch[n], dtype=float)) > 0}
    return branch_differences(system, branch, ignore=[*ramped, *solved])
