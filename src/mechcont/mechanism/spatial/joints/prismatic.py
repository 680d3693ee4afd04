"""The spatial joint ``type = "prismatic"``: Prismatic3 (see :mod:`._base`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from .._rotation import perpendiculars
from ._base import SpatialRow
from .cylindrical import Cylindrical

if TYPE_CHECKING:
    from .._kinematics import SpatialKinematics

__all__ = ["Prismatic3"]


@dataclass(frozen=True)
class Prismatic3(Cylindrical):
    """A cylindrical joint that also locks the rotation about its axis. Reactions as the
    cylindrical joint's and ``T_<name>_3`` (N m, about the axis)."""

    kind: ClassVar[str] = "prismatic"
    ROTATIONS: ClassVar[int] = 3

    def rows(self, kin: SpatialKinematics) -> list[SpatialRow]:
        _, f, g = perpendiculars(self.vector(kin, "axis"), kin.defaults)
        return super().rows(kin) + [self._rotation_row(kin, 3, f, g)]
