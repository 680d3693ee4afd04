"""Pseudo-arclength continuation of one direction: step-size control, events within a step, and a thin driver.

:class:`~._corrector.PseudoArclength` (its own module: the maths of one step) predicts, corrects
and takes the tangent on any :class:`~._problem.ContinuationProblem` (equilibria, fold curves).
Here, the walk around it: :class:`BranchSteps` is an iterator over the points of one direction:
each ``next()`` takes one accepted step (:class:`StepSizeController` choosing its length),
locates the events inside it, and yields the points to record. :func:`run_direction` is the
driver that collects them. Why a direction ended is a :class:`Termination`.
"""

from __future__ import annotations

import math
import signal
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from enum import Enum
from types import MappingProxyType
from typing import Any, NamedTuple

import numpy as np

from .._signals import stopping
from .._status import Status
from ._corrector import PseudoArclength
from ._events import Event, Hit, PointState
from ._options import ContinuationOptions
from ._problem import ContinuationProblem

__all__ = ["StepSizeController", "Termination", "BranchSteps", "RecordedPoint",
           "DirectionResult", "run_direction"]


#: a stopping event's value this close to zero at the start (relative to its bound) is the start on it
_ON_BOUND = 1e-14


class Termination(Enum):
    """Why one direction of a branch ended; ``status`` is what :class:`Branch` reports."""

    BOUND = "reached a bound"
    STOP_EVENT = "stopped at an event"
    START_ON_BOUND = "the start lies on a bound and this direction leaves it"
    MAX_STEPS = "took max_steps steps"
    STEP_UNDERFLOW = "step size fell below dsmin"
    BRANCHES_TOO_CLOSE = "branches too close to separate"
    SIGNAL = "stopped by a signal"

    @property
    def status(self) -> Status:
        """:attr:`Status.COMPLETED` for a normal end, :attr:`Status.STEP_UNDERFLOW` for a failure."""
        failed = (Termination.STEP_UNDERFLOW, Termination.BRANCHES_TOO_CLOSE)
        return Status.STEP_UNDERFLOW if self in failed else Status.COMPLETED




class StepSizeController:
    """AUTO-style step control: grow after an easy step, shrink after a hard or rejected one.

    ``ds`` starts at ``options.ds``; a step whose corrector took at most 3 iterations
    multiplies it by ``grow`` (up to ``dsmax``), one that took 6 or more by ``shrink``
    (down to ``dsmin``); a rejected step multiplies it by ``shrink`` and :meth:`reject`
    returns False once it falls below ``dsmin``.
    """

    def __init__(self, options: ContinuationOptions) -> None:
        self.options = options
        self.ds = options.ds

    def reject(self) -> bool:
        """Shrink after a rejected step; False when the step fell below ``dsmin``."""
        self.ds *= self.options.engine.shrink
        return self.ds >= self.options.dsmin

    def retry_short_of(self, sigma: float) -> bool:
        """Retry with half the distance to a discontinuity at ``sigma``; False below ``dsmin``."""
        o = self.options
        self.ds = max(0.5 * sigma, o.engine.shrink * o.dsmin)
        return self.ds >= o.dsmin

    def accept(self, iterations: int) -> None:
        """Adapt after an accepted step whose corrector took ``iterations``."""
        o = self.options
        if iterations <= 3:
            self.ds = min(self.ds * o.engine.grow, o.dsmax)
        elif iterations >= 6:
            self.ds = max(self.ds * o.engine.shrink, o.dsmin)


class RecordedPoint(NamedTuple):
    """A point of a branch as the iterator yields it: its :class:`PointState`, its label (``""`` for a plain
    step, ``"LP"``, ``"EP"``, an event's name...), what its event adds (``{"status": "located", "stop": ...}``,
    the keys :class:`~._special_point.SpecialPoint` reads) and its arclength ``s`` from the start (scaled).
    Immutable; a tuple (one is made per step: a frozen dataclass costs twice as much to make)."""

    state: PointState
    label: str = ""
    info: Mapping[str, Any] = MappingProxyType({})
    s: float = 0.0


