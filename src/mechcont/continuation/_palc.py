"""Pseudo-arclength continuation: the stepper and the driver.

The stepper works on any :class:`~._problem.ContinuationProblem` (equilibria, fold
curves); the driver runs it in one direction and collects points and special points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg.lapack import dgesv as _dgesv
from scipy.optimize import brentq

from ._events import Event, PointState
from ._newton import residual_met
from ._options import ContinuationOptions

__all__ = ["PseudoArclength", "DirectionResult", "run_direction"]


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
      where Newton in the parameter alone would fail;
    * **new tangent**: solve ``[G_z(z1); t0^T] t = e_(n+1)`` and normalise; bordering
      with the previous tangent keeps the orientation (``t0^T t1 > 0``) continuous through
      folds.

    A step is rejected and ``ds`` shrunk when Newton needs more than ``max_newton``
    iterations, when a correction does not contract by ``max_contraction`` (slow
    convergence is the sign of a corrector drifting to another branch), or when the
    tangent turns by more than ``max_angle``. That is how the stepper avoids jumping
    silently between close branches or across a sharp fold.
    """

    def __init__(self, problem, options: ContinuationOptions):
        self.problem = problem
        self.options = options
        self.D = np.asarray(problem.scale, dtype=float)
        self.n = len(self.D) - 1

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

    def state(self, z, tangent, jac=None) -> PointState:
        """The :class:`PointState` events see at ``z`` with unit ``tangent``."""
        u = z * self.D
        return PointState(z=z, u=u, tangent=tangent, jac=self.Gz(z) if jac is None else jac, x=self.problem.full(u))

    # -- tangent --------------------------------------------------------------------
    def initial_tangent(self, z, direction: int) -> np.ndarray:
        """Null vector of G_z at ``z`` oriented so the parameter increases (direction=+1)."""
        _, _, vt = np.linalg.svd(self.Gz(z))
        t = vt[-1]
        p = self.problem.param_index
        ref = t[p] if abs(t[p]) > 1e-12 else t[np.argmax(np.abs(t))]
        return t * (direction * np.sign(ref) or 1.0)

    def tangent(self, z, border, jac=None) -> np.ndarray:
        """Unit tangent at ``z`` from [G_z; border^T] t = e_(n+1), oriented along ``border``."""
        jac = self.Gz(z) if jac is None else jac
        A = np.empty((self.n + 1, self.n + 1))
        A[:-1] = jac
        A[-1] = border
        rhs = np.zeros(self.n + 1)
        rhs[-1] = 1.0
        _, _, t, info = _dgesv(A, rhs)
        if info != 0:
            raise np.linalg.LinAlgError("singular tangent system")
        t /= np.linalg.norm(t)
        return t if t @ border > 0 else -t

    # -- corrector --------------------------------------------------------------------
    def correct(self, z_pred, t0, z_start=None):
        """Newton on [G(z); t0.(z - z_pred)] = 0 from ``z_start`` (default ``z_pred``).

        Returns ``(z, jac, iterations)`` or ``(None, reason, iterations)``.
        """
        o = self.options
        z = np.array(z_pred if z_start is None else z_start, dtype=float)
        A = np.empty((self.n + 1, self.n + 1))
        A[-1] = t0
        b = np.empty(self.n + 1)
        prev = step = math.inf
        for it in range(1, o.max_newton + 2):
            r, jac = self.evaluate(z)
            if not (math.isfinite(r.sum()) and math.isfinite(jac.sum())):
                return None, "residual not finite (outside the model's domain)", it
            if step < o.newton_tol and residual_met(r, jac, z, o.residual_tol):
                return z, jac, it - 1
            if it > o.max_newton:
                break
            A[:-1] = jac
            b[:-1] = -r
            b[-1] = -(t0 @ (z - z_pred))
            _, _, dz, info = _dgesv(A, b)
            if info != 0:
                return None, "singular bordered Jacobian", it
            z = z + dz
            step = np.abs(dz).max()
            if step > o.max_contraction * prev and step > 1e3 * o.newton_tol:
                return None, "corrector converging too slowly", it
            prev = step
        return None, f"corrector needed more than {o.max_newton} iterations", o.max_newton

    def point_at(self, z0, t0, sigma):
        """The branch point on the hyperplane at distance ``sigma`` along ``t0`` from ``z0``."""
        z, jac, _ = self.correct(z0 + sigma * t0, t0)
        if z is None:
            raise RuntimeError(jac)
        return self.state(z, self.tangent(z, t0, jac), jac)


@dataclass
class DirectionResult:
    """Points of one continuation direction (start point first)."""

    states: list = field(default_factory=list)
    stability: list = field(default_factory=list)
    labels: list = field(default_factory=list)
    info: list = field(default_factory=list)
    arclength: list = field(default_factory=list)
    status: str = "completed"
    message: str = ""


