"""Quasi-static sweeps: the engineers' brute-force way to find jumps and downlock loads.

A sweep ramps parameters (loads) slowly through a sequence of segments — for instance the
applied force down and then up again — while the mechanism is simulated in time, records
the response, and reports every jump of a watched quantity with the load at which it
happened. Slow sweeps follow the stable branches of continuation; each jump happens just
after a fold, by a margin that shrinks as the sweep slows.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .._status import Status
from ..equations import velocity_name
from ..errors import InputError
from ._events import Crossing
from ._jumps import JumpWindow, find_jump_windows, find_runaway
from ._peaks import DenseHistory
from ._ramps import MAX_SWEEP_SECONDS, Ramp, RampSpec, _schedule, parse_ramps
from ._result import SimulationResult
from ._simulate import assemble, check_fixed_stops, initial_vector, simulate

if TYPE_CHECKING:

    from ..equations import Model
    from ._contact import StopEvent

__all__ = ["Ramp", "Jump", "SweepResult", "sweep", "parse_ramps", "sweep_start"]

#: Most integration steps a sweep may need (its length over the largest time step).
MAX_SWEEP_STEPS = 1e6


@dataclass(frozen=True)
class Jump:
    """A jump found in a sweep.

    Attributes
    ----------
    parameter, value:
        The ramped parameter and its value when the jump was detected (the jump load).
    time:
        Detection time (s).
    segment, direction:
        Index of the sweep segment and its ramp direction (+1 up, -1 down).
    before, after:
        Coordinates ``{name: value}`` at the start and at the end of the fast motion.
    t_start, t_end:
        Start and end of the fast motion (s).
    """

    parameter: str
    value: float
    time: float
    segment: int
    direction: int
    before: dict[str, float]
    after: dict[str, float]
    t_start: float
    t_end: float


@dataclass(frozen=True)
class SweepResult:
    """A recorded sweep: the time history, its segments and the jumps found.

    ``result["theta1"]`` etc. give columns as in :class:`SimulationResult`;
    :meth:`curve` gives one segment as (parameter, watched) arrays for plotting over a branch.
    ``runaway`` is the fast motion of ``watch`` that had not settled when the sweep ended (a crank
    spinning away past its last fold; :func:`._jumps.find_runaway`): ``value`` is the load where it
    started, ``after`` the coordinates at the end; None when the sweep ended at rest. It follows a fold as a
    jump does (:func:`~mechcont.dynamics.runaway_gap`, :func:`~mechcont.dynamics.branch_runaway_gap`).
    """

    simulation: SimulationResult
    ramps: tuple[Ramp, ...]
    segment_times: np.ndarray
    watch: str
    jumps: list[Jump]
    threshold: list[float]
    runaway: Jump | None = None

    @property
    def t(self) -> np.ndarray:
        """Sample times (s)."""
        return self.simulation.t

    @property
    def values(self) -> np.ndarray:
        """Full variable vectors per sample (N x len(names))."""
        return self.simulation.values

    @property
    def names(self) -> tuple[str, ...]:
        """Column names of :attr:`values`."""
        return self.simulation.names

    def __getitem__(self, name: str) -> np.ndarray:
        return self.simulation[name]

    @property
    def stop_events(self) -> list[StopEvent]:
        """The stop events (:class:`~._contact.StopEvent`) of a sweep with stops, in time order."""
        return self.simulation.stop_events

    def stop_loads(self, kind: str, stop: str | None = None) -> list[float]:
        """The first ramped parameter's value at each stop event of ``kind`` (``"contact"``,
        ``"impact"``, ``"release"``), of stop ``stop`` or any: the sweep's contact and release loads."""
        name = self.ramps[0].name
        column = self[name]
        return [float(column[ev.row]) for ev in self.stop_events
                if ev.kind == kind and (stop is None or ev.stop == stop)]

    def segment_mask(self, i: int) -> np.ndarray:
        """Boolean mask of the samples in segment ``i``."""
        t0, t1 = self.segment_times[i]
        return (self.t >= t0) & (self.t <= t1)

    def curve(self, i: int) -> tuple[np.ndarray, np.ndarray]:
        """Segment ``i`` as (ramped parameter values, watched values)."""
        m = self.segment_mask(i)
        return self[self.ramps[i].name][m], self[self.watch][m]

    def to_csv(self, path: str | Path) -> Path:
        """Write the time history as CSV: ``t``, the variables, the velocities and a ``label``
        column marking ``JUMP`` on the last sample before each jump's fast motion (so
        ``mechcont draw MODEL --point sweep.csv:JUMP1`` draws the mechanism as it lets go) and
        ``RUNAWAY`` on the last sample before the runaway. Returns the path."""
        labels = [""] * len(self.t)
        for j in self.jumps:
            i = max(int(np.searchsorted(self.t, j.t_start, side="right")) - 1, 0)
            labels[i] = "JUMP"
        if self.runaway is not None:
            labels[max(int(np.searchsorted(self.t, self.runaway.t_start, side="right")) - 1, 0)] = "RUNAWAY"
        return self.simulation.to_csv(path, labels)


