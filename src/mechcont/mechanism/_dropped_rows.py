"""Which redundant rigid rows of a (spatial) closure to drop, and how well the kept ones are
conditioned (rows scaled to unit length; see :class:`.spatial._generate._RowChoice` for why the choice
is made again along a branch)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.linalg import qr

__all__ = ["SWITCH_RATIO", "conditioning", "choose_dropped"]


#: The dropped rows are chosen again where the kept rigid rows come this close to losing rank:
#: their smallest singular value over the rank-th one of all the rigid rows (rows scaled to unit
#: length; 1 at best, 0 where the kept rows are dependent). A fresh choice scores far above it
#: (:func:`choose_dropped`; 0.45 to 0.75 on the Bennett linkage), so the choice does not chatter,
#: and the reactions, which grow like its inverse near the singularity, stay within about
#: 1 / SWITCH_RATIO times the minimum-norm ones (10 times on the Bennett linkage's turn).
SWITCH_RATIO = 0.05


def unit_rows(A: np.ndarray) -> np.ndarray:
    norms = np.linalg.norm(A, axis=1)
    return A / np.where(norms > 0, norms, 1.0)[:, None]


def _rank(sv: np.ndarray, rtol: float = 1e-9) -> int:
    return int(np.sum(sv > rtol * max(sv[0], 1e-300))) if sv.size else 0


def conditioning(A: np.ndarray, dropped: Sequence[int]) -> float:
    """How far the rows of ``A`` left after ``dropped`` are from losing rank, relative to all of ``A``'s:
    ``sigma_min(kept) / sigma_rank(all)`` of the rows scaled to unit length, in [0, 1] (interlacing)."""
    B = unit_rows(A)
    sv = np.linalg.svd(B, compute_uv=False)
    r = _rank(sv)
    if r == 0:
        return 1.0
    kept = np.delete(B, list(dropped), axis=0)
    sk = np.linalg.svd(kept, compute_uv=False)
    return float(sk[r - 1] / sv[r - 1]) if len(sk) >= r else 0.0


def choose_dropped(A: np.ndarray, protect: np.ndarray) -> tuple[int, ...]:
    """The rows of ``A`` to drop so that the rest are independent and well conditioned: QR with column
    pivoting of ``A^T`` (rows scaled to unit length) takes, one by one, the row farthest from the span
    of those taken; the rows left after ``rank`` are dropped. ``protect`` rows (the Euler-parameter
    normalisations, independent of everything else) are weighted so that they are taken first."""
    B = unit_rows(A) * np.where(protect, 10.0, 1.0)[:, None]
    r = _rank(np.linalg.svd(unit_rows(A), compute_uv=False))
    _, _, piv = qr(B.T, mode="economic", pivoting=True)
    return tuple(sorted(int(i) for i in piv[r:]))
