"""Uniform gravity: the ``[gravity]`` table (:class:`Gravity` in the plane, :class:`SpatialGravity` in space)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from .._expr import Value
from .._plugin import Kinematics
from ._base import Loads

if TYPE_CHECKING:
    from .._description import Mechanism

__all__ = ["Gravity", "SpatialGravity"]


class _Gravity:
    """The potential ``-sum m g u . r_cg`` of every body."""

    SPACES: ClassVar[tuple[str, ...]] = ("plane",)

    def acceleration(self, kin: Kinematics) -> sp.Matrix:
        """The acceleration vector (m/s^2) in global axes."""
        raise NotImplementedError

    def vectors(self) -> list[str]:
        """Key paths of its vectors that must not be zero."""
        return []

    def apply(self, kin: Kinematics, out: Loads) -> None:
        """Add the potential of every body's weight."""
        gvec = self.acceleration(kin)
        for b in kin.mech.bodies:
            out.V -= kin.body_mass(b) * gvec.dot(kin.cg(b.name))


@dataclass(frozen=True)
class Gravity(_Gravity):
    """Uniform gravity of magnitude ``g`` (m/s^2) pointing at ``angle`` (rad; default -y)."""

    g: Value = "g"
    angle: Value = -sp.pi / 2

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """``g`` and ``angle``."""
        yield "gravity.g", self.g
        yield "gravity.angle", self.angle

    def acceleration(self, kin: Kinematics) -> sp.Matrix:
        """``g (cos angle, sin angle)``."""
        g, ang = kin.mech.value("gravity.g"), kin.mech.value("gravity.angle")
        return sp.Matrix([g * sp.cos(ang), g * sp.sin(ang)])


@dataclass(frozen=True)
class SpatialGravity(_Gravity):
    """Uniform gravity of magnitude ``g`` (m/s^2) along ``direction`` (default ``-z``)."""

    g: Value = "g"
    direction: tuple[Value, Value, Value] = (0, 0, -1)

    SPACES: ClassVar[tuple[str, ...]] = ("space",)

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """``g`` and the direction."""
        yield "gravity.g", self.g
        yield from mech.vector_values("gravity.direction", self.direction)

    def vectors(self) -> list[str]:
        """The direction must not be zero."""
        return ["gravity.direction"]

    def acceleration(self, kin: Kinematics) -> sp.Matrix:
        """``g direction / |direction|``."""
        return kin.mech.value("gravity.g") * kin.direction("gravity.direction", self.direction)
