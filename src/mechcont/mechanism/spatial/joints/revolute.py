"""The spatial joint ``type = "revolute"``: Revolute3 (see :mod:`._base`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import sympy as sp

from .._rotation import perpendiculars
from ._base import SpatialJoint, SpatialRow, Vector

if TYPE_CHECKING:
    from .._kinematics import SpatialKinematics

__all__ = ["Revolute3"]


@dataclass(frozen=True)
class Revolute3(SpatialJoint):
    """A hinge: ``a`` and ``b`` coincide and ``axis`` stays common to both bodies.
    Reactions ``R_<name>_x/y/z`` (N) and ``T_<name>_1``, ``T_<name>_2`` (N m, about two
    directions normal to the axis)."""

    axis: Vector = (0, 0, 1)
    kind: ClassVar[str] = "revolute"
    VECTORS: ClassVar[tuple[str, ...]] = ("axis",)
    ROTATIONS: ClassVar[int] = 2

    def rows(self, kin: SpatialKinematics) -> list[SpatialRow]:
        return self._point_rows(kin) + self._axis_rows(kin, self.vector(kin, "axis"))

    def drawn_axes(self, kin: SpatialKinematics) -> list[sp.Matrix]:
        return [kin.turn(self.a, perpendiculars(self.vector(kin, "axis"), kin.defaults)[0])]
