"""Where the compiled statics group puts each derivative in its one flat output (``_StaticsLayout``), and
views of a compiled function's output as one dense array (``_Part``): the bookkeeping of
:class:`~._mechanics.MechanicalModel`'s compiled code, apart from the mechanics."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
import numpy.typing as npt

__all__ = ["_flat", "_StaticsLayout", "_Part"]


def _flat(entries: Sequence[tuple[tuple[int, ...], object]], shape: tuple[int, ...]) -> np.ndarray:
    """Flat (C-order) positions in an array of ``shape`` of the indices of ``(index, expr)`` entries."""
    if not entries:
        return np.zeros(0, dtype=np.intp)
    return np.asarray(np.ravel_multi_index(np.array([i for i, _ in entries], dtype=np.intp).T, shape), dtype=np.intp)


class _StaticsLayout:
    """Where the values of the compiled statics function go: Phi_q, Q, dQ/dq, Hess(Phi_k).

    Small models (at most ``DENSE_MAX`` entries in all) compute every entry, zeros
    included, in the order Phi_q, Q, dQ/dq, Hess(Phi) (C order each): the blocks are views
    and the curvature term one small product. Larger ones compute only the non-zero entries
    (of Phi_q, then Q, dQ/dq, the Hessians): they are scattered with index arrays and the
    Hessians contracted with the multipliers by ``bincount``; no Python loop over positions.
    """

    def __init__(self, nc: int, nq: int, a_pos: npt.ArrayLike, dq_pos: npt.ArrayLike, hess_k: npt.ArrayLike,
                 hess_ij: npt.ArrayLike, dense: bool) -> None:
        self.nc, self.nq, self.dense = nc, nq, dense
        self.a_pos, self.dq_pos = np.asarray(a_pos, np.intp), np.asarray(dq_pos, np.intp)
        self.hess_k, self.hess_ij = np.asarray(hess_k, np.intp), np.asarray(hess_ij, np.intp)
        if dense:
            na, nd, nh = nc * nq, nq * nq, nc * nq * nq
        else:
            na, nd, nh = len(self.a_pos), len(self.dq_pos), len(self.hess_k)
        self.a_slice = slice(0, na)
        self.q_slice = slice(na, na + nq)
        self.dq_slice = slice(na + nq, na + nq + nd)
        self.hess_slice = slice(na + nq + nd, na + nq + nd + nh)
        self.size = na + nq + nd + nh

    def positions(self) -> np.ndarray:
        """Flat positions, in the dense layout, of the entries in the order they are listed."""
        o = self.nc * self.nq + self.nq
        hess = self.hess_k * (self.nq * self.nq) + self.hess_ij
        return np.concatenate([self.a_pos, self.nc * self.nq + np.arange(self.nq, dtype=np.intp), o + self.dq_pos,
                               o + self.nq * self.nq + hess]).astype(np.intp)

    def constraint_jacobian(self, vals: np.ndarray) -> np.ndarray:
        """Phi_q (n_c x n_q) from the statics values."""
        if self.dense:
            return vals[self.a_slice].reshape(self.nc, self.nq)
        A = np.zeros(self.nc * self.nq)
        A[self.a_pos] = vals[self.a_slice]
        return A.reshape(self.nc, self.nq)

    def constraint_jacobians(self, vals: np.ndarray) -> np.ndarray:
        """Phi_q of every row of ``vals`` (shape (m, size)): array (m, n_c, n_q)."""
        m = len(vals)
        if self.dense:
            return vals[:, self.a_slice].reshape(m, self.nc, self.nq)
        A = np.zeros((m, self.nc * self.nq))
        A[:, self.a_pos] = vals[:, self.a_slice]
        return A.reshape(m, self.nc, self.nq)

    def stiffnesses(self, vals: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """K of every row of ``vals`` (shape (m, size)) with the multipliers ``lam`` (m, n_c): (m, n_q, n_q)."""
        m, nq, nc = len(vals), self.nq, self.nc
        if self.dense:
            K = -vals[:, self.dq_slice].reshape(m, nq, nq)
            if nc:
                K = K + (lam[:, None, :] @ vals[:, self.hess_slice].reshape(m, nc, nq * nq)).reshape(m, nq, nq)
            return K
        K = np.zeros((m, nq * nq))
        K[:, self.dq_pos] = -vals[:, self.dq_slice]
        if len(self.hess_k):
            w = lam[:, self.hess_k] * vals[:, self.hess_slice]
            flat = (np.arange(m)[:, None] * (nq * nq) + self.hess_ij[None, :]).reshape(-1)
            K += np.bincount(flat, weights=w.reshape(-1), minlength=m * nq * nq).reshape(m, nq * nq)
        return K.reshape(m, nq, nq)

    def stiffness(self, vals: np.ndarray, lam: np.ndarray | None) -> np.ndarray:
        """K = -dQ/dq + sum_k lam_k Hess(Phi_k) (n_q x n_q) from the statics values."""
        nq = self.nq
        K: np.ndarray
        if self.dense:
            K = -vals[self.dq_slice].reshape(nq, nq)
            if lam is not None and self.nc:
                K = K + (np.asarray(lam, dtype=float) @ vals[self.hess_slice].reshape(self.nc, nq * nq)).reshape(nq, nq)
            return K
        K = np.zeros(nq * nq)
        K[self.dq_pos] = -vals[self.dq_slice]
        if lam is not None and len(self.hess_k):
            K += np.bincount(self.hess_ij, weights=np.asarray(lam, dtype=float)[self.hess_k] * vals[self.hess_slice],
                             minlength=nq * nq)
        return K.reshape(nq, nq)


class _Part:
    """``f(x) -> ndarray``: a slice of another compiled function's values, scattered into ``shape``
    (or, with ``pos`` None, the slice itself reshaped)."""

    def __init__(self, source: Callable[[npt.ArrayLike], np.ndarray], part: slice, pos: np.ndarray | None,
                 shape: tuple[int, ...]) -> None:
        self.source, self.part, self.shape = source, part, tuple(shape)
        self.pos = None if pos is None else np.asarray(pos, np.intp)

    def __call__(self, x: npt.ArrayLike) -> np.ndarray:
        if self.pos is None:
            return self.source(x)[self.part].reshape(self.shape)
        out = np.zeros(int(np.prod(self.shape, dtype=np.int64)))
        out[self.pos] = self.source(x)[self.part]
        return out.reshape(self.shape)
