"""Hopf points of equilibria located exactly: the test function, the critical pair and its polish,
the frequency and the first Lyapunov coefficient.

Everything here asks the model's :class:`~mechcont.equations.Dynamics` (``dynamics_of(model)``) for
its linearisation ``E dz/dt = A dz`` and nothing else, so it serves ODE models and mechanisms alike.

* **Detection**: the bialternate-product test function ``psi = prod_{i<j} (lambda_i + lambda_j)``
  (the determinant of ``2A (.) I``, computed from the eigenvalues) changes sign where a complex pair
  crosses the imaginary axis (a Hopf point, ``lambda = +-i omega``) *and* where two real eigenvalues
  pass through ``(kappa, -kappa)`` (a neutral saddle). :func:`bialternate_test` returns it scale-tamed.
* **Which one**: the critical pair is the pair ``(lambda_1, lambda_2)`` with the smallest
  ``|lambda_1 + lambda_2|``; its product ``kappa = lambda_1 lambda_2`` is ``omega^2 > 0`` at a Hopf
  point and ``-kappa^2 < 0`` at a neutral saddle, which is dropped.
* **Location**: Newton on the minimally extended system ``G(u, p) = 0, g(u, p) = lambda_1 + lambda_2
  = 0`` (square in the branch's unknowns and parameter), with ``dg/dx`` from eigenvalue perturbation
  ``d lambda = w^H (dA - lambda dE) v / (w^H E v)``: exact for ODE models (the model's generated second
  derivatives contract ``dA v``), central differences of the linearisation otherwise. Without ``E`` the
  pair's sum is differentiated as a whole, ``dg = trace(P dA)`` with ``P`` the spectral projector onto
  the pair's invariant plane (from an ordered Schur form): finite through a Bogdanov–Takens point, where
  the pair is a Jordan block and each eigenvalue's own derivative (``w^H v = 0``) is not.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..equations import Dynamics, OdeDynamics
from ..errors import ConvergenceError

__all__ = ["HopfPoint", "CriticalPair", "HopfTest", "bialternate_test", "first_lyapunov", "polish_hopf"]

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

    Zero when a sum is within rounding of zero (at most 1e-9 of the largest ``|lambda|``: an undamped
    mechanism's pairs ``+-i omega`` at every point). ``psi`` is real (the sums of conjugate pairs pair
    up); its sign is ``(-1)^k`` with ``k pi`` the sum of the sums' arguments."""
    lam = np.asarray(lam, dtype=complex)
    if len(lam) < 2:
        return 1.0
    i, j = _pairs(len(lam))
    s = lam[i] + lam[j]
    mag = np.abs(s)
    # a sum at rounding (|s| <= 1e-9 max|lambda|, n_unstable_dynamic's zero) is zero: an undamped mechanism's
    # pairs +-i omega sum to noise of either sign at every point, which would be a Hopf point at every step
    if not np.all(mag > 1e-9 * float(np.max(np.abs(lam)))):
        return 0.0
    k = int(round(float(np.sum(np.angle(s))) / math.pi))
    return (-1.0 if k % 2 else 1.0) * float(np.exp(np.mean(np.log(mag))))


@functools.lru_cache(maxsize=32)
def _pairs(n: int) -> tuple[np.ndarray, np.ndarray]:
    """``np.triu_indices(n, 1)``, kept: it costs more than the eigenvalues of a small system."""
    return np.triu_indices(n, 1)


@dataclass(frozen=True)
class CriticalPair:
    """The eigenvalue pair nearest to summing to zero, with what its gradient needs.

    ``lam``: the two eigenvalues (1/s; ``lam[0]`` with ``Im >= 0`` for a complex pair); ``right``,
    ``left``: their right and left eigenvectors (columns); ``A``, ``E``: the pencil (``E`` None: identity).
    """

    lam: np.ndarray
    right: np.ndarray
    left: np.ndarray
    A: np.ndarray
    E: np.ndarray | None
    n_others_unstable: int

    @property
    def g(self) -> float:
        """``lambda_1 + lambda_2`` (1/s): zero at a Hopf point."""
        return float((self.lam[0] + self.lam[1]).real)

    @property
    def kappa(self) -> float:
        """``lambda_1 lambda_2`` (1/s^2): ``omega^2`` at a Hopf point, negative at a neutral saddle."""
        return float((self.lam[0] * self.lam[1]).real)

    @property
    def complex(self) -> bool:
        """True for a complex-conjugate pair (a Hopf point when ``g = 0``)."""
        return self.kappa > 0 and abs(self.lam[0].imag) > 0

    @property
    def omega(self) -> float:
        """``|Im lambda|`` (rad/s) of a complex pair, else 0."""
        return abs(float(self.lam[0].imag)) if self.complex else 0.0


