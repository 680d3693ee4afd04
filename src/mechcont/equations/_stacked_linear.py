"""The stacked algebra of a mechanism's linearisation at many points at once (``MechanismDynamics._reduced`` and
``linearise_near``): the allowed motions and reactions of each row from its constraint Jacobian, the reduced
mass, damping, stiffness and element-state blocks, and the state matrices ``(A, E)``, by stacked NumPy calls
instead of one Python step per row.

These matrices are small (a few degrees of freedom, constraint Jacobians of a few rows) and a Hopf polish asks
for five of them per Newton iteration, so the cost is the number of NumPy calls, not their arithmetic: one
singular value decomposition (of the reference row) instead of one per row, the blocks of each row's products
in two stacked products, the state matrix's rows written whole."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.linalg.lapack import dgesv as _dgesv
from scipy.linalg.lapack import dsyevd as _dsyevd

from .. import _dense
from ..errors import ConvergenceError
from ._stability import constraint_rank

__all__ = ["Reduced", "motions_and_reactions", "positive_definite", "reduced_blocks", "stacked_ranks", "state_matrices"]


def positive_definite(Mr: np.ndarray) -> bool:
    """Whether every reduced mass of the stack ``Mr`` (m, d, d) is positive definite with every eigenvalue above
    1e-12 of its largest (one stacked eigenvalue call; none for one degree of freedom, whose mass is its
    eigenvalue)."""
    # the eigenvalues of the lower triangles: Mr = N^T M N is symmetric to rounding
    if Mr.shape[1] == 1:
        w = Mr[:, 0]
    elif len(Mr) == 1:  # one matrix (a single linearisation): LAPACK's dsyevd, as np.linalg.eigvalsh calls it
        w1, _, info = _dsyevd(Mr[0], compute_v=0, lower=1)
        if info:
            raise np.linalg.LinAlgError("Eigenvalues did not converge")
        w = w1[None]
    else:
        w = np.linalg.eigvalsh(Mr)
    return bool(np.all(w[:, 0] > 1e-12 * np.maximum(w[:, -1], 1e-300)))


def _solve(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``np.linalg.solve(A, B)`` of the stacks ``A`` (m, n, n) and ``B`` (m, n, k); a stack of one by LAPACK's
    ``dgesv`` called directly (what ``np.linalg.solve`` calls, without its stacked-call overhead)."""
    if len(A) != 1:
        return np.linalg.solve(A, B)
    _, _, X, info = _dgesv(A[0], B[0])
    if info:
        raise np.linalg.LinAlgError("Singular matrix")
    return X[None]


def stacked_ranks(P: np.ndarray, sv: np.ndarray, kept: int) -> np.ndarray:
    """Each row's :func:`constraint_rank` of the stacked constraint Jacobians ``P`` with singular values ``sv``,
    at most ``kept``: decided for all rows at once where each is full rank or its small singular values are
    zeros to rounding (the usual case: no rescaled decomposition), row by row otherwise."""
    top = np.maximum(sv[:, 0], 1e-300)[:, None]
    r = np.count_nonzero(sv > 1e-10 * top, axis=1)
    small = (sv > 1e-14 * top) & (np.arange(sv.shape[1])[None, :] >= r[:, None])
    if small.any():
        r = np.array([constraint_rank(P[i], sv[i]) for i in range(len(P))])
    return np.minimum(r, kept)


