"""A user-defined load, expressions in the parameters and coordinates: ``type = "custom"``
(:class:`CustomLoad`, :class:`SpatialCustomLoad`)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from .._expr import Value
from ._base import Draw, K, Load, Loads, check_at_point

if TYPE_CHECKING:
    from .._description import Mechanism
    from .._kinematics import PlanarKinematics
    from ..spatial._kinematics import SpatialKinematics

__all__ = ["CustomLoad", "SpatialCustomLoad"]


class _Custom(Load[K]):
    """What the custom loads share: a point, and their expressions (the ``COORDINATE_KEYS``)."""

    at: str
    REQUIRED: ClassVar[tuple[str, ...]] = ("at",)

    def check(self, mech: Mechanism) -> None:
        """Its point must be a body point."""
        check_at_point(self, self.at, mech)

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its force and moment components."""
        for key in self.COORDINATE_KEYS:
            yield self.field(key), getattr(self, key)


@dataclass(frozen=True)
class CustomLoad(_Custom["PlanarKinematics"]):
    """A user-defined load: force ``(fx, fy)`` (N, global axes) at point ``at`` and a moment
    (N m) on that point's body; expressions may use parameters and coordinates."""

    name: str
    at: str
    fx: Value = 0
    fy: Value = 0
    moment: Value = 0

    kind: ClassVar[str] = "custom"
    KEYS: ClassVar[frozenset[str]] = frozenset({"at", "fx", "fy", "moment"})
    COORDINATE_KEYS: ClassVar[tuple[str, ...]] = ("fx", "fy", "moment")

    def apply(self, kin: PlanarKinematics, out: Loads) -> None:
        """Virtual work ``f . dP/dq + M dtheta/dq``; its force drawn at its point."""
        mech = kin.mech
        P = kin.point(self.at)
        force = sp.Matrix([mech.value(self.field("fx")), mech.value(self.field("fy"))])
        out.add(kin.force_work(P, force, kin.angle(self.at), mech.value(self.field("moment"))))
        out.arrow(self.name, P, force)

    def draw(self, kin: PlanarKinematics, add: Draw) -> None:
        """A moment that is not identically zero is drawn around its point."""
        M = sp.sympify(kin.mech.value(self.field("moment")), strict=True)
        if M != 0:
            add("moment", self.name, [kin.point(self.at), sp.Matrix([M, 0])])


@dataclass(frozen=True)
class SpatialCustomLoad(_Custom["SpatialKinematics"]):
    """A user-defined load: force ``(fx, fy, fz)`` (N, global axes) at point ``at`` and moment
    ``(mx, my, mz)`` (N m, global axes) on that point's body; expressions may use the
    parameters and the coordinates."""

    name: str
    at: str
    fx: Value = 0
    fy: Value = 0
    fz: Value = 0
    mx: Value = 0
    my: Value = 0
    mz: Value = 0

    kind: ClassVar[str] = "custom"
    SPACES: ClassVar[tuple[str, ...]] = ("space",)
    KEYS: ClassVar[frozenset[str]] = frozenset({"at", "fx", "fy", "fz", "mx", "my", "mz"})
    COORDINATE_KEYS: ClassVar[tuple[str, ...]] = ("fx", "fy", "fz", "mx", "my", "mz")

    def apply(self, kin: SpatialKinematics, out: Loads) -> None:
        """Virtual work of the force at its point and ``2 E^T m of the moment; its force drawn at its point."""
        mech = kin.mech
        P = kin.point(self.at)
        force = sp.Matrix([mech.value(self.field(k)) for k in ("fx", "fy", "fz")])
        moment = sp.Matrix([mech.value(self.field(k)) for k in ("mx", "my", "mz")])
        out.add([a + b for a, b in zip(kin.force_work(P, force), kin.moment_work(self.at.split(".")[0], moment))])
        out.arrow(self.name, P, force)
