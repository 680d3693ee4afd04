"""Redundant constraint rows in the time simulation: which rows the accelerations are solved with.

An over-constrained mechanism (``redundant = "drop"``: a Bennett or Bricard loop, a planar loop of
spatial joints) has rigid rows that are dependent on the constraint manifold but, a drift of ``d``
away from it, only nearly so: the matrix ``A M^-1 A^T`` of all the rows then has singular values of
the order of ``d``. Deciding their rank by a fixed cut-off (the pseudo-inverse's 1e-8) makes the
right-hand side switch between two different solves as the drift crosses the cut-off: where the
near-dependent rows are inverted, their inconsistent Baumgarte terms divided by ``d`` give
accelerations of 1e6 and more, the integrator rejects step after step, and the motion crawls and
loses energy (the Bricard loop stalled at 0.38 s).

Here, as in the statics (:mod:`mechcont.mechanism._dropped_rows`), the rank is structural: the
model says how many rows are redundant (``Model.dropped_constraints``), and that many are left out
of the solve, chosen by QR with column pivoting of the rows scaled to unit length (the rows farthest
from the span of those taken are kept). The kept rows are independent, so the solve is the regular
Cholesky one (as fast as a mechanism without redundancy), smooth in the state; on the manifold the
dropped rows are implied by the kept ones, so the accelerations are those of the Moore–Penrose form.
Where the kept rows come close to losing rank along the motion (their conditioning below
:data:`SWITCH_RATIO` of what it was when they were chosen) they are chosen again; the dropped rows'
multipliers are zero in that solve; the history reports the minimum-norm ones (:meth:`KeptRows.minimum_norm`:
the self-stresses taken out, so the reactions do not jump where the rows are chosen again), flagged as
statically indeterminate.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import qr

from ..mechanism import SWITCH_RATIO, unit_rows

__all__ = ["KeptRows", "SWITCH_RATIO"]


class KeptRows:
    """The joint rows the accelerations are solved with, when ``n_drop`` of them are redundant.

    :meth:`select` gives the indices of the kept rows; :meth:`stale` watches their conditioning through the
    solve's own Cholesky factor (its diagonal spread, :func:`~._udwadia_kalaba._cholesky_solve`) and chooses
    them again where it falls below :data:`SWITCH_RATIO` of its value when they were chosen. ``changes`` holds
    the times at which they were chosen again, ``singular`` those where even the new choice was no better
    (the whole set lost rank: a singular configuration), ``dropped`` the rows left out now."""

    def __init__(self, n_drop: int) -> None:
        self.n_drop = int(n_drop)
        self.keep: np.ndarray | None = None
        self.dropped: tuple[int, ...] = ()
        self.reference: float | None = None  # the solve's spread with the rows as chosen
        self.changes: list[float] = []
        self.singular: list[float] = []
        self._before = 0.0
        self._time = 0.0

    def _choose(self, A: np.ndarray) -> None:
        _, _, piv = qr(unit_rows(A).T, mode="economic", pivoting=True)
        n = A.shape[0] - self.n_drop
        self.keep = np.sort(piv[:n])
        self.dropped = tuple(sorted(int(i) for i in piv[n:]))
        self.reference = None

    def select(self, A: np.ndarray) -> np.ndarray:
        """Indices of the rows of ``A`` (all the joints' rows) to solve with."""
        if self.keep is None:
            self._choose(A)
        assert self.keep is not None
        return self.keep

    def stale(self, t: float, A: np.ndarray, spread: list[float]) -> bool:
        """True (and the rows chosen again from ``A``, the joints' rows at time ``t``) when the solve just made
        with the kept rows found them losing rank: ``spread[0]``, its Cholesky factor's diagonal spread, below
        :data:`SWITCH_RATIO` times the first one with these rows (0 where the factorisation failed)."""
        s = spread[0] if spread else 1.0
        if self.reference is None:
            self.reference = s
            return False
        if s >= SWITCH_RATIO * self.reference:
            return False
        self._before = self.reference
        self._choose(A)
        self.changes.append(t)
        self._time = t
        return True

    def rechosen(self, spread: list[float]) -> None:
        """After the solve with the rows chosen again: its spread becomes the reference; a choice no better
        than the one it replaced marks a singular configuration."""
        self.reference = spread[0] if spread else 1.0
        if self.reference < SWITCH_RATIO * self._before:
            self.singular.append(self._time)

    def minimum_norm(self, A: np.ndarray, z: np.ndarray) -> np.ndarray:
        """The multipliers ``z`` (first those of the joint rows ``A``, then any others) with the joint part's
        self-stresses taken out: its component along the ``n_drop`` left singular vectors of ``A`` of the
        smallest singular values (``w`` with ``A^T w = 0`` on the manifold), which change no force. The same
        forces ``A^T z``, the smallest joint multipliers that give them."""
        n = A.shape[0]
        U = np.linalg.svd(A, full_matrices=True)[0]
        W = U[:, n - self.n_drop:]
        out = np.array(z, float)
        out[:n] -= W @ (W.T @ out[:n])
        return out