def sweep_start(system: Model, start: Mapping[str, float], ramps: Sequence[Ramp], *, equilibrium: bool = True,
                start_field: str = "x0") -> np.ndarray:
    """The state a sweep of ``ramps`` starts from: the mechanism assembled with the ``start`` coordinates
    or conditions held and each ramped parameter at its first segment's start value; with
    ``equilibrium`` then the equilibrium nearest it (Newton from there, every parameter kept).
    An assembly that fails names ``start_field``."""
    values = dict(start)
    for r in ramps:  # each ramped parameter begins at its first segment's start value
        values.setdefault(r.name, r.start)
    try:
        x0 = assemble(system, values, hold=[n for n in start if n in system.names])
    except InputError as exc:
        if exc.field != "x0":
            raise
        raise InputError(start_field, str(exc).split(": ", 1)[1]) from None
    if equilibrium:
        from ..continuation import find_equilibrium

        x0 = find_equilibrium(system, values={n: x0[system.index(n)] for n in system.parameter_names}, guess=x0)
    return x0


#: A ramped parameter stays within this many of its scales (``system.scales()``) of zero.
MAX_RAMP_SCALES = 1e6


def sweep(system: Model, x0: np.ndarray | Mapping[str, float] | Sequence[float], ramp: RampSpec, *, watch: str,
          damping: float = 0.0, settle: float = 0.0, through: float | None = None, rate_threshold: float | None = None,
          stop_on_jump: bool = False,
          method: str = "RK45", rtol: float = 1e-6, atol: float = 1e-8, max_step: float | None = None,
          baumgarte: tuple[float, float] | None = (10.0, 10.0),
          progress: Callable[[float], None] | None = None, stops: bool | Sequence[str] = False) -> SweepResult:
    """Ramp parameters slowly, simulate the mechanism, and detect the jumps of ``watch``.

    Parameters
    ----------
    system:
        A model with ``mechanics`` (e.g. ``build_overcentre(LU=0.4, c=...)``).
    x0:
        Assembled start (full vector or ``{name: value}``); ideally an equilibrium at the
        first ramp's start load, otherwise use ``settle`` to let it come to rest.
    ramp:
        Segments, see :func:`parse_ramps`: e.g. ``{"F": [(60, -90, 2), (-90, 110, 2)]}``
        ramps F down from 60 N to -90 N and back up to 110 N at 2 N/s. Each ramped
        parameter holds its first start value before its first segment and its last value
        after its last one.
    watch:
        Coordinate whose jumps are detected (e.g. ``"theta1"``).
    damping:
        Mass-proportional (Rayleigh) damping, 1/s (see :func:`simulate`); model dampers
        such as the overcentre's ``c`` are set through its parameters.
    settle:
        Seconds at the initial loads before the first segment (not searched for jumps).
    through:
        Time jumps where ``watch`` passes through this value instead of by rate alone.
    rate_threshold:
        Rate of ``watch`` (units/s) above which motion counts as a jump; default 10 times
        ``span / moving time``: the segment's duration less the time ``watch`` rests, e.g. on a stop
        (see :mod:`._jumps`).
    stop_on_jump:
        Stop the simulation the first time ``watch`` passes ``through`` (requires it).
    method, rtol, atol, baumgarte:
        Passed to :func:`simulate`.
    max_step:
        Largest time step (s); default 1/400 of the shortest segment, so each segment is
        resolved by at least 400 samples.
    progress:
        Called with the simulated time after each step.
    stops:
        True (all the model's stops) or stop names: simulated as unilateral constraints (see
        :func:`simulate`); their events (contact, impact, release) are in ``result.stop_events``
        with the ramped loads at each (:meth:`SweepResult.stop_loads`). The stops' reactions in
        ``x0`` are ignored (they are computed).

    Returns
    -------
    SweepResult
        The record, its segments and the detected :class:`Jump` list (jump loads), and its
        ``runaway`` (a motion of ``watch`` that had not settled by the end, or None).
    """
    ramps = parse_ramps(ramp)
    for r in ramps:
        system.index(r.name)
        reach = MAX_RAMP_SCALES * system.variable(r.name).scale
        if max(abs(r.start), abs(r.stop)) > reach:  # 1e308 N: the integrator's steps shrink without end
            unit = system.variable(r.name).unit
            raise InputError("ramp", f"{r.name}: {r.start:g} -> {r.stop:g} goes beyond {reach:g} {unit} ({MAX_RAMP_SCALES:g} "
                                     f"times its scale), where no simulation of the mechanism can follow")
    if stops:
        check_fixed_stops(system, [r.name for r in ramps], stops, "ramp")
    coords = [system.names[i] for i in system.mechanics.q_index] if system.mechanics is not None else []
    if watch not in coords:
        raise InputError("watch", f"must be a coordinate of the model; valid: {', '.join(coords)}")
    if not (math.isfinite(settle) and 0 <= settle <= MAX_SWEEP_SECONDS):
        raise InputError("settle", f"must be a number of seconds between 0 and {MAX_SWEEP_SECONDS:g}")
    if through is not None and not math.isfinite(through):
        raise InputError("through", "must be a finite value of the watched coordinate")
    if stop_on_jump and through is None:
        raise InputError("stop_on_jump", "needs a `through` value to stop at")
    x = initial_vector(system, x0)
    reactions = _reaction_indices(system, stops)
    x[reactions] = 0.0
    seg_times, loads = _schedule(ramps, settle)
    if max_step is None:
        max_step = min(r.duration for r in ramps) / 400.0
    total = settle + sum(r.duration for r in ramps)
    if total > MAX_SWEEP_SECONDS or (max_step > 0 and total / max_step > MAX_SWEEP_STEPS):
        raise InputError("ramp", f"the sweep lasts {total:.3g} s at time steps of at most {max_step:.3g} s (1/400 of "
                                 f"the shortest segment): {total / max_step:.3g} steps, more than "
                                 f"{MAX_SWEEP_STEPS:g}; make the segments' durations comparable (rates) or shorter")
    if isinstance(damping, (int, float)) and math.isfinite(damping) and total * damping / 3 > MAX_SWEEP_STEPS:
        # an explicit Runge-Kutta step stays below about 3/damping (s) for stability
        raise InputError("damping", f"{damping:g} 1/s over {total:.3g} s needs about {total * damping / 3:.3g} "
                                    f"integration steps, more than {MAX_SWEEP_STEPS:g}; lower the damping or the "
                                    f"sweep's duration")
    events = [Crossing(watch, through, 0, stop_on_jump)] if through is not None else None
    # one integration per phase (settle, then each segment), so that the samples include
    # every segment boundary and no step straddles a kink of the load
    phases = ([(0.0, settle)] if settle > 0 else []) + [tuple(ab) for ab in seg_times]
    parts: list[SimulationResult] = []
    qd = None
    for a, b in phases:
        part = simulate(system, x, (a, b), qdot0=qd, loads=loads, method=method, rtol=rtol, atol=atol,
                        baumgarte=baumgarte, damping=damping, max_step=max_step, events=events,
                        progress=progress, stops=stops)
        parts.append(part)
        x, qd = part.values[-1].copy(), part.qdot[-1]
        x[reactions] = 0.0  # computed again by the next phase, which finds the same contacts
        if part.status is not Status.FINISHED:
            break
    sim = _concatenate(parts)
    t, w, wdot = sim.t, sim[watch], sim[velocity_name(watch)]
    in_sweep = t >= settle
    crossings = sim.t_events[0] if through is not None else None

    def found(span: float) -> tuple[list[Jump], list[float]]:
        jumps, thresholds = [], []
        for k, ((a, b), r) in enumerate(zip(seg_times, ramps)):
            idx = np.flatnonzero((t >= a) & (t <= b))
            if idx.size < 2:
                thresholds.append(float("nan"))
                continue
            windows, thr = find_jump_windows(t, w, wdot, int(idx[0]), int(idx[-1]), span=span,
                                             threshold=rate_threshold, crossings=crossings)
            thresholds.append(thr)
            jumps += [_jump(sim, r, k, loads, win) for win in windows]
        return jumps, thresholds

    jumps, thresholds = found(float(np.ptp(w[in_sweep])) if in_sweep.any() else 0.0)
    # a fast motion at the end that this threshold catches is a jump (still in flight, maybe); a runaway's own
    # span inflates it out of reach, so only a runaway that no jump found overlaps counts
    runaway = _runaway(sim, watch, ramps, seg_times, loads, np.flatnonzero(in_sweep))
    if runaway is not None and jumps and jumps[-1].t_end >= runaway.t_start:
        runaway = None
    if runaway is not None:  # the quasi-static rate's scale is the span before it
        jumps, thresholds = found(float(np.ptp(w[in_sweep & (t <= runaway.t_start)])))
        jumps, runaway = _runaway_from_jumps(jumps, runaway, sim)
    return SweepResult(simulation=sim, ramps=ramps, segment_times=seg_times, watch=watch, jumps=jumps,
                       threshold=thresholds, runaway=runaway)


