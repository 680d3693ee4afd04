"""The critical eigenvalue pair of a linearisation and the slope of its sum: what the Hopf test function's
gradient contracts (:func:`contractions`), from the pair's eigenvectors where it is well apart, else from its
invariant plane (ordered Schur form of ``A``) or its deflating subspaces (ordered QZ form of the pencil
``(A, E)``), smooth through a Bogdanov-Takens point where the pair is a Jordan block."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from .. import _dense
from ..errors import ConvergenceError

__all__ = ["CriticalPair", "contractions", "critical_pair", "pair_indices"]


@dataclass(frozen=True)
class CriticalPair:
    """The eigenvalue pair nearest to summing to zero, with what its gradient needs.

    ``lam``: the two eigenvalues (1/s; ``lam[0]`` with ``Im >= 0`` for a complex pair); ``right``,
    ``left``: their right and left eigenvectors (columns); ``A``, ``E``: the pencil (``E`` None: identity);
    ``n_others_unstable``: the other eigenvalues with positive real part; ``spectrum``: every finite
    eigenvalue (None: not kept).
    """

    lam: np.ndarray
    right: np.ndarray
    left: np.ndarray
    A: np.ndarray
    E: np.ndarray | None
    n_others_unstable: int
    spectrum: np.ndarray | None = None

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


@functools.lru_cache(maxsize=32)
def pair_indices(n: int) -> tuple[np.ndarray, np.ndarray]:
    """``np.triu_indices(n, 1)``, kept: it costs more than the eigenvalues of a small system."""
    return np.triu_indices(n, 1)


def critical_pair(A: np.ndarray, E: np.ndarray | None) -> CriticalPair:
    """The :class:`CriticalPair` of the pencil ``(A, E)`` (``E`` None: the identity; both real, (n, n)): the pair of
    finite eigenvalues whose sum is nearest to zero. Raises :class:`ConvergenceError` where fewer than two are
    finite, LinAlgError where the eigenvalues cannot be computed."""
    if E is None:
        # LAPACK's kernel without numpy.linalg.eig's wrapper; the left eigenvectors are the rows of V^-1 (w_k^H v_k =
        # 1): one LAPACK call fewer than scipy's. NaN where V is singular (a defective matrix, at a Bogdanov-Takens
        # point): no gradient from the eigenvectors there
        lam, vr = _dense.eig(A)
        inv = _dense.inverse(vr)
        vl = np.full_like(vr, np.nan) if inv is None else inv.conj().T
    else:
        import scipy.linalg

        lam, vl, vr = scipy.linalg.eig(A, E, left=True, right=True)
        finite = np.isfinite(lam)
        lam, vl, vr = lam[finite], vl[:, finite], vr[:, finite]
    n = len(lam)
    if n < 2:
        raise ConvergenceError("the dynamics have fewer than two finite eigenvalues: no Hopf point", partial=None)
    if n == 2:  # one pair (no search, and no fancy indexing: a small system's eigenvalues cost less than those)
        if lam[0].imag < lam[1].imag:
            lam, vr, vl = lam[::-1], vr[:, ::-1], vl[:, ::-1]
        return CriticalPair(lam, vr, vl, A, E, 0, lam)
    i, j = pair_indices(n)
    k = int(np.abs(lam[i] + lam[j]).argmin())
    a, b = int(i[k]), int(j[k])
    if lam[a].imag < lam[b].imag:
        a, b = b, a
    ab = [a, b]
    crit = lam[ab]
    others = int(np.count_nonzero(lam.real > 0)) - int(np.count_nonzero(crit.real > 0))
    return CriticalPair(crit, vr[:, ab], vl[:, ab], A, E, others, lam)


#: One term of ``dg = sum_k w_k^H dA v_k - w_k^H dE u_k``: ``(v_k, w_k, u_k)``, ``u_k`` None without ``E``.
_Term = tuple[np.ndarray, np.ndarray, np.ndarray | None]


def contractions(pair: CriticalPair) -> tuple[list[_Term], bool]:
    """``(terms, conjugate)``: what ``dg = sum_k w_k^H dA v_k - w_k^H dE u_k`` contracts. From the pair's invariant
    plane where an ordered Schur (without ``E``: :func:`_pair_plane`) or QZ form (with ``E``:
    :func:`_pencil_plane`) splits it from the other eigenvalues: smooth through a Bogdanov–Takens point, where
    the pair is a Jordan block. Else from its eigenvectors, ``w_k^H (dA - lambda_k dE) v_k / (w_k^H E v_k)``;
    ``conjugate``: only the first of a conjugate pair is listed (the sum is twice its real part)."""
    if pair.E is None:
        # a pair well apart (|lambda_1 - lambda_2| >= 1e-3 |A|): its eigenvectors' derivatives are good to
        # eps |A| / |lambda_1 - lambda_2| <= 2e-13, and cost no ordered Schur form
        # (np.linalg.norm(A, 1), the largest column sum, without its wrapper)
        apart = abs(pair.lam[0] - pair.lam[1]) >= 1e-3 * float(np.abs(pair.A).sum(axis=0).max(initial=0.0))
        plane = None if apart and np.isfinite(np.add.reduce(pair.left, None)) else _pair_plane(pair)
        if plane is not None:
            return [(plane[0][:, k], plane[1][:, k], None) for k in range(2)], False
    else:
        pencil = _pencil_plane(pair)
        if pencil is not None:
            V, W, U = pencil
            return [(V[:, k], W[:, k], U[:, k]) for k in range(2)], False
    conjugate = bool(pair.lam[0].imag != 0 and pair.lam[1] == np.conj(pair.lam[0]))
    terms: list[_Term] = []
    for k in range(1 if conjugate else 2):
        v, w = pair.right[:, k], pair.left[:, k]
        Ev = v if pair.E is None else pair.E @ v
        w = w / np.conj(np.vdot(w, Ev))
        terms.append((v, w, None if pair.E is None else pair.lam[k] * v))
    return terms, conjugate


def _pencil_plane(pair: CriticalPair) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """``(V, W, U)`` (n, 2) for the pencil ``(A, E)``: ``d(lambda_1 + lambda_2) = trace(G W_l^H dA V) - trace(G
    W_l^H dE V M)`` with ``V`` the pair's right deflating subspace, ``W_l`` its left one, ``G = (W_l^H E V)^-1`` and
    ``M = G W_l^H A V`` (the pair's 2 x 2 block), returned as ``W = W_l G^H`` and ``U = V M``; None when an
    ordered real QZ form does not split the pair from the other finite eigenvalues (and the infinite ones).

    From ``Q^T A Z = S``, ``Q^T E Z = T`` with the pair in the leading blocks: ``V = Z_1``, and ``W_l = Q_1 - Q_2
    L^T`` with ``(R, L)`` solving the generalised Sylvester equations ``S11 R - L S22 = -S12``, ``T11 R - L T22 =
    -T12`` (LAPACK's ``dtgsyl``), which block-diagonalise the pencil: smooth where the pair is a Jordan block
    (a Bogdanov-Takens point), as long as it stays apart from the other eigenvalues."""
    import scipy.linalg
    from scipy.linalg.lapack import dtgsyl

    A, E, lam = pair.A, pair.E, pair.lam
    assert E is not None
    n = len(A)
    every = pair.spectrum if pair.spectrum is not None else scipy.linalg.eigvals(A, E)
    every = every[np.isfinite(every)]
    near = np.sort(np.minimum(np.abs(every - lam[0]), np.abs(every - lam[1])))
    gap = float(near[2]) if len(near) > 2 else math.inf
    if not gap > 0:
        return None

    def chosen(alpha: np.ndarray, beta: np.ndarray) -> np.ndarray:
        with np.errstate(divide="ignore", invalid="ignore"):
            z = np.asarray(alpha, complex) / beta
        ok = np.isfinite(z) & (np.abs(beta) > 0)
        return np.asarray(ok & (np.minimum(np.abs(z - lam[0]), np.abs(z - lam[1])) < 0.5 * gap))

    try:
        S, T, alpha, beta, Q, Z = scipy.linalg.ordqz(A, E, sort=chosen, output="real")
    except (np.linalg.LinAlgError, ValueError):
        return None
    if int(np.count_nonzero(chosen(alpha, beta))) != 2 or not np.all(chosen(alpha[:2], beta[:2])):
        return None
    V = Z[:, :2]
    Wl = Q[:, :2]
    if n > 2:
        R, L, scale, _, info = dtgsyl(S[:2, :2], S[2:, 2:], -S[:2, 2:], T[:2, :2], T[2:, 2:], -T[:2, 2:])
        if info < 0 or not scale > 0:
            return None
        Wl = Wl - Q[:, 2:] @ (L / scale).T
    try:
        G = np.linalg.inv(T[:2, :2])
    except np.linalg.LinAlgError:
        return None
    M = G @ S[:2, :2]
    return V, Wl @ G.T, V @ M


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
    every = pair.spectrum if pair.spectrum is not None else np.linalg.eigvals(A)
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