class HopfTest:
    """The Hopf quantities of a model's dynamics at full vectors ``x``.

    ``dynamics``: a :class:`~mechcont.equations.Dynamics` (``dynamics_of(model)``); ``system``: the
    model's equation system (its generated second derivatives give exact gradients for an ODE model).
    """

    def __init__(self, dynamics: Dynamics, system=None):
        self.dynamics = dynamics
        self.system = system
        self._ode = isinstance(dynamics, OdeDynamics) and system is not None
        # each variable's typical size (the model's scales): the finite-difference steps' unit
        self._scales = None if system is None else np.abs(np.asarray(system.scales(), float))
        if self._ode:
            self._cols = np.array([system.index(n) for n in dynamics.state_names], dtype=np.intp)

    def test_value(self, x: np.ndarray) -> float:
        """:func:`bialternate_test` of the linearisation's eigenvalues at ``x``."""
        return bialternate_test(self.dynamics.linearise(x).eigenvalues())

    def pair(self, x: np.ndarray) -> CriticalPair:
        """The :class:`CriticalPair` at ``x``."""
        lin = self.dynamics.linearise(x)
        A, E = np.asarray(lin.A, float), None if lin.E is None else np.asarray(lin.E, float)
        if E is None:
            # the left eigenvectors are the rows of V^-1 (w_k^H v_k = 1): one LAPACK call fewer than scipy's
            lam, vr = np.linalg.eig(A)
            try:
                vl = np.linalg.inv(vr).conj().T
            except np.linalg.LinAlgError:  # a defective matrix (at a Bogdanov-Takens point): no gradient there
                vl = np.full_like(vr, np.nan)
        else:
            import scipy.linalg

            lam, vl, vr = scipy.linalg.eig(A, E, left=True, right=True)
        finite = np.isfinite(lam)
        lam, vl, vr = lam[finite], vl[:, finite], vr[:, finite]
        if len(lam) < 2:
            raise ConvergenceError("the dynamics have fewer than two finite eigenvalues: no Hopf point", partial=None)
        i, j = _pairs(len(lam))
        k = int(np.argmin(np.abs(lam[i] + lam[j])))
        a, b = int(i[k]), int(j[k])
        if lam[a].imag < lam[b].imag:
            a, b = b, a
        others = np.delete(lam, [a, b])
        return CriticalPair(np.array([lam[a], lam[b]]), vr[:, [a, b]], vl[:, [a, b]], A, E,
                            int(np.sum(others.real > 0)))

    def gradient(self, x: np.ndarray, columns: Sequence[int] | np.ndarray, pair: CriticalPair) -> np.ndarray:
        """``dg/dx`` over the full-vector columns ``columns`` (``g = lambda_1 + lambda_2``), as a real row.
        Without ``E`` it is finite through a Bogdanov–Takens point (:func:`_pair_plane`); with ``E`` it is
        not finite where the pair is defective (``w^H E v = 0``), which the correctors take as a failed point."""
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            return self._gradient(x, np.asarray(columns, dtype=np.intp), pair)

    def _gradient(self, x: np.ndarray, cols: np.ndarray, pair: CriticalPair) -> np.ndarray:
        out = np.zeros(len(cols), dtype=complex)
        plane = _pair_plane(pair) if pair.E is None else None
        # a conjugate pair's second gradient is the conjugate of the first: their sum is twice its real part
        conjugate = plane is None and pair.lam[0].imag != 0 and pair.lam[1] == np.conj(pair.lam[0])
        right, left = plane if plane is not None else (pair.right, pair.left)
        for k in range(1 if conjugate else 2):
            lam, v, w = pair.lam[k], right[:, k], left[:, k]
            Ev = v if pair.E is None else pair.E @ v
            den = 1.0 if plane is not None else np.vdot(w, Ev)
            if self._ode:
                def dAv(part):
                    full = np.zeros(len(x))
                    full[self._cols] = part
                    return self.system.jacobian_derivative(x, full)[:, cols]

                out += (np.conj(w) @ (dAv(v.real) + 1j * dAv(v.imag))) / den
            else:
                out += self._fd_gradient(x, cols, lam, v, w) / den
        return 2 * out.real if conjugate else out.real

    def _fd_gradient(self, x, cols, lam, v, w) -> np.ndarray:
        """``w^H (dA - lam dE) v`` per column by central differences (step ``eps^(1/3)`` of the column's
        value or typical size, whichever is larger: truncation and rounding errors balance at ``eps^(2/3)``,
        about 4e-11 relative)."""
        out = np.zeros(len(cols), dtype=complex)
        for n, c in enumerate(cols):
            h = _EPS ** (1 / 3) * (max(self._scales[c] if self._scales is not None else 1.0, abs(x[c])) or 1.0)
            lins = []
            for sgn in (1.0, -1.0):
                xs = np.array(x, float)
                xs[c] += sgn * h
                lins.append(self.dynamics.linearise(xs))
            dA = (np.asarray(lins[0].A) - np.asarray(lins[1].A)) / (2 * h)
            M = dA if lins[0].E is None else dA - lam * (np.asarray(lins[0].E) - np.asarray(lins[1].E)) / (2 * h)
            out[n] = np.vdot(w, M @ v)
        return out


