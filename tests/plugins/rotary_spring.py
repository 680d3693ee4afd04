"""A rotary spring as one module: ``[test_rotary_springs.NAME]`` (an extension written in a test only).

A linear spring between the two points ``a`` and ``b`` of a pin (they coincide): potential
``k/2 (phi - angle)^2`` (J), ``phi`` the rotation (rad) of ``b``'s body relative to ``a``'s about
``axis`` (space only; design pose, default +z), written once for both spaces against the kinematics
protocol (``kin.relative_rotation``). It is drawn from its two points, which coincide: its drawing
anchors are not a line of action, so the assembly diagnostics must not refuse it (the ``ends()``
trap of issue 34).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, ClassVar

import sympy as sp

from mechcont.equations import Limit
from mechcont.mechanism._plugin import Draw, Kinematics
from mechcont.mechanism.elements import TwoPointElement
from mechcont.mechanism.loads import Loads


@dataclass(frozen=True)
class RotarySpring(TwoPointElement):
    """Stiffness ``k`` (N m/rad) and free angle ``angle`` (rad) between the pin points ``a`` and ``b``."""

    name: str
    a: str
    b: str
    k: Any
    angle: Any = 0
    axis: tuple[Any, Any, Any] = (0, 0, 1)

    table: ClassVar[str] = "test_rotary_springs"
    KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "k", "angle", "axis"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("a", "b", "k")
    TEXT_KEYS: ClassVar[tuple[str, ...]] = ("a", "b")

    def values(self, mech: Any) -> Iterator[tuple[str, Any]]:
        """Its stiffness, free angle and (in space) axis."""
        yield self.field("k"), self.k
        yield self.field("angle"), self.angle
        if mech.space == "space":
            yield from mech.vector_values(self.field("axis"), list(self.axis))

    def limits(self, kin: Kinematics, solve: bool) -> list[Limit]:
        """A non-negative stiffness (the one signature of every plug-in's limits)."""
        return [self.value_limit(kin, "k", False, "rotary stiffness (N m/rad)")]

    def line_of_action(self) -> tuple[str, str] | None:
        """None: a moment about the pin, along no line (its two points coincide)."""
        return None

    def rotation(self, kin: Kinematics) -> sp.Expr:
        """``phi`` (rad): the rotation of ``b``'s body relative to ``a``'s about the axis."""
        axis = sp.Matrix([kin.mech.value(self.field(f"axis.{c}")) for c in "xyz"]) if kin.dimension == 3 else None
        return kin.relative_rotation(self.a, self.b, axis)

    def apply(self, kin: Kinematics, out: Loads) -> None:
        """Potential ``k/2 (phi - angle)^2``."""
        v = kin.mech.value
        out.V += v(self.field("k")) / 2 * (self.rotation(kin) - v(self.field("angle"))) ** 2

    def draw(self, kin: Kinematics, add: Draw) -> None:
        """A coil at the pin."""
        add("torsion_spring", self.name, [kin.point(self.b)])
