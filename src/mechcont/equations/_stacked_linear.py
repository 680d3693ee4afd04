"""The stacked algebra of a mechanism's linearisation at many points at once (``MechanismDynamics._reduced`` and
``linearise_near``): each row's constraint rank, its reduced masses' definiteness, and the state matrices ``(A, E)``
from the reduced mass, damping, stiffness and element-state blocks, by stacked NumPy calls instead of one Python
step per row."""

from __future__ import annotations

import numpy as np

from ._stability import constraint_rank

__all__ = ["positive_definite", "stacked_ranks", "state_matrices"]


def positive_definite(Mr: np.ndarray) -> bool:
    """Whether every reduced mass of the stack ``Mr`` (m, d, d) is positive definite with every eigenvalue above
    1e-12 of its largest (one stacked eigenvalue call)."""
    w = np.linalg.eigvalsh(0.5 * (Mr + Mr.transpose(0, 2, 1)))
    return bool(np.all(w[:, 0] > 1e-12 * np.maximum(w[:, -1], 1e-300)))


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


def state_matrices(mats: tuple[np.ndarray, ...], descriptor: bool | None) -> tuple[np.ndarray, np.ndarray | None]:
    """``(A, E)`` stacked from the reduced matrices ``(Mr, Cr, Kr, Br, Rq N, Rv N, Rs)`` of each row
    (``MechanismDynamics._reduced``): the explicit form where every reduced mass is positive definite
    (``descriptor`` None) or when ``descriptor`` is False, else the descriptor form."""
    Mr, Cr, Kr, Br, Rq, Rv, Rs = mats
    m, d, ns = len(Mr), Mr.shape[1], Rs.shape[1]
    A = np.zeros((m, 2 * d + ns, 2 * d + ns))
    E = None
    if d:
        A[:, :d, d:2 * d] = np.eye(d)
        if descriptor is None:
            descriptor = not positive_definite(Mr)
        if not descriptor:
            # one solve for the three blocks (Mr is symmetric positive definite and small)
            S = np.linalg.solve(Mr, np.concatenate([Kr, Cr, Br], axis=2))
            A[:, d:2 * d, :d], A[:, d:2 * d, d:2 * d], A[:, d:2 * d, 2 * d:] = (
                -S[:, :, :d], -S[:, :, d:2 * d], S[:, :, 2 * d:])
        else:  # a motion without mass (the statics allows massless bodies): the descriptor form
            E = np.repeat(np.eye(2 * d + ns)[None], m, axis=0)
            E[:, d:2 * d, d:2 * d] = Mr
            A[:, d:2 * d, :d], A[:, d:2 * d, d:2 * d], A[:, d:2 * d, 2 * d:] = -Kr, -Cr, Br
    A[:, 2 * d:, :d], A[:, 2 * d:, d:2 * d], A[:, 2 * d:, 2 * d:] = Rq, Rv, Rs
    return A, E
