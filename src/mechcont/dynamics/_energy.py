"""The energy audit of a time history: kinetic, potential, dissipated, external work and the residual.

Columns (J) of every :class:`~._result.SimulationResult` of :func:`~._simulate.simulate`:

``E_kin``
    ``1/2 qdot^T M qdot``.
``E_pot``
    The model's potential ``V(q, p)`` (gravity, springs, force-mode actuators, conservative loads,
    compliant joints; :meth:`~mechcont.equations.MechanicalModel.potential_energy`) at the row's
    parameter values, plus the energy ``k p^2 / 2`` stored in the compliant stops.
``E_diss``
    Energy dissipated since the start: the work done against the velocity-dependent applied forces
    (dampers ``c v + c2 v |v|``; a custom load that depends on the velocities counts here too),
    against the Rayleigh damping ``d M qdot``, in the compliant stops' dampers (the work their reactions
    take from the mechanism less the energy their springs store), and the kinetic energy lost at each
    impact on a rigid stop (``E_kin`` just before less just after).
``W_ext``
    Work done on the mechanism since the start by the loads that the potential does not hold (drag,
    follower and custom loads, constant stop reactions of a run without stops) and by the loads that
    vary in time (``dV/dt`` at fixed ``q``): the work of the applied forces at rest, ``int qdot . Q(q, 0) dt``,
    plus the change of ``V``. For a conservative model it stays at zero (a check of ``V`` against ``Q``).
``E_residual``
    ``E_kin + E_pot + E_diss - W_ext - E0`` with ``E0 = E_kin + E_pot`` at the start: zero for the exact
    motion. The constraint forces do no work on an allowed motion and the velocity-product forces
    none on any (``qdot . h = -1/2 qdot^T Mdot qdot`` cancels in ``dE_kin/dt``), so the residual measures
    the integration error, the constraint drift, and any error of the equations of motion themselves
    (a missing inertial force shows at once).

The state functions (``E_kin``, ``E_pot``) are evaluated at the saved rows after the run. The
integrals are not trapezoids over the rows: each step's powers are integrated on the integrator's
own dense output by Gauss–Legendre quadrature (:class:`EnergyLedger`). Why quadrature and not
extra ODE states: added states would enter the integrator's error norm and step-size control, so
auditing a run would change the run; the quadrature leaves the motion exactly as it was. Why Gauss:
``n`` points are exact for polynomials of degree ``2n - 1``, so three points (four for DOP853) make
an error per step (``O(h^6)``, ``O(h^8)``) no larger than the method's own local error (``O(h^5)`` for
RK45, ``O(h^8)`` for DOP853) at any step its error control accepts; they cost three or four
evaluations of the applied forces (twice each: with and without the velocities) per step, a fraction
of one right-hand side.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from scipy.integrate import DenseOutput

    from ._udwadia_kalaba import ConstrainedDynamics

__all__ = ["EnergyLedger", "EnergyBalance", "ENERGY_COLUMNS", "energy_columns", "BOUND_FACTOR"]

#: The audit's columns, all in J.
ENERGY_COLUMNS = ("E_kin", "E_pot", "E_diss", "W_ext", "E_residual")

#: The residual the tolerances explain, per unit of the energy error their steps allow (see
#: :attr:`EnergyBalance.bound`).
BOUND_FACTOR = 1.0

#: Gauss–Legendre points per step: three for the methods of order up to 5 (exact to degree 5, an error
#: ``O(h^6)`` below their local error ``O(h^5)``), four for DOP853's dense output of order 7.
_RULES = {n: np.polynomial.legendre.leggauss(n) for n in (3, 4)}


class EnergyLedger:
    """Running integrals of the powers that are not derivatives of state functions, over the
    integrator's steps: ``[damper and Rayleigh dissipation, work of the applied forces at rest, work of
    the compliant stops' reactions on the mechanism]`` (J), each integrated on a step's dense output;
    and :attr:`explained`, the energy error the integrator's tolerances allow, summed over the steps
    (:meth:`step_error`). ``rtol``, ``atol``: the integrator's tolerances (``atol`` scalar or per state).
    ``active`` False: nothing is integrated (a run whose balance nobody reads: a bisection's)."""

    def __init__(self, dyn: ConstrainedDynamics, rtol: float, atol: float | Sequence[float] | np.ndarray, method: str = "RK45",
                 active: bool = True) -> None:
        self.dyn = dyn
        self.active = active
        self.nodes, self.weights = _RULES[4 if method == "DOP853" else 3]
        self.acc = np.zeros(3)
        self.rtol = float(rtol)
        self.atol = np.broadcast_to(np.asarray(atol, float), (2 * dyn.nq,))
        #: The energy error (J) the tolerances explain, summed over the steps so far.
        self.explained = 0.0

    def step_error(self, t: float, y: np.ndarray) -> float:
        """The energy error (J) one step ending at ``(t, y)`` may make within its tolerances: the
        integrator keeps each state's local error near ``atol + rtol |y_i|``, and the energy moves by
        ``dE/dy_i`` per unit of it: the momentum ``M qdot`` for the velocities; for the coordinates, along
        the motions the joints allow, the net generalised force ``M qddot`` (applied and inertial forces
        less what the constraints take), and across the constraints the constraint force
        ``M qddot - Q``: a position error there is drift, which the stabilised constraint forces pull back,
        and the potential at the drifted position differs by that force times it (a lock resting on its
        stop: ``M qddot`` is zero, the stop's reaction is not). ``sum |dE/dy_i| (atol_i + rtol |y_i|)``."""
        dyn, nq = self.dyn, self.dyn.nq
        q, qd = y[:nq], y[nq:]
        x = dyn.full(t, q)
        tol = self.atol + self.rtol * np.abs(y)
        known = dyn.recall(t, q, qd)  # the step's last evaluation, at its end
        M = dyn.mass_matrix(x)
        if known is None:
            qdd = dyn.acceleration(t, q, qd)
            known = dyn.recall(t, q, qd)
            if known is None:  # an evaluation that is not kept (element states): the net force alone
                return float(np.abs(M @ qdd) @ tol[:nq] + np.abs(M @ qd) @ tol[nq:])
        net = M @ known[0]
        return float((np.abs(net) + np.abs(net - known[2])) @ tol[:nq] + np.abs(M @ qd) @ tol[nq:])

    def powers(self, t: float, y: np.ndarray) -> np.ndarray:
        """``[dissipated, rest-force, compliant-stop]`` powers (W) at ``(t, y)``."""
        dyn, mech = self.dyn, self.dyn.mech
        q, qd = y[: dyn.nq], y[dyn.nq:]
        x = dyn.full(t, q)
        Q0 = mech.applied_forces(x)
        p_diss = -float(qd @ (mech.applied_forces(x, qd) - Q0))
        if dyn.damping:
            p_diss += dyn.damping * float(qd @ (dyn.mass_matrix(x) @ qd))
        p_stop = 0.0
        contacts = dyn.contacts
        if contacts is not None and contacts.law:
            idx = contacts.law.index
            rate = contacts.gradients(x, idx) @ qd
            p_stop = float(contacts.law.reactions(contacts.gaps(x)[idx], rate) @ rate)
        return np.array([p_diss, float(qd @ Q0), p_stop])

    def integral(self, sol: DenseOutput, a: float, b: float) -> np.ndarray:
        """The powers integrated from ``a`` to ``b`` on the dense output ``sol`` (J): :meth:`powers` at the
        Gauss points, the applied forces of all of them in one call of the compiled code."""
        if b <= a or not self.active:
            return np.zeros(3)
        h = 0.5 * (b - a)
        ts = 0.5 * (a + b) + h * self.nodes
        Y = np.asarray(sol(ts), float).T  # (points, states)
        dyn, mech, nq = self.dyn, self.dyn.mech, self.dyn.nq
        if (dyn.contacts is not None and dyn.contacts.law) or dyn.damping:
            P = np.array([self.powers(t, y) for t, y in zip(ts, Y)])
        else:  # the usual case, batched: Q(x, qdot) and Q(x, 0) at every point
            X = dyn.fulls(ts, Y[:, :nq])
            qd = Y[:, nq:]
            Q = mech.applied_forces_batch(np.vstack([X, X]), np.vstack([qd, np.zeros_like(qd)]))
            Qv, Q0 = Q[:len(ts)], Q[len(ts):]
            P = np.stack([-np.einsum("ij,ij->i", qd, Qv - Q0), np.einsum("ij,ij->i", qd, Q0), np.zeros(len(ts))], axis=1)
        return h * (self.weights @ P)

    def advance(self, sol: DenseOutput, a: float, b: float) -> None:
        """Add the integrals over the step ``[a, b]``."""
        self.acc = self.acc + self.integral(sol, a, b)

    def close_step(self, t: float, y: np.ndarray) -> None:
        """Add the :meth:`step_error` of a step that ended at ``(t, y)``."""
        if self.active:
            self.explained += self.step_error(t, y)


def energy_columns(dyn: ConstrainedDynamics, y: np.ndarray, values: np.ndarray, work: np.ndarray, jumps: list[int],
                   y0: np.ndarray, t0: float) -> dict[str, np.ndarray]:
    """The audit's columns (J) at the saved rows.

    ``y``, ``values``: the rows' states and full variable vectors; ``work``: :class:`EnergyLedger` integrals
    at each row (rows x 3); ``jumps``: the rows just after a stop event (the row before is just before it);
    ``(t0, y0)``: the start (after the contacts were set up)."""
    mech, nq = dyn.mech, dyn.nq
    contacts = dyn.contacts

    # (E_kin, E_pot, V): E_pot less V is what the compliant stops store
    def state(yi: np.ndarray, xi: np.ndarray) -> tuple[float, float, float]:
        v = mech.potential_energy(xi)
        e_pot = v
        if contacts is not None and contacts.law:
            e_pot += float(np.sum(contacts.law.energy(contacts.gaps(xi)[contacts.law.index])))
        return 0.5 * float(yi[nq:] @ (mech.mass(xi) @ yi[nq:])), e_pot, v

    k0, p0, v0 = state(y0, dyn.full(t0, y0[:nq]))
    rows = np.array([state(yi, xi) for yi, xi in zip(y, values)]).reshape(-1, 3)
    e_kin, e_pot, v = rows[:, 0], rows[:, 1], rows[:, 2]
    work = np.asarray(work, float).reshape(-1, 3)
    lost = np.zeros(len(y))
    for i in jumps:
        lost[i] = e_kin[i - 1] - e_kin[i]
    stop_work = work[:, 2]
    stored = (e_pot - v) - (p0 - v0)  # the compliant stops' springs, from the start
    e_diss = work[:, 0] + np.cumsum(lost) - stop_work - stored
    w_ext = work[:, 1] + (v - v0)
    residual = e_kin + e_pot + e_diss - w_ext - (k0 + p0)
    return dict(zip(ENERGY_COLUMNS, (e_kin, e_pot, e_diss, w_ext, residual)))


@dataclass(frozen=True)
class EnergyBalance:
    """The energy balance of a time history at its end (J), and whether it closes.

    ``E_kin``, ``E_pot``, ``E_diss``, ``W_ext``, ``residual``: the audit's columns at the last row
    (:mod:`._energy`); ``worst``: the largest ``|E_residual|`` over the rows; ``E0``: the energy at the
    start; ``scale``: the energy exchanged, the largest of ``|E_kin|``, ``|E_pot - E_pot(0)|``, ``E_diss``
    and ``|W_ext|`` over the rows; ``explained``: the energy error the integrator's tolerances allow,
    summed over its steps (:meth:`EnergyLedger.step_error`)."""

    E_kin: float
    E_pot: float
    E_diss: float
    W_ext: float
    residual: float
    worst: float
    E0: float
    scale: float
    explained: float

    @property
    def bound(self) -> float:
        """The residual the tolerances explain (J): ``BOUND_FACTOR`` times :attr:`explained`. Each accepted
        step keeps its local error within the tolerances, and moves the energy by at most the step's
        :meth:`EnergyLedger.step_error` (to first order); the steps' errors add up, and along an unstable or
        stiff motion (a hard contact) earlier errors grow, hence the factor. A missing force or a wrong
        inertia leaves residuals of the order of :attr:`scale`, far above it at any useful tolerance."""
        return BOUND_FACTOR * self.explained

    @property
    def closes(self) -> bool:
        """True when the worst residual is within :attr:`bound`."""
        return self.worst <= self.bound

    def describe(self, unit: str = "J") -> str:
        """One line: ``energy [J]: start 10, kinetic 1.2, potential 3.4, dissipated 5.6, external work 0.2,
        residual 1e-07 (worst 2e-07, bound 3e-05)``: the end of the history (E_kin + E_pot + dissipated
        - external work = start + residual), its energies in ``unit`` (the history's
        :attr:`~._result.SimulationResult.energy_unit`)."""
        return (f"energy [{unit}]: start {self.E0:.6g}, kinetic {self.E_kin:.6g}, potential {self.E_pot:.6g}, "
                f"dissipated {self.E_diss:.6g}, external work {self.W_ext:.6g}, residual {self.residual:.3g} "
                f"(worst {self.worst:.3g}, bound {self.bound:.3g})")

    @classmethod
    def of(cls, columns: dict[str, np.ndarray], explained: float) -> EnergyBalance:
        """The balance of a history's audit ``columns`` (:data:`ENERGY_COLUMNS`) whose integration's
        tolerances explain an energy error ``explained`` (J)."""
        k, p, d, w, r = (np.asarray(columns[c], float) for c in ENERGY_COLUMNS)
        e0 = float(k[0] + p[0] + d[0] - w[0] - r[0])
        scale = float(max(np.max(np.abs(k)), np.max(np.abs(p - p[0])), np.max(np.abs(d)), np.max(np.abs(w))))
        return cls(float(k[-1]), float(p[-1]), float(d[-1]), float(w[-1]), float(r[-1]), float(np.max(np.abs(r))),
                   e0, scale, float(explained))
