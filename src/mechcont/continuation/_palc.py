"""Pseudo-arclength continuation: the stepper, its step-size control, and a thin driver.

:class:`PseudoArclength` holds the maths (predictor, corrector, tangent) on any
:class:`~._problem.ContinuationProblem` (equilibria, fold curves). :class:`BranchSteps`
is an iterator over the points of one direction: each ``next()`` takes one accepted step,
locates the events inside it, and yields the points to record. :func:`run_direction` is
the driver that collects them. Why a direction ended is a :class:`Termination`.
"""

from __future__ import annotations

import math
import signal
from collections.abc import Iterator
from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from .. import _dense
from .._signals import stopping
from .._status import Status
from . import _kernel
from ._events import Event, PointState, branch_point_test
from ._linalg import DenseLU
from ._newton import residual_met, step_noise
from ._options import ContinuationOptions
from ._problem import ContinuationProblem

_add, _max = np.add.reduce, np.maximum.reduce
# why a correction failed, in the same words from both correctors
_NOT_FINITE = "residual not finite (outside the model's domain)"
_SINGULAR = "singular bordered Jacobian"
_TOO_SLOW = "corrector converging too slowly"
_SINGULAR_TANGENT = "singular tangent system"
_WORDS = {"not_finite": _NOT_FINITE, "singular": _SINGULAR, "too_slow": _TOO_SLOW, "singular_tangent": _SINGULAR_TANGENT}


def _too_many(max_newton: int) -> str:
    return f"corrector needed more than {max_newton} iterations"