def _describe(problem, x) -> str:
    names = getattr(problem, "names", ())
    idx = getattr(problem, "idx", None)
    if idx is None:
        return ""
    shown = [f"{n}={x[i]:.6g}" for n, i in list(zip(names, idx))[-3:]]
    return " at " + ", ".join(shown)


def run_direction(problem, u0: np.ndarray, direction: int, options: ContinuationOptions, events: list[Event],
                  tangent0: np.ndarray | None = None, progress=None) -> DirectionResult:
    """Continue from ``u0`` (a converged point) in one direction.

    ``direction`` +1 follows increasing continuation parameter initially, -1 decreasing.
    Returns a :class:`DirectionResult`; it always holds what was computed, with
    ``status``/``message`` saying why it ended.
    """
    eng = PseudoArclength(problem, options)
    z = np.asarray(u0, float) / eng.D
    t = eng.initial_tangent(z, direction) if tangent0 is None else direction * np.asarray(tangent0, float)
    cur = eng.state(z, t)
    res = DirectionResult()

    def record(st: PointState, label="", info=None, s=0.0):
        res.states.append(st)
        res.stability.append(problem.stability(st.u) if options.stability else -1)
        res.labels.append(label)
        res.info.append(info or {})
        res.arclength.append(s)

    record(cur)
    values = [ev.value(problem, cur) for ev in events]
    ds = options.ds
    s = 0.0
    for _ in range(options.max_steps):
        while True:
            z1, jac, iters = eng.correct(cur.z + ds * cur.tangent, cur.tangent)
            if z1 is not None:
                try:
                    t1 = eng.tangent(z1, cur.tangent, jac)
                except np.linalg.LinAlgError:
                    reason = "singular tangent system"
                else:
                    angle = math.acos(min(1.0, max(-1.0, float(t1 @ cur.tangent))))
                    if angle <= options.max_angle:
                        break
                    reason = f"tangent turned by {math.degrees(angle):.1f} deg"
            else:
                reason = jac
            ds *= options.shrink
            if ds < options.dsmin:
                res.status = "step size underflow"
                res.message = (f"step size fell below dsmin={options.dsmin:g}{_describe(problem, cur.x)}: {reason}; "
                               "the branch may end here (singular point) or need a smaller dsmin")
                res.labels[-1] = res.labels[-1] or "EP"
                res.info[-1] = {**res.info[-1], "reason": res.message}
                return res
        new = eng.state(z1, t1, jac)
        step = float(np.linalg.norm(z1 - cur.z))
        new_values = [ev.value(problem, new) for ev in events]
        leaving = [ev for ev, v0, v1 in zip(events, values, new_values) if ev.stop and v0 == 0 and v1 < 0]
        if leaving:  # started exactly on a bound and this direction leaves the interval
            res.labels[-1] = leaving[0].label
            res.info[-1] = {**res.info[-1], "bound_of": getattr(leaving[0], "name", ""), **leaving[0].point_info()}
            res.message = f"start lies on the bound of {getattr(leaving[0], 'name', leaving[0].label)}"
            return res
        hits = []
        jumped = None
        for ev, v0, v1 in zip(events, values, new_values):
            if v0 == 0 or v1 == 0 or (v0 > 0) == (v1 > 0):
                continue
            hit = _locate(eng, problem, cur, ds, ev, v0, v1)
            if ev.continuous and (hit[1] is None or abs(ev.value(problem, hit[1])) > 1e-6 * max(abs(v0), abs(v1))):
                # the test function jumps instead of crossing zero: the corrector landed on
                # another branch. Retry with a step short of the discontinuity.
                jumped = hit[0]
                break
            hits.append((ev, _refined(eng, problem, cur, ev, hit)))
        if jumped is None:
            # An event crossed twice within the step (two close folds, or a bound the
            # branch leaves and re-enters) shows no sign change between the step's ends,
            # but does at a point located inside the step: look there too.
            for ev, v0 in zip(events, values):
                own = [h[1][0] for h in hits if h[0] is ev]
                if v0 == 0:
                    continue
                for other, (sigma, st, _) in sorted(hits, key=lambda h: h[1][0]):
                    if other is ev or (own and sigma >= min(own)):
                        continue
                    v_mid = ev.value(problem, st) if st is not None else v0
                    if v_mid != 0 and (v_mid > 0) != (v0 > 0) and sigma > 0:
                        hit = _locate(eng, problem, cur, sigma, ev, v0, v_mid)
                        hits.append((ev, _refined(eng, problem, cur, ev, hit)))
                        break
        if jumped is not None:
            ds = max(0.5 * jumped, options.shrink * options.dsmin)
            if ds < options.dsmin:
                res.status = "step size underflow"
                res.message = (f"branches too close to separate{_describe(problem, cur.x)}: a test function jumps "
                               "within dsmin; reduce dsmin")
                res.labels[-1] = res.labels[-1] or "EP"
                return res
            continue
        hits.sort(key=lambda h: h[1][0])
        stop = False
        for ev, (sigma, st, info) in hits:
            if len(res.states) == 1 and sigma <= 1e-6 * ds:
                continue  # the start itself is the special point (e.g. leaving a BP)
            if st is None:
                continue
            record(st, ev.label, {**info, **ev.point_info()}, s + sigma)
            if ev.stop:
                stop = True
                break
        if stop:
            res.status = "completed"
            what, why = res.info[-1].get("bound_of"), res.info[-1].get("reason")
            res.message = f"reached bound of {what}" if what else (f"stopped at the {why}" if why else
                                                                    f"stopped at {res.labels[-1]}")
            return res
        s += step
        record(new, s=s)
        cur, values = new, new_values
        if progress is not None:
            progress(1)
        if iters <= 3:
            ds = min(ds * options.grow, options.dsmax)
        elif iters >= 6:
            ds = max(ds * options.shrink, options.dsmin)
    res.labels[-1] = res.labels[-1] or "EP"
    res.info[-1] = {**res.info[-1], "reason": "max_steps"}
    res.status = "completed"
    res.message = f"stopped after max_steps={options.max_steps}"
    return res


