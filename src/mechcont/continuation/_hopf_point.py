"""Hopf points of equilibria located exactly: the test function, the critical pair and its polish,
the frequency and the first Lyapunov coefficient.

Everything here asks the model's :class:`~mechcont.equations.Dynamics` (``dynamics_of(model)``) for
its linearisation ``E dz/dt = A dz`` and nothing else, so it serves ODE models and mechanisms alike (an ODE
model's polish reads ``A`` off the equilibrium Jacobian it evaluates anyway: :meth:`HopfTest.state_positions`).

* **Detection**: the bialternate-product test function ``psi = prod_{i<j} (lambda_i + lambda_j)``
  (the determinant of ``2A (.) I``, computed from the eigenvalues) changes sign where a complex pair
  crosses the imaginary axis (a Hopf point, ``lambda = +-i omega``) *and* where two real eigenvalues
  pass through ``(kappa, -kappa)`` (a neutral saddle). :func:`bialternate_test` returns it scale-tamed.
* **Which one**: the critical pair is the pair ``(lambda_1, lambda_2)`` with the smallest
  ``|lambda_1 + lambda_2|``; its product ``kappa = lambda_1 lambda_2`` is ``omega^2 > 0`` at a Hopf
  point and ``-kappa^2 < 0`` at a neutral saddle, which is dropped.
* **Location**: Newton on the minimally extended system ``G(u, p) = 0, g(u, p) = lambda_1 + lambda_2
  = 0`` (square in the branch's unknowns and parameter; :func:`polish_hopf`, :mod:`._hopf_newton`), ``g``'s slope
  from eigenvalue perturbation ``d lambda = w^H (dA - lambda dE) v / (w^H E v)``: for an ODE model its whole
  gradient, exact (one call of the generated second derivatives), and each step one square solve; otherwise
  each step bordered, the slope needed along two directions only, by central differences of the linearisation (a
  mechanism's in one batch, ``MechanismDynamics.linearise_near``). Where the pair comes near a Jordan block its sum
  is differentiated as a whole on its invariant plane: ``dg = trace(P dA)`` with ``P`` the spectral projector from
  an ordered Schur form, or for a pencil ``(A, E)`` from an ordered QZ form and the generalised Sylvester equations
  that split its deflating subspaces: finite through a Bogdanov–Takens point, where each eigenvalue's own
  derivative (``w^H E v = 0``) is not.
* **l1**: :mod:`._lyapunov`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from .. import _dense
from ..equations import NEUTRAL_RTOL, Dynamics, EquationSystem, OdeDynamics
from ._hopf_newton import polish_hopf
from ._hopf_plane import CriticalPair, contractions, critical_pair, pair_indices
from ._lyapunov import first_lyapunov, state_scales
from ._problem import ContinuationProblem, EquilibriumProblem

__all__ = ["HopfPoint", "CriticalPair", "HopfTest", "bialternate_test", "first_lyapunov", "polish_hopf",
           "secant_fraction", "state_scales"]

_EPS = np.finfo(float).eps


@dataclass(frozen=True)
class HopfPoint:
    """What a Hopf point (``HB``) carries besides its values (``SpecialPoint.extra["hopf"]``).

    Attributes
    ----------
    frequency:
        ``omega`` (rad/s), the imaginary part of the critical eigenvalue pair ``+-i omega``.
    lyapunov:
        The first Lyapunov coefficient ``l1`` (Kuznetsov's invariant formula, eigenvector normalised
        ``<q, q> = 1``; units of 1/s per squared state unit): negative, supercritical (a stable cycle
        is born on the unstable side); positive, subcritical (an unstable cycle on the stable side).
    eigenvector:
        ``q`` with ``A q = i omega q`` (``E``'s pencil for a descriptor system), ``|q| = 1``, over
        :attr:`state_names`.
    state_names:
        The dynamics' state names.
    residual:
        The located point's largest residual: equilibrium rows relative to their terms, and
        ``|lambda_1 + lambda_2| / |lambda_1|``.
    lyapunov_method:
        How ``l1``'s derivatives were taken (exact second derivatives, or finite differences).
    """

    frequency: float
    lyapunov: float
    eigenvector: np.ndarray
    state_names: tuple[str, ...]
    residual: float
    lyapunov_method: str = ""

    @property
    def period(self) -> float:
        """``2 pi / omega`` (s), the period of the cycles born there."""
        return 2 * math.pi / self.frequency

    @property
    def criticality(self) -> str:
        """``"supercritical (stable cycles)"``, ``"subcritical (unstable cycles)"`` or, at ``l1 = 0``
        to rounding, ``"degenerate (l1 = 0)"``."""
        if not math.isfinite(self.lyapunov) or self.lyapunov == 0.0:
            return "degenerate (l1 = 0)"
        return "supercritical (stable cycles)" if self.lyapunov < 0 else "subcritical (unstable cycles)"


def bialternate_test(lam: np.ndarray) -> float:
    """``sign(psi) |psi|^(1/m)`` with ``psi = prod_{i<j} (lambda_i + lambda_j)`` over the ``m`` pairs of the
    eigenvalues ``lam`` (1/s): continuous in the matrix, zero at Hopf points and neutral saddles.

    Zero when a sum is within rounding of zero (at most NEUTRAL_RTOL = 1e-9 of the largest ``|lambda|``: an undamped
    mechanism's pairs ``+-i omega`` at every point). ``psi`` is real (the sums of conjugate pairs pair
    up); its sign is ``(-1)^k`` with ``k pi`` the sum of the sums' arguments."""
    lam = np.asarray(lam, dtype=complex)
    if len(lam) < 2:
        return 1.0
    i, j = pair_indices(len(lam))
    s = lam[i] + lam[j]
    mag = np.abs(s)
    # a sum at rounding (|s| <= NEUTRAL_RTOL max|lambda|, n_unstable_dynamic's zero) is zero: an undamped mechanism's
    # pairs +-i omega sum to noise of either sign at every point, which would be a Hopf point at every step
    if not np.all(mag > NEUTRAL_RTOL * float(np.max(np.abs(lam)))):
        return 0.0
    k = int(round(float(np.sum(np.angle(s))) / math.pi))
    return (-1.0 if k % 2 else 1.0) * float(np.exp(np.mean(np.log(mag))))


def secant_fraction(v0: float, v1: float, pairs: int) -> float:
    """Where between two points, as a fraction of the way from the first, the Hopf point lies that their
    :func:`bialternate_test` values ``v0``, ``v1`` (of opposite signs) bracket, ``pairs`` the number of eigenvalue
    pairs ``m`` the values were taken over: the secant's zero of ``sign(v) |v|^m = psi``, not of ``v``.

    ``psi`` is the product of the pair sums, smooth with a simple zero where the critical pair's sum ``g`` has one
    (the other sums change slowly), so its secant errs by the square of the step, as a fold's does; ``v``'s own
    secant does not (``|v| ~ |g|^(1/m)``: near the zero ``v`` is all curvature, and its secant lands about
    midway). The ratio ``(|v1| / |v0|)^m`` is formed from logarithms (``m`` is 10 for 5 states)."""
    if v0 == 0.0 or v1 == 0.0 or (v0 > 0) == (v1 > 0) or pairs < 1:
        return v0 / (v0 - v1) if v0 != v1 else 0.5
    t = pairs * (math.log(abs(v1)) - math.log(abs(v0)))
    return 1.0 / (1.0 + math.exp(min(t, 700.0)))


class HopfTest:
    """The Hopf quantities of a model's dynamics at full vectors ``x``.

    ``dynamics``: a :class:`~mechcont.equations.Dynamics` (``dynamics_of(model)``); ``system``: the
    model's equation system (its generated second derivatives give exact gradients for an ODE model).
    """

    def __init__(self, dynamics: Dynamics, system: EquationSystem | None = None) -> None:
        self.dynamics = dynamics
        self.system = system
        self._exact = system if isinstance(dynamics, OdeDynamics) else None
        # each variable's typical size (the model's scales): the finite-difference steps' unit
        self._scales = None if system is None else np.abs(np.asarray(system.scales(), float))
        self._cols = (np.zeros(0, np.intp) if self._exact is None else
                      np.array([self._exact.index(n) for n in dynamics.state_names], dtype=np.intp))
        self._second: tuple[Callable[[np.ndarray], np.ndarray], np.ndarray, np.ndarray, int] | None = None
        #: the number of eigenvalue pairs the last :meth:`test_value` was taken over (:func:`secant_fraction`'s)
        self.pairs = 0

    def test_value(self, x: np.ndarray) -> float:
        """:func:`bialternate_test` of the linearisation's eigenvalues at ``x``."""
        lam = self.dynamics.linearise(x).eigenvalues()
        self.pairs = len(lam) * (len(lam) - 1) // 2
        return bialternate_test(lam)

    def pair(self, x: np.ndarray) -> CriticalPair:
        """The :class:`CriticalPair` at ``x``."""
        lin = self.dynamics.linearise(x)
        return critical_pair(np.asarray(lin.A, float), None if lin.E is None else np.asarray(lin.E, float))

    def gradient(self, x: np.ndarray, columns: Sequence[int] | np.ndarray, pair: CriticalPair) -> np.ndarray:
        """``dg/dx`` over the full-vector columns ``columns`` (``g = lambda_1 + lambda_2``), as a real row.
        Without ``E`` it is finite through a Bogdanov–Takens point (:func:`_pair_plane`); with ``E`` it is
        not finite where the pair is defective (``w^H E v = 0``), which the correctors take as a failed point."""
        cols = np.asarray(columns, dtype=np.intp)
        with _dense.quiet():
            if self._exact is not None:
                return self._exact_gradient(x, cols, pair)
            return self._fd_derivatives(x, cols, np.eye(len(cols)), pair)

    def derivatives(self, x: np.ndarray, columns: Sequence[int] | np.ndarray, directions: np.ndarray,
                    pair: CriticalPair) -> np.ndarray:
        """``d g(x + s d) / ds`` at ``s = 0`` for each row ``d`` of ``directions`` (values over the full-vector
        columns ``columns``, in the variables' units): one value per row, ``gradient . d`` without the whole
        gradient. A mechanism's takes two linearisations per direction (central differences, all in one batch
        where the dynamics offer ``linearise_near``), where the gradient takes two per column."""
        cols = np.asarray(columns, dtype=np.intp)
        directions = np.atleast_2d(np.asarray(directions, dtype=float))
        with _dense.quiet():
            if self._exact is not None:
                return directions @ self._exact_gradient(x, cols, pair)
            return self._fd_derivatives(x, cols, directions, pair)

    def state_positions(self, problem: ContinuationProblem) -> np.ndarray | None:
        """Where the dynamics' states are among ``problem``'s unknowns, when ``problem.evaluate``'s Jacobian holds the
        linearisation: an ODE model's equilibrium problem on the same system with every state among its unknowns (or
        its parameter), whose Jacobian's state columns are ``A = df/dz`` exactly. None otherwise."""
        system = self._exact
        if (system is None or not isinstance(problem, EquilibriumProblem) or problem.system is not system
                or getattr(self.dynamics, "model", None) is not system or problem.idx is None):
            return None
        where = {int(c): k for k, c in enumerate(problem.idx)}
        if not all(int(c) in where for c in self._cols):
            return None
        return np.array([where[int(c)] for c in self._cols], dtype=np.intp)

    def _exact_gradient(self, x: np.ndarray, cols: np.ndarray, pair: CriticalPair) -> np.ndarray:
        """The ODE model's gradient ``sum_k w_k^H (dA v_k)`` (:func:`contractions`' terms), with ``dA v`` from the
        generated second derivatives: ``d2 f_i / dz_j dx_c`` weighted by ``Re(conj(w_i) v_j)`` summed over the terms,
        one compiled call for the real and imaginary parts alike."""
        if self._second is None:
            system = self._exact
            assert system is not None
            nv, n = len(system.names), len(self._cols)
            fn, i, j, k = system.columns(np.arange(nv)).second_derivative_entries()
            at = np.full(nv, n, dtype=np.intp)  # the state's position, n (a zero weight) for other variables
            at[self._cols] = np.arange(n, dtype=np.intp)
            self._second = (fn, i * (n + 1) + at[j], k, nv)
        values, flat, c, nv = self._second
        n = len(self._cols)
        terms, conjugate = contractions(pair)
        M = np.zeros((n, n + 1))  # Re(conj(w_i) v_j), a zero column for the other variables
        for v, w, _ in terms:  # an ODE model has no E
            M[:, :n] += (w.conj()[:, None] * v).real
        if conjugate:
            M *= 2.0
        return np.bincount(c, weights=values(x) * M.ravel()[flat], minlength=nv)[cols]

    def _fd_derivatives(self, x: np.ndarray, cols: np.ndarray, directions: np.ndarray,
                        pair: CriticalPair) -> np.ndarray:
        """``w^H (dA - lam dE) v`` along each direction by central differences of the linearisation (the steps:
        :meth:`_stencil`)."""
        h, moving, X = self._stencil(x, cols, directions)
        if len(moving) == 0:
            return np.zeros(len(directions))
        A, E = self._linearisations(x, X, pair.E is not None)
        return self._contract(pair, A, E, h, moving, len(directions))

    def _stencil(self, x: np.ndarray, cols: np.ndarray, directions: np.ndarray) -> tuple[np.ndarray, np.ndarray,
                                                                                        np.ndarray]:
        """``(h, moving, X)``: the steps of the directions that move anything, their positions, and the full
        vectors ``x + h d`` then ``x - h d``. The step moves the direction's largest component (relative to its
        column's value or typical size, whichever is larger) by ``eps^(1/3)`` of that size, so that truncation
        and rounding errors balance at ``eps^(2/3)``, about 4e-11 relative (for a unit direction, the step of
        that column alone)."""
        size = np.abs(np.asarray(x, float)[cols])
        if self._scales is not None:
            size = np.maximum(self._scales[cols], size)
        size = np.where(size > 0, size, 1.0)
        reach = np.max(np.abs(directions) / size, axis=1, initial=0.0)
        moving = np.flatnonzero(reach > 0)
        h = _EPS ** (1 / 3) / reach[moving]
        m = len(moving)
        X = np.repeat(np.asarray(x, float)[None, :], 2 * m, axis=0)
        X[:m, cols] += h[:, None] * directions[moving]
        X[m:, cols] -= h[:, None] * directions[moving]
        return h, moving, X

    @staticmethod
    def _contract(pair: CriticalPair, A: np.ndarray, E: np.ndarray | None, h: np.ndarray, moving: np.ndarray,
                  n: int) -> np.ndarray:
        """The slopes of ``g`` from the linearisations ``A`` (and ``E``) at :meth:`_stencil`'s points."""
        m = len(moving)
        dA = (A[:m] - A[m:]) / (2 * h)[:, None, None]
        dE = None if E is None else (E[:m] - E[m:]) / (2 * h)[:, None, None]
        out = np.zeros(n, dtype=complex)
        terms, conjugate = contractions(pair)
        for v, w, u in terms:
            out[moving] += np.conj(w) @ dA @ v
            if dE is not None and u is not None:
                out[moving] -= np.conj(w) @ dE @ u
        return 2 * out.real if conjugate else out.real

    def pair_and_derivatives(self, x: np.ndarray, columns: Sequence[int] | np.ndarray,
                             directions: np.ndarray) -> tuple[CriticalPair, np.ndarray]:
        """``(pair(x), derivatives(x, columns, directions, pair))``, where the dynamics offer ``linearise_near``
        with ``x``'s own linearisation in the same batch as the differenced ones (one set of compiled calls)."""
        near = getattr(self.dynamics, "linearise_near", None)
        if near is None or self._exact is not None:
            pair = self.pair(x)
            return pair, self.derivatives(x, columns, directions, pair)
        cols = np.asarray(columns, dtype=np.intp)
        directions = np.atleast_2d(np.asarray(directions, dtype=float))
        h, moving, X = self._stencil(x, cols, directions)
        A, E = near(x, np.vstack([np.asarray(x, float)[None, :], X]), None)
        A, E = np.asarray(A, float), None if E is None else np.asarray(E, float)
        pair = critical_pair(A[0], None if E is None else E[0])
        with _dense.quiet():
            return pair, self._contract(pair, A[1:], None if E is None else E[1:], h, moving, len(directions))

    def _linearisations(self, x: np.ndarray, X: np.ndarray, descriptor: bool) -> tuple[np.ndarray, np.ndarray | None]:
        """``(A, E)`` stacked at the rows of ``X`` (near ``x``): the dynamics' ``linearise_near`` where it has
        one (a mechanism's, in a basis that moves smoothly from ``x``'s), else one ``linearise`` per row."""
        near = getattr(self.dynamics, "linearise_near", None)
        if near is not None:
            A, E = near(x, X, descriptor)
            return np.asarray(A, float), None if E is None else np.asarray(E, float)
        lins = [self.dynamics.linearise(xi) for xi in X]
        A = np.array([np.asarray(lin.A, float) for lin in lins])
        if not descriptor:
            return A, None
        eye = np.eye(A.shape[1])
        return A, np.array([eye if lin.E is None else np.asarray(lin.E, float) for lin in lins])


