"""One freefall run (:func:`freefall`) and its result (:class:`FreefallResult`): what a run reports is described
in :mod:`.freefall`, the public module.

The run and its result, apart from :mod:`.freefall` (the public module, which also gathers the poses and the
critical airspeed built on runs): :mod:`._critical` calls :func:`freefall`, so it cannot be in a module that
imports :mod:`._critical`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from .._status import Status
from ..equations import Model, StopLimit
from ..errors import InputError
from ._budget import MAX_STEPS
from ._dampers import DamperTension, damper_tensions
from ._events import AtRestOnStops, ConditionCrossing, Crossing
from ._peaks import Peak, locate_peaks
from ._poses import Lock, find_lock_stops, held_pose, lock_spec
from ._result import SimulationResult

__all__ = ["FreefallResult", "StopLock", "freefall", "LOCKED", "AT_REST", "MOVING", "FAILED"]

#: Outcomes of a freefall run: locked; at rest short of locking; still moving at ``until`` (it may have
#: struck the lock and left it); the integrator failed.
LOCKED, AT_REST, MOVING, FAILED = Status.LOCKED, Status.AT_REST, Status.STILL_MOVING, Status.FAILED


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


@dataclass(frozen=True)
class FreefallResult:
    """The outcome of one freefall simulation.

    Attributes
    ----------
    outcome:
        A :class:`~mechcont._status.Status`: ``"locked"``, ``"at rest"`` (short of locking), ``"still moving"``
        (at ``until``; it may have struck the lock and left it: see ``stops``) or ``"failed"`` (the integrator failed).
    lock:
        What counted as locked: ``"stop NAME"`` or ``"NAME = VALUE"``.
    time_to_lock:
        When it locked (s): the lock stop's last contact (or the condition reached); None otherwise.
    impact_speed:
        The rate of the lock stop's condition at its first impact, or of the lock condition when
        reached (its unit per s); None when it did not get there.
    final_speed:
        ``max |qdot|`` at the end (coordinate units per s).
    history:
        The :class:`SimulationResult`.
    stops:
        ``{stop: StopLock}`` for each lock stop (several: locked when every one is in contact at
        rest; ``time_to_lock`` is then the last of their lock times, ``impact_speed`` the last one's).
    tension, reaction_columns:
        What the peak loads are computed from: the dampers' :class:`DamperTension`, ``{stop: R_NAME}``.

    The peak loads, :attr:`damper_peaks` and :attr:`reaction_peaks`, are located on the integrator's dense
    output when first asked for (a bisection that needs only the outcome does not pay for them).
    """

    outcome: str
    lock: str
    time_to_lock: float | None
    impact_speed: float | None
    final_speed: float
    history: SimulationResult
    stops: dict[str, StopLock] = field(default_factory=dict)
    tension: DamperTension | None = field(default=None, repr=False, compare=False)
    reaction_columns: dict[str, str] = field(default_factory=dict, repr=False)  # {stop: its R_NAME column}
    #: Why the run is or is not at rest where it ended (statics, :func:`~._settle.settled`); "" when locked.
    settling: str = ""
    #: False when the outcome could still change with a longer run: still moving (creeping, or bouncing on a
    #: lock that would hold: its static reaction is positive).
    decided: bool = True
    _peaks: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def damper_peaks(self) -> dict[str, Peak]:
        """``{damper: Peak}``: the largest ``|tension|`` (N) and when (s), located on the integrator's dense
        output (:func:`~._peaks.locate_peaks`), not sampled at the rows."""
        if "dampers" not in self._peaks:
            t = self.tension
            if t is None or not t.names:
                self._peaks["dampers"] = {}
            else:
                rows = damper_tensions(t.system, self.history)
                found = locate_peaks(self.history, lambda x, qd: [abs(v) for v in t(x, qd).values()], full=False,
                                     rows=np.abs(np.array([rows[n] for n in t.names])).T)
                self._peaks["dampers"] = dict(zip(t.names, found))
        return self._peaks["dampers"]

    @property
    def reaction_peaks(self) -> dict[str, Peak]:
        """``{stop: Peak}``: the largest reaction (units of ``R_NAME``) and when (s), located alike."""
        if "reactions" not in self._peaks:
            self._peaks["reactions"] = {n: self.history.peak(r) for n, r in self.reaction_columns.items()}
        return self._peaks["reactions"]

    @property
    def peak_damper(self) -> dict[str, float]:
        """``{damper: largest |tension|}`` (N), located (:attr:`damper_peaks` has the times)."""
        return {n: p.value for n, p in self.damper_peaks.items()}

    @property
    def peak_reaction(self) -> dict[str, float]:
        """``{stop: largest reaction}`` (units of ``R_NAME``), located (:attr:`reaction_peaks` has the times)."""
        return {n: p.value for n, p in self.reaction_peaks.items()}

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
        stop reactions and the lock quantity's rate, by name, and of the dampers' tensions under
        ``"damper"``, default N); a run that did not lock ends with
        where it is: the columns ``show`` (default every coordinate)."""
        units = units or {}
        t_end = float(self.history.t[-1])
        what: dict[str, str] = {AT_REST: "at rest short of locking", MOVING: f"still moving at t = {t_end:.6g} s"}
        lines = [f"outcome: {what.get(self.outcome, self.outcome)} (lock: {self.lock})"]
        if self.outcome == AT_REST and self.settling:
            lines.append(f"at rest: {self.settling}")
        if self.outcome == MOVING and self.settling:
            lines.append(f"creeping: max speed {self.final_speed:.3g}, not at rest ({self.settling})")
        if not self.decided:
            lines.append("undecided: a longer run (--until) could still change the outcome")
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
        for name, p in self.damper_peaks.items():
            lines.append(f"peak damper tension {name}: {p.value:.6g} {units.get('damper', 'N')} at t = {p.time:.6g} s")
        for name, p in self.reaction_peaks.items():
            u = f" {units[name]}" if units.get(name) else ""
            lines.append(f"peak stop reaction {name}: {p.value:.6g}{u}" + (f" at t = {p.time:.6g} s" if p.value > 0 else ""))
        if self.outcome != LOCKED:
            t, pose = self.history.t[-1], self.history.at(len(self.history) - 1)
            lines.append(f"at t = {t:.6g} s: max speed {self.final_speed:.3g}, "
                         + ", ".join(f"{c} = {pose[c]:.6g}" for c in (show or self.history.coordinates)))
        return lines


def freefall(system: Model, start: Mapping[str, float], *, lock: Lock, until: float, values: Mapping[str, float] | None = None,
             damping: float = 0.0, rtol: float = 1e-8, atol: float = 1e-10, rest_speed: float = 1e-4,
             max_step: float = math.inf, guess: np.ndarray | None = None, method: str = "RK45", end_at_lock: bool = False,
             held_by: str | None = None, audit: bool = True, max_steps: int | None = None) -> FreefallResult:
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
        died out: its stop reactions differ from the static ones by the remaining dynamics). A run at rest
        short of its lock at a stable equilibrium (:func:`~._settle.settled`) ends there too: nothing more
        can change (a long ``until`` costs no more than the motion).
    values:
        Parameter values (SI) overriding the model's, e.g. ``{"U": 60.0}``.
    damping, rtol, atol, max_step, method:
        As for :func:`~mechcont.dynamics.simulate` (``method="Radau"`` for a stiff mechanism, e.g. a stiff
        compliant attachment, whose fast vibration is damped).
    rest_speed:
        A run that ends with every coordinate speed below this (rad/s, m/s), not locked, *and* at a stable
        equilibrium with the static forces pointing back to it (:func:`~._settle.settled`) is *at rest* short
        of locking; otherwise it is *still moving* (a slow one *creeping*, e.g. near the ghost of a fold).
        Positive and finite.
    guess:
        A full variable vector to assemble from (default the model's own pose), e.g. the end of a
        retraction run: a mechanism with several assemblies at the ``start`` values takes the one
        nearest it.
    held_by:
        A parameter (the force that holds the gear up, e.g. the retraction actuator's): the released pose
        is then the static equilibrium with ``start`` held and it solved for (:func:`held_pose`). Without it
        compliant joints are at the deflection of the gear held by a reaction conjugate to each ``start`` value
        (:func:`~mechcont.dynamics.assemble`).
    max_steps:
        The integrator's step budget (:func:`~mechcont.dynamics.simulate`'s; default its own): a stiff run ends
        early with the outcome ``"failed"`` and a message naming the stiff element.
    audit:
        Keep the history's energy audit (False in :func:`critical_airspeed`'s runs, which read only the outcome).

    Returns
    -------
    FreefallResult
    """
    from ._settle import SettledOffLock
    from ._simulate import assemble, simulate

    if not (math.isfinite(until) and until > 0):
        raise InputError("until", f"must be a positive number of seconds, got {until}")
    if not (math.isfinite(rest_speed) and rest_speed > 0):
        raise InputError("rest_speed", f"must be a positive finite speed (rad/s, m/s), got {rest_speed:g}")
    model = system
    if values:
        model = model.with_values(dict(values))
    stop, target = lock_spec(model, lock)
    lock_stops = find_lock_stops(model, lock) or []
    if held_by is not None:
        guess = held_pose(model, start, held_by, guess=guess)
    x0 = assemble(model, dict(start) if guess is None else model.vector(dict(start), base=_states_of(model, guess)),
                  hold=list(start), kinematic=held_by is not None)  # held_pose's pose is already static
    _check_forces(model, x0, values)
    events: Sequence = ()
    if target is not None:
        name, value = target
        side = float(np.sign(value - x0[model.index(name)])) or 1.0
        mechanics = model.mechanics
        coordinates = mechanics.coordinates if mechanics is not None else ()
        events = [Crossing(name, value, direction=int(side), terminal=True) if name in coordinates
                  else ConditionCrossing(model, name, value, int(side))]
    if lock_stops and end_at_lock:  # ends locked, or at rest short of the lock where nothing more can change
        events = [AtRestOnStops(model, lock_stops, rest_speed), SettledOffLock(model, lock_stops, rest_speed)]
    stops = bool(model.stops)
    result = simulate(model, x0, (0.0, float(until)), stops=stops, damping=damping, rtol=rtol, atol=atol,
                      max_step=max_step, events=events, method=method, audit=audit,
                      max_steps=MAX_STEPS if max_steps is None else max_steps)
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
    settling, decided = "", True
    if t_lock is not None:
        outcome = LOCKED
    elif not result.success:
        outcome = FAILED
    else:
        outcome, settling, decided = _unlocked_outcome(model, result, speed, rest_speed, lock_stops, per_stop)
    tension = DamperTension(model, result.coordinates)  # made once
    columns = {s.name: s.reaction for s in model.stops} if stops else {}
    return FreefallResult(outcome, lock_text, t_lock, impact, speed, result, per_stop, tension, columns,
                          settling, decided)


def _unlocked_outcome(model: Model, result: SimulationResult, speed: float, rest_speed: float,
                      lock_stops: Sequence[StopLimit], per_stop: Mapping[str, StopLock]) -> tuple[Status, str, bool]:
    """``(outcome, why, decided)`` of a run that ran to its end without locking: at rest only at a stable
    equilibrium with nothing on the way (:func:`~._settle.settled`); a slow run elsewhere creeps (still
    moving, undecided), as does one bouncing on a lock that would hold (its static reaction positive)."""
    from ._settle import lock_reactions, settled

    if speed <= rest_speed:
        last = {}
        for ev in result.stop_events:
            last[ev.stop] = ev.kind
        touching = [s for s in model.stops if last.get(s.name) == "contact"]
        verdict = settled(model, result.values[-1], touching)
        if verdict.at_rest:
            return AT_REST, verdict.why, True
        why = verdict.why
    else:
        why = ""
    left = [s for s in lock_stops if per_stop.get(s.name) is not None and per_stop[s.name].left is not None]
    if left and len(left) == len(lock_stops):  # struck the lock and left it: back for good only if it holds
        reactions = lock_reactions(model, lock_stops, result.values[-1])
        if reactions is not None and not np.all(reactions > 0):
            return MOVING, why, True  # the lock cannot hold here: it has left for good
    if any(_turned_back(result, s) for s in lock_stops if per_stop[s.name].impact_speed is None):
        # it came nearest the lock and went back: with no time-varying loads its energy only falls, so it
        # cannot get nearer again (rigorous for one degree of freedom; a swing about a stable equilibrium)
        return MOVING, why, True
    return MOVING, why, False


def _turned_back(result: SimulationResult, stop: StopLimit) -> bool:
    """True when the run came nearest ``stop`` (its gap, condition units) before its end and then moved away from
    it by more than the gap's rounding."""
    gap = float(stop.side) * (np.asarray(result[stop.condition], float) - float(stop.limit))
    k = int(np.argmin(gap))
    return k < len(gap) - 1 and gap[-1] - gap[k] > 1e-9 * (1.0 + abs(float(stop.limit)))


