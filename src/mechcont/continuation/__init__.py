"""Continuation: problems (lenses on an equation system), the pseudo-arclength engine,
events (LP, BP, CP, HB, BT, GH, EP, UZ) and branch results.

The package is callable: ``mechcont.continuation(system, x0, "F")`` is
:func:`continuation` (so ``import mechcont; mechcont.continuation(...)`` reads as the API).
"""

import sys
import types
from typing import TYPE_CHECKING, Any

from .._lazy import lazy_exports
from ._api import continuation, continue_folds, locate_fold, switch_branch
from ._branch import Branch, SpecialPoint, cell_count, cell_number, check_branch_table, read_branch_table, read_table, unit_header
from ._cycle_branch import CycleBranch
from ._cycle_start import HopfOrigin, hopf_point
from ._cycles import cycles_from_hopf, cycles_from_samples
from ._events import BoundEvent, BranchPointEvent, Event, FoldEvent, LimitEvent, PointState, ValueEvent
from ._fold_point import fold_scaling, polish_fold
from ._folds import CuspEvent, FoldProblem
from ._hopf import BogdanovTakensEvent, GeneralisedHopfEvent, HopfEvent, HopfProblem
from ._hopf_api import continue_hopf, locate_hopf
from ._hopf_point import HopfPoint
from ._linalg import DenseLU, LinearSolver, MinimumNorm
from ._newton import find_equilibrium
from ._options import ContinuationOptions, EngineSettings
from ._palc import BranchSteps, Termination
from ._problem import ContinuationProblem, EquilibriumProblem, choose_unknowns, unstable_rates
from ._scaling import equilibrate
from ._special_point import Landing, NonSmoothFold
from ._start import MAX_STEPS, check_max_steps, run_options, start_point

#: names for the layers above imported from their modules on first use: sensitivities, moving a point, batches
_LAZY = {
    **dict.fromkeys(["Sensitivity", "SPECIAL_POINTS", "check_parameters", "equilibrium_sensitivity", "fold_sensitivity",
                     "point_sensitivity", "write_json", "variable_indices", "solve_equilibrated", "derivative_units",
                     "state_table"], "_sensitivity"),
    **dict.fromkeys(["move_point", "check_point", "PointLost"], "_move"),
    **dict.fromkeys(["travel"], "_variants"),
    **dict.fromkeys(["fold_batch", "newton_batch"], "_batch"),
}

__all__ = [
    "continuation", "continue_folds", "switch_branch", "locate_fold", "find_equilibrium", "ContinuationOptions", "EngineSettings",
    "Branch",
    "SpecialPoint", "NonSmoothFold", "Landing",
    "Event", "FoldEvent", "BranchPointEvent", "BoundEvent", "LimitEvent", "ValueEvent", "CuspEvent",
    "PointState", "ContinuationProblem", "EquilibriumProblem", "FoldProblem", "choose_unknowns",
    "Termination", "BranchSteps", "LinearSolver", "DenseLU", "MinimumNorm", "read_branch_table", "read_table",
    "MAX_STEPS", "check_max_steps", "run_options", "start_point", "HopfEvent", "HopfProblem", "HopfPoint",
    "BogdanovTakensEvent", "GeneralisedHopfEvent", "continue_hopf", "locate_hopf", "CycleBranch", "HopfOrigin",
    "hopf_point",
    "cycles_from_hopf", "cycles_from_samples",
    # for the layers above (analysis, dynamics, outputs, cli): the engine's pieces they build on
    "cell_count", "cell_number", "check_branch_table", "unit_header", "fold_scaling", "polish_fold", "equilibrate",
    "Sensitivity", "SPECIAL_POINTS", "check_parameters", "equilibrium_sensitivity", "fold_sensitivity", "point_sensitivity",
    "write_json", "variable_indices", "solve_equilibrated", "derivative_units", "state_table", "move_point", "check_point",
    "PointLost", "travel", "fold_batch", "newton_batch", "unstable_rates",
]

if TYPE_CHECKING:  # what the lazy names are, for type checkers and IDEs
    from ._batch import fold_batch, newton_batch
    from ._move import PointLost, check_point, move_point
    from ._sensitivity import (
        SPECIAL_POINTS,
        Sensitivity,
        check_parameters,
        derivative_units,
        equilibrium_sensitivity,
        fold_sensitivity,
        point_sensitivity,
        solve_equilibrated,
        state_table,
        variable_indices,
        write_json,
    )
    from ._variants import travel

__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())


class _CallablePackage(types.ModuleType):
    """This package's type: calling it calls :func:`continuation`."""

    def __call__(self, *args: Any, **kwargs: Any) -> Branch:
        return continuation(*args, **kwargs)


sys.modules[__name__].__class__ = _CallablePackage