__all__ = ["PseudoArclength", "StepSizeController", "Termination", "BranchSteps", "RecordedPoint",
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


class PseudoArclength:
    r"""Pseudo-arclength predictor–corrector on a scaled problem.

    Let ``G: R^(n+1) -> R^n`` and ``z = u / D`` the unknowns divided by their typical
    magnitudes ``D`` (so that a newton and a radian weigh alike); ``G_z = G_u D``.
    From a point ``z0`` with unit tangent ``t0`` (``G_z(z0) t0 = 0``, ``|t0| = 1``):

    * **predictor**: ``z_p = z0 + ds t0``;
    * **corrector**: Newton on the bordered system

      .. math::  G(z) = 0, \qquad t_0^T (z - z_p) = 0,

      i.e. iterations ``[G_z; t0^T] dz = -[G; t0^T (z - z_p)]``. The hyperplane through
      the predictor orthogonal to ``t0`` cuts the branch transversally even at a fold,
      where Newton in the parameter alone would fail. It has converged when the distance
      to the solution is below ``newton_tol``, either because a correction is that small
      (the corrected point is returned unevaluated, with the Jacobian of the point the
      correction was computed at: Newton's linear model makes its residual of the order of
      the correction squared, and the Jacobians differ by terms of the order of the
      correction), or because the residuals pass :func:`~._newton.residual_met` and the
      contraction ``q = |dz_k| / |dz_(k-1)| < 1`` of the last two corrections bounds the
      distance by ``q / (1 - q) |dz_k|``. Both save the last, confirming evaluation of a
      quadratically converging Newton. On an ill-conditioned system (a joint compliance of
      1e10 N/m) the corrections stall at the noise that rounding of the residual causes
      (:func:`~._newton.step_noise`); a point whose residuals pass and whose correction has
      stopped contracting at that noise level is converged too. There the unknowns that
      enter linearly (the self-stress of a stiff compliant loop, set by the misfit the
      predictor leaves) also lag the geometry by one iteration: one correction that does not
      shrink is allowed when the residual fell tenfold with it;
    * **new tangent**: solve ``[G_z(z1); t0^T] t = e_(n+1)`` and normalise; bordering
      with the previous tangent keeps the orientation (``t0^T t1 > 0``) continuous through
      folds.

    A step is rejected and ``ds`` shrunk when Newton needs more than ``max_newton``
    iterations, when a correction does not contract by ``max_contraction`` (slow
    convergence is the sign of a corrector drifting to another branch), or when the
    tangent turns by more than ``max_angle``. That is how the stepper avoids jumping
    silently between close branches or across a sharp fold. The bordered systems are
    solved by ``options.linear_solver``.
    """

    def __init__(self, problem: ContinuationProblem, options: ContinuationOptions):
        self.problem = problem
        self.options = options
        self.solver = options.linear_solver
        # the default solver called without its method's frame; it leaves its arguments unchanged,
        # so the tangent's right-hand side and matrix need no fresh copies per point
        self._dense = type(self.solver) is DenseLU
        self._solve = _dense.solve if self._dense else self.solver.solve
        self._raw = self._dense and _dense.RAW_SOLVE  # its unchecked kernel (see correct)
        self.D = np.asarray(problem.scale, dtype=float)
        self.n = len(self.D) - 1
        self._e_last = np.zeros(self.n + 1)  # right-hand side of the tangent system
        self._e_last[-1] = 1.0
        self._A_tangent = np.empty((self.n + 1, self.n + 1))
        #: the compiled corrector (:mod:`._kernel`) where it applies: one call per step
        self.kernel = _kernel.bordered_newton(problem, self.D, options)

    # -- evaluation in scaled coordinates -----------------------------------------------
    def G(self, z):
        """Residual at the scaled point ``z``."""
        return self.problem.residual(z * self.D)

    def Gz(self, z):
        """Jacobian with respect to the scaled unknowns, dG/dz = dG/du D."""
        return self.problem.jacobian(z * self.D) * self.D

    def evaluate(self, z):
        """Residual and scaled Jacobian at ``z`` in one model evaluation."""
        r, J = self.problem.evaluate(z * self.D)
        return r, J * self.D

    def state(self, z, tangent, jac=None, bp_test: float | None = None) -> PointState:
        """The :class:`PointState` events see at ``z`` with unit ``tangent`` (``bp_test``: the
        branch-point test function when already known)."""
        u = z * self.D
        return PointState(z=z, u=u, tangent=tangent, jac=self.Gz(z) if jac is None else jac, x=self.problem.full(u),
                          bp_test=bp_test)

    def step(self, z0, t0, sigma, z_start=None):
        """Predict ``z0 + sigma t0``, correct (from ``z_start`` if given) and take the new tangent.

        Returns ``(state, iterations, "")`` with the new point's :class:`PointState`, or
        ``(None, iterations, reason)`` when the corrector or the tangent fails. The compiled
        corrector takes the whole step in one call where it applies (:mod:`._kernel`).
        """
        if self.kernel is not None:
            code, iters, z, jac, t, sign, logdet = self.kernel.step(z0, t0, sigma, z_start)
            if code:
                return None, iters, _WORDS.get(_kernel.CODE_NAMES[code], _too_many(self.options.max_newton))
            # BranchPointEvent's value from the tangent system's factors
            return self.state(z, t, jac, branch_point_test(sign, logdet, len(z))), iters, ""
        z, jac, iters = self.correct(z0 + sigma * t0, t0, z_start)
        if z is None:
            return None, iters, jac
        try:
            t = self.tangent(z, t0, jac)
        except np.linalg.LinAlgError:
            return None, iters, _SINGULAR_TANGENT
        return self.state(z, t, jac), iters, ""

    # -- tangent --------------------------------------------------------------------
    def initial_tangent(self, z, direction: int) -> np.ndarray:
        """Null vector of G_z at ``z`` oriented so the parameter increases (direction=+1)."""
        _, _, vt = _dense.svd(self.Gz(z))
        t = vt[-1]
        p = self.problem.param_index
        ref = t[p] if abs(t[p]) > 1e-12 else t[np.argmax(np.abs(t))]
        return t * (direction * np.sign(ref) or 1.0)

    def tangent(self, z, border, jac=None) -> np.ndarray:
        """Unit tangent at ``z`` from [G_z; border^T] t = e_(n+1), oriented along ``border``."""
        jac = self.Gz(z) if jac is None else jac
        A = self._A_tangent if self._dense else np.empty((self.n + 1, self.n + 1))
        A[:-1] = jac
        A[-1] = border
        t: np.ndarray | None
        if self._raw:
            with _dense.quiet():
                t = _dense.solve_raw(A, self._e_last)
        else:
            t = self._solve(A, self._e_last if self._dense else self._e_last.copy())
        norm = math.sqrt(t.dot(t)) if t is not None else math.nan  # = np.linalg.norm(t), without its overhead
        if t is None or not math.isfinite(norm):  # NaN: an exact zero pivot
            raise np.linalg.LinAlgError(_SINGULAR_TANGENT)
        t /= norm
        return t if t @ border > 0 else -t

    # -- corrector --------------------------------------------------------------------
    def correct(self, z_pred, t0, z_start=None):
        """Newton on [G(z); t0.(z - z_pred)] = 0 from ``z_start`` (default ``z_pred``).

        Returns ``(z, jac, iterations)`` or ``(None, reason, iterations)``; a lagging
        correction (see the class docstring) is not counted: the step control judges the
        geometry's convergence.
        """
        if self._raw:  # the error state entered once, not per solve
            with _dense.quiet():
                return self._correct(z_pred, t0, z_start, _dense.solve_raw)
        return self._correct(z_pred, t0, z_start, self._solve)

    def _correct(self, z_pred, t0, z_start, solve):
        o = self.options
        tol, D, evaluate = o.newton_tol, self.D, self.problem.evaluate
        z = np.array(z_pred if z_start is None else z_start, dtype=float)
        A = np.empty((self.n + 1, self.n + 1))
        A[-1] = t0
        jac = A[:-1]  # the scaled Jacobian is written straight into the bordered matrix
        b = np.empty(self.n + 1)
        b_residual = b[:-1]
        prev = error = math.inf
        lag, r_prev = True, None
        for it in range(1, o.max_newton + 2):
            r, J = evaluate(z * D)
            np.multiply(J, D, out=jac)
            # a non-finite residual is not tested here: it makes the correction non-finite (below),
            # and the residual tests that come first (residual_met) fail on it
            if error < tol and residual_met(r, jac, z, o.residual_tol):  # (a small step returned below)
                return (z, jac.copy(), it - 1 - (not lag)) if math.isfinite(_add(jac, None)) else (None, _NOT_FINITE, it)
            if it > o.max_newton:
                if not math.isfinite(_add(r, None)):
                    return None, _NOT_FINITE, it
                break
            np.negative(r, out=b_residual)
            # the hyperplane's row: z = z_pred at first; from a z_start, the first correction lands on
            # the hyperplane, and the later ones move within it (t0.dz = 0 up to rounding)
            b[-1] = -(t0 @ (z - z_pred)) if it == 1 and z_start is not None else 0.0
            dz = solve(A, b)
            step = _max(np.abs(dz), None) if dz is not None else math.nan
            if not math.isfinite(step):
                # np.add.reduce(a, None) is a.sum() without the method's Python frame (same bits)
                if not (math.isfinite(_add(r, None)) and math.isfinite(_add(jac, None))):
                    return None, _NOT_FINITE, it
                return None, _SINGULAR, it  # an exact zero pivot
            if step < tol:
                # converged without evaluating z + dz: Newton's linear model makes its residual
                # of order |dz|^2 (r + G_z dz = 0), and its Jacobian differs from the one
                # returned by terms of order |dz| < newton_tol
                return (z + dz, jac.copy(), it - (not lag)) if math.isfinite(_add(jac, None)) else (None, _NOT_FINITE, it)
            if step > o.max_contraction * prev:  # not contracting (always false at the first iteration)
                if residual_met(r, jac, z, o.residual_tol) and step <= 10 * step_noise(solve, A, jac, z):
                    # stalled at the rounding floor of an ill-conditioned system (a stiff compliance):
                    # z is as converged as double precision allows, the correction is noise
                    return (z, jac.copy(), it - (not lag)) if math.isfinite(_add(jac, None)) else (None, _NOT_FINITE, it)
                if lag and _max(np.abs(r), None) <= 0.1 * _max(np.abs(r_prev), None):
                    # the residual fell tenfold while the correction did not shrink: unknowns that
                    # enter the equations linearly (the self-stress of a stiff compliant loop) follow
                    # the geometry's correction one iteration late; allowed once per correction
                    lag = False
                    step = math.inf  # a lagging correction bounds nothing: no contraction estimate from it
                elif step > 1e3 * tol:
                    return None, _TOO_SLOW, it
            z, r_prev = z + dz, r
            if prev < math.inf:
                # the distance left to the solution, from the observed contraction q of the
                # last two corrections: |z - z*| <= q / (1 - q) |dz| (Deuflhard); Newton's
                # quadratic convergence makes it an overestimate
                q = step / prev
                error = q / (1.0 - q) * step if q < 1.0 else math.inf  # no bound unless contracting
            prev = step
        return None, _too_many(o.max_newton), o.max_newton

    def point_at(self, z0, t0, sigma, z_start=None):
        """The branch point on the hyperplane at distance ``sigma`` along ``t0`` from ``z0``
        (Newton starts at ``z_start``, by default the predictor ``z0 + sigma t0``)."""
        st, _, why = self.step(z0, t0, sigma, z_start)
        if st is None:
            raise np.linalg.LinAlgError(why) if why == _SINGULAR_TANGENT else RuntimeError(why)
        return st


class StepSizeController:
    """AUTO-style step control: grow after an easy step, shrink after a hard or rejected one.

    ``ds`` starts at ``options.ds``; a step whose corrector took at most 3 iterations
    multiplies it by ``grow`` (up to ``dsmax``), one that took 6 or more by ``shrink``
    (down to ``dsmin``); a rejected step multiplies it by ``shrink`` and :meth:`reject`
    returns False once it falls below ``dsmin``.
    """

    def __init__(self, options: ContinuationOptions):
        self.options = options
        self.ds = options.ds

    def reject(self) -> bool:
        """Shrink after a rejected step; False when the step fell below ``dsmin``."""
        self.ds *= self.options.shrink
        return self.ds >= self.options.dsmin

    def retry_short_of(self, sigma: float) -> bool:
        """Retry with half the distance to a discontinuity at ``sigma``; False below ``dsmin``."""
        o = self.options
        self.ds = max(0.5 * sigma, o.shrink * o.dsmin)
        return self.ds >= o.dsmin

    def accept(self, iterations: int) -> None:
        """Adapt after an accepted step whose corrector took ``iterations``."""
        o = self.options
        if iterations <= 3:
            self.ds = min(self.ds * o.grow, o.dsmax)
        elif iterations >= 6:
            self.ds = max(self.ds * o.shrink, o.dsmin)


@dataclass
class RecordedPoint:
    """A point of a branch as the iterator yields it: state, label, info, arclength."""

    state: PointState
    label: str = ""
    info: dict = field(default_factory=dict)
    s: float = 0.0


def _describe(problem: ContinuationProblem, x) -> str:
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
            f"give bounds (--bounds {names[k]}=LO:HI, or ContinuationOptions(bounds=...))")


