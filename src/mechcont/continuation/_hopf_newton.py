"""Newton on the minimally extended Hopf system ``G(u) = 0, g(u) = lambda_1 + lambda_2 = 0``: :func:`polish_hopf`.

Two ways to a step, the same step to rounding:

* an ODE model's equilibrium problem (:meth:`HopfTest.state_positions`): the linearisation is the Jacobian's state
  columns, already evaluated with the residual, and ``g``'s whole gradient costs one call of the generated second
  derivatives (:meth:`HopfTest.gradient`), so the step is one solve of the square ``(n + 1)`` system;
* any other (a mechanism's): bordered, ``dz = dz0 + t phi`` with ``phi`` the null vector of ``G``'s Jacobian and
  ``dz0`` its least-norm step, ``t`` from ``g``'s slope along those two directions only
  (:meth:`HopfTest.pair_and_derivatives`: two differenced linearisations each, where the gradient takes two per
  unknown).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .. import _dense
from ..errors import ConvergenceError
from ._hopf_plane import CriticalPair, critical_pair
from ._problem import ContinuationProblem

if TYPE_CHECKING:
    from ._hopf_point import HopfTest

__all__ = ["polish_hopf"]

#: Newton on the Hopf system stops where the step (in the problem's scaled unknowns) is below this times
#: max(1, |z|): the located point is then within that of the solution
_NEWTON_TOL = 1e-14


def polish_hopf(test: HopfTest, problem: ContinuationProblem, u0: np.ndarray,
                max_iter: int = 30) -> tuple[np.ndarray, CriticalPair, float]:
    """Newton on ``G(u) = 0, lambda_1 + lambda_2 = 0`` from ``u0`` (the unknowns of the equilibrium
    ``problem``, its parameter among them), in ``problem.scale``'s units.

    Each step solves the extended system (the module's two ways): an ODE model's as one square solve with ``g``'s
    exact gradient, any other's bordered, with ``g``'s slope along the least-norm step and the null vector.

    It stops where the step is below :data:`_NEWTON_TOL` (1e-14) times ``max(1, |z|)`` in the scaled unknowns
    ``z = u / problem.scale``, or stalls below 1e-10 (the step no longer halves: the derivatives' noise floor),
    and returns the stepped point, evaluated once more for its residual and pair. Two shortcuts that change
    the result by rounding only: a step below 1e-14 itself, or a stalled one, returns the point it was taken
    from (its residuals and pair already at hand); and where quadratic convergence (``e_{k+1} = C e_k^2``,
    ``C`` from the last two steps, the last below 1e-6 times ``max(1, |z|)``) puts the next step below 1e-14,
    the stepped point is returned without the iteration that would confirm it.

    Returns ``(u, pair, residual)``: the located unknowns, the :class:`CriticalPair` there and the
    largest relative residual. Raises :class:`ConvergenceError` when Newton does not converge.
    """
    idx = problem.idx
    assert idx is not None, "a Hopf point is located on an equilibrium problem (full-vector columns)"
    D = np.asarray(problem.scale, float)
    z = np.asarray(u0, float) / D
    states = test.state_positions(problem)
    last = math.inf
    with _dense.quiet():
        for _ in range(max_iter):
            u = z * D
            x = problem.full(u)
            r, J = problem.evaluate(u)
            _check_finite(r)
            if states is not None:
                pair, dz = _square_step(test, x, idx, r, J, D, states)
            else:
                pair, dz = _bordered_step(test, x, idx, r, J, D)
            step = float(np.max(np.abs(dz)))
            if not math.isfinite(step):
                raise ConvergenceError("the Hopf system is singular there", partial=None)
            tol = _NEWTON_TOL * max(1.0, float(np.max(np.abs(z + dz))))
            if step < _NEWTON_TOL or (step >= 0.5 * last and step < 1e-10):
                # z is within rounding of the solution (1e-14 in the scaled unknowns, or the steps' noise floor,
                # where they no longer halve): z itself is returned, with its residuals and pair already at hand
                return u, pair, _converged(r, J, u, problem, pair)
            z = z + dz
            # stepped to within the tolerance, or (quadratic convergence, e_{k+1} = C e_k^2 with C = step / last^2,
            # trusted once the steps are below 1e-6 of the unknowns) to within rounding, 1e-14 in the scaled
            # unknowns, of the solution: the new z is returned, only its residuals and pair are needed
            if step < tol or (last < math.inf and step < 1e8 * tol and step ** 3 < _NEWTON_TOL * last ** 2):
                u = z * D
                r, J = problem.evaluate(u)
                _check_finite(r)
                pair = test.pair(problem.full(u)) if states is None else critical_pair(J[:, states], None)
                return u, pair, _converged(r, J, u, problem, pair)
            last = step
    raise ConvergenceError(f"the Hopf system did not converge from the detected point (after {max_iter} Newton "
                           "iterations)", partial=None)


def _check_finite(r: np.ndarray) -> None:
    """Raise :class:`ConvergenceError` where a residual is not finite."""
    if not np.isfinite(r).all():
        raise ConvergenceError("the Hopf system left the model's domain (a residual not finite)", partial=None)


def _square_step(test: HopfTest, x: np.ndarray, idx: np.ndarray, r: np.ndarray, J: np.ndarray, D: np.ndarray,
                 states: np.ndarray) -> tuple[CriticalPair, np.ndarray]:
    """``(pair, dz)`` of an ODE model's equilibrium problem: the pair of the Jacobian's state columns, and the step
    that solves ``[J D; grad g D] dz = -[r; g]``."""
    pair = critical_pair(J[:, states], None)
    g = pair.g
    if not math.isfinite(g):
        raise ConvergenceError("the Hopf system left the model's domain (a residual not finite)", partial=None)
    n = len(r)
    K = np.empty((n + 1, n + 1))
    K[:n] = J * D
    K[n] = test.gradient(x, idx, pair) * D
    rhs = np.empty(n + 1)
    rhs[:n] = -r
    rhs[n] = -g
    dz = _dense.solve(K, rhs)
    if dz is None:
        raise ConvergenceError("the Hopf system is singular there", partial=None)
    return pair, dz


def _bordered_step(test: HopfTest, x: np.ndarray, idx: np.ndarray, r: np.ndarray, J: np.ndarray,
                   D: np.ndarray) -> tuple[CriticalPair, np.ndarray]:
    """``(pair, dz)``: the step ``dz0 + t phi`` (the module's second way), ``dz0`` and ``phi`` from the QR
    factorisation ``(J D)^T = Q R``: ``phi = Q_n``, ``dz0 = Q_1 R_1^-T (-r)``."""
    n = len(r)
    Q, R = _dense.qr_complete(np.ascontiguousarray((J * D).T))
    R1 = R[:n]
    if not np.all(np.abs(R1.diagonal()) > 0):
        raise ConvergenceError("the Hopf system is singular there", partial=None)
    y = _dense.solve(np.ascontiguousarray(R1.T), -r)  # R_1^T is lower triangular
    if y is None:
        raise ConvergenceError("the Hopf system is singular there", partial=None)
    dz0 = Q[:, :n] @ y
    phi = Q[:, n]
    pair, slope = test.pair_and_derivatives(x, idx, np.vstack([dz0, phi]) * D)
    if not np.isfinite(pair.g):
        raise ConvergenceError("the Hopf system left the model's domain (a residual not finite)", partial=None)
    return pair, dz0 + (-(pair.g + slope[0]) / slope[1]) * phi


def _converged(r: np.ndarray, J: np.ndarray, u: np.ndarray, problem: ContinuationProblem,
               pair: CriticalPair) -> float:
    """The located point's :func:`_relative_residual`; raises :class:`ConvergenceError` where it is above 1e-8
    (the steps stalled away from a solution, or at a non-finite one)."""
    residual = _relative_residual(r, J, u, problem, pair)
    if not residual <= 1e-8:
        raise ConvergenceError(f"the Hopf system stalled at a relative residual of {residual:.3g}", partial=None)
    return residual


def _relative_residual(r: np.ndarray, J: np.ndarray, u: np.ndarray, problem: ContinuationProblem,
                       pair: CriticalPair) -> float:
    """The largest of each equilibrium row's residual over the size of its terms, and ``|g| / |lambda|``."""
    D = np.abs(np.asarray(problem.scale, float))
    terms = np.abs(J) @ np.maximum(np.abs(u), D) + np.abs(r)
    rows = np.abs(r) / np.maximum(terms, np.finfo(float).tiny)
    size = max(abs(pair.lam[0]), abs(pair.lam[1]), np.finfo(float).tiny)
    return float(max(rows.max(initial=0.0), abs(pair.g) / size))
