"""Aerodynamic cross-flow drag on a segment of a body: ``type = "drag"`` (:class:`Drag`, :class:`SpatialDrag`)."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from ...equations import Limit
from ...errors import InputError
from .._expr import Value
from ._base import K, Load, Loads, check_on_body

if TYPE_CHECKING:
    from .._description import Mechanism
    from .._kinematics import PlanarKinematics
    from ..spatial._kinematics import SpatialKinematics

__all__ = ["Drag", "SpatialDrag", "DRAG_SMOOTHING"]

#: Velocity (m/s) below which the drag's |u_n| is smoothed: sqrt(u_n^2 + DRAG_SMOOTHING^2).
DRAG_SMOOTHING = 1e-6
_LIMITS = (("rho", False, "air density (kg/m^3)"), ("d", True, "diameter (m)"), ("CD", False, "drag coefficient"))


class _Segment(Load[K]):
    """What the drags share: a body, two of its points, air density, diameter and coefficient."""

    body: str
    start: str
    end: str
    REQUIRED: ClassVar[tuple[str, ...]] = ("body",)

    def check(self, mech: Mechanism) -> None:
        """Its body and its two points must exist."""
        check_on_body(self, self.body, mech, ("start", "end"))

    def limits(self, kin: K, solve: bool) -> list[Limit]:
        """Air density and drag coefficient non-negative, diameter positive."""
        return [self.value_limit(kin, key, strict, what) for key, strict, what in _LIMITS]

    def static_error(self) -> bool:
        """A segment from a point to itself."""
        return self.start == self.end


@dataclass(frozen=True)
class Drag(_Segment["PlanarKinematics"]):
    """Aerodynamic drag on the segment from point ``start`` to point ``end`` of ``body``.

    Cross-flow model of the paper's eq. 12: with the air velocity ``U (cos alpha, sin alpha)``
    (m/s, rad), the segment of length ``L`` and unit normal ``n`` (left of start->end), the
    normal flow ``u_n = U sin(alpha - theta_axis)`` gives the force
    ``1/2 rho C_D d L u_n |u_n| n`` (N) at the segment's midpoint; its moment about ``start``
    is the paper's ``D = 1/4 rho (U cos(alpha - theta + pi/2))^2 d L^2 C_D`` with the sign of
    ``u_n``. ``|u_n|`` is smoothed as ``sqrt(u_n^2 + (1e-6 m/s)^2)`` so the Jacobian exists
    at ``U = 0`` (force change < 1e-11 N).
    """

    name: str
    body: str
    rho: Value = "rho"
    U: Value = "U"
    alpha: Value = "alpha"
    d: Value = "d"
    CD: Value = "C_D"
    start: str = "a"
    end: str = "b"

    kind: ClassVar[str] = "drag"
    KEYS: ClassVar[frozenset[str]] = frozenset({"body", "rho", "U", "alpha", "d", "CD", "start", "end"})

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """``rho``, ``U``, ``alpha``, ``d``, ``CD``."""
        for key in ("rho", "U", "alpha", "d", "CD"):
            yield self.field(key), getattr(self, key)

    def check_values(self, mech: Mechanism, values: Mapping[str, float]) -> None:
        """The segment needs two points (checked with the values, as a planar description always was)."""
        if self.static_error():
            raise InputError(self.field("end"), "the drag segment needs two different points")

    def apply(self, kin: PlanarKinematics, out: Loads) -> None:
        """Generalised forces of the drag force at the segment's midpoint; drawn there."""
        mech = kin.mech
        rho, U, alpha, d, CD = (mech.value(self.field(a)) for a in ("rho", "U", "alpha", "d", "CD"))
        A, B = kin.point(f"{self.body}.{self.start}"), kin.point(f"{self.body}.{self.end}")
        pa, pb = kin.local_point(self.body, self.start), kin.local_point(self.body, self.end)
        L2 = (pb[0] - pa[0]) ** 2 + (pb[1] - pa[1]) ** 2  # squared segment length (no sqrt: stays smooth)
        perp = sp.Matrix([-(B - A)[1], (B - A)[0]])  # L times the unit normal n
        s = U * (sp.cos(alpha) * perp[0] + sp.sin(alpha) * perp[1])  # L u_n
        # 1/2 rho C_D d L u_n |u_n| n  with |u_n| -> sqrt(u_n^2 + eps^2), written without L itself
        force = rho * CD * d / 2 * s * sp.sqrt(s ** 2 + DRAG_SMOOTHING ** 2 * L2) / L2 * perp
        P = (A + B) / 2
        out.add(kin.force_work(P, force))
        out.arrow(self.name, P, force)


@dataclass(frozen=True)
class SpatialDrag(_Segment["SpatialKinematics"]):
    """Aerodynamic cross-flow drag on the segment from point ``start`` to point ``end`` of ``body``.

    With the air velocity ``U * direction / |direction|`` (m/s), the segment ``D = P_end -
    P_start`` of length ``L`` and the air velocity's component normal to it ``w_n``, the force
    ``1/2 rho C_D d L |w_n| w_n`` (N) acts at the segment's midpoint (the planar drag's model in
    space; ``|w_n|`` smoothed as ``sqrt(|w_n|^2 + (1e-6 m/s)^2)`` so the Jacobian exists at
    ``U = 0``).
    """

    name: str
    body: str
    rho: Value = "rho"
    U: Value = "U"
    direction: tuple[Value, Value, Value] = (1, 0, 0)
    d: Value = "d"
    CD: Value = "C_D"
    start: str = "a"
    end: str = "b"

    kind: ClassVar[str] = "drag"
    SPACES: ClassVar[tuple[str, ...]] = ("space",)
    KEYS: ClassVar[frozenset[str]] = frozenset({"body", "rho", "U", "direction", "d", "CD", "start", "end"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("body", "direction")
    VECTORS: ClassVar[tuple[str, ...]] = ("direction",)

    def check(self, mech: Mechanism) -> None:
        """Its body and two different points of it."""
        super().check(mech)
        if self.static_error():
            raise InputError(self.field("end"), "the drag segment needs two different points")

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """``rho``, ``U``, ``d``, ``CD`` and the air's direction."""
        for key in ("rho", "U", "d", "CD"):
            yield self.field(key), getattr(self, key)
        yield from mech.vector_values(self.field("direction"), self.direction)

    def vectors(self) -> list[str]:
        """The air's direction must not be zero."""
        return [self.field("direction")]

    def apply(self, kin: SpatialKinematics, out: Loads) -> None:
        """Generalised forces of the drag force at the segment's midpoint; drawn there."""
        from ..spatial._rotation import dot

        mech = kin.mech
        rho, U, d, CD = (mech.value(self.field(a)) for a in ("rho", "U", "d", "CD"))
        w = U * kin.direction(self.field("direction"), self.direction)
        A, B = kin.point(f"{self.body}.{self.start}"), kin.point(f"{self.body}.{self.end}")
        local = kin.local_point(self.body, self.end) - kin.local_point(self.body, self.start)
        L2 = dot(local, local)  # squared segment length, constant on a rigid body (no sqrt of coordinates)
        D = B - A
        W = L2 * w - dot(w, D) * D  # L^2 w_n
        # 1/2 rho C_D d L |w_n| w_n with |w_n| -> sqrt(|w_n|^2 + eps^2), written through W = L^2 w_n
        force = rho * CD * d / 2 * sp.sqrt(dot(W, W) + DRAG_SMOOTHING ** 2 * L2 ** 2) / L2 ** sp.Rational(3, 2) * W
        P = (A + B) / 2
        out.add(kin.force_work(P, force))
        out.arrow(self.name, P, force)
