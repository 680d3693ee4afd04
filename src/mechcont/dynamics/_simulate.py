"""Time simulation of a mechanism: the Udwadia–Kalaba equation on an adaptive Runge–Kutta."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, DenseOutput, OdeSolver, Radau

from .._status import Status
from ..equations import units_of, velocity_coordinate
from ..errors import InputError
from ._assembly import assemble, initial_vector
from ._budget import MAX_STEPS
from ._contact import MAX_EVENTS_AT_ONCE
from ._energy import EnergyLedger, energy_columns
from ._events import EventTracker
from ._peaks import DenseHistory
from ._reactions import fill_conditions, fill_reactions
from ._result import SimulationResult
from ._stall import motion_warning
from ._udwadia_kalaba import ConstrainedDynamics

if TYPE_CHECKING:
    from ..equations import Model
    from ._budget import StepBudget
    from ._contact import StopConstraints, StopEvent
    from ._events import EventFunction

__all__ = ["simulate", "initial_vector", "assemble", "check_integrator", "METHODS"]  # assemble, initial_vector from ._assembly

_ASSEMBLY_TOL = 1e-6

#: The integrators by SciPy's names: explicit Runge–Kutta, then implicit (for stiff mechanisms).
METHODS = {"RK45": RK45, "RK23": RK23, "DOP853": DOP853, "Radau": Radau, "BDF": BDF, "LSODA": LSODA}


def _velocities(system: Model, qdot0: Mapping[str, float] | Sequence[float] | np.ndarray | None,
                coordinates: Sequence[str]) -> np.ndarray:
    nq = len(coordinates)
    if qdot0 is None:
        return np.zeros(nq)
    if isinstance(qdot0, Mapping):
        qd = np.zeros(nq)
        for k, v in qdot0.items():
            name = velocity_coordinate(k, coordinates) or k
            if name not in coordinates:
                raise InputError(k, f"not a coordinate; valid: {', '.join(coordinates)}")
            qd[coordinates.index(name)] = float(v)
        return qd
    qd = np.array(qdot0, float)
    if qd.shape != (nq,) or not np.all(np.isfinite(qd)):
        raise InputError("qdot0", f"needs {nq} finite velocities ordered like the coordinates ({', '.join(coordinates)})")
    return qd


#: Range of relative tolerances the integrator is given: a few ulps up to 10 %.
_RTOL = (1e-13, 0.1)
#: Range of absolute tolerances (each state's unit, m, rad, m/s): rounding of a state of 0.01 to 1.
_ATOL = (1e-15, 1.0)


def simulate(system: Model, x0: np.ndarray | Mapping[str, float] | Sequence[float], t_span: tuple[float, float], *,
             qdot0: Mapping[str, float] | Sequence[float] | np.ndarray | None = None,
             loads: Mapping[str, Callable[[float], float]] | None = None, method: str = "RK45",
             rtol: float = 1e-6, atol: float = 1e-9, baumgarte: tuple[float, float] | None = (10.0, 10.0),
             projection: bool = False, damping: float = 0.0, max_step: float = math.inf,
             t_eval: Sequence[float] | np.ndarray | None = None, events: Sequence[EventFunction] | None = None,
             progress: Callable[[float], None] | None = None, stops: bool | Sequence[str] = False,
             max_stop_events: int = 10_000, audit: bool = True, max_steps: int = MAX_STEPS) -> SimulationResult:
    """Simulate a mechanism in time (paper's state-space model, eqs. 1–5, for any mechanism).

    The state is ``(q, qdot)`` (for the overcentre the paper's 12 states), followed by the force elements'
    first-order states ``s`` where the model has any (integrated with their rates; the history has a column
    for each, their start from ``x0``; the energy audit is then left out, and stops are not simulated with
    them yet); accelerations come
    from the Udwadia–Kalaba fundamental equation (see :mod:`._udwadia_kalaba`), integrated
    by an adaptive explicit Runge–Kutta method (``RK45`` is Dormand–Prince, Matlab's ODE45).

    Parameters
    ----------
    system:
        A :class:`~mechcont.equations.Model` with ``mechanics``.
    x0:
        Start: full variable vector or ``{name: value}`` (coordinates and parameters, SI).
        The coordinates are first projected onto ``Phi = 0`` (minimum-kinetic-energy
        correction) and the velocities onto ``Phi_q qdot = 0``.
    t_span:
        ``(t0, t1)`` in s, ``t1 > t0``.
    qdot0:
        Initial velocities (array ordered like the coordinates, or ``{name: value}``);
        default at rest.
    loads:
        ``{parameter: callable t -> value}``: time-varying applied loads (e.g. a ramp of F).
    method:
        ``RK45`` (default), ``RK23``, ``DOP853``, or an implicit one (``Radau``, ``BDF``, ``LSODA``).
    rtol, atol:
        Integrator tolerances (atol in the units of each state).
    baumgarte:
        ``(alpha, beta)`` in 1/s for ``Phi'' + 2 alpha Phi' + beta^2 Phi = 0``, or None.
    projection:
        After every accepted step project ``(q, qdot)`` back onto ``Phi = 0`` and
        ``Phi_q qdot = 0`` (Runge–Kutta methods only).
    damping:
        Extra mass-proportional (Rayleigh) damping coefficient in 1/s, force ``-d M qdot``.
    max_step:
        Largest step (s).
    t_eval:
        Times at which to store the solution (interpolated); default: every accepted step.
    events:
        :class:`Crossing` objects or callables ``g(t, x, qdot)`` (attributes ``terminal``,
        ``direction`` as in SciPy); occurrences go to ``t_events`` and ``x_events``.
    progress:
        Called with the current time after every accepted step.
    stops:
        True (all of the model's stops) or the names of the stops to simulate as unilateral
        constraints (impacts with the stop's ``restitution``, contact, release; see
        :mod:`._contact`), or, for a stop with ``contact = "compliant"``, as a penalty reaction
        (:mod:`._compliant`); default False: stops are ignored (their reactions stay at their values).
        With stops the reactions ``R_NAME`` are computed (they must be 0 in ``x0``) and the
        history has two rows at each stop event after the start, just before and just after it
        (the velocities jump at an impact).
    max_stop_events:
        The simulation stops (status FAILED) after this many stop events.
    max_steps:
        The step budget: the run ends (status FAILED, the history kept up to there, a message naming the stiff
        element and suggesting ``method="Radau"``) once the steps taken plus those still needed at the recent
        step size would exceed it (:mod:`._budget`).
    audit:
        Keep the energy audit (``result.energy``, :attr:`~._result.SimulationResult.balance`); False skips
        its quadrature (about a fifth of a small mechanism's run) where nobody reads it, e.g. the runs of
        a bisection.

    Returns
    -------
    SimulationResult
        Time history with named columns; ``constraint_drift`` reports ``max |Phi|``. Its reaction
        columns are the reactions at each row (:mod:`._reactions`: the multipliers of the solve
        that gives the accelerations), and the energy audit's columns ``E_kin``, ``E_pot``,
        ``E_diss``, ``W_ext``, ``E_residual`` (J; :mod:`._energy`) follow; ``balance`` sums it up.
    """
    t0, t1, cls = _checked_options(method, t_span, rtol, atol, max_step, projection)
    x = initial_vector(system, x0)
    dyn = ConstrainedDynamics(system, x, loads=loads, baumgarte=baumgarte, damping=damping)
    coords = tuple(system.names[i] for i in dyn.q_index)
    nq = dyn.nq
    y0 = _start_state(system, dyn, t0, x, qdot0, coords)
    contacts = None
    if dyn.ns:
        # the element states store and dissipate energy of their own, which the audit does not yet count
        audit = False
        if stops:
            raise InputError("stops", "stops are not simulated together with first-order element states "
                                      f"({', '.join(dyn.mech.element_states)}) yet; simulate without --stops")
    if stops and loads:
        check_fixed_stops(system, loads, stops, "loads")
    if stops:
        from ._contact import StopConstraints

        contacts = dyn.contacts = StopConstraints(system, dyn, None if stops is True else stops,
                                                  rest_height=_rest_height(system, rtol, atol))
        y0 = contacts.begin(t0, y0)
    solver = cls(dyn, t0, y0, t1, rtol=rtol, atol=atol, max_step=max_step)
    tracker = EventTracker(events, system, coords)
    tracker.start(dyn, t0, y0)
    history = _History(t0, y0, t1, t_eval, contacts, EnergyLedger(dyn, rtol, atol, method, active=audit))
    segments: list = []  # per accepted step: (t_old, t_end, its dense output, the stops in contact)
    status, detail, failure = Status.FINISHED, "", ""
    at_once, t_last_event = 0, -math.inf
    budget = _budget(t0, t1, max_steps)
    while True:
        t_old = solver.t
        why = solver.step()
        if solver.status == "failed":
            status = Status.FAILED
            detail = f"Stopped at t = {solver.t:.6g} s ({method}: {why})."
            failure = why or "failed"
            break
        if projection:  # back onto Phi = 0, Phi_q qdot = 0; restart the FSAL derivative there
            qp, qdp = dyn.project(solver.t, solver.y[:nq], solver.y[nq:2 * nq])
            solver.y = np.concatenate([qp, qdp, solver.y[2 * nq:]])
            solver.f = dyn(solver.t, solver.y)
        t_new, y_new = solver.t, solver.y
        sol = solver.dense_output()  # kept per step: events, stops, t_eval, peaks and the energy audit's quadrature
        hit = contacts.locate(t_old, t_new, y_new, sol) if contacts is not None else None
        if hit is not None:  # the step ends at the stop event
            t_new, y_new = hit[0], sol(hit[0])
        t_stop = tracker.step(dyn, t_old, t_new, y_new, sol)
        if t_stop is not None:
            hit = None  # a terminal event comes first
        t_end = t_new if t_stop is None else t_stop
        history.step(sol, t_old, t_new, y_new, t_end, ends_at_event=t_stop is not None or hit is not None)
        segments.append((t_old, t_end, sol, _mode(contacts)))
        if progress is not None:
            progress(t_end)
        if t_stop is None and hit is None and budget.exceeded(t_end, dyn, y_new):
            status, failure = Status.FAILED, "step budget"
            detail = _over_budget(system, dyn, budget, t_end, y_new, method)
            break
        if t_stop is not None:
            status = Status.EVENT
            break
        if hit is not None:
            assert contacts is not None  # a stop event comes only from the contacts
            at_once = at_once + 1 if hit[0] == t_last_event else 0
            t_last_event = hit[0]
            if at_once > MAX_EVENTS_AT_ONCE or len(contacts.events) > max_stop_events:
                status = Status.FAILED
                detail = (f"Stopped at t = {hit[0]:.6g} s: {len(contacts.events)} stop events"
                          + (f", {at_once} at this instant (no consistent contact set)" if at_once > MAX_EVENTS_AT_ONCE
                             else f", more than max_stop_events = {max_stop_events}") + ".")
                break
            y_after, _ = contacts.handle(hit[0], y_new, hit[1])
            history.add(hit[0], y_after)  # the row after the event (the velocities jump at an impact)
            if tracker.jump(dyn, hit[0], y_after) is not None:  # the jump itself ended the run (e.g. came to rest)
                status = Status.EVENT
                break
            solver = cls(dyn, hit[0], y_after, t1, rtol=rtol, atol=atol, max_step=max_step)
            continue
        if solver.status == "finished":
            break
    ys = np.array(history.ys).reshape(-1, 2 * nq + dyn.ns)
    result = _assemble_result(system, dyn, coords, np.array(history.ts), ys, status, tracker, detail, history.modes,
                              history.known)
    if audit:
        result.energy = energy_columns(dyn, ys, result.values, np.array(history.ws), history.jumps, y0, t0)
        result.energy_tolerance = history.ledger.explained
    result.dense = DenseHistory(system, dyn, segments)
    result.integrator_failure = failure
    result.motion_warning = motion_warning(result, dyn)
    return result


def check_fixed_stops(system: Model, varied: Iterable[str], stops: bool | Sequence[str], field: str) -> None:
    """:class:`InputError` naming ``field`` when a parameter ``varied`` in time (a load, a ramp) is one a simulated
    stop's limit (or a compliant stop's stiffness or damping) is written in: a time simulation keeps each stop
    where the model's values put it (impacts on a fixed stop), so the stop would silently stay there while the
    parameter's column says otherwise. ``stops``: True (all the model's) or the names of those simulated."""
    varied = set(varied)
    if not stops:
        return
    for s in system.stops:
        if not isinstance(stops, bool) and s.name not in stops:
            continue
        for key in (s.key, *(("stiffness", "damping") if s.contact == "compliant" else ())):
            used = sorted(system.written_in(f"stops.{s.name}.{key}") & varied)
            if used:
                raise InputError(field, f"{used[0]} moves stop {s.name} (its {key} is written in {used[0]}), which a "
                                        "time simulation keeps where the model's values put it; give "
                                        f"{used[0]} a value (--set) instead of varying it in time")


def _budget(t0: float, t1: float, max_steps: int) -> StepBudget:
    """The run's :class:`~._budget.StepBudget`; :class:`InputError` unless ``max_steps`` is a positive integer."""
    from ._budget import StepBudget

    if isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer)) or max_steps < 1:
        raise InputError("max_steps", f"must be a positive whole number of integrator steps, got {max_steps!r}")
    return StepBudget(t0, t1, int(max_steps))


def _over_budget(system: Model, dyn: ConstrainedDynamics, budget: StepBudget, t: float, y: np.ndarray, method: str) -> str:
    """The one-line message of a run ended by its step budget: where, the step size, the stiff element."""
    from ._budget import stiffest

    return (f"Stopped at t = {t:.6g} s: {method} steps of {budget.h:.3g} s would take {budget.projected(t):.3g} steps "
            f"to t = {budget.t1:.6g} s, more than the budget of {budget.max_steps} (max_steps): the mechanism is stiff "
            f"there, set by {stiffest(system, dyn, t, y)}; use method Radau (implicit) or raise the budget.")


def _checked_options(method: str, t_span: tuple[float, float], rtol: float, atol: float | np.ndarray, max_step: float,
                     projection: bool) -> tuple[float, float, type[OdeSolver]]:
    """``(t0, t1, solver class)`` of :func:`simulate`'s options; :class:`InputError` naming a bad one."""
    check_integrator(method, rtol, atol)
    try:
        t0, t1 = (float(v) for v in t_span)
    except (TypeError, ValueError):
        raise InputError("t_span", "must be (t0, t1) in seconds") from None
    if not (math.isfinite(t0) and math.isfinite(t1) and t1 > t0):
        raise InputError("t_span", f"needs finite t0 < t1, got ({t0}, {t1})")
    if not max_step > 0:
        raise InputError("max_step", "must be positive")
    cls = METHODS[method]
    if projection and cls not in (RK23, RK45, DOP853):  # explicit RK: y and f can be reset after a step
        raise InputError("projection", f"is supported with RK23, RK45 and DOP853, not {method}")
    return t0, t1, cls


def check_integrator(method: str, rtol: float, atol: float | Sequence[float] | np.ndarray) -> None:
    """Check an integrator choice: ``method`` one of :data:`METHODS`, ``rtol`` (relative) within
    ``[1e-13, 0.1]``, ``atol`` (absolute, in each state's unit; a number or one per state) within
    ``[1e-15, 1]``: tolerances that double precision can meet; :class:`InputError` naming ``method``,
    ``rtol`` or ``atol`` and what is valid."""
    if method not in METHODS:
        raise InputError("method", f"unknown integrator {method!r}; valid: {', '.join(METHODS)}")
    if not _RTOL[0] <= rtol <= _RTOL[1]:  # below: rounding noise; above: no accuracy at all (1e300 was accepted)
        raise InputError("rtol", f"must be between {_RTOL[0]:g} and {_RTOL[1]:g} (the integrator's relative tolerance), "
                                 f"got {rtol:g}")
    a = np.asarray(atol, float)
    if not (a.size and np.all(np.isfinite(a)) and np.all((_ATOL[0] <= a) & (a <= _ATOL[1]))):
        # below: the error norm of a state near zero meets rounding (1e-300 overflowed SciPy's first step to NaN)
        raise InputError("atol", f"must be finite, between {_ATOL[0]:g} and {_ATOL[1]:g} (the integrator's absolute "
                                 f"tolerance, in each state's unit), got {atol}")


def _start_state(system: Model, dyn: ConstrainedDynamics, t0: float, x: np.ndarray,
                 qdot0: Mapping[str, float] | Sequence[float] | np.ndarray | None, coords: Sequence[str]) -> np.ndarray:
    """``(q, qdot)`` at ``t0``: ``x``'s coordinates (assembled, else :class:`InputError`) and ``qdot0``,
    projected onto the constraints and their rates."""
    phi0 = dyn.mech.phi(dyn.full(t0, x[dyn.q_index]))
    if phi0.size and np.max(np.abs(phi0)) > _ASSEMBLY_TOL:
        raise InputError("x0", f"coordinates violate the constraints by {np.max(np.abs(phi0)):.3g}; "
                               "start from an assembled configuration (mechcont.dynamics.assemble)")
    q, qd = dyn.project(t0, x[dyn.q_index], _velocities(system, qdot0, list(coords)))
    return np.concatenate([q, qd, x[dyn.s_index]])


class _History:
    """The rows :func:`simulate` keeps: every accepted step, or the ``t_eval`` times (interpolated on the
    step's dense output), and a row at each event; with the stops in contact at each row."""

    def __init__(self, t0: float, y0: np.ndarray, t1: float, t_eval: Sequence[float] | np.ndarray | None,
                 contacts: StopConstraints | None, ledger: EnergyLedger) -> None:
        self.times = None if t_eval is None else np.asarray(t_eval, float)
        if self.times is not None and (self.times.ndim != 1 or np.any(np.diff(self.times) < 0)
                                       or self.times[0] < t0 or self.times[-1] > t1):
            raise InputError("t_eval", "must be increasing times within t_span")
        first = self.times is None or (self.times.size and self.times[0] == t0)
        self.ts: list[float] = [t0] if first else []
        self.ys: list[np.ndarray] = [y0] if first else []
        self.contacts = contacts
        self.modes = [_mode(contacts)] * len(self.ts)  # the stops in contact at each saved row
        self.k_eval = 1 if self.ts and self.times is not None else 0
        self.ledger = ledger
        self.ws: list[np.ndarray] = [ledger.acc] * len(self.ts)  # the energy integrals at each saved row
        self.known: list = [None] * len(self.ts)  # each row's multipliers, when the integrator solved there
        self.jumps: list[int] = []  # the rows just after a stop event

    def step(self, sol: DenseOutput, t_old: float, t_new: float, y_new: np.ndarray, t_end: float, ends_at_event: bool) -> None:
        """The rows of a step from ``t_old`` that ended at ``t_end`` (``t_new`` unless an event came first),
        and the step's energy integrals (on its dense output ``sol``) up to each."""
        ts, ys, times = self.ts, self.ys, self.times
        before, n = self.ledger.acc, len(ts)
        self.ledger.advance(sol, t_old, t_end)
        if times is not None:
            while self.k_eval < times.size and times[self.k_eval] <= t_end:
                ts.append(float(times[self.k_eval]))
                ys.append(sol(times[self.k_eval]))
                self.k_eval += 1
            if ends_at_event and (not ts or ts[-1] < t_end):
                ts.append(t_end)
                ys.append(sol(t_end))
        elif ends_at_event:
            ts.append(t_end)
            ys.append(sol(t_end))
        else:
            ts.append(t_new)
            ys.append(y_new.copy())
        self.modes += [_mode(self.contacts)] * (len(ts) - len(self.modes))
        self.ws += [self.ledger.acc if tr == t_end else before + self.ledger.integral(sol, t_old, tr) for tr in ts[n:]]
        nq = self.ledger.dyn.nq
        self.known += [self.ledger.dyn.recall(tr, yr[:nq], yr[nq:2 * nq], yr[2 * nq:]) for tr, yr in zip(ts[n:], ys[n:])]
        self.ledger.close_step(t_new, y_new)

    def add(self, t: float, y: np.ndarray) -> None:
        """One more row (the state just after a stop event)."""
        self.jumps.append(len(self.ts))
        self.ts.append(t)
        self.ys.append(y)
        self.modes.append(_mode(self.contacts))
        self.ws.append(self.ledger.acc)
        self.known.append(None)


def _mode(contacts: StopConstraints | None) -> tuple[int, ...]:
    return () if contacts is None else tuple(contacts.active)


def _rest_height(system: Model, rtol: float, atol: float | np.ndarray) -> float:
    """Smallest rebound height (condition units) the integrator resolves: its error on a gap near
    the limit, ``atol + rtol |limit|`` (at least 1e-12)."""
    limits = [abs(float(s.limit)) for s in system.stops] or [0.0]
    return max(float(np.min(atol)) + rtol * max(limits), 1e-12)


def _assemble_result(system: Model, dyn: ConstrainedDynamics, coords: tuple[str, ...], t: np.ndarray, y: np.ndarray,
                     status: Status, tracker: EventTracker, detail: str = "", modes: list[tuple[int, ...]] | None = None,
                     known: list[Any] | None = None) -> SimulationResult:
    nq = dyn.nq
    values = np.array([dyn.full_of(ti, yi) for ti, yi in zip(t, y)]).reshape(-1, len(system.names))
    fill_conditions(system, values)
    modes = modes if modes is not None else [()] * len(t)
    indeterminate = fill_reactions(system, dyn, t, y, values, modes, known)
    stop_events = _stop_events(dyn.contacts, t) if dyn.contacts is not None else []
    qdot = y[:, nq:2 * nq]
    mech = dyn.mech
    drift = max((float(np.max(np.abs(mech.phi(xi)), initial=0.0)) for xi in values), default=0.0)
    vdrift = max((float(np.max(np.abs(mech.phi_q(xi) @ vi), initial=0.0)) for xi, vi in zip(values, qdot)),
                 default=0.0)
    t_events, x_events = tracker.results()
    return SimulationResult(t=t, values=values, qdot=qdot, names=tuple(system.names), coordinates=coords,
                            status=status, constraint_drift=drift, velocity_drift=vdrift,
                            t_events=t_events, x_events=x_events, nfev=dyn.nfev, detail=detail, stop_events=stop_events,
                            indeterminate_rows=indeterminate,
                            units={v.name: v.unit for v in system.variables},
                            energy_unit=units_of(system).label("J"))


def _stop_events(contacts: StopConstraints, t: np.ndarray) -> list[StopEvent]:
    """The stop events with their row numbers."""
    from dataclasses import replace

    out, i = [], 0
    for ev in contacts.events:  # rows are in time order; an event's row is the last one at its time
        while i + 1 < len(t) and t[i + 1] <= ev.time:
            i += 1
        out.append(replace(ev, row=i))
    return out