def _pair_plane(pair: CriticalPair) -> tuple[np.ndarray, np.ndarray] | None:
    """``(V, W)`` (n, 2) with ``W^H V = I`` and ``V W^H`` the spectral projector of ``pair.A`` onto the
    critical pair's invariant plane, so that ``d(lambda_1 + lambda_2) = sum_k W_k^H dA V_k``; None when an
    ordered Schur form does not split the pair from the other eigenvalues (the pair's own eigenvectors
    serve then).

    ``V`` is the leading block ``Q_1`` of the Schur form ``A = Q [[T11, T12], [0, T22]] Q^H`` with the pair
    in ``T11``, and ``W = Q_1 + Q_2 X^H`` with ``T11 X - X T22 = T12``: smooth where the pair is a Jordan
    block (a Bogdanov-Takens point), as long as it stays apart from the other eigenvalues."""
    import scipy.linalg

    A, lam = pair.A, pair.lam
    n = len(A)
    every = np.linalg.eigvals(A)
    near = np.minimum(np.abs(every - lam[0]), np.abs(every - lam[1]))
    order = np.argsort(near)
    gap = float(near[order[2]]) if n > 2 else math.inf
    if not gap > 0:
        return None
    T, Q, sdim = scipy.linalg.schur(A.astype(complex), output="complex",
                                    sort=lambda z: min(abs(z - lam[0]), abs(z - lam[1])) < 0.5 * gap)
    if sdim != 2:
        return None
    V = Q[:, :2]
    if n == 2:
        return V, V
    try:
        X = scipy.linalg.solve_sylvester(T[:2, :2], -T[2:, 2:], T[:2, 2:])
    except (np.linalg.LinAlgError, ValueError):
        return None
    return V, V + Q[:, 2:] @ X.conj().T


