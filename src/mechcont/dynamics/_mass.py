"""The mass matrix's inverse square root ``M^-1/2``, whole or block by block (:mod:`._udwadia_kalaba` uses it)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import InputError

__all__ = ["inverse_sqrt", "MassBlocks"]


def inverse_sqrt(M: np.ndarray) -> np.ndarray:
    """Symmetric inverse square root ``M^-1/2`` of a symmetric positive definite matrix.

    Raises :class:`InputError` (field ``mass_matrix``) if ``M`` is not positive definite.
    """
    M = np.asarray(M, float)
    if np.count_nonzero(M - np.diag(np.diag(M))) == 0:
        d = np.diag(M)
        if np.any(d <= 0):
            raise InputError("mass_matrix", "must be positive definite (a mass or inertia is <= 0)")
        return np.diag(1.0 / np.sqrt(d))
    w, V = np.linalg.eigh(0.5 * (M + M.T))
    if w.min() <= 0:
        raise InputError("mass_matrix", "must be positive definite (an eigenvalue is <= 0)")
    return (V / np.sqrt(w)) @ V.T


class MassBlocks:
    """The block-diagonal structure of a mass matrix: its coupled coordinates (the connected components
    of its non-zero pattern), grouped by block size, so that :meth:`inverse_sqrt` decomposes each block
    (one batched ``eigh`` per size) instead of the whole matrix.

    ``pattern`` is the set of ``(i, j)`` positions that may be non-zero (from the symbolic matrix)."""

    def __init__(self, n: int, pattern: Sequence[Sequence[int]]) -> None:
        parent = list(range(n))

        def root(i: int) -> int:
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        for i, j in pattern:
            parent[root(i)] = root(j)
        blocks: dict[int, list[int]] = {}
        for i in range(n):
            blocks.setdefault(root(i), []).append(i)
        by_size: dict[int, list[list[int]]] = {}
        for b in blocks.values():
            by_size.setdefault(len(b), []).append(b)
        self.n = n
        self.groups = [np.array(g) for g in by_size.values()]  # each (blocks, size)
        # each group's entries as flat positions in M (blocks, size, size): one take gathers them
        self._flat = [g[:, :, None] * n + g[:, None, :] for g in self.groups]

    def inverse(self, M: np.ndarray) -> np.ndarray:
        """``M^-1`` of a matrix with this structure, block by block (each group's blocks gathered and scattered
        by their flat positions: one ``take``, one batched inverse and one assignment per block size)."""
        flat = np.ascontiguousarray(M, dtype=float).reshape(-1)
        out = np.zeros(self.n * self.n)
        for pos in self._flat:
            out[pos] = np.linalg.inv(flat.take(pos))
        return out.reshape(self.n, self.n)

    def inverse_sqrt(self, M: np.ndarray) -> np.ndarray:
        """``M^-1/2`` of a matrix with this structure (the same as :func:`inverse_sqrt`, block by block)."""
        out = np.zeros((self.n, self.n))
        for g in self.groups:
            rows, cols = g[:, :, None], g[:, None, :]
            B = M[rows, cols]
            w, V = np.linalg.eigh(0.5 * (B + B.transpose(0, 2, 1)))
            if w.min() <= 0:
                raise InputError("mass_matrix", "must be positive definite (an eigenvalue is <= 0)")
            out[rows, cols] = (V / np.sqrt(w)[:, None, :]) @ V.transpose(0, 2, 1)
        return out
