"""The spatial joint ``type = "weld"``: Weld3 (see :mod:`._base`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import sympy as sp

from ._base import SpatialJoint, SpatialRow

if TYPE_CHECKING:
    from .._kinematics import SpatialKinematics

__all__ = ["Weld3"]


@dataclass(frozen=True)
class Weld3(SpatialJoint):
    """A rigid connection: ``a`` and ``b`` coincide and the bodies keep their design-pose
    relative orientation. Reactions ``R_<name>_x/y/z`` (N) and ``T_<name>_1..3`` (N m, about
    the x, y, z axes of ``a``'s body)."""

    kind: ClassVar[str] = "weld"
    ROTATIONS: ClassVar[int] = 3

    def rows(self, kin: SpatialKinematics) -> list[SpatialRow]:
        ex, ey, ez = (sp.Matrix([int(i == j) for j in range(3)]) for i in range(3))
        return self._point_rows(kin) + [self._rotation_row(kin, 1, ey, ez), self._rotation_row(kin, 2, ez, ex),
                                        self._rotation_row(kin, 3, ex, ey)]
