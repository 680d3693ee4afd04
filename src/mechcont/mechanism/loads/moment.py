"""A pure moment on a body: ``type = "moment"`` (planar :class:`Moment`, spatial :class:`SpatialMoment`)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from .._expr import Value
from ._base import Draw, Load, Loads, check_on_body

if TYPE_CHECKING:
    from .._description import Mechanism
    from .._kinematics import PlanarKinematics
    from ..spatial._kinematics import SpatialKinematics

__all__ = ["Moment", "SpatialMoment"]


@dataclass(frozen=True)
class Moment(Load["PlanarKinematics"]):
    """A pure moment (N m, counter-clockwise positive) on a body; conservative (potential ``-M theta``)."""

    name: str
    body: str
    magnitude: Value

    kind: ClassVar[str] = "moment"
    KEYS: ClassVar[frozenset[str]] = frozenset({"body", "magnitude"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("body", "magnitude")

    def check(self, mech: Mechanism) -> None:
        """Its body must exist."""
        check_on_body(self, self.body, mech)

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its magnitude."""
        yield self.field("magnitude"), self.magnitude

    def apply(self, kin: PlanarKinematics, out: Loads) -> None:
        """Potential ``-M theta`` of its body."""
        out.V -= kin.mech.value(self.field("magnitude")) * kin.body_q[self.body][2]

    def draw(self, kin: PlanarKinematics, add: Draw) -> None:
        """Drawn around the body's pin to the ground if it has one, else around the body's origin."""
        add("moment", self.name, [kin.moment_anchor(self.body), sp.Matrix([kin.mech.value(self.field("magnitude")), 0])])


@dataclass(frozen=True)
class SpatialMoment(Load["SpatialKinematics"]):
    """A pure moment ``magnitude`` (N m) about the fixed global ``axis`` (right-hand rule) on a body."""

    name: str
    body: str
    magnitude: Value
    axis: tuple[Value, Value, Value] = (0, 0, 1)

    kind: ClassVar[str] = "moment"
    SPACES: ClassVar[tuple[str, ...]] = ("space",)
    KEYS: ClassVar[frozenset[str]] = frozenset({"body", "magnitude", "axis"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("body", "magnitude", "axis")
    VECTORS: ClassVar[tuple[str, ...]] = ("axis",)

    def check(self, mech: Mechanism) -> None:
        """Its body must exist."""
        check_on_body(self, self.body, mech)

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its magnitude and axis."""
        yield self.field("magnitude"), self.magnitude
        yield from mech.vector_values(self.field("axis"), self.axis)

    def vectors(self) -> list[str]:
        """The axis must not be zero."""
        return [self.field("axis")]

    def apply(self, kin: SpatialKinematics, out: Loads) -> None:
        """Generalised forces ``2 E^T n`` on the body's Euler parameters (a moment of fixed direction
        does no work that a potential could give); drawn at the body's first ground joint."""
        n = kin.mech.value(self.field("magnitude")) * kin.direction(self.field("axis"), self.axis)
        out.add(kin.moment_work(self.body, n))
        out.arrow(self.name, kin.moment_anchor(self.body), n, "moment")