class BranchSteps(Iterator[RecordedPoint]):
    """The points of one continuation direction, one accepted step at a time.

    Iterating yields :class:`RecordedPoint` objects: the start point first, then for each
    accepted step the special points located inside it (in arclength order) and the step's
    end point. When the direction ends, :attr:`termination` says why, :attr:`message`
    explains it, and :attr:`end_label` / :attr:`end_info` are what the last yielded point
    should be labelled with (``EP`` at ``max_steps`` or a step-size underflow).
    """

    def __init__(self, problem: ContinuationProblem, u0: np.ndarray, direction: int, options: ContinuationOptions,
                 events: list[Event], tangent0: np.ndarray | None = None):
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
        self.end_info: dict = {}
        self._queue: list[RecordedPoint] = [RecordedPoint(self.current)]

    def __next__(self) -> RecordedPoint:
        while not self._queue:
            if self.termination is not None:
                raise StopIteration
            self._step()
        return self._queue.pop(0)

    # -- one accepted step ------------------------------------------------------------
    def _end(self, how: Termination, message: str, label: str = "", info: dict | None = None) -> None:
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
                if angle <= self.options.max_angle:
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

    def _events_in_step(self, cur: PointState, ds: float, new_values: list[float]):
        """Events whose sign changes within the step, located and polished.

        Returns ``(hits, jumped)``: ``hits`` a list of ``(event, (sigma, state, info))``;
        ``jumped`` the step position of a continuous test function's jump (the corrector
        landed on another branch), else None.
        """
        eng, problem = self.stepper, self.problem
        hits: list = []
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


