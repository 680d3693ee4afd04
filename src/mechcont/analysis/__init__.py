"""Analyses built on continuation: families of equilibria (surfaces), downlock, unlock folds, stops, design maps."""

from .design import DesignRegion, DesignRow, FoldLocus, design_region, fold_locus
from .downlock import DownlockBranch, downlock, downlock_condition, downlock_point
from .redundancy import RedundancyReport, RedundancyState, redundancy_along
from .stops import StopRun, continuation_with_stops, equilibrium_on_stops, stability_on_stops, stops_in_contact
from .surface import equilibrium_family
from .unlock import UnlockFolds, unlock_folds, unlock_force_along, with_unlock_columns

__all__ = ["equilibrium_family", "downlock", "downlock_point", "downlock_condition", "fold_locus", "design_region",
           "DesignRegion", "DesignRow", "FoldLocus", "DownlockBranch", "UnlockFolds", "unlock_folds",
           "unlock_force_along", "with_unlock_columns", "redundancy_along", "RedundancyReport", "RedundancyState",
           "StopRun", "continuation_with_stops", "equilibrium_on_stops", "stability_on_stops",
           "stops_in_contact"]
