"""Stops in the time simulation: unilateral constraints with impacts, contact and release.

A stop keeps a condition ``c(q)`` on one side of a limit; its *gap* ``g = side (c - limit)`` is
``>= 0`` where the mechanism may be. Each stop is, at any time, either

* **free**: no force; the simulation watches ``g`` and locates ``g = 0`` (an *impact*) on the
  integrator's dense output to the root finder's tolerance;
* **in contact**: one more constraint row ``grad g . qddot = -qdot' Hess(g) qdot`` (Baumgarte
  stabilised like the joints) whose multiplier is the contact reaction ``R >= 0`` (the stop's
  generalised force is ``R grad g``, the same as ``side R dc/dq`` of the description's
  ``R_NAME``); the simulation locates ``R = 0`` (a *release*).

The impact is Newton's law on the stop's condition: the velocity jump is the impulse the
constrained mechanism feels, the smallest change in the kinetic-energy metric that keeps every
joint's velocity constraint ``Phi_q qdot = 0`` (and those of the stops in contact) and sets the
gap rate to ``-e`` times its value before. In Udwadia–Kalaba form, with ``A`` the rows kept and
``d`` the wanted change of ``A qdot``,

    delta qdot = M^-1/2 (A M^-1/2)^+ d,

which is the solution of ``M delta qdot = A^T P, A delta qdot = d`` (``P`` the impulses).

Chattering (``e < 1`` bouncing to rest): the rebound is not made when the flight it would start
would rise less than the integrator can resolve (height ``(e v)^2 / (2 |g''|)`` below
:attr:`StopConstraints.rest_height`); the stop goes into contact instead (a plastic impact). The
rebound speeds fall geometrically, so a finite number of impacts reaches that height.

The gradient and curvature of a gap come from the mechanics itself: the stop's generalised force
is linear in its reaction, so ``grad g = Q(R = 1) - Q(R = 0)`` and ``Hess g = -(K(R = 1) - K(R = 0))``
(``K`` the tangent stiffness at zero joint multipliers), exactly, for planar and spatial models.
The gap's value is the description's condition row ``c(q) - NAME``.

A stop with ``contact = "compliant"`` is never a constraint row: it pushes with a penalty
reaction (:mod:`._compliant`) applied through the dynamics' forces, and its events are only its
penetration crossing zero (``contact`` going in, ``release`` coming out; no velocity jump).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._roots import brentq
from ..errors import InputError
from ._compliant import CompliantLaw
from ._udwadia_kalaba import fundamental_equation

if TYPE_CHECKING:
    from scipy.integrate import DenseOutput

    from ..equations import Model, StopLimit
    from ._udwadia_kalaba import ConstrainedDynamics

__all__ = ["StopEvent", "StopConstraints"]

#: A stop counts as touching at the start when its gap is within this (condition units), as in the
#: quasi-static analysis (:data:`mechcont.analysis.stops.GAP_TOL`).
START_GAP_TOL = 1e-9
#: Most stop events at one instant before the simulation gives up (an inconsistent active set).
MAX_EVENTS_AT_ONCE = 50


@dataclass(frozen=True)
class StopEvent:
    """One stop event of a time simulation.

    Attributes
    ----------
    time:
        When (s).
    stop:
        The stop's name.
    kind:
        ``"impact"`` (arrival at the limit with a speed), ``"contact"`` (the stop becomes a
        constraint: after a plastic impact, a rebound too small to resolve, or at the start) or
        ``"release"`` (its reaction fell to zero and it lets go). For a compliant stop:
        ``"contact"`` when its penetration becomes positive, ``"release"`` when it returns to zero.
    speed:
        For an impact: the approach speed of the condition (its unit per s, > 0); else 0.
    rebound:
        For an impact: the condition's speed away from the limit just after (``e`` times
        ``speed``, or 0 when the stop stays in contact); else 0.
    row:
        Index of the history row at the event (after the jump, for an impact).
    """

    time: float
    stop: str
    kind: str
    speed: float = 0.0
    rebound: float = 0.0
    row: int = -1

    def describe(self, unit: str = "") -> str:
        """One line: ``t = 0.4567 s  impact  rest  speed 3.2 rad/s, rebound 1.6 rad/s``."""
        u = f" {unit or '1'}/s"
        what = f"  speed {self.speed:.6g}{u}, rebound {self.rebound:.6g}{u}" if self.kind == "impact" else ""
        return f"t = {self.time:.9g} s  {self.kind:<7s}  {self.stop}{what}"


def _stops_of(system: Model, names: Iterable[str] | None) -> list[StopLimit]:
    have = system.stops
    if names is None:
        return list(have)
    by_name = {s.name: s for s in have}
    out = []
    for n in names:
        if n not in by_name:
            raise InputError("stops", f"unknown stop {n!r}; stops of {system.name}: "
                                      f"{', '.join(by_name) or 'none (declare [stops.NAME] in the description)'}")
        out.append(by_name[n])
    return out


def _restitution(system: Model, name: str) -> float:
    """The ``restitution`` of stop ``name`` (its :class:`~mechcont.equations.StopLimit`'s, 0 by default)."""
    for s in system.stops:
        if s.name == name:
            return float(s.restitution)
    return 0.0


class StopConstraints:
    """The stops of a model as unilateral constraints of a :class:`ConstrainedDynamics`.

    Parameters
    ----------
    system:
        A model with stops.
    dyn:
        The :class:`~._udwadia_kalaba.ConstrainedDynamics` simulating it; its parameter vector
        must hold every stop reaction at 0 (the reactions are computed, not applied).
    names:
        The stops to use (default all of the model's).
    rest_height:
        Rebounds that would rise less than this (condition units) are not made: the stop goes
        into contact (see the module docstring).
    """

    def __init__(self, system: Model, dyn: ConstrainedDynamics, names: Iterable[str] | None = None,
                 rest_height: float = 1e-9) -> None:
        self.system, self.dyn = system, dyn
        self.stops = _stops_of(system, names)
        if not self.stops:
            raise InputError("stops", f"{system.name} declares no stops ([stops.NAME] in the description)")
        rows = list(system.equation_names)
        self.row = np.array([rows.index(f"cond_{s.condition}") for s in self.stops])
        self.cond = np.array([system.index(s.condition) for s in self.stops])
        self.reaction = np.array([system.index(s.reaction) for s in self.stops])
        self.side = np.array([float(s.side) for s in self.stops])
        self.limit = np.array([float(s.limit) for s in self.stops])
        self._residual = system.columns(())  # the residual alone: no Jacobian columns to form
        self.e = np.array([_restitution(system, s.name) for s in self.stops])
        self.names = [s.name for s in self.stops]
        if np.any(dyn.x[self.reaction] != 0):
            k = int(np.flatnonzero(dyn.x[self.reaction] != 0)[0])
            raise InputError(self.stops[k].reaction, "is computed by a simulation with stops (the contact reaction); "
                                                     "leave it at 0")
        self.law = CompliantLaw(self.stops)
        self.soft = frozenset(self.law.index)
        #: The compliant stops penetrated (between their contact and release events).
        self.pressed: set[int] = set()
        self.rest_height = float(rest_height)
        self.active: list[int] = []
        self.events: list[StopEvent] = []
        self._g_old = np.zeros(len(self.stops))
        self._r_old = np.zeros(len(self.stops))
        self._fresh: set[int] = set()

    # -- the gaps and their derivatives ------------------------------------------------------
    def gaps(self, x: np.ndarray) -> np.ndarray:
        """Gap of every stop, ``side (c - limit)`` (condition units; >= 0 allowed)."""
        xc = np.array(x, float)
        xc[self.cond] = 0.0
        c = self._residual.residual_and_jacobian(xc)[0][self.row]  # the row is c(q) - NAME
        return self.side * (c - self.limit)

    def _with_reaction(self, x: np.ndarray, k: int) -> np.ndarray:
        y = np.array(x, float)
        y[self.reaction[k]] = 1.0
        return y

    def gradients(self, x: np.ndarray, which: Iterable[int]) -> np.ndarray:
        """``grad g`` (rows, one per stop in ``which``) with respect to the coordinates."""
        mech = self.dyn.mech
        q0 = mech.applied_forces(x)
        return np.array([mech.applied_forces(self._with_reaction(x, k)) - q0 for k in which]).reshape(-1, self.dyn.nq)

    def curvatures(self, x: np.ndarray, qd: np.ndarray, which: Iterable[int]) -> np.ndarray:
        """``qdot' Hess(g) qdot`` per stop in ``which`` (condition units per s^2)."""
        # Hess g = dQ/dq(R = 1) - dQ/dq(R = 0): the tangent stiffness at zero multipliers is -dQ/dq, so the
        # applied forces' Jacobian alone gives it, without the constraints' curvature term (zero there)
        mech = self.dyn.mech
        d0 = mech.force_jacobian(x)
        return np.array([qd @ ((mech.force_jacobian(self._with_reaction(x, k)) - d0) @ qd) for k in which])

    def penalized(self, x: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """``x`` (whose stop reactions are 0) with the compliant stops' penalty reactions set."""
        if not self.law:
            return x
        idx = self.law.index
        y = np.array(x, float)
        y[self.reaction[idx]] = self.law.reactions(self.gaps(x)[idx], self.gradients(x, idx) @ qd)
        return y

    # -- the equations of motion with the stops in contact ------------------------------------
    def rows(self, x: np.ndarray, qd: np.ndarray, A: np.ndarray, b: np.ndarray,
             which: Iterable[int] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``(A, b)`` of the acceleration-level constraints with the rows of the stops ``which``
        (default: those in contact) appended, Baumgarte-stabilised like the joints."""
        which = self.active if which is None else list(which)
        if not which:
            return A, b
        G = self.gradients(x, which)
        bs = -self.curvatures(x, qd, which)
        dyn = self.dyn
        if dyn.alpha or dyn.beta:
            bs = bs - 2.0 * dyn.alpha * (G @ qd) - dyn.beta**2 * self.gaps(x)[which]
        return np.vstack([A, G]), np.concatenate([b, bs])

    def reactions(self, t: float, y: np.ndarray, which: Iterable[int] | None = None) -> np.ndarray:
        """Contact reactions (units of ``R_NAME``) of the stops ``which`` (default: in contact),
        the multipliers of their rows in ``M qddot = Q + A^T z``."""
        which = self.active if which is None else list(which)
        if not which:
            return np.zeros(0)
        dyn = self.dyn
        kept = self.active
        self.active = which
        try:
            z = dyn.multipliers(t, y[: dyn.nq], y[dyn.nq:])[1]
        finally:
            self.active = kept
        return z[len(z) - len(which):]

    def rates(self, t: float, y: np.ndarray) -> np.ndarray:
        """Gap rates ``grad g . qdot`` of every stop (condition units per s)."""
        dyn = self.dyn
        x = dyn.full(t, y[: dyn.nq])
        return self.gradients(x, range(len(self.stops))) @ y[dyn.nq:]

    def _free_gap_acceleration(self, t: float, y: np.ndarray, k: int) -> float:
        """``g''`` of stop ``k`` if it were free, with the others as they are."""
        dyn = self.dyn
        q, qd = y[: dyn.nq], y[dyn.nq:]
        x = dyn.full(t, q)
        qdd = dyn.acceleration(t, q, qd)
        return float(self.gradients(x, [k])[0] @ qdd + self.curvatures(x, qd, [k])[0])

    # -- events ------------------------------------------------------------------------------
    def start(self, t: float, y: np.ndarray) -> None:
        """Remember the gaps and reactions at the start of an integration phase."""
        dyn = self.dyn
        self._g_old = self.gaps(dyn.full(t, y[: dyn.nq]))
        # free stops at their limits (just rebounded or released) are watched from the top of their flight
        self._fresh = {k for k in range(len(self.stops))
                       if k not in self.active and k not in self.soft and self._g_old[k] < self.rest_height}
        self._r_old = np.zeros(len(self.stops))
        if self.active:
            self._r_old[self.active] = self.reactions(t, y)

    def begin(self, t: float, y: np.ndarray) -> np.ndarray:
        """The contact set at the start (stops at their limits whose reaction pushes); returns
        the state with the contacts' gap rates made consistent. Raises :class:`InputError`
        if the start is past a limit."""
        dyn = self.dyn
        g = self.gaps(dyn.full(t, y[: dyn.nq]))
        for k, gk in enumerate(g):
            if gk < -START_GAP_TOL and k not in self.soft:
                s = self.stops[k]
                raise InputError("x0", f"the start is past the limit of stop {s.name} ({s.condition} "
                                       f"{'>=' if s.side > 0 else '<='} {s.limit:.6g}) by {-gk:.3g}; start on its allowed side")
        touching = [k for k in range(len(g)) if g[k] <= START_GAP_TOL and k not in self.soft]
        self.pressed = {k for k in self.soft if g[k] <= START_GAP_TOL}
        y = self._impulse(t, y, touching, np.zeros(len(touching))) if touching else y
        self.active = list(touching)
        self._consistent(t, y)
        for k in sorted([*self.active, *self.pressed]):
            self.events.append(StopEvent(t, self.names[k], "contact"))
        self.start(t, y)
        return y

    def _consistent(self, t: float, y: np.ndarray) -> list[int]:
        """Release, one at a time (most negative first), the stops in contact that pull; returns them."""
        released = []
        while self.active:
            R = self.reactions(t, y)
            j = int(np.argmin(R))
            if R[j] >= 0:
                break
            released.append(self.active.pop(j))
        return released

    def _impulse(self, t: float, y: np.ndarray, which: list[int], target: np.ndarray) -> np.ndarray:
        """The state after the impulse that sets the gap rates of ``which`` to ``target`` and
        keeps the joints' and the other contacts' velocity constraints (module docstring)."""
        dyn = self.dyn
        q, qd = y[: dyn.nq], y[dyn.nq:]
        x = dyn.full(t, q)
        others = [k for k in self.active if k not in which]
        A = np.vstack([dyn.mech.phi_q(x).reshape(-1, dyn.nq), self.gradients(x, [*others, *which])])
        want = np.concatenate([np.zeros(A.shape[0] - len(which)), target])
        dv = fundamental_equation(dyn.mass_inv_sqrt(x), np.zeros(dyn.nq), A, want - A @ qd)
        return np.concatenate([q, qd + dv])

    def locate(self, t_old: float, t_new: float, y_new: np.ndarray, sol: DenseOutput) -> tuple[float, int] | None:
        """The first stop event in the step ``[t_old, t_new]``: ``(time, stop index)``, or None.

        A free stop's gap going from > 0 to <= 0, or a contact's reaction from > 0 to <= 0; the
        time is found by Brent's method on the dense output ``sol``. A stop that left its limit at
        the start of the phase (a rebound, a release) is watched from the top of its flight."""
        dyn = self.dyn
        g_new = self.gaps(dyn.full(t_new, y_new[: dyn.nq]))
        r_new = np.zeros(len(self.stops))
        if self.active:
            r_new[self.active] = self.reactions(t_new, y_new)
        best: tuple[float, int] | None = None
        xtol = 1e-13 * max(1.0, abs(t_new))

        def gap(tt: float, k: int) -> float:
            return float(self.gaps(dyn.full(tt, sol(tt)[: dyn.nq]))[k])

        for k in range(len(self.stops)):
            a = t_old
            if k in self.soft:  # the penetration's sign changes: into contact, or out
                # > 0 across: out of a pressed stop, into a free one (fixed during locate)
                def f(tt: float, k: int = k, /) -> float:
                    return gap(tt, k) if k in self.pressed else -gap(tt, k)
                if not (f(t_new) > 0):
                    continue
                if f(a) > 0:  # already across at the start of the step (a graze): the event is there
                    best = (a, k) if best is None or a < best[0] else best
                    continue
            elif k in self.active:
                if not (self._r_old[k] > 0 >= r_new[k]):
                    continue
                j = self.active.index(k)

                def f(tt: float, j: int = j, /) -> float:
                    return float(self.reactions(tt, sol(tt))[j])
            else:
                def f(tt: float, k: int = k, /) -> float:
                    return gap(tt, k)
                if k in self._fresh:
                    if g_new[k] > 0:
                        continue
                    a = self._top(t_old, t_new, sol, k)
                    if f(a) <= 0:  # the gap did not open: an event only if pressed past what is resolved
                        if g_new[k] < -self.rest_height:
                            best = (a, k) if best is None or a < best[0] else best
                        continue
                elif not (self._g_old[k] > 0 >= g_new[k]):
                    continue
            te = t_new if f(t_new) == 0 else brentq(f, a, t_new, xtol=xtol)
            if best is None or te < best[0]:
                best = (te, k)
        if best is None:
            self._g_old, self._r_old = g_new, r_new
            self._fresh = {k for k in self._fresh if g_new[k] <= 0}
        return best

    def _top(self, t_old: float, t_new: float, sol: DenseOutput, k: int) -> float:
        """When the gap rate of stop ``k`` changes from + to - in the step (else ``t_old``)."""
        def rate(tt: float) -> float:
            return float(self.rates(tt, sol(tt))[k])
        if rate(t_old) > 0 > rate(t_new):
            return brentq(rate, t_old, t_new, xtol=1e-13 * max(1.0, abs(t_new)))
        return t_old

    def handle(self, t: float, y: np.ndarray, k: int) -> tuple[np.ndarray, list[StopEvent]]:
        """Apply the event of stop ``k`` at ``(t, y)`` (an impact or a release); returns the state
        after it and the events (an impact may be followed by contact, and by releases of others)."""
        out: list[StopEvent] = []
        added = False
        if k in self.soft:  # the state goes on unchanged; only the bookkeeping switches
            kind = "release" if k in self.pressed else "contact"
            self.pressed ^= {k}
            out.append(StopEvent(t, self.names[k], kind))
            self.events.extend(out)
            self.start(t, y)
            return y, out
        if k in self.active:  # its reaction fell to zero
            self.active.remove(k)
            out.append(StopEvent(t, self.names[k], "release"))
        else:
            v = float(self.rates(t, y)[k])
            y_stick = self._impulse(t, y, [k], np.zeros(1))
            rebound = -self.e[k] * v if v < 0 else 0.0
            bounce = False
            if rebound > 0:
                acc = self._free_gap_acceleration(t, y_stick, k)
                bounce = not (acc < 0 and rebound**2 / (2 * -acc) < self.rest_height)
            if v < 0:
                out.append(StopEvent(t, self.names[k], "impact", -v, rebound if bounce else 0.0))
            if bounce:
                y = self._impulse(t, y, [k], np.array([rebound]))
            else:
                y, added = y_stick, True
                self.active.append(k)
        released = self._consistent(t, y)
        if added and k not in released:
            out.append(StopEvent(t, self.names[k], "contact"))
        out += [StopEvent(t, self.names[j], "release") for j in released if j != k]
        self.events.extend(out)
        self.start(t, y)
        return y, out