def _refined(eng: PseudoArclength, problem, cur: PointState, ev: Event, hit):
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


def _locate(eng: PseudoArclength, problem, cur: PointState, ds: float, ev: Event, v0: float, v1: float):
    """Zero of ``ev`` between ``cur`` (sigma=0) and the accepted step (sigma=ds).

    Returns ``(sigma, state, info)``; ``state`` is None when location failed.
    """
    from ._events import BoundEvent

    info = {"status": "located"}
    if isinstance(ev, BoundEvent):
        info.update(bound_of=ev.name, bound=ev.bound)
        st = _solve_on_bound(eng, problem, cur, ds, ev, v0, v1)
        if st is not None:
            return float(cur.tangent @ (st.z - cur.z)), st, info
    elif type(ev).refine is not Event.refine:
        # events polished afterwards (folds): a secant guess is close enough for the polish
        sigma = ds * v0 / (v0 - v1)
        try:
            return sigma, eng.point_at(cur.z, cur.tangent, sigma), {"status": "approximate"}
        except (RuntimeError, np.linalg.LinAlgError):
            pass
    cache = {}

    def f(sigma):
        st = eng.point_at(cur.z, cur.tangent, sigma)
        cache[sigma] = st
        return ev.value(problem, st)

    try:
        sigma = brentq(f, 0.0, ds, xtol=1e-14 * max(1.0, ds), rtol=8.9e-16, maxiter=100)
        st = cache.get(sigma) or eng.point_at(cur.z, cur.tangent, sigma)
    except (RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
        # not located: keep the event, at the secant estimate, marked as approximate
        sigma = ds * v0 / (v0 - v1)
        try:
            st = eng.point_at(cur.z, cur.tangent, sigma)
        except (RuntimeError, np.linalg.LinAlgError):
            return ds, None, {"status": "approximate", "reason": str(exc)}
        return sigma, st, {"status": "approximate", "reason": f"not located: {exc}"}
    return sigma, st, info


def _solve_on_bound(eng: PseudoArclength, problem, cur: PointState, ds, ev, v0, v1):
    """The branch point where a bounded unknown equals its bound: Newton on [G; x_k - b]."""
    idx = getattr(problem, "idx", None)
    if idx is None or ev.index not in idx:
        return None
    k = int(np.flatnonzero(idx == ev.index)[0])
    z = cur.z + (ds * v0 / (v0 - v1)) * cur.tangent
    target = ev.bound / eng.D[k]
    A = np.zeros((eng.n + 1, eng.n + 1))
    A[-1, k] = 1.0
    b = np.empty(eng.n + 1)
    for _ in range(eng.options.max_newton + 2):
        r, jac = eng.evaluate(z)
        if not math.isfinite(r.sum()):
            return None
        b[:-1] = -r
        b[-1] = target - z[k]
        if residual_met(r, jac, z, eng.options.residual_tol) and abs(b[-1]) < 1e-15 * max(1.0, abs(target)):
            return eng.state(z, eng.tangent(z, cur.tangent, jac), jac)
        A[:-1] = jac
        _, _, dz, info = _dgesv(A, b)
        if info != 0:
            return None
        z = z + dz
        if np.abs(dz).max() < eng.options.newton_tol:
            z[k] = target
    return None
