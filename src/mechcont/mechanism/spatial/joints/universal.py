"""The spatial joint ``type = "universal"``: Universal (see :mod:`._base`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import sympy as sp

from ....errors import InputError
from ..._expr import evaluate
from .._rotation import perpendiculars
from ._base import SpatialJoint, SpatialRow, Vector

if TYPE_CHECKING:
    from ..._description import Mechanism
    from .._kinematics import SpatialKinematics

__all__ = ["Universal"]


@dataclass(frozen=True)
class Universal(SpatialJoint):
    """A Cardan joint: ``a`` and ``b`` coincide; ``axis_a`` (fixed in ``a``'s body) stays
    perpendicular to ``axis_b`` (fixed in ``b``'s body); the two must be perpendicular in the
    design pose. Reactions ``R_<name>_x/y/z`` (N) and ``T_<name>_1`` (N m)."""

    axis_a: Vector = (1, 0, 0)
    axis_b: Vector = (0, 1, 0)
    kind: ClassVar[str] = "universal"
    VECTORS: ClassVar[tuple[str, ...]] = ("axis_a", "axis_b")
    ROTATIONS: ClassVar[int] = 1

    def perpendicular(self, mech: Mechanism) -> list[list[sp.Expr]]:
        """``axis_a`` and ``axis_b`` must be perpendicular in the design pose."""
        return [[mech.value(f"joints.{self.name}.{axis}.{c}") for axis in ("axis_a", "axis_b") for c in "xyz"]]

    def check_values(self, mech: Mechanism, values: Mapping[str, float]) -> None:
        """``axis_a`` perpendicular to ``axis_b`` at ``values`` (one-line InputError)."""
        a = [evaluate(mech.value(f"joints.{self.name}.axis_a.{c}"), values, "") for c in "xyz"]
        b = [evaluate(mech.value(f"joints.{self.name}.axis_b.{c}"), values, "") for c in "xyz"]
        c = sum(p * q for p, q in zip(a, b)) / (sum(p * p for p in a) * sum(q * q for q in b)) ** 0.5
        if abs(c) > 1e-9:
            raise InputError(f"joints.{self.name}.axis_b", f"must be perpendicular to axis_a in the design pose "
                                                           f"(cosine of the angle between them {c:.3g})")

    def rows(self, kin: SpatialKinematics) -> list[SpatialRow]:
        ua = perpendiculars(self.vector(kin, "axis_a"), kin.defaults)[0]
        ub = perpendiculars(self.vector(kin, "axis_b"), kin.defaults)[0]
        return self._point_rows(kin) + [self._rotation_row(kin, 1, ua, ub)]

    def drawn_axes(self, kin: SpatialKinematics) -> list[sp.Matrix]:
        return [kin.turn(self.a, perpendiculars(self.vector(kin, "axis_a"), kin.defaults)[0]),
                kin.turn(self.b, perpendiculars(self.vector(kin, "axis_b"), kin.defaults)[0])]
