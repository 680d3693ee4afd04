"""Analyses built on continuation: families of equilibria (surfaces), downlock, unlock folds, design maps."""

from .design import DesignRegion, DesignRow, FoldLocus, design_region, fold_locus
from .downlock import DownlockBranch, downlock, downlock_condition, downlock_point
from .redundancy import RedundancyReport, RedundancyState, redundancy_along
from .surface import equilibrium_family
from .unlock import UnlockFolds, unlock_folds, unlock_force_along, with_unlock_columns

__all__ = ["equilibrium_family", "downlock", "downlock_point", "downlock_condition", "fold_locus", "design_region",
           "DesignRegion", "DesignRow", "FoldLocus", "DownlockBranch", "UnlockFolds", "unlock_folds",
           "unlock_force_along", "with_unlock_columns", "redundancy_along", "RedundancyReport", "RedundancyState"]