def polish_hopf(test: HopfTest, problem, u0: np.ndarray, max_iter: int = 30):
    """Newton on ``G(u) = 0, lambda_1 + lambda_2 = 0`` from ``u0`` (the unknowns of the equilibrium
    ``problem``, its parameter among them), in ``problem.scale``'s units.

    Returns ``(u, pair, residual)``: the located unknowns, the :class:`CriticalPair` there and the
    largest relative residual. Raises :class:`ConvergenceError` when Newton does not converge.
    """
    D = np.asarray(problem.scale, float)
    z = np.asarray(u0, float) / D
    last = math.inf
    for _ in range(max_iter):
        u = z * D
        x = problem.full(u)
        r, J = problem.evaluate(u)
        pair = test.pair(x)
        if not (np.isfinite(r).all() and np.isfinite(pair.g)):
            raise ConvergenceError("the Hopf system left the model's domain (a residual not finite)", partial=None)
        M = np.vstack([J * D, test.gradient(x, problem.idx, pair) * D])
        F = np.append(r, pair.g)
        try:
            dz = np.linalg.solve(M, -F)
        except np.linalg.LinAlgError:
            raise ConvergenceError("the Hopf system is singular there", partial=None) from None
        step = float(np.max(np.abs(dz)))
        if not math.isfinite(step):
            raise ConvergenceError("the Hopf system is singular there", partial=None)
        z = z + dz
        if step < 1e-14 * max(1.0, float(np.max(np.abs(z)))) or (step >= 0.5 * last and step < 1e-10):
            u = z * D
            x = problem.full(u)
            r, J = problem.evaluate(u)
            pair = test.pair(x)
            residual = _relative_residual(r, J, u, problem, pair)
            if not residual <= 1e-8:  # the steps stalled away from a solution (or at a non-finite one)
                raise ConvergenceError(f"the Hopf system stalled at a relative residual of {residual:.3g}",
                                       partial=None)
            return u, pair, residual
        last = step
    raise ConvergenceError(f"the Hopf system did not converge from the detected point (after {max_iter} Newton "
                           "iterations)", partial=None)


def _relative_residual(r, J, u, problem, pair: CriticalPair) -> float:
    """The largest of each equilibrium row's residual over the size of its terms, and ``|g| / |lambda|``."""
    D = np.abs(np.asarray(problem.scale, float))
    terms = np.abs(J) @ np.maximum(np.abs(u), D) + np.abs(r)
    rows = np.abs(r) / np.maximum(terms, np.finfo(float).tiny)
    size = max(abs(pair.lam[0]), abs(pair.lam[1]), np.finfo(float).tiny)
    return float(max(rows.max(initial=0.0), abs(pair.g) / size))


def state_scales(dynamics: Dynamics, system, omega: float) -> np.ndarray:
    """Each state's typical size near a Hopf point or on a cycle of angular frequency ``omega`` (rad/s): its
    variable's scale in ``system``; a velocity state ``NAME_dot`` that is no variable (a mechanism's), its
    coordinate's scale times ``omega`` (it swings ``omega`` times its coordinate's amplitude); else 1."""
    if system is None:
        return np.ones(len(dynamics.state_names))
    known = dict(zip(system.names, np.abs(np.asarray(system.scales(), float))))

    def scale(n: str) -> float:
        if n in known:
            return float(known[n]) or 1.0
        if n.endswith("_dot") and n[:-4] in known:
            return (float(known[n[:-4]]) or 1.0) * max(omega, _EPS)
        return 1.0
    return np.array([scale(n) for n in dynamics.state_names])


