"""Continuation: problems (lenses on an equation system), the pseudo-arclength engine,
events (LP, BP, CP, HB, BT, GH, EP, UZ) and branch results.

The package is callable: ``mechcont.continuation(system, x0, "F")`` is
:func:`continuation` (so ``import mechcont; mechcont.continuation(...)`` reads as the API).
"""

import sys
import types

from ._api import continuation, continue_folds, locate_fold, switch_branch
from ._branch import Branch, SpecialPoint, read_branch_table, read_table
from ._cycle_branch import CycleBranch
from ._cycle_start import HopfOrigin, hopf_point
from ._cycles import cycles_from_hopf, cycles_from_samples
from ._events import BoundEvent, BranchPointEvent, Event, FoldEvent, LimitEvent, PointState, ValueEvent
from ._folds import CuspEvent, FoldProblem
from ._hopf import BogdanovTakensEvent, GeneralisedHopfEvent, HopfEvent, HopfProblem
from ._hopf_api import continue_hopf, locate_hopf
from ._hopf_point import HopfPoint
from ._linalg import DenseLU, LinearSolver, MinimumNorm
from ._newton import find_equilibrium
from ._options import ContinuationOptions
from ._palc import BranchSteps, Termination
from ._problem import ContinuationProblem, EquilibriumProblem, choose_unknowns
from ._start import MAX_STEPS, check_max_steps, run_options, start_point

__all__ = [
    "continuation", "continue_folds", "switch_branch", "locate_fold", "find_equilibrium", "ContinuationOptions", "Branch",
    "SpecialPoint", "Event", "FoldEvent", "BranchPointEvent", "BoundEvent", "LimitEvent", "ValueEvent", "CuspEvent",
    "PointState", "ContinuationProblem", "EquilibriumProblem", "FoldProblem", "choose_unknowns",
    "Termination", "BranchSteps", "LinearSolver", "DenseLU", "MinimumNorm", "read_branch_table", "read_table",
    "MAX_STEPS", "check_max_steps", "run_options", "start_point", "HopfEvent", "HopfProblem", "HopfPoint",
    "BogdanovTakensEvent", "GeneralisedHopfEvent", "continue_hopf", "locate_hopf", "CycleBranch", "HopfOrigin",
    "hopf_point",
    "cycles_from_hopf", "cycles_from_samples",
]


class _CallablePackage(types.ModuleType):
    """This package's type: calling it calls :func:`continuation`."""

    def __call__(self, *args, **kwargs):
        return continuation(*args, **kwargs)


sys.modules[__name__].__class__ = _CallablePackage
