"""Assembly: a consistent configuration, its degrees of freedom, and the internal forces.

* :func:`close_constraints` — Gauss-Newton with minimum-norm steps on ``Phi(q) = 0`` over
  the coordinates that are not held, starting from approximate positions (so the result is
  the consistent configuration nearest the guess, in the least-squares sense).
* :func:`dof_report` — degrees of freedom ``n_q - rank(Phi_q)`` and the redundant
  constraints (rows that add no rank to the rows declared before them), grouped by joint.
* :func:`assemble` — the whole first point of a continuation: close the loops with some
  states held, then solve the equilibrium rows for the joint reactions and any freed loads
  (linear in the reactions: the paper's ``F = A^-1 B``), then polish with Newton.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..equations import EquationSystem
from ..errors import ConvergenceError, InputError

__all__ = ["close_constraints", "dof_report", "DofReport", "assemble"]


def close_constraints(phi: Callable[[np.ndarray], np.ndarray], phi_q: Callable[[np.ndarray], np.ndarray],
                      x: np.ndarray, q_index: np.ndarray, free: np.ndarray, *,
                      tol: float = 1e-12, max_iter: int = 60,
                      scale: np.ndarray | None = None,
                      step_scale: np.ndarray | None = None,
                      row_scale: np.ndarray | None = None) -> tuple[np.ndarray, bool]:
    """Minimise ``|Phi|`` over the coordinates ``free`` (positions in ``q_index``) from ``x``.

    Parameters
    ----------
    phi, phi_q:
        Callables of the full vector: constraint residuals and their coordinate Jacobian.
    x:
        Full variable vector (start; held coordinates keep their values).
    q_index:
        Position in ``x`` of each coordinate (columns of ``phi_q``).
    free:
        Boolean mask over the coordinates: which ones may move.
    tol:
        Target ``max |Phi|`` (m for position constraints); with ``scale``, relative to each row's size
        ``sum_j |dPhi_i/dq_j| scale_j`` instead.
    scale:
        Typical magnitude of each coordinate (the mechanism's length for a position, 1 for an angle):
        the steps are least-squares in these units and the target relative to them, so the closure is
        the same whatever units the description is written in. None: unit weights, ``tol`` absolute.
    step_scale:
        The size of each coordinate the minimum-norm steps are measured in, when not ``scale`` (which then
        sets only the target): the generators' first assembly passes one SI unit of each coordinate in the
        description's units (1000 for a length in mm, 1 for an angle, all 1 in SI), so its steps, which choose
        the default pose of every shipped description, are those of the SI file in any units.
    row_scale:
        With ``step_scale``: one SI unit of each row's residual in the description's units (1000 for a
        position row in mm, 1 for a normalisation or an angle row). The least-squares steps and the descent
        test weigh the rows in SI, so a redundant closure (rows the linearisation cannot all meet) takes the
        SI file's steps too. None: the rows as they are.

    Returns
    -------
    (x, converged):
        The improved vector and whether ``max |Phi| <= tol`` was reached (otherwise ``x`` is
        the best least-squares point found: the loops cannot close).
    """
    x = np.array(x, dtype=float)
    cols = np.flatnonzero(free)
    idx = q_index[cols]
    size = np.ones(len(q_index)) if scale is None else np.asarray(scale, dtype=float)
    weight = size if step_scale is None else np.asarray(step_scale, dtype=float)
    per_row = 1.0 if row_scale is None else 1.0 / np.asarray(row_scale, dtype=float)

    # tol per row: absolute, or relative to the row's size in the coordinates' units
    def target(y: np.ndarray) -> float | np.ndarray:
        return tol if scale is None else tol * (np.abs(phi_q(y)) * size).sum(axis=1)

    r = phi(x)
    for _ in range(max_iter):
        if r.size == 0 or np.all(np.abs(r) <= target(x)):
            return x, True
        A = phi_q(x)[:, cols]
        step, *_ = np.linalg.lstsq(A * weight[cols] * np.reshape(per_row, (-1, 1)), -r * per_row, rcond=1e-12)
        step *= weight[cols]
        norm0, t = np.linalg.norm(r * per_row), 1.0
        while t > 1e-6:
            trial = x.copy()
            trial[idx] += t * step
            r_new = phi(trial)
            if np.all(np.isfinite(r_new)) and np.linalg.norm(r_new * per_row) < norm0:
                break
            t *= 0.5
        else:
            return x, False  # no descent: a least-squares minimum with |Phi| > 0
        x, r = trial, r_new
        if np.linalg.norm(t * step / weight[cols]) <= 1e-15 * (1 + np.linalg.norm(x[idx] / weight[cols])):
            break
    return x, bool(r.size == 0 or np.all(np.abs(r) <= target(x)))


@dataclass(frozen=True)
class DofReport:
    """Degrees of freedom at a configuration.

    Attributes
    ----------
    dof:
        ``n_q - rank(Phi_q)``.
    rank:
        Numerical rank of the constraint Jacobian.
    redundant:
        Groups of joints whose constraints are linearly dependent, one group per redundant
        constraint (the dependent row's joint first, then the joints of the independent rows
        it is a combination of: together they are statically indeterminate).
    dependent:
        Indices of the dependent (redundant) constraint rows, one per group: walking the
        rows in declaration order, a row is dependent when it adds nothing to the rank of
        the rows before it (so the later-declared joint is the one reported as redundant).
    """

    dof: int
    rank: int
    redundant: tuple[tuple[str, ...], ...]
    dependent: tuple[int, ...] = ()

    @property
    def redundant_joints(self) -> tuple[str, ...]:
        """Every joint involved in a redundancy, in order of first appearance."""
        out: list[str] = []
        for group in self.redundant:
            out.extend(j for j in group if j not in out)
        return tuple(out)


def dof_report(phi_q: np.ndarray, row_joints: Sequence[str], rtol: float = 1e-9) -> DofReport:
    """Degrees of freedom and redundant constraints of a constraint Jacobian.

    Parameters
    ----------
    phi_q:
        Constraint Jacobian ``Phi_q`` (n_c x n_q) at an assembled configuration.
    row_joints:
        The joint of each row (names used in the report).
    rtol:
        Singular values below ``rtol`` times the largest count as zero.

    Returns
    -------
    DofReport
        ``dof = n_q - rank``; each row that is a linear combination of the rows declared
        before it is a redundant constraint, reported with the joints of the rows that
        combine into it (coefficients above ``1e-8`` of the largest).
    """
    phi_q = np.atleast_2d(np.asarray(phi_q, dtype=float))
    n_c, n_q = phi_q.shape
    if n_c == 0:
        return DofReport(n_q, 0, ())
    # row scaling: a row in metres and a row in radians weigh alike
    norms = np.linalg.norm(phi_q, axis=1)
    A = phi_q / np.where(norms > 0, norms, 1.0)[:, None]
    sv = np.linalg.svd(A, compute_uv=False)
    tol = rtol * max(sv[0] if sv.size else 0.0, 1e-300)
    rank = int(np.sum(sv > tol))
    independent: list[int] = []
    dependent: list[int] = []
    for row in range(n_c):
        if norms[row] == 0:
            dependent.append(row)
            continue
        trial = np.linalg.svd(A[independent + [row]], compute_uv=False)
        if trial.size == len(independent) + 1 and trial[-1] > tol:
            independent.append(row)
        else:
            dependent.append(row)
    groups = []
    for row in dependent:
        coef, *_ = np.linalg.lstsq(A[independent].T, A[row], rcond=None) if independent else (np.zeros(0),)
        scale = max(np.abs(coef).max(initial=0.0), 1e-300)
        involved = [row_joints[row]]
        for c, i in zip(coef, independent):
            if abs(c) > 1e-8 * max(scale, 1.0) and row_joints[i] not in involved:
                involved.append(row_joints[i])
        groups.append(tuple(involved))
    return DofReport(n_q - rank, rank, tuple(groups), tuple(dependent))


def assemble(system: EquationSystem, values: Mapping[str, float] | None = None,
             hold: Mapping[str, float] | None = None, free: Iterable[str] = (), guess: np.ndarray | None = None,
             *, tol: float = 1e-10, max_iter: int = 30) -> np.ndarray:
    """An equilibrium of a generated mechanism system from approximate positions.

    Parameters
    ----------
    system:
        A system with ``mechanics`` (e.g. from :meth:`Mechanism.build`).
    values:
        Parameter (or state) values to set first, by name (SI).
    hold:
        States held at given values, e.g. ``{"theta1": 0.3}`` (one per degree of freedom).
    free:
        Parameters solved for instead, e.g. ``["F"]`` (as many as held states).
    guess:
        Full starting vector (default: the system's default values).
    tol:
        Convergence tolerance on the scaled residual.

    Returns
    -------
    numpy.ndarray
        Full variable vector (ordered like ``system.names``) satisfying all equations.

    Raises
    ------
    InputError
        Unknown names, or a count of unknowns different from the number of equations.
    ConvergenceError
        The loops cannot close at the held values, or Newton did not converge.
    """
    hold, free = dict(hold or {}), list(free)
    x = system.vector(values, base=guess)
    x = system.vector(hold, base=x)
    states = [n for n in system.state_names if n not in hold]
    for n in free:
        system.index(n)
    unknowns = states + [n for n in free if n not in states]
    if len(unknowns) != system.n_equations:
        raise InputError("free", f"{system.n_equations} equations but {len(unknowns)} unknowns; hold as many "
                                 f"states as you free parameters (held {len(hold)}, freed {len(free)})")
    mech = system.mechanics
    if mech is None:
        raise InputError("system", f"model '{system.name}' has no mechanics: only a mechanism's model can be assembled")
    q_index = mech.q_index
    free_q = np.array([system.names[i] not in hold for i in q_index])
    x, ok = close_constraints(mech.phi, mech.phi_q, x, q_index, free_q, scale=system.scales()[q_index])
    if not ok:
        raise ConvergenceError(f"the constraints cannot be satisfied with {hold or 'the given values'} "
                               f"(max |Phi| = {np.max(np.abs(mech.phi(x))):.3g})", partial=x)
    u_idx = np.array([system.index(n) for n in unknowns])
    scale = system.scales()[u_idx]
    # Newton on every unknown: the coordinates are already consistent, so the first
    # steps are the linear solve for the reactions (and freed loads), F = A^-1 B.
    for _ in range(max_iter):
        r = system.residual(x)
        J = system.jacobian(x)[:, u_idx] * scale
        try:
            step = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            step, *_ = np.linalg.lstsq(J, -r, rcond=None)
        x[u_idx] += step * scale
        if np.max(np.abs(step)) <= tol:
            break
    r = system.residual(x)
    # each row against the size of its terms at the unknowns' scales: a file in millimetres and grams has
    # rows a million times larger, solved as well
    size = (np.abs(system.jacobian(x)[:, u_idx]) * scale).sum(axis=1)
    if not np.all(np.isfinite(r)) or not np.all(np.abs(r) <= 1e-8 * size):
        raise ConvergenceError(f"assembly did not converge (max residual {np.max(np.abs(r)):.3g})", partial=x)
    return x