def _runaway_from_jumps(jumps: list[Jump], runaway: Jump, sim: SimulationResult) -> tuple[list[Jump], Jump]:
    """The jumps found at the quasi-static rate scale that run on to the end of the sweep (one per segment the
    runaway crosses, each ending where the next begins) are the runaway's start: it starts with the first of
    them. Returns the other jumps and the runaway."""
    end, first = float(sim.t[-1]), None
    for j in reversed(jumps):
        if j.t_end < end:
            break
        first, end = j, j.t_start
    if first is None:
        return jumps, runaway
    kept = [j for j in jumps if j.t_end < first.t_start]
    return kept, (runaway if runaway.t_start < first.t_start else replace(first, after=runaway.after,
                                                                             t_end=runaway.t_end))


def _runaway(sim: SimulationResult, watch: str, ramps: Sequence[Ramp], seg_times: np.ndarray,
             loads: Mapping[str, Callable[[float], float]], idx: np.ndarray) -> Jump | None:
    """The runaway of ``watch`` at the end of the samples ``idx`` (the sweep after settling) as a
    :class:`Jump` timed where it started, or None (:func:`._jumps.find_runaway`)."""
    if idx.size < 3 or sim.status is not Status.FINISHED:  # stopped at an event or failed: no end reached
        return None
    win = find_runaway(sim.t, sim[watch], sim[velocity_name(watch)], int(idx[0]), int(idx[-1]),
                       duration=ramps[-1].duration)
    if win is None:
        return None
    k = min(int(np.searchsorted(seg_times[:, 1], win.time)), len(ramps) - 1)  # the segment it started in
    return _jump(sim, ramps[k], k, loads, win)


