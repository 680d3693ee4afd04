"""The weld: a rigid connection of two bodies at a point."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import sympy as sp

from .._expr import Value
from ._base import ConstraintRow, Draw, PlanarJoint, angle_row, point_rows

if TYPE_CHECKING:
    from .._kinematics import PlanarKinematics

__all__ = ["Weld"]


@dataclass(frozen=True)
class Weld(PlanarJoint):
    """Points ``a`` and ``b`` coincide and ``theta_b - theta_a = angle`` (a fixed angle offset).
    Reactions ``R_<name>_x, R_<name>_y`` (N) and ``T_<name>`` (N m) on ``b``'s body."""

    name: str
    a: str
    b: str
    angle: Value = 0
    kind: ClassVar[str] = "weld"
    KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "angle"})
    VALUES: ClassVar[tuple[str, ...]] = ("angle",)
    COINCIDENT: ClassVar[bool] = True

    def locked_angle(self, kin: PlanarKinematics) -> sp.Expr:
        return self.value(kin, "angle")

    def rows(self, kin: PlanarKinematics) -> list[ConstraintRow]:
        return [*point_rows(self, kin), angle_row(self, kin, self.locked_angle(kin))]

    def draw(self, kin: PlanarKinematics, add: Draw) -> None:
        add("ground" if self.grounded() else "pin", self.name, [kin.point(self.b)])