def motions_and_reactions(P: np.ndarray, Q: np.ndarray, kept: int, project: bool) -> tuple[np.ndarray, np.ndarray]:
    """``(N, lam)`` of every row of the stacked constraint Jacobians ``P`` (m, n_c, n_q) with the forces ``Q``
    (m, n_q): a basis ``N`` (m, n_q, d) of each row's allowed motions (the null space of its ``Phi_q``) and the
    reactions ``lam`` (m, n_c), the least-squares solution of ``Phi_q^T lam = Q`` (the least-norm one where rows
    are redundant), the rank held at most ``kept`` (the partition's).

    ``project`` False: each row's ``N`` is its own right singular vectors beyond the rank (orthonormal). True:
    the first row's, projected onto each row's null space (a basis that moves smoothly with the row, for
    differences of the linearisation; orthonormal at the first row, to second order in the rows' distance
    elsewhere). Raises :class:`~mechcont.errors.ConvergenceError` where the rank differs between rows and
    ``project`` is False.

    The usual case (the first row of full row rank and every other row close enough to it that its rank cannot
    differ, by Weyl's bound on the singular values: ``|sv_i - sv_0| <= ||P_i - P_0||``) takes one decomposition,
    of the first row: with ``P_0 = U S V^T``, each row's ``W_i = S^-1 U^T P_i`` spans its row space with
    ``W_0 = V^T``, so ``W_i W_i^T`` is the identity plus the rows' differences and the least-squares solves of
    every row (``N_i = N_0 - W_i^T (W_i W_i^T)^-1 W_i N_0``, ``lam_i = U S^-1 (W_i W_i^T)^-1 W_i Q_i``) are as
    well conditioned as the decomposition itself: the same matrices as each row's own decomposition, to
    rounding. Otherwise each row is decomposed."""
    m, nc, nq = P.shape
    if nc == 0 or m == 0:  # no constraints: every motion allowed, no reactions
        return np.repeat(np.eye(nq)[None], m, axis=0), np.zeros((m, nc))
    U0, s0, Vt0 = _dense.svd(P[0])
    # full row rank (the usual case: constraint_rank's test, without its call) or the rank decided again
    r = nc if nc <= min(nq, kept) and s0[-1] > 1e-10 * max(s0[0], 1e-300) else min(constraint_rank(P[0], s0), kept)
    if m == 1:
        lam = U0[:, :r] @ ((Vt0[:r] @ Q[0]) / s0[:r])
        return Vt0[r:].T[None], lam[None]
    if project and r == nc:
        # ||P_i - P_0||_2 <= ||P_i - P_0||_F <= sqrt(n_c n_q) max |P_i - P_0|
        far = float(np.sqrt(nc * nq) * abs(P - P[0]).max())
        if s0[-1] - far > 1e-10 * (s0[0] + far):
            d = nq - r
            W = (U0.T / s0[:, None]) @ P
            B = np.empty((m, nq, d + 1))
            B[:, :, :d] = Vt0[r:].T
            B[:, :, d] = Q
            Y = np.linalg.solve(W @ W.transpose(0, 2, 1), W @ B)
            return B[:, :, :d] - W.transpose(0, 2, 1) @ Y[:, :, :d], Y[:, :, d] @ (U0 / s0).T
    U, sv, Vt = np.linalg.svd(P)
    ranks = stacked_ranks(P, sv, kept)
    r = int(ranks[0])
    if np.all(ranks == r):
        V = Vt[:, :r]
        lam = (U[:, :, :r] @ ((V @ Q[:, :, None])[:, :, 0] / sv[:, :r])[:, :, None])[:, :, 0]
        if not project:
            return Vt[:, r:].transpose(0, 2, 1), lam
        N0 = Vt0[r:].T  # the first row's as in every other case (any basis of a row space gives one projection)
        return N0[None] - V.transpose(0, 2, 1) @ (V @ N0), lam
    if not project:
        raise ConvergenceError("the constraints' rank changes between the points linearised together")
    # off the constraint manifold (a linearisation differenced in a coordinate: the Hopf test's gradient) redundant
    # rows turn independent by the size of the step; held at the first row's rank, the allowed motions and the
    # reactions vary smoothly instead of losing a dimension
    lam = np.array([U[i, :, :k] @ ((Vt[i, :k] @ Q[i]) / sv[i, :k]) for i, k in enumerate(ranks)])
    N0 = Vt0[r:].T
    return np.array([N0 - Vt[i, :k].T @ (Vt[i, :k] @ N0) for i, k in enumerate(ranks)]), lam