def _jump(sim: SimulationResult, r: Ramp, k: int, loads: Mapping[str, Callable[[float], float]],
          win: JumpWindow) -> Jump:
    """The :class:`Jump` of the fast motion ``win`` in segment ``k`` (ramp ``r``): its load from the schedule
    ``loads``, the coordinates where it starts and ends."""
    return Jump(parameter=r.name, value=loads[r.name](win.time), time=win.time, segment=k, direction=r.direction,
                before=_coords_at(sim, win.i_start), after=_coords_at(sim, win.i_end), t_start=win.t_start,
                t_end=win.t_end)


def _concatenate(parts: list[SimulationResult]) -> SimulationResult:
    """One result from consecutive phases (the first sample of each later phase is dropped)."""
    first = parts[0]
    keep = [slice(None)] + [slice(1, None)] * (len(parts) - 1)
    n_ev = len(first.t_events)
    stop_events, offset = list(first.stop_events), len(first.t)
    for prev, p in zip(parts, parts[1:]):  # a later phase's first row is its predecessor's last
        still = _in_contact_at_end(prev)  # not a new contact when the next phase starts on it
        stop_events += [replace(ev, row=ev.row + offset - 1) for ev in p.stop_events
                        if not (ev.kind == "contact" and ev.time == p.t[0] and ev.stop in still)]
        offset += len(p.t) - 1
    dense = [p.dense for p in parts if p.dense]
    return SimulationResult(
        t=np.concatenate([p.t[k] for p, k in zip(parts, keep)]),
        values=np.concatenate([p.values[k] for p, k in zip(parts, keep)]),
        qdot=np.concatenate([p.qdot[k] for p, k in zip(parts, keep)]),
        names=first.names, coordinates=first.coordinates, status=parts[-1].status,
        constraint_drift=max(p.constraint_drift for p in parts),
        velocity_drift=max(p.velocity_drift for p in parts),
        t_events=[np.concatenate([p.t_events[i] for p in parts]) for i in range(n_ev)],
        x_events=[np.concatenate([p.x_events[i] for p in parts]) for i in range(n_ev)],
        nfev=sum(p.nfev for p in parts), detail=parts[-1].detail, units=first.units, stop_events=stop_events,
        integrator_failure=parts[-1].integrator_failure,
        dense=DenseHistory.joined(dense) if len(dense) == len(parts) else None)


def _reaction_indices(system: Model, stops: bool | Sequence[str]) -> list[int]:
    """Indices of the reactions of the simulated stops (none without stops)."""
    if not stops:
        return []
    from ._contact import _stops_of

    return [system.index(s.reaction) for s in _stops_of(system, None if stops is True else stops)]


def _in_contact_at_end(part: SimulationResult) -> set[str]:
    """The stops in contact at the end of a phase, from its events."""
    state: dict[str, bool] = {}
    for ev in part.stop_events:
        if ev.kind in ("contact", "release"):
            state[ev.stop] = ev.kind == "contact"
    return {n for n, on in state.items() if on}


def _coords_at(sim: SimulationResult, i: int) -> dict[str, float]:
    return {c: float(sim[c][i]) for c in sim.coordinates}
