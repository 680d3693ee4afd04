"""The pseudo-arclength stepper's maths: predictor, bordered Newton corrector and tangent (:class:`PseudoArclength`).

Apart from :mod:`._palc` (which walks a direction: step-size control, events, why it ended) because this
is the numerical kernel on one step, shared with event location (:mod:`._events`) and mirrored by the
compiled corrector (:mod:`._kernel`), while the walk around it is bookkeeping; each changes for its own
reasons. The corrector's failure words are here: both correctors report them.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .. import _dense
from .._status import Status
from . import _kernel
from ._events import PointState, branch_point_test
from ._linalg import DenseLU
from ._newton import residual_met, step_noise
from ._options import ContinuationOptions
from ._problem import ContinuationProblem

__all__ = ["PseudoArclength"]

_add, _max = np.add.reduce, np.maximum.reduce
# why a correction failed, in the same words from both correctors
_NOT_FINITE, _SINGULAR, _TOO_SLOW = Status.NOT_FINITE, Status.SINGULAR, Status.TOO_SLOW
_SINGULAR_TANGENT = Status.SINGULAR_TANGENT
_WORDS = {"not_finite": _NOT_FINITE, "singular": _SINGULAR, "too_slow": _TOO_SLOW, "singular_tangent": _SINGULAR_TANGENT}


#: What the corrector returns: ``(z, scaled Jacobian, iterations)``, or ``(None, why it failed, iterations)``
Correction = tuple[np.ndarray, np.ndarray, int] | tuple[None, str, int]


def _too_many(max_newton: int) -> str:
    return f"corrector needed more than {max_newton} iterations"


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

    def __init__(self, problem: ContinuationProblem, options: ContinuationOptions) -> None:
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
    def G(self, z: np.ndarray) -> np.ndarray:
        """Residual at the scaled point ``z``."""
        return self.problem.residual(z * self.D)

    def Gz(self, z: np.ndarray) -> np.ndarray:
        """Jacobian with respect to the scaled unknowns, dG/dz = dG/du D."""
        return self.problem.jacobian(z * self.D) * self.D

    def evaluate(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Residual and scaled Jacobian at ``z`` in one model evaluation."""
        r, J = self.problem.evaluate(z * self.D)
        return r, J * self.D

    def state(self, z: np.ndarray, tangent: np.ndarray, jac: np.ndarray | None = None,
              bp_test: float | None = None) -> PointState:
        """The :class:`PointState` events see at ``z`` with unit ``tangent`` (``bp_test``: the
        branch-point test function when already known)."""
        u = z * self.D
        return PointState(z=z, u=u, tangent=tangent, jac=self.Gz(z) if jac is None else jac, x=self.problem.full(u),
                          bp_test=bp_test)

    def step(self, z0: np.ndarray, t0: np.ndarray, sigma: float,
             z_start: np.ndarray | None = None) -> tuple[PointState | None, int, str]:
        """Predict ``z0 + sigma t0``, correct (from ``z_start`` if given) and take the new tangent.

        Returns ``(state, iterations, "")`` with the new point's :class:`PointState`, or
        ``(None, iterations, reason)`` when the corrector or the tangent fails. The compiled
        corrector takes the whole step in one call where it applies (:mod:`._kernel`).
        """
        if self.kernel is not None:
            out = self.kernel.step(z0, t0, sigma, z_start)
            if out[2] is None:  # a non-zero code: no arrays
                return None, out[1], _WORDS.get(_kernel.CODE_NAMES[out[0]], _too_many(self.options.engine.max_newton))
            _, iters, z, jac, t, sign, logdet = out
            # BranchPointEvent's value from the tangent system's factors
            return self.state(z, t, jac, branch_point_test(sign, logdet, len(z))), iters, ""
        corrected = self.correct(z0 + sigma * t0, t0, z_start)
        if corrected[0] is None:
            return None, corrected[2], corrected[1]
        z, jac, iters = corrected
        try:
            t = self.tangent(z, t0, jac)
        except np.linalg.LinAlgError:
            return None, iters, _SINGULAR_TANGENT
        return self.state(z, t, jac), iters, ""

    # -- tangent --------------------------------------------------------------------
    def initial_tangent(self, z: np.ndarray, direction: int) -> np.ndarray:
        """Null vector of G_z at ``z`` oriented so the parameter increases (direction=+1)."""
        _, _, vt = _dense.svd(self.Gz(z))
        t = vt[-1]
        p = self.problem.param_index
        ref = t[p] if abs(t[p]) > 1e-12 else t[np.argmax(np.abs(t))]
        return t * (direction * np.sign(ref) or 1.0)

    def tangent(self, z: np.ndarray, border: np.ndarray, jac: np.ndarray | None = None) -> np.ndarray:
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
    def correct(self, z_pred: np.ndarray, t0: np.ndarray, z_start: np.ndarray | None = None) -> Correction:
        """Newton on [G(z); t0.(z - z_pred)] = 0 from ``z_start`` (default ``z_pred``).

        Returns ``(z, jac, iterations)`` or ``(None, reason, iterations)``; a lagging
        correction (see the class docstring) is not counted: the step control judges the
        geometry's convergence.
        """
        if self._raw:  # the error state entered once, not per solve
            with _dense.quiet():
                return self._correct(z_pred, t0, z_start, _dense.solve_raw)
        return self._correct(z_pred, t0, z_start, self._solve)

    def _correct(self, z_pred: np.ndarray, t0: np.ndarray, z_start: np.ndarray | None,
                 solve: Callable[[np.ndarray, np.ndarray], np.ndarray | None]) -> Correction:
        o = self.options.engine
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
                if lag and r_prev is not None and _max(np.abs(r), None) <= 0.1 * _max(np.abs(r_prev), None):
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

    def point_at(self, z0: np.ndarray, t0: np.ndarray, sigma: float, z_start: np.ndarray | None = None) -> PointState:
        """The branch point on the hyperplane at distance ``sigma`` along ``t0`` from ``z0``
        (Newton starts at ``z_start``, by default the predictor ``z0 + sigma t0``)."""
        st, _, why = self.step(z0, t0, sigma, z_start)
        if st is None:
            raise np.linalg.LinAlgError(why) if why == _SINGULAR_TANGENT else RuntimeError(why)
        return st