class Reduced(NamedTuple):
    """The reduced matrices of a stack of linearisations (each (m, ., .)), laid out as the state matrix takes
    them: the reduced mass ``Mr``, the accelerations' rows ``[-Kr | -Cr]`` (stiffness and damping, negated), the
    element states' forces ``Br``, the states' rates along the allowed motions ``[Rq N | Rv N]`` and ``Rs``."""

    Mr: np.ndarray
    KC: np.ndarray
    Br: np.ndarray
    R: np.ndarray
    Rs: np.ndarray

    def matrices(self) -> tuple[np.ndarray, ...]:
        """``(Mr, Cr, Kr, Br, Rq N, Rv N, Rs)`` (see ``MechanismDynamics.reduced_matrices``)."""
        d = self.Mr.shape[1]
        return self.Mr, -self.KC[:, :, d:], -self.KC[:, :, :d], self.Br, self.R[:, :, :d], self.R[:, :, d:], self.Rs

    def rows(self, first: int) -> Reduced:
        """The stack from its row ``first`` on."""
        return Reduced(*(part[first:] for part in self))


def reduced_blocks(N: np.ndarray, M: np.ndarray, negC: np.ndarray, negK: np.ndarray, dQs: np.ndarray,
                   J: np.ndarray) -> Reduced:
    """The :class:`Reduced` matrices of every row from the allowed motions ``N`` (m, n_q, d), the mass and the
    negated damping and stiffness ``M, -C, -K`` (m, n_q, n_q), the forces' derivatives in the element states
    ``dQs`` (m, n_q, n_s) and the states' rates' derivatives ``J = dr/d(q, qdot, s)`` (m, n_s, 2 n_q + n_s):
    ``N^T X N`` for the three matrices and ``N^T dQs`` in two stacked products, ``dr/dq N`` and ``dr/dqdot N``
    in one."""
    m, nq, d = N.shape
    ns = dQs.shape[2]
    L = N.transpose(0, 2, 1) @ np.concatenate([negK, negC, M, dQs], axis=2)  # (m, d, 3 n_q + n_s)
    # row i of the (m, d, 3, d) product is (N^T X N)[i] for X = -K, -C, M: the three side by side
    KCM = (L[:, :, :3 * nq].reshape(m, d, 3, nq) @ N[:, None]).reshape(m, d, 3 * d)
    R = (J[:, :, :2 * nq].reshape(m, ns, 2, nq) @ N[:, None]).reshape(m, ns, 2 * d)
    return Reduced(KCM[:, :, 2 * d:], KCM[:, :, :2 * d], L[:, :, 3 * nq:], R, J[:, :, 2 * nq:])


def state_matrices(red: Reduced, descriptor: bool | None) -> tuple[np.ndarray, np.ndarray | None]:
    """``(A, E)`` stacked from the :class:`Reduced` matrices of each row (``MechanismDynamics._reduced``): the
    explicit form where every reduced mass is positive definite (``descriptor`` None) or when ``descriptor`` is
    False, else the descriptor form."""
    m, d, ns = len(red.Mr), red.Mr.shape[1], red.Rs.shape[1]
    A = np.zeros((m, 2 * d + ns, 2 * d + ns))
    E = None
    if d:
        A[:, :d, d:2 * d] = np.eye(d)
        if descriptor is None:
            descriptor = not positive_definite(red.Mr)
        rows = np.concatenate([red.KC, red.Br], axis=2) if ns else red.KC  # (-Kr, -Cr, Br)
        if not descriptor:
            # one solve for the three blocks (Mr is symmetric positive definite and small); one degree of freedom:
            # a division, what the solve's LU does for one unknown
            A[:, d:2 * d] = rows / red.Mr if d == 1 else _solve(red.Mr, rows)
        else:  # a motion without mass (the statics allows massless bodies): the descriptor form, undivided
            E = np.repeat(np.eye(2 * d + ns)[None], m, axis=0)
            E[:, d:2 * d, d:2 * d] = red.Mr
            A[:, d:2 * d] = rows
    if ns:
        A[:, 2 * d:, :2 * d] = red.R
        A[:, 2 * d:, 2 * d:] = red.Rs
    return A, E
