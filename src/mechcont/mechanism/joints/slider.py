"""The slider: point ``b`` slides along a line through point ``a``, rotation free."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import sympy as sp

from .._expr import Value
from ._base import ConstraintRow, Draw, PlanarJoint, line_row

if TYPE_CHECKING:
    from .._kinematics import PlanarKinematics
    from .prismatic import Prismatic

__all__ = ["Slider", "draw_slider"]


@dataclass(frozen=True)
class Slider(PlanarJoint):
    """Point ``b`` slides along the line through point ``a`` at ``angle`` (rad) in ``a``'s
    frame (the global frame for a ground point); rotation stays free (pin in a slot).
    Reaction ``R_<name>``: the force (N) on ``b``'s body along the line's left normal."""

    name: str
    a: str
    b: str
    angle: Value = 0
    kind: ClassVar[str] = "slider"
    KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "angle"})
    VALUES: ClassVar[tuple[str, ...]] = ("angle",)

    def line_angle(self, kin: PlanarKinematics) -> sp.Expr:
        """Global angle (rad) of the line."""
        return kin.angle(self.a) + self.value(kin, "angle")

    def rows(self, kin: PlanarKinematics) -> list[ConstraintRow]:
        return [line_row(self, kin, self.line_angle(kin))]

    def draw(self, kin: PlanarKinematics, add: Draw) -> None:
        draw_slider(self, kin, add)


def draw_slider(joint: Slider | Prismatic, kin: PlanarKinematics, add: Draw) -> None:
    """A block at ``b`` on a guide along the joint's line (``joint.line_angle``)."""
    phi = joint.line_angle(kin)
    add("slider", joint.name, [kin.point(joint.b), sp.Matrix([sp.cos(phi), sp.sin(phi)])])