def _describe(problem: ContinuationProblem, x: np.ndarray) -> str:
    names, idx = problem.names, problem.idx
    if idx is None:
        return ""
    shown = [f"{n}={x[i]:.6g}" for n, i in list(zip(names, idx))[-3:]]
    return " at " + ", ".join(shown)


def _runaway(problem: ContinuationProblem, first: PointState, last: PointState) -> str:
    """A hint naming the unknown that grew most (in its scales) when max_steps ran out."""
    names = problem.names
    scale = np.asarray(problem.scale, dtype=float)
    if len(names) != len(scale):
        return ""
    growth = np.abs(last.u - first.u) / scale
    k = int(np.argmax(growth))
    if growth[k] < 10:
        return ""
    return (f"; {names[k]} went from {first.u[k]:.6g} to {last.u[k]:.6g} and may grow without bound: "
            f"give it bounds (--bounds {names[k]}=LO:HI, or bounds={{'{names[k]}': (LO, HI)}} in the options)")


class BranchSteps(Iterator[RecordedPoint]):
    """The points of one continuation direction, one accepted step at a time.

    Iterating yields :class:`RecordedPoint` objects: the start point first, then for each
    accepted step the special points located inside it (in arclength order) and the step's
    end point. When the direction ends, :attr:`termination` says why, :attr:`message`
    explains it, and :attr:`end_label` / :attr:`end_info` are what the last yielded point
    should be labelled with (``EP`` at ``max_steps`` or a step-size underflow).
    """

    def __init__(self, problem: ContinuationProblem, u0: np.ndarray, direction: int, options: ContinuationOptions,
                 events: list[Event], tangent0: np.ndarray | None = None) -> None:
        self.problem, self.options, self.events = problem, options, list(events)
        self.stepper = PseudoArclength(problem, options)
        self.control = StepSizeController(options)
        z = np.asarray(u0, float) / self.stepper.D
        t = self.stepper.initial_tangent(z, direction) if tangent0 is None else direction * np.asarray(tangent0, float)
        self.current = self.stepper.state(z, t)
        self.first = self.current
        self.values = [ev.value(problem, self.current) for ev in self.events]
        self.s = 0.0
        self.steps = 0
        self.termination: Termination | None = None
        self.message = ""
        self.end_label = ""
        self.end_info: dict[str, Any] = {}
        self._queue: list[RecordedPoint] = [RecordedPoint(self.current)]

    def __next__(self) -> RecordedPoint:
        while not self._queue:
            if self.termination is not None:
                raise StopIteration
            self._step()
        return self._queue.pop(0)

    # -- one accepted step ------------------------------------------------------------
    def _end(self, how: Termination, message: str, label: str = "", info: dict[str, Any] | None = None) -> None:
        self.termination, self.message = how, message
        self.end_label, self.end_info = label, info or {}

    def _step(self) -> None:
        signum = stopping()
        if signum is not None:  # SIGTERM in `mechcont continue`: end here, so the branch so far is written
            name = signal.Signals(signum).name
            self._end(Termination.SIGNAL, f"stopped by {name} after {self.steps} steps", "EP", {"reason": name})
            return
        if self.steps >= self.options.max_steps:
            self._end(Termination.MAX_STEPS,
                      f"stopped after max_steps={self.options.max_steps}{_runaway(self.problem, self.first, self.current)}",
                      "EP", {"reason": "max_steps"})
            return
        eng, cur, problem = self.stepper, self.current, self.problem
        while True:
            ds = self.control.ds
            new, iters, reason = eng.step(cur.z, cur.tangent, ds)
            if new is not None:
                angle = math.acos(min(1.0, max(-1.0, float(new.tangent @ cur.tangent))))
                if angle <= self.options.engine.max_angle:
                    break
                reason = f"tangent turned by {math.degrees(angle):.1f} deg"
            if not self.control.reject():
                msg = (f"step size fell below dsmin={self.options.dsmin:g}{_describe(problem, cur.x)}: {reason}; "
                       "the branch may end here (singular point) or need a smaller dsmin")
                self._end(Termination.STEP_UNDERFLOW, msg, "EP", {"reason": msg})
                return
        dz = new.z - cur.z
        step = math.sqrt(dz.dot(dz))
        new_values = [ev.value(problem, new) for ev in self.events]
        # started on a bound (to within the rounding of the start's scaled round trip, which can put it
        # an ulp outside) and this direction leaves the interval
        leaving = [ev for ev, v0, v1 in zip(self.events, self.values, new_values)
                   if ev.stop and abs(v0) <= _ON_BOUND * ev.scale and v1 < 0] if self.steps == 0 else None
        if leaving:
            self._end_on_bound(leaving[0])
            return
        hits, jumped = self._events_in_step(cur, ds, new_values)
        if jumped is not None:
            if not self.control.retry_short_of(jumped):
                self._end(Termination.BRANCHES_TOO_CLOSE,
                          f"branches too close to separate{_describe(problem, cur.x)}: a test function jumps "
                          "within dsmin; reduce dsmin", "EP")
            return
        hits.sort(key=lambda h: h[1][0])
        for ev, (sigma, st, info) in hits:
            if self.steps == 0 and sigma <= 1e-6 * ds:
                if ev.stop and new_values[self.events.index(ev)] < 0:  # the start lies on a bound (to within
                    # rounding) and this direction leaves it
                    self._end_on_bound(ev)
                    return
                continue  # the start itself is the special point (e.g. leaving a BP)
            if st is None:
                continue
            self._queue.append(RecordedPoint(st, ev.label, {**info, **ev.point_info()}, self.s + sigma))
            if ev.stop:
                what, why = self._queue[-1].info.get("bound_of"), self._queue[-1].info.get("reason")
                msg = (f"reached bound of {what}" if what else
                       f"stopped at the {why}" if why else f"stopped at {ev.label}")
                self._end(Termination.BOUND if what else Termination.STOP_EVENT, msg)
                return
        self.s += step
        self._queue.append(RecordedPoint(new, s=self.s))
        self.current, self.values = new, new_values
        self.steps += 1
        self.control.accept(iters)

    def _end_on_bound(self, ev: Event) -> None:
        """End the direction at its start: it lies on ``ev``'s bound and this direction leaves it."""
        self._end(Termination.START_ON_BOUND, f"start lies on the bound of {ev.name or ev.label}", ev.label,
                  {"bound_of": ev.name, **ev.point_info()})

    def _events_in_step(self, cur: PointState, ds: float,
                        new_values: list[float]) -> tuple[list[tuple[Event, Hit]], float | None]:
        """Events whose sign changes within the step, located and polished.

        Returns ``(hits, jumped)``: ``hits`` a list of ``(event, (sigma, state, info))``;
        ``jumped`` the step position of a continuous test function's jump (the corrector
        landed on another branch), else None.
        """
        eng, problem = self.stepper, self.problem
        hits: list[tuple[Event, Hit]] = []
        for ev, v0, v1 in zip(self.events, self.values, new_values):
            if v0 == 0 or v1 == 0 or (v0 > 0) == (v1 > 0):
                continue
            hit = ev.locate(eng, problem, cur, ds, v0, v1)
            if ev.continuous and (hit[1] is None or hit[2].get("status") != "located"
                                  or abs(ev.value(problem, hit[1])) > 1e-6 * max(abs(v0), abs(v1))):
                # the test function jumps instead of crossing zero: the corrector landed on
                # another branch. Retry with a step short of the discontinuity.
                return hits, hit[0]
            hits.append((ev, _refined(eng, problem, cur, ev, hit)))
        if not hits:  # the usual step: nothing crossed, so nothing crossed twice either
            return hits, None
        # An event crossed twice within the step (two close folds, or a bound the branch
        # leaves and re-enters) shows no sign change between the step's ends, but does at
        # a point located inside the step: look there too.
        for ev, v0 in zip(self.events, self.values):
            own = [h[1][0] for h in hits if h[0] is ev]
            if v0 == 0:
                continue
            for other, (sigma, st, _) in sorted(hits, key=lambda h: h[1][0]):
                if other is ev or (own and sigma >= min(own)):
                    continue
                v_mid = ev.value(problem, st) if st is not None else v0
                if v_mid != 0 and (v_mid > 0) != (v0 > 0) and sigma > 0:
                    hit = ev.locate(eng, problem, cur, sigma, v0, v_mid)
                    hits.append((ev, _refined(eng, problem, cur, ev, hit)))
                    break
        return hits, None