def _check_forces(model: Model, x0: np.ndarray, values: Mapping[str, float] | None) -> None:
    """:class:`InputError` (field ``values``) when the forces on the released pose are not finite numbers (a
    parameter so large that a force overflows, e.g. an airspeed of 1e308 in a quadratic drag)."""
    mech = model.mechanics
    if mech is None:
        return
    with np.errstate(all="ignore"):
        forces = mech.applied_forces(x0)
    if not np.all(np.isfinite(forces)):
        given = ", ".join(f"{k} = {v:g}" for k, v in (values or {}).items()) or "the model's values"
        raise InputError("values", f"the forces on the released pose are not finite at {given} (a value so large "
                                   "that a force overflows): use values of physical size")


def _states_of(model: Model, guess: np.ndarray) -> np.ndarray:
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


def _rate(model: Model, result: SimulationResult, name: str, i: int) -> float:
    """d(name)/dt at row ``i``: a coordinate's velocity, or a condition's ``grad c . qdot``."""
    if name in result.coordinates:
        return float(result.qdot[i, result.coordinates.index(name)])
    rows = list(model.equation_names)
    k = rows.index(f"cond_{name}")
    _, J = model.residual_and_jacobian(result.values[i])
    q_index = np.array([model.index(c) for c in result.coordinates])
    return float(J[k, q_index] @ result.qdot[i])
