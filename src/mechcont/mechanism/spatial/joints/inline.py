"""The spatial joint ``type = "inline"``: Inline (see :mod:`._base`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from .._rotation import dot, perpendiculars
from ._base import SpatialJoint, SpatialRow, Vector

if TYPE_CHECKING:
    from .._kinematics import SpatialKinematics

__all__ = ["Inline"]


@dataclass(frozen=True)
class Inline(SpatialJoint):
    """Point ``b`` stays on the line through ``a`` along ``axis`` (fixed in ``a``'s body); every
    rotation is free (a ball in a slot: the planar slider's spatial form). Reactions
    ``R_<name>_1``, ``R_<name>_2`` (N, normal to the line)."""

    axis: Vector = (1, 0, 0)
    kind: ClassVar[str] = "inline"
    VECTORS: ClassVar[tuple[str, ...]] = ("axis",)
    COINCIDENT: ClassVar[bool] = False
    TRANSLATIONS: ClassVar[int] = 2

    def _line_rows(self, kin: SpatialKinematics) -> list[SpatialRow]:
        _, f, g = perpendiculars(self.vector(kin, "axis"), kin.defaults)
        d = kin.point(self.a) - kin.point(self.b)
        k, n = self._k(kin, "stiffness"), self.name
        return [SpatialRow(n, f"{n}_n{i}", f"R_{n}_{i}", "N", dot(kin.turn(self.a, v), d), k)
                for i, v in ((1, f), (2, g))]

    def rows(self, kin: SpatialKinematics) -> list[SpatialRow]:
        return self._line_rows(kin)