def _refined(eng: PseudoArclength, problem: ContinuationProblem, cur: PointState, ev: Event, hit: Hit) -> Hit:
    """``hit`` after the event's own polish (folds), with its step position recomputed.

    The polish can move a point well along the step when the located guess was rough, so
    ordering the step's events (a bound before a fold beyond it) must use the final point.
    """
    sigma, st, info = hit
    if st is None:
        return hit
    refined = ev.refine(problem, st)
    if refined is None:
        return hit
    u_ref, extra = refined
    st = eng.state(u_ref / eng.D, st.tangent)
    return float(cur.tangent @ (st.z - cur.z)), st, {**info, **extra}


@dataclass(frozen=True)
class DirectionResult:
    """Points of one continuation direction (start point first), row by row: ``states``, their number of
    unstable directions (``stability``, -1 when not computed), ``labels``, ``info`` (as
    :attr:`RecordedPoint.info`) and scaled ``arclength``; and how the direction ended."""

    states: tuple[PointState, ...]
    stability: tuple[int, ...]
    labels: tuple[str, ...]
    info: tuple[Mapping[str, Any], ...]
    arclength: tuple[float, ...]
    status: Status
    message: str
    termination: Termination


def run_direction(problem: ContinuationProblem, u0: np.ndarray, direction: int, options: ContinuationOptions, events: list[Event],
                  tangent0: np.ndarray | None = None, progress: Callable[[int], object] | None = None,
                  stability: bool = True) -> DirectionResult:
    """Continue from ``u0`` (a converged point) in one direction: the driver of :class:`BranchSteps`.

    ``direction`` +1 follows increasing continuation parameter initially, -1 decreasing.
    ``progress(k)`` is called with 1 after every accepted step. ``stability=False`` leaves
    the stability to the caller (-1 at every point; a caller joining two directions computes
    it in one batch). Returns a :class:`DirectionResult`; it always holds what was computed,
    with ``status`` / ``message`` / ``termination`` saying why it ended.
    """
    steps = BranchSteps(problem, u0, direction, options, events, tangent0)
    states: list[PointState] = []
    labels: list[str] = []
    info: list[Mapping[str, Any]] = []
    arclength: list[float] = []
    for point in steps:
        states.append(point.state)
        labels.append(point.label)
        info.append(point.info)
        arclength.append(point.s)
        if progress is not None and not point.label and point.s > 0:
            progress(1)
    # one batch for the whole direction: a point's stability plays no part in the stepping
    stab = (problem.stability_batch(np.array([st.u for st in states])) if options.stability and stability
            else [-1] * len(states))
    assert steps.termination is not None  # the iterator stops only after setting it
    if steps.end_label:
        labels[-1] = labels[-1] or steps.end_label
    if steps.end_info:
        info[-1] = {**info[-1], **steps.end_info}
    return DirectionResult(tuple(states), tuple(stab), tuple(labels), tuple(info), tuple(arclength),
                           steps.termination.status, steps.message, steps.termination)