def first_lyapunov(dynamics: Dynamics, x: np.ndarray, omega: float, system=None) -> tuple[float, np.ndarray, str]:
    """The first Lyapunov coefficient at the Hopf point ``x`` of frequency ``omega`` (rad/s).

    Kuznetsov's invariant formula (Elements of Applied Bifurcation Theory, 3rd ed., eq. (3.20)):

        l1 = Re( <p, C(q,q,qb)> - 2 <p, B(q, A^-1 B(q,qb))> + <p, B(qb, (2 i omega - A)^-1 B(q,q))> ) / (2 omega)

    with ``A q = i omega q``, ``A^T p = -i omega p``, ``<q, q> = 1``, ``<p, q> = 1`` (``<a, b> = a^H b``),
    ``B``, ``C`` the second and third derivatives of the rates ``f(z)``. For an ODE model (with its
    ``system``) ``B`` is exact (the generated second derivatives) and ``C`` Richardson-extrapolated
    central differences of ``B`` (step ``eps^(1/5)``: about 1e-13 relative); otherwise ``B`` is central
    differences of the rates' Jacobian (step ``eps^(1/3)``) and ``C`` extrapolated central differences of
    that (step ``eps^(1/6)``: about 1e-8 relative). The steps are relative to each state's scale
    (:func:`state_scales`): a mechanism's velocity states swing ``omega`` times their coordinates, and a step
    sized by them would move the coordinates, where the nonlinearity is, by almost nothing.
    ``C(q,q,qb) = D_a S + i D_b S`` with ``q = a + i b`` and ``S(z) = B_z(a,a) + B_z(b,b)`` (real), by
    trilinearity and symmetry. Returns ``(l1, q, method)``.
    """
    dyn = dynamics
    z0 = dyn.state_at(x)
    A = np.asarray(dyn.rates_jacobian(z0, x), float)
    exact = isinstance(dyn, OdeDynamics) and system is not None
    cols = np.array([system.index(n) for n in dyn.state_names]) if exact else None
    sc = state_scales(dyn, system, omega)

    def H(pairs):  # [d(J a)/dz at state z for (z, a) in pairs]: the matrices b -> B_z(a, b)
        if exact:
            out = []
            for z, a in pairs:
                full = np.zeros(len(x))
                full[cols] = a
                out.append(system.jacobian_derivative(dyn.full_vector(z, x), full)[:, cols])
            return out
        hs = [_EPS ** (1 / 3) * max(1.0, float(np.max(np.abs(z) / sc))) / max(float(np.max(np.abs(a) / sc)), _EPS)
              for z, a in pairs]
        states = [w for (z, a), h in zip(pairs, hs) for w in (z + h * a, z - h * a)]
        batch = getattr(dyn, "rates_jacobian_batch", None)  # all the Jacobians in one call where offered
        J = (np.asarray(batch(np.array(states), x), float) if batch is not None
             else [np.asarray(dyn.rates_jacobian(w, x), float) for w in states])
        return [(J[2 * i] - J[2 * i + 1]) / (2 * h) for i, h in enumerate(hs)]

    lam, V = np.linalg.eig(A)
    q = V[:, int(np.argmin(np.abs(lam - 1j * omega)))]
    q = q / np.linalg.norm(q)
    lamT, W = np.linalg.eig(A.T)
    p = W[:, int(np.argmin(np.abs(lamT + 1j * omega)))]
    p = p / np.conj(np.vdot(p, q))
    a, b = q.real, q.imag

    # Richardson's extrapolation of central differences (error O(h^4)): for the exact B, h = eps^(1/5) balances
    # rounding (eps / h) and truncation (h^4) near 1e-13; for a B itself from differences (noise ~ eps^(2/3)),
    # h = eps^(1/6) balances them near 1e-8
    step = _EPS ** (1 / 5) if exact else _EPS ** (1 / 6)
    scale = max(1.0, float(np.max(np.abs(z0) / sc)))
    # every derivative l1 needs, taken at once: B at z0 along a and b (B(qb, .) = B(q, .) with b negated),
    # and S(z) = B_z(a, a) + B_z(b, b) at z0 +- h d, z0 +- 2 h d for d = a, b (for C)
    centres = []
    for d in (a, b):
        nd = float(np.max(np.abs(d) / sc))
        if nd > 0:
            h = step * scale / nd
            centres += [(d, k, h, z0 + k * h * d, z0 - k * h * d) for k in (1, 2)]
    Hs = H([(z0, a), (z0, b)] + [(zc, v) for *_, zp, zm in centres for zc in (zp, zm) for v in (a, b)])
    Ha, Hb = Hs[0], Hs[1]
    Sv = [Hs[2 + 2 * i] @ a + Hs[3 + 2 * i] @ b for i in range(2 * len(centres))]

    def B(conj, v):  # the complex bilinear form at the equilibrium, B(q, v) or (conj) B(qb, v)
        return Ha @ v + (-1j if conj else 1j) * (Hb @ v)

    def D(d):
        rows = [i for i, c in enumerate(centres) if c[0] is d]
        if not rows:
            return np.zeros(len(z0))
        central = [(Sv[2 * i] - Sv[2 * i + 1]) / (2 * centres[i][1] * centres[i][2]) for i in rows]
        return (4 * central[0] - central[1]) / 3

    C = D(a) + 1j * D(b)
    qb = np.conj(q)
    n = len(z0)
    h11 = np.linalg.solve(A, B(False, qb))
    h20 = np.linalg.solve(2j * omega * np.eye(n) - A, B(False, q))
    l1 = float(np.real(np.vdot(p, C) - 2 * np.vdot(p, B(False, h11)) + np.vdot(p, B(True, h20))) / (2 * omega))
    method = ("exact second derivatives, third by extrapolated central differences" if exact
              else "finite differences of the rates' Jacobian")
    return l1, q, method
