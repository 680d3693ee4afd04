"""A stretched-string tyre (top view): ``[tyres.NAME]``, planar and spatial.

The model (Pacejka's single-contact-point relaxation model; the tyre model of the shimmy studies
of Somieski 1997 and Thota, Krauskopf & Lowenberg 2009)
---------------------------------------------------------------------------------------------------
The mechanism travels at ``speed`` ``V`` (m/s) along global ``+x``: relative to it the ground
moves at ``-V e_x``. The wheel is the body ``body``; its heading ``h`` is that body's x axis, its
lateral axis ``l`` the heading turned +90 degrees (to the left, seen from above: ``l = e_z x h``);
``P`` is the contact point ``at``. The tyre's contact patch is displaced from the wheel plane by the
lateral deflection ``y`` (m, along ``l``): a first-order state ``y_NAME`` of the mechanism, with

    dy/dt = -v_lat - (V/sigma) y,       v_lat = (dP/dt + V e_x) . l,

``v_lat`` (m/s) the contact point's velocity relative to the ground along the lateral axis and
``sigma`` the ``relaxation_length`` (m). The ground exerts on the wheel the side force

    F(y) = C y / sigma                              (linear; ``max_force`` absent)
    F(y) = F_max tanh(C y / (sigma F_max))          (saturating; same slope at y = 0)

(N) along ``l``, at ``P - t h`` (``t`` the ``pneumatic_trail``, m: the force acts behind the contact
point, giving the self-aligning moment ``-t F``); ``C`` is the ``cornering_stiffness`` (N/rad).

Signs, on paper: a wheel held at a yaw angle ``psi`` (heading ``h = (cos psi, sin psi)``,
``l = (-sin psi, cos psi)``) rolling along ``+x`` at rest in the mechanism has ``v_lat = V e_x . l =
-V sin psi``, so the deflection relaxes (time constant ``sigma/V``) to ``y = sigma sin psi`` and the
side force to ``F = C sin psi ~ C psi`` along ``+l``: the ground pushes the wheel the way it is
steered, the slip angle being ``alpha = -v_lat/V = sin psi``. On a caster wheel swivelling about a
pin at the origin with its contact point a caster length ``e`` behind (``P = -e h``) the moment of
that force about the pin is ``(-e h) x (F l) = -e F``: it turns the wheel back towards the direction
of travel, as a trailing caster does. Swivelling about that fixed pin (``dP/dt = -e psi' l``),
``dy/dt = e psi' + V sin psi - (V/sigma) y``:
the lag of ``y`` behind ``psi`` (the ``V/sigma`` pole) is what feeds shimmy when ``e < sigma``
(see ``tests/test_shimmy_dynamics.py`` for the Routh-Hurwitz Hopf speeds of this caster).

Relation to von Schlippe and the straight-tangent approximation: von Schlippe and Dietrich's
string model remembers the path of the leading contact point over the contact length (a delay
equation); taking the string between the leading contact point and its tangent point straight
(the *straight-tangent* approximation) and lumping the contact patch into one point gives this
first-order equation for the deflection at the centre of the contact patch; Pacejka's relaxation
length model is the same equation. It holds for wavelengths of the motion ``2 pi V / omega`` long
against the contact length.

Limits: no vertical dynamics (``C``, ``sigma``, ``F_max`` are fixed, not functions of a vertical
load), no camber, no longitudinal slip, one contact point (no tread-width turn-slip moment; the
only aligning moment is the pneumatic trail's), a constant ``speed`` (a parameter, ``> 0``: at rest
the deflection is not determined by anything), a wheel rolling forwards (a heading within 90
degrees of ``+x``). In continuation the tyre sits at its steady state (its rate at rest is one of
the equations); the time simulation and the dynamic stability integrate or linearise it.
In space the ground plane is the global x-y plane (z up): the heading is the body's x axis
projected on it (normalised; undefined for a vertical wheel x axis), ``l = e_z x h``, ``v_lat`` and
the force lie in that plane.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from ...equations import Limit, velocity_symbol
from ...errors import InputError
from .._expr import Value, symbol
from .._plugin import Kinematics
from .._values import parameter_values
from ._base import Draw, Element, ElementState

if TYPE_CHECKING:
    from .._description import Mechanism
    from ..loads import Loads

__all__ = ["Tyre"]


@dataclass(frozen=True)
class Tyre(Element):
    """A stretched-string tyre on ``body`` at its point ``at``: one state ``y_NAME`` (m), the side
    force ``F(y)`` (N) along the wheel's lateral axis; see the module docstring."""

    name: str
    body: str
    at: str
    speed: Value
    relaxation_length: Value
    cornering_stiffness: Value
    max_force: Value | None = None
    pneumatic_trail: Value = 0

    table: ClassVar[str] = "tyres"
    KEYS: ClassVar[frozenset[str]] = frozenset({"body", "at", "speed", "relaxation_length", "cornering_stiffness",
                                                "max_force", "pneumatic_trail"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("body", "at", "speed", "relaxation_length", "cornering_stiffness")
    TEXT_KEYS: ClassVar[tuple[str, ...]] = ("body", "at")
    LENGTH_KEYS: ClassVar[tuple[str, ...]] = ("relaxation_length",)

    @property
    def state(self) -> str:
        """The name of the lateral deflection state (``y_<name>``)."""
        return f"y_{self.name}"

    @property
    def point(self) -> str:
        """The contact point reference ``"<body>.<point>"`` (``at`` may name the point alone)."""
        return self.at if "." in self.at else f"{self.body}.{self.at}"

    def check(self, mech: Mechanism) -> None:
        """``body`` a body (not the ground), ``at`` a point on it."""
        if self.body == "ground":
            raise InputError(self.field("body"), "a tyre rolls on the ground: give the wheel's body, not \"ground\"")
        if self.body not in mech.body_map:
            raise InputError(self.field("body"), f"unknown body {self.body!r}; bodies: {', '.join(mech.body_map)}")
        body, _ = mech.point_ref(self.point, self.field("at"))
        if body != self.body:
            raise InputError(self.field("at"), f"the contact point must be on the tyre's body {self.body!r}, got {self.at!r}")

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its speed, relaxation length, cornering stiffness, and the optional maximum force and trail."""
        for key in ("speed", "relaxation_length", "cornering_stiffness", "max_force", "pneumatic_trail"):
            value = getattr(self, key)
            if value is not None:
                yield self.field(key), value

    def limits(self, kin: Kinematics, solve: bool) -> list[Limit]:
        """A positive speed and relaxation length (and maximum force), a non-negative cornering stiffness."""
        out = [self.value_limit(kin, "speed", True, "speed (m/s; at rest the tyre's deflection is undetermined)"),
               self.value_limit(kin, "relaxation_length", True, "relaxation length (m)"),
               self.value_limit(kin, "cornering_stiffness", False, "cornering stiffness (N/rad)")]
        if self.max_force is not None:
            out.append(self.value_limit(kin, "max_force", True, "maximum side force (N)"))
        return out

    # -- geometry ------------------------------------------------------------------------
    def _axes(self, kin: Kinematics) -> tuple[sp.Matrix, sp.Matrix]:
        """Heading ``h`` and lateral axis ``l`` (unit, global, in the ground plane)."""
        x = kin.turn(self.point, sp.Matrix([1, 0, 0][:kin.dimension]))
        if kin.dimension == 2:
            return x, sp.Matrix([-x[1], x[0]])
        n = sp.sqrt(x[0] ** 2 + x[1] ** 2)
        return sp.Matrix([x[0] / n, x[1] / n, 0]), sp.Matrix([-x[1] / n, x[0] / n, 0])

    def _ground_velocity(self, kin: Kinematics) -> sp.Matrix:
        """The mechanism's velocity relative to the ground, ``V e_x``, in the kinematics' dimension."""
        V = kin.mech.value(self.field("speed"))
        return sp.Matrix([V, 0, 0][:3 if kin.mech.space == "space" else 2])

    def lateral_velocity(self, kin: Kinematics) -> sp.Expr:
        """``v_lat`` (m/s): the contact point's velocity relative to the ground along the lateral axis,
        in the coordinates and their velocity symbols."""
        P = kin.point(self.point)
        _, lat = self._axes(kin)
        vP = sp.Matrix([sum((sp.diff(c, qi) * velocity_symbol(n) for qi, n in zip(kin.q, kin.coords)), sp.S.Zero)
                        for c in P])
        return (vP + self._ground_velocity(kin)).dot(lat)

    def side_force(self, kin: Kinematics) -> sp.Expr:
        """``F(y)`` (N) along the lateral axis: ``C y/sigma``, or ``F_max tanh(C y/(sigma F_max))``."""
        v = kin.mech.value
        C, sigma = v(self.field("cornering_stiffness")), v(self.field("relaxation_length"))
        y = symbol(self.state)
        if self.max_force is None:
            return C * y / sigma
        Fmax = v(self.field("max_force"))
        return Fmax * sp.tanh(C * y / (sigma * Fmax))

    def _force_point(self, kin: Kinematics) -> sp.Matrix:
        h, _ = self._axes(kin)
        return kin.point(self.point) - kin.mech.value(self.field("pneumatic_trail")) * h

    # -- the protocol ----------------------------------------------------------------------
    def states(self, kin: Kinematics) -> tuple[ElementState, ...]:
        """``y_<name>`` (m): ``dy/dt = -v_lat - (V/sigma) y``."""
        v = kin.mech.value
        rate = -self.lateral_velocity(kin) - v(self.field("speed")) / v(self.field("relaxation_length")) * symbol(self.state)
        at = {symbol(k): val for k, val in parameter_values(kin.mech, {}).items()}
        sigma = abs(float(sp.sympify(v(self.field("relaxation_length"))).xreplace(at)))
        return (ElementState(self.state, "m", rate, scale=sigma / 10 or 1.0, initial=0.0,
                             description=f"lateral deflection of tyre {self.name} (stretched string at speed "
                                         f"{self.speed}, relaxation length {self.relaxation_length}; + to the wheel's "
                                         "left)"),)

    def apply(self, kin: Kinematics, out: Loads) -> None:
        """The side force ``F(y) l`` at the (trailed) contact point: generalised forces ``F l . dP/dq``."""
        _, lat = self._axes(kin)
        out.add(kin.force_work(self._force_point(kin), self.side_force(kin) * lat))

    def draw(self, kin: Kinematics, add: Draw) -> None:
        """The contact point (named after the tyre) and the side force (N) as an arrow at the trailed point."""
        _, lat = self._axes(kin)
        add("point", f"tyre {self.name}", [kin.point(self.point)])
        add("force", self.name, [self._force_point(kin), self.side_force(kin) * lat])
