"""Physical stability of a mechanism's equilibria from its compiled mechanics: the reduced tangent stiffness
on the allowed motions (conservative), or the mass-weighted one (non-conservative loads), and the
constraint rank decided independently of units. :class:`~._mechanics.MechanicalModel` delegates here."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .. import _dense

if TYPE_CHECKING:
    from ._mechanics import MechanicalModel

__all__ = ["StabilityResult", "stability", "count_unstable", "constraint_rank"]


@dataclass(frozen=True)
class StabilityResult:
    """Stability of one equilibrium.

    Attributes
    ----------
    n_unstable:
        Number of unstable directions (negative stiffness eigenvalues, or eigenvalues
        with negative real part / complex pairs for non-conservative loads).
    eigenvalues:
        Eigenvalues of the reduced stiffness ``Z^T K Z`` (conservative, units of the
        stiffness) or of ``(Z^T M Z)^-1 Z^T K Z`` (omega^2, 1/s^2) otherwise.
    conservative:
        Whether the reduced stiffness was symmetric.
    """

    n_unstable: int
    eigenvalues: np.ndarray
    conservative: bool

    @property
    def stable(self) -> bool:
        """True when no direction is unstable."""
        return self.n_unstable == 0


def stability(mech: MechanicalModel, x: np.ndarray, rtol: float = 1e-9, held: np.ndarray | None = None) -> StabilityResult:
    """Physical stability of the equilibrium at ``x`` (a full variable vector).

    ``held`` (optional, shape (k, n_q)): gradients of further relations held fixed, e.g. a
    stop in contact (its reaction's curvature is already in the forces); the motions they
    forbid are removed from the tangent space as the joints' are.

    Reduces the tangent stiffness to the constraint tangent space, ``Kr = Z^T K Z``.
    Conservative (symmetric ``Kr``): the number of negative eigenvalues is the number
    of unstable directions. Otherwise the eigenvalues ``mu`` of
    ``(Z^T M Z)^-1 Kr`` (small oscillations ``s^2 = -mu``) are used: a direction is
    unstable when ``mu`` has a negative real part or is complex (flutter).
    Eigenvalues within ``rtol`` of the largest magnitude count as zero (neutral).
    The count is independent of the units of ``q`` (Sylvester's law of inertia).
    """
    nq, nc = len(mech.coordinates), mech.n_constraints
    layout = mech._statics_layout
    out = mech._statics(mech._args(x))
    if nc:
        A = layout.constraint_jacobian(out)
        U, sv, Vt = _dense.svd(A)
        svs = sv.tolist()  # the rank counted on floats: the same count, without two array operations
        cut = 1e-10 * max(svs[0], 1e-300)
        r = sum(1 for v in svs if v > cut)
        if r < len(svs):  # rank-deficient as written: decide it on the equilibrated matrix
            r = constraint_rank(A, sv)
        lam = U[:, :r] @ ((Vt[:r] @ out[layout.q_slice]) / sv[:r])
        K = layout.stiffness(out, lam)
    else:
        K = layout.stiffness(out, None)
        Vt, r = np.eye(nq), 0
    Z = Vt[r:].T
    if held is not None and len(held) and Z.shape[1]:
        _, hs, hVt = np.linalg.svd(np.atleast_2d(held) @ Z)
        Z = Z @ hVt[int(np.count_nonzero(hs > 1e-10 * max(hs[0], 1e-300))):].T
    if Z.shape[1] == 0:
        return StabilityResult(0, np.zeros(0), True)
    Kr = Z.T @ K @ Z
    if Kr.shape == (1, 1) and math.isfinite(Kr[0, 0]):
        # one degree of freedom (most gears): Kr is its own eigenvalue; the general path
        # below gives the same answer through five more array operations
        k = float(Kr[0, 0])
        return StabilityResult(int(k < -rtol * max(abs(k), 1e-300)), Kr[0].copy(), True)
    scale = max(np.abs(Kr).max(), 1e-300)
    if np.abs(Kr - Kr.T).max() <= 1e-9 * scale:
        ev = np.linalg.eigvalsh(0.5 * (Kr + Kr.T)) if len(Kr) > 1 else Kr[0].copy()
        return StabilityResult(int(np.sum(ev < -rtol * scale)), ev, True)
    Mr = Z.T @ mech.mass(x) @ Z
    mu = np.linalg.eigvals(np.linalg.solve(Mr, Kr))
    tol = rtol * max(np.abs(mu).max(), 1e-300)
    unstable = (mu.real < -tol) | (np.abs(mu.imag) > tol)
    return StabilityResult(int(np.sum(unstable)), mu, False)

def count_unstable(mech: MechanicalModel, X: np.ndarray, rtol: float = 1e-9) -> np.ndarray:
    """Number of unstable directions at every row of ``X`` (full vectors, shape (m, n_variables)).

    The same counts as :meth:`stability` (``n_unstable``) row by row, at a fraction
    of the cost on a branch's worth of points: one call of the compiled statics for all
    rows, stacked SVDs and products. Stacked products may round differently in the last
    bits, so a row whose reduced stiffness is within ``1e-8`` of its scale of zero (a
    fold, where the count is decided by rounding), a row whose constraint rank differs
    from the most common one along ``X`` (redundant rows that persist along a branch, as in
    an over-constrained linkage, are batched like the others) and a non-conservative row go
    through :meth:`stability` itself. Returns an integer array (m,).
    """
    X = np.asarray(X, dtype=float)
    m, nq, nc = len(X), len(mech.coordinates), mech.n_constraints
    if X.ndim != 2 or m == 0:
        return np.array([mech.stability(x, rtol).n_unstable for x in X], dtype=int)
    layout = mech._statics_layout
    args = np.zeros((m, X.shape[1] + nq))
    args[:, :X.shape[1]] = X
    out = mech._statics.batch(args)
    Q = out[:, layout.q_slice]
    if nc:
        A = layout.constraint_jacobians(out)
        U, sv, Vt = np.linalg.svd(A)
        ranks = np.count_nonzero(sv > 1e-10 * np.maximum(sv[:, :1], 1e-300), axis=1)  # stability()'s cut
        for i in np.flatnonzero(ranks < sv.shape[1]):  # as stability() decides a deficient rank
            ranks[i] = constraint_rank(A[i], sv[i])
        r = int(np.bincount(ranks).argmax())
        full = ranks == r   # the other rows through stability() itself
        lam = np.einsum("mij,mj->mi", U[:, :, :r], np.einsum("mij,mj->mi", Vt[:, :r], Q) / sv[:, :r])
        K = layout.stiffnesses(out, lam)
        Z = np.swapaxes(Vt[:, r:], 1, 2)
    else:
        full = np.ones(m, dtype=bool)
        K = layout.stiffnesses(out, np.zeros((m, 0)))
        Z = np.broadcast_to(np.eye(nq), (m, nq, nq))
    d = Z.shape[2]
    if d == 0:
        return np.array([0 if full[i] else mech.stability(X[i], rtol).n_unstable for i in range(m)], dtype=int)
    Kr = np.swapaxes(Z, 1, 2) @ K @ Z
    scale = np.maximum(np.abs(K).max(axis=(1, 2)), 1e-300)
    sym = np.abs(Kr - np.swapaxes(Kr, 1, 2)).max(axis=(1, 2)) <= 1e-9 * np.maximum(np.abs(Kr).max(axis=(1, 2)), 1e-300)
    ev = Kr[:, :, 0] if d == 1 else np.linalg.eigvalsh(0.5 * (Kr + np.swapaxes(Kr, 1, 2)))
    clear = full & sym & np.isfinite(ev).all(axis=1) & (np.abs(ev).min(axis=1) > 1e-8 * scale)
    if d == 1:
        cut = rtol * np.maximum(np.abs(ev[:, 0]), 1e-300)
    else:
        cut = rtol * np.maximum(np.abs(Kr).max(axis=(1, 2)), 1e-300)
    counts = np.count_nonzero(ev < -cut[:, None], axis=1)
    for i in np.flatnonzero(~clear):
        counts[i] = mech.stability(X[i], rtol).n_unstable
    return counts


def constraint_rank(A: np.ndarray, sv: np.ndarray, rtol: float = 1e-10) -> int:
    """The rank of the constraint Jacobian ``A`` (rows: constraints, columns: coordinates) whose
    singular values are ``sv``, independent of the units the mechanism is written in.

    A singular value at most ``rtol`` of the largest counts as zero. When ``A`` as written looks
    rank-deficient, the rank is decided again on ``A`` with its rows and columns scaled to unit
    length: a coordinate in micrometres makes a rotation's column 1e6 times a translation's and
    puts a true singular value below the cut, while a redundant row stays dependent under any
    scaling. Nothing is recomputed for a full-rank ``A`` (the usual case), nor where the small
    singular values are zeros to rounding (below 1e-14 of the largest: an exactly redundant row)."""
    if len(sv) == 0:
        return 0
    top = max(float(sv[0]), 1e-300)
    r = int(np.count_nonzero(sv > rtol * top))
    if r == len(sv) or not np.any(sv[r:] > 1e-14 * top):  # full rank, or zeros to rounding: scaling won't lift them
        return r
    rows = np.linalg.norm(A, axis=1)
    cols = np.linalg.norm(A, axis=0)
    B = A / np.where(rows > 0, rows, 1.0)[:, None] / np.where(cols > 0, cols, 1.0)[None, :]
    s = np.linalg.svd(B, compute_uv=False)
    return int(np.count_nonzero(s > rtol * max(float(s[0]), 1e-300))) if len(s) else 0
