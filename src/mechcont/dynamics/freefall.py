"""Freefall extension: released at rest from the uplock, does the gear fall out and lock?

:func:`freefall` simulates a mechanism with its stops from rest in the retracted pose (an uplock
release) until it locks (the lock stop in contact and at rest, or a lock condition reached), and
reports how it ended: locked; at rest short of locking (it hangs in an intermediate equilibrium, or
back on the uplock); or still moving at the end of the run (e.g. it struck the lock and left it
again); with the time to lock, the impact speed at the lock, the peak damper tensions and the peak
stop reactions.

:func:`critical_airspeed` and :func:`quasi_static_critical` (in :mod:`._critical`, exported here) bracket
the airspeed where the outcome changes by runs, beside its quasi-static predictor.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._status import Status
from ..equations import StopLimit
from ..errors import InputError
from ._critical import CriticalAirspeed, QuasiStaticCritical, critical_airspeed, critical_figure, quasi_static_critical
from ._events import Crossing
from ._result import SimulationResult

__all__ = ["FreefallResult", "StopLock", "freefall", "CriticalAirspeed", "critical_airspeed", "QuasiStaticCritical",
           "quasi_static_critical", "damper_tensions", "critical_figure", "travel_of", "condition_value", "held_pose"]

#: A lock stop counts as on its limit within this gap (condition units) for the end of a run at the lock: far
#: below any gap a free stop has at rest, far above the contact's drift.
LOCK_GAP = 1e-6
#: Outcomes of a freefall run: locked; at rest short of locking; still moving at ``until`` (it may have
#: struck the lock and left it); the integrator failed.
LOCKED, AT_REST, MOVING, FAILED = "locked", "at rest", "still moving", "failed"


@dataclass(frozen=True)
class StopLock:
    """One lock stop of a freefall: ``time`` (s) of its last contact when it ends the run in contact and
    the gear at rest (None otherwise), ``impact_speed`` the rate of its condition at its first impact (its
    unit per s; None when it never struck), ``left`` (s) when it last left the stop after striking it (a
    rebound, a plastic impact whose reaction would pull, a release) if the run ended off the stop (None
    otherwise)."""

    stop: str
    time: float | None
    impact_speed: float | None
    left: float | None = None


@dataclass
class FreefallResult:
    """The outcome of one freefall simulation.

    Attributes
    ----------
    outcome:
        ``"locked"``, ``"at rest"`` (short of locking), ``"still moving"`` (at ``until``; it may have
        struck the lock and left it: see ``stops``) or ``"failed"`` (the integrator failed).
    lock:
        What counted as locked: ``"stop NAME"`` or ``"NAME = VALUE"``.
    time_to_lock:
        When it locked (s): the lock stop's last contact (or the condition reached); None otherwise.
    impact_speed:
        The rate of the lock stop's condition at its first impact, or of the lock condition when
        reached (its unit per s); None when it did not get there.
    peak_damper:
        ``{damper: max |tension|}`` (N) over the history.
    peak_reaction:
        ``{stop: max reaction}`` (units of ``R_NAME``) over the history.
    final_speed:
        ``max |qdot|`` at the end (coordinate units per s).
    history:
        The :class:`SimulationResult`.
    stops:
        ``{stop: StopLock}`` for each lock stop (several: locked when every one is in contact at
        rest; ``time_to_lock`` is then the last of their lock times, ``impact_speed`` the last one's).
    """

    outcome: str
    lock: str
    time_to_lock: float | None
    impact_speed: float | None
    peak_damper: dict[str, float]
    peak_reaction: dict[str, float]
    final_speed: float
    history: SimulationResult
    stops: dict[str, StopLock] = field(default_factory=dict)

    @property
    def locked(self) -> bool:
        """True when the gear locked."""
        return self.outcome == LOCKED

    @property
    def lock_spread(self) -> float | None:
        """How far apart in time (s) the lock stops locked: last lock time minus first; None unless
        every lock stop locked (0 for a single stop)."""
        times = [s.time for s in self.stops.values()]
        if not times or any(t is None for t in times):
            return None
        return max(times) - min(times)  # type: ignore[type-var,operator]

    def describe(self, units: Mapping[str, str] | None = None, show: Sequence[str] = ()) -> list[str]:
        """Readable lines: outcome, time to lock, impact speed, peak loads (``units`` of the
        stop reactions and the lock quantity's rate, by name); a run that did not lock ends with
        where it is: the columns ``show`` (default every coordinate)."""
        units = units or {}
        t_end = float(self.history.t[-1])
        what = {AT_REST: "at rest short of locking", MOVING: f"still moving at t = {t_end:.6g} s"}
        lines = [f"outcome: {what.get(self.outcome, self.outcome)} (lock: {self.lock})"]
        if self.time_to_lock is not None:
            lines.append(f"time to lock: {self.time_to_lock:.6g} s")
        if len(self.stops) > 1:
            for name, st in self.stops.items():
                when = (f"locked at {st.time:.6g} s" if st.time is not None
                        else f"struck and left at {st.left:.6g} s" if st.left is not None else "not locked")
                hit = (f", impact speed {st.impact_speed:.6g} {units.get(name + '_rate', '1/s')}"
                       if st.impact_speed is not None else ", no impact")
                lines.append(f"stop {name}: {when}{hit}")
            if self.lock_spread is not None:
                lines.append(f"locked {self.lock_spread:.6g} s apart")
        elif self.impact_speed is not None:
            lines.append(f"impact speed at the lock: {self.impact_speed:.6g} {units.get('lock_rate', '1/s')}")
            left = next(iter(self.stops.values())).left if self.stops else None
            if left is not None:
                lines.append(f"left the lock stop at {left:.6g} s (it did not hold)")
        for name, v in self.peak_damper.items():
            lines.append(f"peak damper tension {name}: {v:.6g} N")
        for name, v in self.peak_reaction.items():
            lines.append(f"peak stop reaction {name}: {v:.6g} {units.get(name, '')}".rstrip())
        if self.outcome != LOCKED:
            t, pose = self.history.t[-1], self.history.at(len(self.history) - 1)
            lines.append(f"at t = {t:.6g} s: max speed {self.final_speed:.3g}, "
                         + ", ".join(f"{c} = {pose[c]:.6g}" for c in (show or self.history.coordinates)))
        return lines


def damper_tensions(system, result: SimulationResult, h: float = 1e-7, mechanism=None) -> dict[str, np.ndarray]:
    """Tension (N) of every damper of ``system``'s description at every row of ``result``.

    ``T = c v + c2 v |v|`` with ``v = dl/dt`` (see :mod:`mechcont.mechanism.elements.damper`): the
    length ``l`` between the damper's drawn end points, its rate by a central difference along the
    row's velocity (error ``O(h^2)``, relative ~1e-14 at the default ``h``). ``mechanism``: the description's
    mechanism when already at hand (a model loaded from the cache makes it on first use, seconds for a large
    one, and a copy made with other values before that makes it again).
    """
    from ..equations import as_model
    from ..mechanism._values import evaluate

    mech: Any = as_model(system).mechanism if mechanism is None else mechanism
    dampers = list(getattr(mech, "dampers", ()))
    if not dampers or system.scene is None:
        return {}
    params = {v.name: v.value for v in system.variables if v.kind == "parameter"}
    q_index = np.array([system.index(c) for c in result.coordinates])
    out = {d.name: np.zeros(len(result)) for d in dampers}

    def lengths(x):
        ends = {name: (a, b) for name, a, b in system.scene(x).dampers}
        return {n: float(np.linalg.norm(np.asarray(b) - np.asarray(a))) for n, (a, b) in ends.items()}

    coefficients: dict[tuple, list[tuple[float, float]]] = {}  # per parameter vector (they may vary in time)
    for i in range(len(result)):
        x = result.values[i]
        p = {n: float(x[system.index(n)]) for n in params}
        key = tuple(p.values())
        if key not in coefficients:
            coefficients[key] = [(evaluate(mech.value(f"dampers.{d.name}.c"), p, f"dampers.{d.name}.c"),
                                  evaluate(mech.value(f"dampers.{d.name}.c2"), p, f"dampers.{d.name}.c2"))
                                 for d in dampers]
        xp, xm = x.copy(), x.copy()
        xp[q_index] += h * result.qdot[i]
        xm[q_index] -= h * result.qdot[i]
        lp, lm = lengths(xp), lengths(xm)
        for d, (c, c2) in zip(dampers, coefficients[key]):
            v = (lp[d.name] - lm[d.name]) / (2 * h)
            out[d.name][i] = c * v + c2 * v * abs(v)
    return out


def _lock_stops(system, lock) -> list[StopLimit] | None:
    """The lock stops named by ``lock`` (a stop's name or a sequence of names), None for a lock condition."""
    from ..equations import as_model

    if isinstance(lock, str):
        names = [lock]
    elif isinstance(lock, Sequence) and lock and all(isinstance(n, str) for n in lock):
        names = list(lock)
    else:
        return None
    by_name = {s.name: s for s in as_model(system).stops}
    for n in names:
        if n not in by_name:
            raise InputError("lock", f"unknown stop {n!r}; stops of {system.name}: "
                                     f"{', '.join(by_name) or 'none (declare [stops.NAME] in the description)'}")
    if len(set(names)) != len(names):
        raise InputError("lock", f"stop {next(n for n in names if names.count(n) > 1)!r} is named twice")
    return [by_name[n] for n in names]


def _lock_spec(system, lock) -> tuple[StopLimit | None, tuple[str, float] | None]:
    """``(stop, None)`` for a lock stop's name (the first of several), ``(None, (state, value))`` for a
    lock condition."""
    stops = _lock_stops(system, lock)
    if stops is not None:
        return stops[0], None
    try:
        name, value = lock
        value = float(value)
    except (TypeError, ValueError):
        raise InputError("lock", "give a stop's name or (condition, value)") from None
    if name not in system.names or system.variable(name).kind != "state":
        raise InputError("lock", f"{name} is not a state of {system.name} (a coordinate or a condition)")
    if not math.isfinite(value):
        raise InputError("lock", f"the lock value must be finite, got {value}")
    return None, (str(name), value)


def freefall(system, start: Mapping[str, float], *, lock, until: float, values: Mapping[str, float] | None = None,
             damping: float = 0.0, rtol: float = 1e-8, atol: float = 1e-10, rest_speed: float = 1e-4,
             max_step: float = math.inf, guess=None, method: str = "RK45", end_at_lock: bool = False,
             held_by: str | None = None) -> FreefallResult:
    """Release ``system`` at rest in the pose ``start`` and simulate it with its stops until it locks.

    Parameters
    ----------
    system:
        A model with mechanics (a description with stops for ``lock`` = a stop).
    start:
        ``{coordinate or condition: value}`` held while the retracted pose is assembled (SI, rad).
    lock:
        The name of the lock stop (locked: in contact and at rest), a sequence of stop names (locked:
        every one in contact and at rest; e.g. a gear's two sidestays), or ``(state, value)``: locked
        when that coordinate or condition reaches ``value`` (from the side it starts on).
    until:
        Longest simulated time (s).
    end_at_lock:
        End the run as soon as every lock stop is in contact and the mechanism at rest (every coordinate
        speed below ``rest_speed``): it has locked. Then the last row is that instant (the motion has not
        died out: its stop reactions differ from the static ones by the remaining dynamics).
    values:
        Parameter values (SI) overriding the model's, e.g. ``{"U": 60.0}``.
    damping, rtol, atol, max_step, method:
        As for :func:`~mechcont.dynamics.simulate` (``method="Radau"`` for a stiff mechanism, e.g. a stiff
        compliant attachment, whose fast vibration is damped).
    rest_speed:
        A run that ends with every coordinate speed below this (rad/s, m/s) and not locked is *at rest*
        short of locking; otherwise it is *still moving*.
    guess:
        A full variable vector to assemble from (default the model's own pose), e.g. the end of a
        retraction run: a mechanism with several assemblies at the ``start`` values takes the one
        nearest it.
    held_by:
        A parameter (the force that holds the gear up, e.g. the retraction actuator's): the released pose
        is then the static equilibrium with ``start`` held and it solved for (:func:`held_pose`), not a
        kinematic assembly; needed where joints are compliant.

    Returns
    -------
    FreefallResult
    """
    from ..equations import as_model
    from ._simulate import assemble, simulate

    if not (math.isfinite(until) and until > 0):
        raise InputError("until", f"must be a positive number of seconds, got {until}")
    if not rest_speed > 0:
        raise InputError("rest_speed", "must be positive")
    model = as_model(system)
    if values:
        model = model.with_values(dict(values))
    stop, target = _lock_spec(model, lock)
    lock_stops = _lock_stops(model, lock) or []
    if held_by is not None:
        guess = held_pose(model, start, held_by, guess=guess)
    x0 = assemble(model, dict(start) if guess is None else model.vector(dict(start), base=_states_of(model, guess)),
                  hold=list(start))
    events: Sequence = ()
    if target is not None:
        name, value = target
        side = float(np.sign(value - x0[model.index(name)])) or 1.0
        mechanics = model.mechanics
        coordinates = mechanics.coordinates if mechanics is not None else ()
        events = [Crossing(name, value, direction=int(side), terminal=True) if name in coordinates
                  else _ConditionCrossing(model, name, value, int(side))]
    if lock_stops and end_at_lock:
        events = [_AtRestOnStops(model, lock_stops, rest_speed)]
    stops = bool(model.stops)
    result = simulate(model, x0, (0.0, float(until)), stops=stops, damping=damping, rtol=rtol, atol=atol,
                      max_step=max_step, events=events, method=method)
    speed = float(np.max(np.abs(result.qdot[-1]), initial=0.0))
    t_lock = impact = None
    per_stop: dict[str, StopLock] = {}
    if stop is not None:
        at_rest = result.success and (speed <= rest_speed or result.status is Status.EVENT)  # the event: at rest
        per_stop = {s.name: _stop_lock(result, s.name, at_rest) for s in lock_stops}
        if all(s.time is not None for s in per_stop.values()):
            last_stop = max(per_stop.values(), key=lambda s: s.time)  # type: ignore[arg-type,return-value]
            t_lock, impact = last_stop.time, last_stop.impact_speed
        elif len(per_stop) == 1:
            impact = per_stop[stop.name].impact_speed
        lock_text = ("stop " if len(lock_stops) == 1 else "stops ") + ", ".join(s.name for s in lock_stops)
    else:
        assert target is not None
        name, value = target
        lock_text = f"{name} = {value:g}"
        if result.t_events and len(result.t_events[0]):
            t_lock = float(result.t_events[0][0])
            impact = abs(_rate(model, result, name, len(result) - 1))
    if t_lock is not None:
        outcome = LOCKED
    elif not result.success:
        outcome = FAILED
    else:
        outcome = AT_REST if speed <= rest_speed else MOVING
    tensions = damper_tensions(model, result, mechanism=as_model(system).mechanism)  # made once, on the original
    reactions = {s.name: float(np.max(result[s.reaction], initial=0.0)) for s in model.stops} if stops else {}
    return FreefallResult(outcome, lock_text, t_lock, impact, {n: float(np.max(np.abs(v), initial=0.0))
                                                                 for n, v in tensions.items()},
                          reactions, speed, result, per_stop)


def _states_of(model, guess) -> np.ndarray:
    """The model's defaults (its parameter values) with the states of the full vector ``guess``."""
    x, g = model.defaults(), np.asarray(guess, float)
    if g.shape != x.shape:
        raise InputError("guess", f"must be a full vector of {len(x)} values, got shape {g.shape}")
    states = np.array([v.kind == "state" for v in model.variables])
    x[states] = g[states]
    return x


def _stop_lock(result: SimulationResult, name: str, at_rest: bool) -> StopLock:
    """The lock of stop ``name`` in ``result``: its last contact when that is its last contact or release event
    and the run ended at rest, its first impact's speed, and when it last left the stop if it ended off it."""
    evs = [ev for ev in result.stop_events if ev.stop == name]
    first = next((ev for ev in evs if ev.kind == "impact"), None)
    on = bool(evs) and evs[-1].kind == "contact"  # an impact that sticks is followed by its contact event
    # off the stop at the end after striking it: a release, a rebound, or a plastic impact that did not hold
    # (no contact event follows an impact whose reaction would pull)
    left = evs[-1].time if evs and first is not None and not on else None
    return StopLock(name, evs[-1].time if on and at_rest else None, first.speed if first is not None else None, left)


class _AtRestOnStops:
    """Terminal event: every stop of ``stops`` in contact (a constraint of the simulation, or a compliant stop
    pressed) and on its limit (gap below :data:`LOCK_GAP`), and every coordinate speed below ``rest_speed``:
    ``max(max |qdot| - rest_speed, max gap - LOCK_GAP)`` falls through 0 (1 while a stop is out of contact:
    a plastic impact whose reaction would pull stops the gear on the stop for an instant, then it leaves)."""

    terminal, direction = True, -1

    def __init__(self, model, stops: Sequence[StopLimit], rest_speed: float):
        rows = list(model.equation_names)
        self.names = [s.name for s in stops]
        self.contacts = None
        self.model, self.rest_speed = model, rest_speed
        self.rows = np.array([rows.index(f"cond_{s.condition}") for s in stops])
        self.index = np.array([model.index(s.condition) for s in stops])
        self.side = np.array([float(s.side) for s in stops])
        self.limit = np.array([float(s.limit) for s in stops])

    def bind(self, dyn) -> None:
        """Read the stops in contact from the simulation's ``dyn.contacts``."""
        self.contacts = dyn.contacts
        if self.contacts is not None:
            self.stop_index = [self.contacts.names.index(n) for n in self.names]

    def __call__(self, t, x, qd) -> float:
        c = self.contacts
        if c is not None and not all(k in c.active or k in c.pressed for k in self.stop_index):
            return 1.0
        speed = float(np.max(np.abs(qd), initial=0.0)) - self.rest_speed
        if speed > 0:  # moving: the gaps need not be computed
            return speed
        y = np.array(x, float)
        y[self.index] = 0.0
        gaps = self.side * (self.model.residual(y)[self.rows] - self.limit)
        return max(speed, float(np.max(gaps)) - LOCK_GAP)


class _ConditionCrossing:
    """Terminal event: a description's condition (evaluated from the coordinates; the simulation
    fills the condition columns only afterwards) passes ``value`` in ``direction``."""

    terminal = True

    def __init__(self, model, name: str, value: float, direction: int):
        self.model, self.value, self.direction = model, value, direction
        self.row = list(model.equation_names).index(f"cond_{name}")
        self.index = model.index(name)

    def __call__(self, t, x, qd) -> float:
        y = np.array(x, float)
        y[self.index] = 0.0
        return float(self.model.residual(y)[self.row]) - self.value


def _rate(model, result: SimulationResult, name: str, i: int) -> float:
    """d(name)/dt at row ``i``: a coordinate's velocity, or a condition's ``grad c . qdot``."""
    if name in result.coordinates:
        return float(result.qdot[i, result.coordinates.index(name)])
    rows = list(model.equation_names)
    k = rows.index(f"cond_{name}")
    _, J = model.residual_and_jacobian(result.values[i])
    q_index = np.array([model.index(c) for c in result.coordinates])
    return float(J[k, q_index] @ result.qdot[i])


def held_pose(system, start: Mapping[str, float], held_by: str, *, values: Mapping[str, float] | None = None,
              guess=None, steps: int = 8) -> np.ndarray:
    """The retracted pose as a static equilibrium: the ``start`` values held (SI, rad) and the parameter
    ``held_by`` (the force that holds the gear there, e.g. the retraction actuator's, N) solved for; then
    ``held_by`` is set back to its value (the model's, or ``values``'): the gear released at rest.

    :func:`freefall` assembles its pose kinematically, which moves a compliant joint as freely as any
    coordinate the joints leave open (a stiff attachment dragged far off its airframe point); this pose has
    each compliant joint deflected by the load it carries. Solved by Newton from ``guess`` (a full vector)
    or else followed from the model's own pose in ``steps`` equal steps of the held values, each solved from
    the last, so the mechanism keeps the assembly it moves through (as when the gear retracts). Returns the
    full vector; :class:`~mechcont.errors.InputError` naming ``held_by`` when it is not a parameter,
    :class:`~mechcont.errors.ConvergenceError` when no equilibrium is found on the way."""
    from ..continuation import find_equilibrium
    from ..equations import as_model
    from ._simulate import assemble

    model = as_model(system)
    if held_by not in model.names or model.variable(held_by).kind != "parameter":
        raise InputError("held_by", f"{held_by} is not a parameter of {model.name}; valid: "
                                    f"{', '.join(model.parameter_names)}")
    if values:
        model = model.with_values(dict(values))
    if guess is not None:
        x = find_equilibrium(model, hold=dict(start), free=[held_by],
                             guess=model.vector(dict(start), base=np.asarray(guess, float)))
    else:
        x = assemble(model, model.defaults())
        begin = {n: condition_value(model, x, n) for n in start}
        for k in range(1, steps + 1):
            held = {n: begin[n] + (v - begin[n]) * k / steps for n, v in start.items()}
            x = find_equilibrium(model, hold=held, free=[held_by], guess=x)
    x[model.index(held_by)] = model.defaults()[model.index(held_by)]
    return x


def travel_of(system, start: Mapping[str, float], lock, values: Mapping[str, float] | None = None) -> tuple[str, float, float]:
    """The travel of a freefall: ``(variable, value at the released pose, value at the lock)``.

    The variable is the lock stop's condition (the first of several; its limit is the lock value) or the lock
    condition's state; its start value is computed at the pose assembled from ``start``."""
    from ..equations import as_model
    from ._simulate import assemble

    model = as_model(system)
    if values:
        model = model.with_values(dict(values))
    stop, target = _lock_spec(model, lock)
    name, end = (stop.condition, float(stop.limit)) if stop is not None else target  # type: ignore[misc]
    x0 = assemble(model, dict(start), hold=list(start))
    return name, condition_value(model, x0, name), end


def condition_value(system, x, name: str) -> float:
    """The value of the coordinate or declared condition ``name`` at the full vector ``x`` (its unit),
    computed from the coordinates (a condition's own entry in ``x`` need not be up to date)."""
    from ..equations import as_model

    model = as_model(system)
    rows = list(model.equation_names or ())
    if f"cond_{name}" not in rows:
        return float(x[model.index(name)])
    y = np.array(x, float)
    y[model.index(name)] = 0.0
    return float(model.residual(y)[rows.index(f"cond_{name}")])
