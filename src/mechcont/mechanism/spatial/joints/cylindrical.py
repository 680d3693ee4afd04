"""The spatial joint ``type = "cylindrical"``: Cylindrical (see :mod:`._base`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import sympy as sp

from .._rotation import perpendiculars
from ._base import SpatialRow, Vector
from .inline import Inline

if TYPE_CHECKING:
    from .._kinematics import SpatialKinematics

__all__ = ["Cylindrical"]


@dataclass(frozen=True)
class Cylindrical(Inline):
    """``b`` slides along and turns about the line through ``a`` along ``axis`` (fixed in
    ``a``'s body). Reactions ``R_<name>_1``, ``R_<name>_2`` (N, normal to the axis) and
    ``T_<name>_1``, ``T_<name>_2`` (N m)."""

    axis: Vector = (0, 0, 1)
    kind: ClassVar[str] = "cylindrical"
    ROTATIONS: ClassVar[int] = 2

    def rows(self, kin: SpatialKinematics) -> list[SpatialRow]:
        return self._line_rows(kin) + self._axis_rows(kin, self.vector(kin, "axis"))

    def drawn_axes(self, kin: SpatialKinematics) -> list[sp.Matrix]:
        return [kin.turn(self.a, perpendiculars(self.vector(kin, "axis"), kin.defaults)[0])]
