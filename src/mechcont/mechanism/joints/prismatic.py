"""The prismatic joint: a slider that also locks the relative rotation."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import sympy as sp

from .._expr import Value
from ._base import ConstraintRow, Draw, PlanarJoint, angle_row, line_row
from .slider import draw_slider

if TYPE_CHECKING:
    from .._kinematics import PlanarKinematics

__all__ = ["Prismatic"]


@dataclass(frozen=True)
class Prismatic(PlanarJoint):
    """A slider that also locks the relative rotation: ``theta_b - theta_a = relative_angle``.
    Reactions ``R_<name>`` (normal force, N) and ``T_<name>`` (moment on ``b``, N m)."""

    name: str
    a: str
    b: str
    angle: Value = 0
    relative_angle: Value = 0
    kind: ClassVar[str] = "prismatic"
    KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "angle", "relative_angle"})
    VALUES: ClassVar[tuple[str, ...]] = ("angle", "relative_angle")

    def line_angle(self, kin: PlanarKinematics) -> sp.Expr:
        """Global angle (rad) of the line."""
        return kin.angle(self.a) + self.value(kin, "angle")

    def rows(self, kin: PlanarKinematics) -> list[ConstraintRow]:
        return [line_row(self, kin, self.line_angle(kin)), angle_row(self, kin, self.value(kin, "relative_angle"))]

    def draw(self, kin: PlanarKinematics, add: Draw) -> None:
        draw_slider(self, kin, add)