def _refined(eng: PseudoArclength, problem: ContinuationProblem, cur: PointState, ev: Event, hit):
    """``hit`` after the event's own polish (folds), with its step position recomputed.

    The polish can move a point well along the step when the located guess was rough, so
    ordering the step's events (a bound before a fold beyond it) must use the final point.
    """
    sigma, st, info = hit
    refined = ev.refine(problem, st) if st is not None else None
    if refined is None:
        return hit
    u_ref, extra = refined
    st = eng.state(u_ref / eng.D, st.tangent)
    return float(cur.tangent @ (st.z - cur.z)), st, {**info, **extra}


@dataclass
class DirectionResult:
    """Points of one continuation direction (start point first)."""

    states: list = field(default_factory=list)
    stability: list = field(default_factory=list)
    labels: list = field(default_factory=list)
    info: list = field(default_factory=list)
    arclength: list = field(default_factory=list)
    status: Status = Status.COMPLETED
    message: str = ""
    termination: Termination | None = None


def run_direction(problem: ContinuationProblem, u0: np.ndarray, direction: int, options: ContinuationOptions, events: list[Event],
                  tangent0: np.ndarray | None = None, progress=None, stability: bool = True) -> DirectionResult:
    """Continue from ``u0`` (a converged point) in one direction: the driver of :class:`BranchSteps`.

    ``direction`` +1 follows increasing continuation parameter initially, -1 decreasing.
    ``progress(k)`` is called with 1 after every accepted step. ``stability=False`` leaves
    the stability to the caller (-1 at every point; a caller joining two directions computes
    it in one batch). Returns a :class:`DirectionResult`; it always holds what was computed,
    with ``status`` / ``message`` / ``termination`` saying why it ended.
    """
    steps = BranchSteps(problem, u0, direction, options, events, tangent0)
    res = DirectionResult()
    for point in steps:
        res.states.append(point.state)
        res.labels.append(point.label)
        res.info.append(point.info)
        res.arclength.append(point.s)
        if progress is not None and not point.label and point.s > 0:
            progress(1)
    # one batch for the whole direction: a point's stability plays no part in the stepping
    res.stability = (problem.stability_batch(np.array([st.u for st in res.states])) if options.stability and stability
                     else [-1] * len(res.states))
    assert steps.termination is not None  # the iterator stops only after setting it
    res.termination = steps.termination
    res.status = steps.termination.status
    res.message = steps.message
    if steps.end_label:
        res.labels[-1] = res.labels[-1] or steps.end_label
    if steps.end_info:
        res.info[-1] = {**res.info[-1], **steps.end_info}
    return res
