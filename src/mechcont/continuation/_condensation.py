r"""Condensation of parameters: the collocation Jacobian solved through its mesh points (AUTO's scheme).

Interval ``j``'s ``NCOL n`` collocation rows involve only its own nodes — the first (mesh point
``M_j``), the ``NCOL - 1`` inner ones ``I_j`` and the last (``M_(j+1)``) — and the period and the
parameter. With ``S_j = [A_I | A_R]`` (the columns of the inner and last nodes, square) those rows give

.. math::  [\delta I_j; \delta M_{j+1}] = S_j^{-1} (b_j - A_L \delta M_j - a_T \delta T - a_p \delta p),

so the inner nodes are eliminated interval by interval (one small dense inverse each, all at once),
and what is left is a system in the mesh points, ``T`` and ``p`` only: ``NTST`` block rows
``dM_(j+1) + P_j dM_j + ... = w_j`` (a block-bidiagonal matrix, as in multiple shooting: the maps
``-P_j`` are the intervals' transfer matrices, whose product is the monodromy matrix), periodicity,
and the phase and closing rows with the inner nodes' part moved onto the mesh points. That system, of
``(NTST + 1) n + 2`` rows, is factored once (dense LU); the inner nodes follow from the mesh points.
Work per factorisation: ``NTST`` inverses of ``NCOL n`` square blocks and one LU of the reduced
system, against the ``(NTST NCOL + 1) n + 2`` rows of the whole.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import scipy.linalg.lapack

__all__ = ["CondensedLU"]

_GETRF, _GETRS = scipy.linalg.lapack.dgetrf, scipy.linalg.lapack.dgetrs


@dataclass(frozen=True)
class _Pattern:
    """Flat indices into the reduced matrix (row-major) of its fixed entries and of its interval blocks."""

    ones: np.ndarray  # +1: M_(j+1) in interval j's rows, M_NTST in the periodicity rows
    minus: np.ndarray  # -1: M_0 in the periodicity rows
    P: np.ndarray  # interval j's rows: M_j's columns, then T's and p's, in the order of Q[j, inner:, :]
    inner_nodes: np.ndarray  # (ntst, ncol - 1) node numbers of the inner nodes


@functools.lru_cache(maxsize=32)
def _pattern(ntst: int, m: int, n: int) -> _Pattern:
    nr = (ntst + 1) * n + 2
    j, a, b = np.meshgrid(np.arange(ntst), np.arange(n), np.arange(n + 2), indexing="ij")
    row = j * n + a
    col = np.where(b < n, j * n + b, nr - 2 + (b - n))
    r1 = np.arange(ntst * n)
    per = ntst * n + np.arange(n)
    ones = np.concatenate([r1 * nr + (r1 + n), per * nr + per])
    return _Pattern(ones, per * nr + np.arange(n), (row * nr + col).ravel(),
                    np.arange(ntst)[:, None] * m + np.arange(1, m)[None, :])


class CondensedLU:
    """The collocation Jacobian factored by condensation; :meth:`solve` solves it for any right-hand side.

    ``C``: the intervals' collocation blocks (ntst, ncol n, (ncol + 1) n) over their nodes; ``aT``, ``ap``:
    the T and p columns of the collocation rows (ntst, ncol n); ``phase``: the phase row over the nodes;
    ``closing``: the closing row over all unknowns; ``mesh``: the collocation mesh (node indices).
    Raises ``numpy.linalg.LinAlgError`` when a block or the reduced system is singular.
    """

    def __init__(self, C: np.ndarray, aT: np.ndarray, ap: np.ndarray, phase: np.ndarray, closing: np.ndarray,
                 mesh, n: int):
        self.mesh, self.n = mesh, n
        ntst, m = mesh.ntst, mesh.ncol
        inner = (m - 1) * n
        self.Sinv = np.linalg.inv(C[:, :, n:])  # (ntst, m n, m n): rows = [inner nodes; last node]
        B = np.concatenate([C[:, :, :n], aT[:, :, None], ap[:, :, None]], axis=2)
        self.Q = self.Sinv @ B  # (ntst, m n, n + 2): the first node's, T's and p's parts
        nr = (ntst + 1) * n + 2
        pat = _pattern(ntst, m, n)
        K = np.zeros(nr * nr)
        K[pat.ones] = 1.0
        K[pat.minus] = -1.0
        K[pat.P] = self.Q[:, inner:, :].ravel()  # P_R on M_j, then the T and p columns
        K = K.reshape(nr, nr)
        self._inner_idx = pat.inner_nodes
        rows = np.stack([np.concatenate([phase, [0.0, 0.0]]), closing])  # the phase and closing rows
        nodes = rows[:, :-2].reshape(2, mesh.n_nodes, n)
        cI = nodes[:, self._inner_idx].reshape(2, ntst, inner)  # the inner nodes' coefficients
        adj = np.einsum("rji,jik->rjk", cI, self.Q[:, :inner, :])  # their part, moved to M_j, T, p
        coefM = nodes[:, ::m].copy()
        coefM[:, :-1] -= adj[:, :, :n]
        K[nr - 2:, :nr - 2] = coefM.reshape(2, -1)
        K[nr - 2:, nr - 2] = rows[:, -2] - adj[:, :, n].sum(axis=1)
        K[nr - 2:, nr - 1] = rows[:, -1] - adj[:, :, n + 1].sum(axis=1)
        self._border = cI
        with np.errstate(all="ignore"):  # LAPACK's getrf directly: scipy's lu_factor wrapper costs as much as the LU
            lu, piv, info = _GETRF(K, overwrite_a=1)
        if info != 0 or not np.all(np.isfinite(lu)):
            raise np.linalg.LinAlgError("singular collocation Jacobian")
        self.lu = (lu, piv)
        self.nr = nr

    def transfer(self) -> np.ndarray:
        """The intervals' transfer matrices ``Phi_j`` (ntst, n, n): last node from the first, T and p held."""
        inner = (self.mesh.ncol - 1) * self.n
        return -self.Q[:, inner:, :self.n]

    def multipliers(self) -> np.ndarray:
        """The eigenvalues of the monodromy matrix (the transfer matrices' product), largest modulus first."""
        M = np.eye(self.n)
        for Phi in self.transfer():
            M = Phi @ M
        mu = np.linalg.eigvals(M)
        return mu[np.argsort(-np.abs(mu), kind="stable")]

    def solve(self, b: np.ndarray) -> np.ndarray:
        """The solution ``dX`` of ``J dX = b`` (``b`` ordered as the residual: collocation, periodicity, phase, closing)."""
        mesh, n = self.mesh, self.n
        ntst, m = mesh.ntst, mesh.ncol
        inner = (m - 1) * n
        nc = ntst * m * n
        w = np.einsum("jab,jb->ja", self.Sinv, b[:nc].reshape(ntst, m * n))  # (ntst, m n)
        rhs = np.empty(self.nr)
        rhs[:ntst * n] = w[:, inner:].ravel()
        rhs[ntst * n:(ntst + 1) * n] = b[nc:nc + n]
        rhs[self.nr - 2:] = b[nc + n:nc + n + 2] - np.einsum("rji,ji->r", self._border, w[:, :inner])
        red, _ = _GETRS(self.lu[0], self.lu[1], rhs)
        M = red[:-2].reshape(ntst + 1, n)
        dT, dp = red[-2], red[-1]
        Qi = self.Q[:, :inner, :]
        inner_vals = (w[:, :inner] - np.einsum("jik,jk->ji", Qi[:, :, :n], M[:-1])
                      - Qi[:, :, n] * dT - Qi[:, :, n + 1] * dp)
        nodes = np.empty((mesh.n_nodes, n))
        nodes[::m] = M
        nodes[self._inner_idx] = inner_vals.reshape(ntst, m - 1, n)
        return np.concatenate([nodes.ravel(), [dT, dp]])
