"""Rotary (torsion) dampers between two bodies (planar and spatial): ``[torsion_dampers.NAME]``.

A torsion damper between bodies ``a`` and ``b`` (either may be ``"ground"``) exerts on ``b`` the
moment ``-(c w + c2 w |w|)`` (N m) about the relative axis, and the opposite on ``a``, with
``w = dphi/dt`` (rad/s) the rate of the relative angle ``phi`` (see :mod:`._rotary`; in space about
the axis of ``joint``): a shimmy damper. Its generalised forces are ``-(c w + c2 w |w|) dphi/dq``
with ``w = dphi/dq . qdot`` in the velocity symbols, so it vanishes at rest: every continuation
sees no damper, the time simulation and the dynamic stability do (a generalised damping matrix
``c (dphi/dq)(dphi/dq)^T``).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

from ...equations import Limit
from .._expr import Value
from .._plugin import Kinematics
from ._base import Draw, Element
from ._rotary import angle_rate, check_bodies, pivot, relative_angle
from .damper import damper_tension

if TYPE_CHECKING:
    from .._description import Mechanism
    from ..loads import Loads

__all__ = ["TorsionDamper"]


@dataclass(frozen=True)
class TorsionDamper(Element):
    """A rotary damper between bodies ``a`` and ``b``: moment ``c w + c2 w |w|`` (N m) resisting the
    relative rate ``w`` (rad/s); ``c`` >= 0 (N m s/rad), ``c2`` >= 0 (N m s^2/rad^2)."""

    name: str
    a: str
    b: str
    c: Value
    c2: Value = 0
    joint: str | None = None

    table: ClassVar[str] = "torsion_dampers"
    KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "c", "c2", "joint"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("a", "b", "c")
    TEXT_KEYS: ClassVar[tuple[str, ...]] = ("a", "b", "joint")

    def check(self, mech: Mechanism) -> None:
        """``a``, ``b`` bodies (or the ground), ``joint`` (required in space) joining them."""
        check_bodies(self, mech)

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its linear and quadratic damping."""
        yield self.field("c"), self.c
        yield self.field("c2"), self.c2

    def limits(self, kin: Kinematics, solve: bool) -> list[Limit]:
        """Both coefficients non-negative."""
        return [self.value_limit(kin, "c", False, "torsional damping (N m s/rad)"),
                self.value_limit(kin, "c2", False, "quadratic torsional damping (N m s^2/rad^2)")]

    def apply(self, kin: Kinematics, out: Loads) -> None:
        """Generalised forces ``-(c w + c2 w |w|) dphi/dq``, ``w = dphi/dq . qdot``."""
        grad, rate = angle_rate(relative_angle(self, kin), kin)
        v = kin.mech.value
        moment = damper_tension(v(self.field("c")), v(self.field("c2")), rate)
        out.add([-moment * g for g in grad])

    def draw(self, kin: Kinematics, add: Draw) -> None:
        """A rotary dashpot (``torsion_damper``) at the joint between ``a`` and ``b``."""
        add("torsion_damper", self.name, [pivot(self, kin)])
