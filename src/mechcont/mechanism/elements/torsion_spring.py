"""Rotary (torsion) springs between two bodies (planar and spatial): ``[torsion_springs.NAME]``.

A torsion spring between bodies ``a`` and ``b`` (either may be ``"ground"``) stores

    V = k/2 (phi - angle)^2     (J),

``phi`` the rotation of ``b`` relative to ``a`` (rad: ``theta_b - theta_a`` in the plane; in space
about the axis of the revolute or cylindrical joint ``joint``, see :mod:`._rotary`), ``angle`` its
free relative angle (rad), ``k`` (N m/rad). The moment it exerts on ``b`` is ``-k (phi - angle)``
about the axis (and the opposite on ``a``). It is drawn as a coil at the joint, not as a line
between two points: its "ends" sit on one pin, so it has no line of action
(:meth:`Element.line_of_action`, None) and no drawing anchors (:meth:`Element.ends`).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

from ...equations import Limit
from .._expr import Value
from .._plugin import Kinematics
from ._base import Draw, Element
from ._rotary import check_bodies, pivot, relative_angle

if TYPE_CHECKING:
    from .._description import Mechanism
    from ..loads import Loads

__all__ = ["TorsionSpring"]


@dataclass(frozen=True)
class TorsionSpring(Element):
    """A linear torsion spring between bodies ``a`` and ``b``: potential ``k/2 (phi - angle)^2`` (J),
    ``phi`` the relative angle (rad) of ``b`` to ``a``, ``k`` >= 0 (N m/rad); see the module docstring."""

    name: str
    a: str
    b: str
    k: Value
    angle: Value = 0
    joint: str | None = None

    table: ClassVar[str] = "torsion_springs"
    KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "k", "angle", "joint"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("a", "b", "k")
    TEXT_KEYS: ClassVar[tuple[str, ...]] = ("a", "b", "joint")

    def check(self, mech: Mechanism) -> None:
        """``a``, ``b`` bodies (or the ground), ``joint`` (required in space) joining them."""
        check_bodies(self, mech)

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its stiffness and free angle."""
        yield self.field("k"), self.k
        yield self.field("angle"), self.angle

    def limits(self, kin: Kinematics, solve: bool) -> list[Limit]:
        """A non-negative stiffness."""
        return [self.value_limit(kin, "k", False, "torsional stiffness (N m/rad)")]

    def apply(self, kin: Kinematics, out: Loads) -> None:
        """Potential ``k/2 (phi - angle)^2`` (J)."""
        v = kin.mech.value
        out.V += v(self.field("k")) / 2 * (relative_angle(self, kin) - v(self.field("angle"))) ** 2

    def draw(self, kin: Kinematics, add: Draw) -> None:
        """A coil (``torsion_spring``) at the joint between ``a`` and ``b``."""
        add("torsion_spring", self.name, [pivot(self, kin)])
