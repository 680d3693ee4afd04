"""Batched square solves: Newton for many parameter sets of one model at once.

A study asks the same question (hold these states, free that force) at thousands of
parameter sets. One :func:`~mechcont.continuation.find_equilibrium` call costs a few
hundred microseconds of Python around a few microseconds of compiled code; here every
step is done for all rows together: the residual and Jacobian of every row in one call
of the compiled code (:meth:`~mechcont.equations.EquationSystem.residual_and_jacobian_batch`),
the Newton steps by one stacked :func:`numpy.linalg.solve`, and masks that freeze the rows
that have converged.

:func:`newton_batch` is the batched twin of :func:`~mechcont.continuation._newton.newton_square`:
the same damped Newton iteration (full step, halved while the row-scaled residual norm does
not decrease, at most six halvings), the same stopping test (scaled step below ``tol`` and
:func:`~mechcont.continuation._newton.residual_met`), applied row by row. What it does not
do is stop at a singular Jacobian in mid-iteration (the single-point solve estimates the
condition number at every iteration from its LU factors): a row whose last Jacobian is that
ill-conditioned, or that does not converge, or meets a non-finite value, is reported as not
converged, so that the caller hands it to the single-point path (the stragglers).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..equations import EquationSystem
from ._newton import SINGULAR_CONDITION

__all__ = ["BatchSolution", "BatchFolds", "newton_batch", "fold_batch"]

@dataclass(frozen=True)
class BatchSolution:
    """Result of :func:`newton_batch`.

    Attributes
    ----------
    x:
        Full variable vectors, one row per parameter set (SI units); rows that did not
        converge hold the last iterate.
    converged:
        Boolean mask of the rows that met the stopping test.
    iterations:
        Newton iterations used by each row.
    reason:
        Why a row did not converge (``""`` for converged rows).
    """

    x: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    reason: np.ndarray


def _residual_met(r: np.ndarray, J: np.ndarray, u: np.ndarray, tol: float) -> np.ndarray:
    """Row-wise :func:`~mechcont.continuation._newton.residual_met` for stacked ``r (m, n)``, ``J (m, n, n)``."""
    floor = 100 * np.finfo(float).eps * np.abs(J * u[:, None, :]).sum(axis=2)
    return np.all(np.abs(r) <= np.maximum(tol, floor), axis=1)


def _stacked_solve(J: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``J[i]^-1 b[i]`` for every row; rows with a singular ``J[i]`` get nan (one LAPACK call when none is)."""
    with np.errstate(all="ignore"):
        try:
            return np.linalg.solve(J, b[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:  # one singular row spoils the stacked call: solve row by row
            out = np.full(b.shape, np.nan)
            for i in range(len(J)):
                try:
                    out[i] = np.linalg.solve(J[i], b[i])
                except np.linalg.LinAlgError:
                    pass
            return out


def newton_batch(system: EquationSystem, X0: np.ndarray, unknowns: Sequence[str], *, tol: float = 1e-10,
                 residual_tol: float = 1e-10, max_iter: int = 50) -> BatchSolution:
    """Solve ``G(x) = 0`` for the ``unknowns`` at every row of ``X0``, all rows at once.

    Parameters
    ----------
    system:
        The compiled equation system.
    X0:
        Full variable vectors ``(m, n_variables)``: held values and parameters as given,
        the unknowns' entries as the initial guess.
    unknowns:
        Names solved for, one per equation (see
        :func:`~mechcont.continuation.choose_unknowns`).
    tol, residual_tol, max_iter:
        As for :func:`~mechcont.continuation.find_equilibrium`: the scaled Newton step and
        the residuals (or their floating-point floor) must fall below them.

    Returns
    -------
    BatchSolution
        Solutions, the converged mask, iterations and reasons; never raises for a row that
        fails (its reason says why).
    """
    system.compile()
    X = np.array(X0, dtype=float, copy=True)
    if X.ndim != 2 or X.shape[1] != len(system.names):
        raise ValueError(f"expected an array (rows, {len(system.names)} variables), got shape {X.shape}")
    idx = np.array([system.index(n) for n in unknowns])
    if len(idx) != system.n_equations:
        raise ValueError(f"{len(idx)} unknowns for {system.n_equations} equations")
    scale = system.scales()[idx]
    m = len(X)
    converged = np.zeros(m, dtype=bool)
    iterations = np.zeros(m, dtype=int)
    reason = np.full(m, "", dtype=object)
    active = np.arange(m)
    for it in range(1, max_iter + 1):
        if not len(active):
            break
        Xa = X[active]
        r_a, J_full = system.residual_and_jacobian_batch(Xa)  # r_a equals the last line search's residual
        J = J_full[:, :, idx]
        u = Xa[:, idx]
        # rows measured against the size of their terms, as in newton_square
        row = np.abs(J * scale).max(axis=2)
        row[~(row > 0)] = 1.0
        norm = np.linalg.norm(r_a / row, axis=1)
        du = _stacked_solve(J, -r_a)
        bad = ~np.all(np.isfinite(du), axis=1)
        # backtracking line search, row by row: halve lam while the scaled residual norm grows
        lam = np.ones(len(active))
        trial = u.copy()
        r_trial = np.zeros_like(r_a)
        searching = ~bad
        while searching.any():
            s = np.nonzero(searching)[0]
            Xt = Xa[s].copy()
            Xt[:, idx] = u[s] + lam[s, None] * du[s]
            rt = system.residual_batch(Xt)
            with np.errstate(all="ignore"):
                n_trial = np.linalg.norm(rt / row[s], axis=1)
            ok = np.isfinite(n_trial) & ((n_trial < norm[s]) | (lam[s] < 1 / 64) | (n_trial < residual_tol))
            done = s[ok]
            trial[done] = Xt[ok][:, idx]
            r_trial[done] = rt[ok]
            searching[done] = False
            lam[s[~ok]] *= 0.5
        good = ~bad
        iterations[active[good]] = it
        X[active[good][:, None], idx] = trial[good]
        with np.errstate(all="ignore"):
            step = np.max(np.abs(lam[:, None] * du / scale), axis=1)
        met = good & (step < tol) & _residual_met(r_trial, J, trial, residual_tol)
        if met.any():  # the single-point solve would have refused a singular Jacobian
            where = np.nonzero(met)[0]
            with np.errstate(all="ignore"):
                cond = np.linalg.cond(J[where] * scale / row[where][:, :, None])
            singular = where[~(cond <= SINGULAR_CONDITION)]
            reason[active[singular]] = "singular Jacobian at the solution"
            bad[singular] = True
            met[singular] = False
        for i in np.nonzero(bad)[0]:
            if not reason[active[i]]:
                reason[active[i]] = f"singular Jacobian or non-finite step at iteration {it}"
        converged[active[met]] = True
        active = active[~met & ~bad]
    for i in active:
        reason[i] = f"Newton did not converge in {max_iter} iterations"
    return BatchSolution(X, converged, iterations, reason)


@dataclass(frozen=True)
class BatchFolds:
    """Result of :func:`fold_batch`.

    Attributes
    ----------
    x:
        Full variable vectors at the folds (SI units), one row per parameter set.
    v:
        Null vectors over the states (unscaled, unit length), one row each.
    converged:
        Boolean mask of the rows that met the stopping test.
    iterations:
        Newton iterations used by each row.
    """

    x: np.ndarray
    v: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray


def _hessian_contraction(system: EquationSystem, X: np.ndarray, VF: np.ndarray) -> np.ndarray:
    """Row-wise :meth:`~mechcont.equations.EquationSystem.jacobian_derivative`: ``(m, n_eq, n_variables)``."""
    from scipy import sparse

    code = system.compile(second_derivatives=True)._code
    n_eq, n = system.n_equations, len(system.names)
    W = code["hess_values"].batch(X) * VF[:, code["hess_j"]]
    key = "_batch_hess_scatter"
    S = code.get(key)
    if S is None:  # entry k of the second derivatives adds to flat position hess_ik[k]
        nnz = len(code["hess_ik"])
        S = code[key] = sparse.csr_matrix((np.ones(nnz), (code["hess_ik"], np.arange(nnz))), shape=(n_eq * n, nnz))
    return np.asarray(S @ W.T).T.reshape(len(X), n_eq, n)


def fold_batch(system: EquationSystem, X0: np.ndarray, V0: np.ndarray, states: Sequence[str], param: str, *,
               tol: float = 1e-11, residual_tol: float = 1e-10, max_iter: int = 30) -> BatchFolds:
    """Folds in ``param`` near every row of ``X0`` at once: Newton on the standard augmented system.

    The batched twin of :func:`~mechcont.continuation._fold_point.polish_fold`: unknowns the
    ``states``, ``param`` and the null vector ``v_hat`` in equilibrated coordinates
    (``v = col * v_hat``, ``|v_hat| = 1``), equations ``G = 0``, ``G_s col v_hat = 0``,
    ``(|v_hat|^2 - 1)/2 = 0``, rows and columns equilibrated. One scaling serves all rows: it
    is read off the Jacobian at the first row (:func:`~mechcont.continuation._fold_point.fold_scaling`),
    so the rows should be perturbations of one fold (a tolerance study); Newton's iterates do
    not depend on the scaling, only the stopping test is measured in it. Full Newton steps (no
    line search), stopped per row when the scaled step is below ``tol`` and the residuals
    below ``residual_tol`` or their floating-point floor.

    Parameters
    ----------
    system:
        The compiled model.
    X0:
        Full variable vectors ``(m, n_variables)``: each row's parameters, and a guess of its fold.
    V0:
        Guess of the null vector over the states ``(m, len(states))`` or ``(len(states),)``.
    states, param:
        The unknowns whose Jacobian is singular at the fold, and the fold's parameter.

    Returns
    -------
    BatchFolds
        Never raises for a row that fails: it is not in ``converged`` (hand it to the
        single-point path).
    """
    from ._fold_point import fold_scaling

    X = np.array(X0, dtype=float, copy=True)
    m = len(X)
    idx = np.array([system.index(n) for n in [*states, param]])
    n = len(states)
    state_idx = idx[:n]
    row, col = fold_scaling(system, X[0], idx)
    V0 = np.broadcast_to(np.asarray(V0, dtype=float), (m, n))
    VH = V0 / col[:n]
    VH = VH / np.linalg.norm(VH, axis=1, keepdims=True)
    rows = np.concatenate([row, row, [1.0]])
    cols = np.concatenate([col, np.ones(n)])
    converged = np.zeros(m, dtype=bool)
    iterations = np.zeros(m, dtype=int)
    active = np.arange(m)
    n_eq = system.n_equations
    for it in range(1, max_iter + 1):
        if not len(active):
            break
        Xa, vh = X[active], VH[active]
        r, J = system.residual_and_jacobian_batch(Xa)
        Jv = J[:, :, state_idx] * col[:n]
        VF = np.zeros_like(Xa)
        VF[:, state_idx] = col[:n] * vh
        H = _hessian_contraction(system, Xa, VF)
        F = np.concatenate([r, np.einsum("mij,mj->mi", Jv, vh), 0.5 * (np.sum(vh * vh, axis=1, keepdims=True) - 1)], 1)
        JF = np.zeros((len(active), 2 * n_eq + 1, len(idx) + n))
        JF[:, :n_eq, :len(idx)] = J[:, :, idx]
        JF[:, n_eq:2 * n_eq, :len(idx)] = H[:, :, idx]
        JF[:, n_eq:2 * n_eq, len(idx):] = Jv
        JF[:, 2 * n_eq, len(idx):] = vh
        dU = _stacked_solve(JF * rows[:, None] * cols, -rows * F)
        good = np.all(np.isfinite(dU), axis=1)
        U = np.concatenate([Xa[:, idx], vh], axis=1) + cols * np.where(good[:, None], dU, 0.0)
        X[active[:, None], idx] = U[:, :len(idx)]
        VH[active] = U[:, len(idx):]
        iterations[active] = it
        step = np.max(np.abs(dU), axis=1)
        r_new, J_new = system.residual_and_jacobian_batch(X[active])
        met = good & (step < tol) & _residual_met(r_new, J_new[:, :, idx], X[active][:, idx], residual_tol)
        converged[active[met]] = True
        active = active[good & ~met]
    v = col[:n] * VH
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    return BatchFolds(X, v, converged, iterations)
