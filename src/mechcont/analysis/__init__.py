"""Analyses built on continuation: families of equilibria (surfaces), downlock, unlock folds, stops, design maps.

Each name is imported from its module on first use (PEP 562), so a command that needs one
analysis does not import the others (the design maps' SciPy, for one).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_exports
from . import _special_points  # noqa: F401  (the loads of SR and CP points for Branch.sensitivity)

# ``downlock`` names both a function and the module defining it: imported now, so that the name is the
# function whatever imports the module later (an import binds a submodule to its package's name)
from .downlock import downlock

#: public name -> the module of this package that defines it
_LAZY = {
    **dict.fromkeys(["DesignRegion", "DesignRow", "FoldLocus", "design_region", "fold_locus"], "design"),
    **dict.fromkeys(["DynamicStability", "dynamic_stability", "with_dynamic_stability"], "dynamic_stability"),
    **dict.fromkeys(["DownlockResult", "downlock_condition", "downlock_point"], "downlock"),
    **dict.fromkeys(["RedundancyReport", "RedundancyState", "redundancy_along"], "redundancy"),
    **dict.fromkeys(["StopRun", "continuation_with_stops", "equilibrium_on_stops", "stability_on_stops",
                     "stops_in_contact"], "stops"),
    "equilibrium_family": "surface",
    **dict.fromkeys(["OdeReport", "ode_report", "ode_equations"], "ode_check"),
    **dict.fromkeys(["UnlockFolds", "unlock_folds", "unlock_force_along", "with_unlock_columns"], "unlock"),
}

__all__ = ["equilibrium_family", "downlock", "downlock_point", "downlock_condition", "fold_locus", "design_region",
           "DesignRegion", "DesignRow", "FoldLocus", "DownlockResult", "UnlockFolds", "unlock_folds",
           "unlock_force_along", "with_unlock_columns", "redundancy_along", "RedundancyReport", "RedundancyState",
           "StopRun", "continuation_with_stops", "equilibrium_on_stops", "stability_on_stops",
           "stops_in_contact", "OdeReport", "ode_report", "ode_equations", "DynamicStability", "dynamic_stability",
           "with_dynamic_stability"]

if TYPE_CHECKING:  # what the lazy names are, for type checkers and IDEs
    from .design import DesignRegion, DesignRow, FoldLocus, design_region, fold_locus
    from .downlock import DownlockResult, downlock_condition, downlock_point
    from .dynamic_stability import DynamicStability, dynamic_stability, with_dynamic_stability
    from .ode_check import OdeReport, ode_equations, ode_report
    from .redundancy import RedundancyReport, RedundancyState, redundancy_along
    from .stops import StopRun, continuation_with_stops, equilibrium_on_stops, stability_on_stops, stops_in_contact
    from .surface import equilibrium_family
    from .unlock import UnlockFolds, unlock_folds, unlock_force_along, with_unlock_columns


__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())
