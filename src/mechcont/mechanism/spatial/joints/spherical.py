"""The spatial joint ``type = "spherical"``: Spherical (see :mod:`._base`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from ._base import SpatialJoint, SpatialRow

if TYPE_CHECKING:
    from .._kinematics import SpatialKinematics

__all__ = ["Spherical"]


@dataclass(frozen=True)
class Spherical(SpatialJoint):
    """A ball joint: ``a`` and ``b`` coincide. Reactions ``R_<name>_x/y/z`` (N, global axes)."""

    kind: ClassVar[str] = "spherical"

    def rows(self, kin: SpatialKinematics) -> list[SpatialRow]:
        return self._point_rows(kin)
