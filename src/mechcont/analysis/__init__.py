"""Analyses built on continuation: families of equilibria (surfaces), downlock, design maps."""

from .design import DesignRegion, DesignRow, FoldLocus, design_region, fold_locus
from .downlock import downlock, downlock_condition, downlock_point
from .surface import equilibrium_family

__all__ = ["equilibrium_family", "downlock", "downlock_point", "downlock_condition", "fold_locus", "design_region",
           "DesignRegion", "DesignRow", "FoldLocus"]
