"""Exact sensitivities to parameters: of equilibria, folds and branch points, and of downlock forces.

The derivatives of equilibria, folds and branch points are the engine's
(:mod:`mechcont.continuation._sensitivity`: the implicit-function theorem on exact Jacobians,
nothing differenced), re-exported here; this module adds the downlock force (the lock
condition held, the force among the unknowns) and a branch's columns of derivatives. Results
are in SI units per SI unit (``N/(N/m)`` for a force by a stiffness); angles in radians.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from ..continuation import choose_unknowns
from ..continuation._sensitivity import (
    Sensitivity,
    check_parameters,
    derivative_unit,
    equilibrium_sensitivity,
    fold_sensitivity,
    point_sensitivity,
    write_json,
)
from ..equations import EquationSystem
from ..errors import InputError

__all__ = ["Sensitivity", "equilibrium_sensitivity", "fold_sensitivity", "downlock_sensitivity", "point_sensitivity",
           "derivative_unit", "check_parameters", "write_json", "with_sensitivity_columns"]


def downlock_sensitivity(system: EquationSystem, params: Iterable[str], values: Mapping[str, float] | None = None, *,
                         hold: Mapping[str, float] | None = None, force: str | None = None,
                         condition: str | None = None, x: np.ndarray | None = None) -> Sensitivity:
    """Derivatives of the downlock force (condition held, force solved) with respect to ``params``.

    Solves the downlocked point at ``values`` (:func:`~mechcont.analysis.downlock.downlock_point`)
    unless ``x`` gives it, then :func:`equilibrium_sensitivity` with the condition's states
    held and the force among the unknowns. Returns a :class:`Sensitivity` of kind
    ``"downlock"`` (N per unit of each parameter).
    """
    from .downlock import downlock_condition, downlock_point

    h, f = downlock_condition(system, hold, force, condition=condition)
    if x is None:
        x = downlock_point(system, values, hold=h, force=f)
    unknowns = choose_unknowns(system, hold=h, free=[f])
    return equilibrium_sensitivity(system, x, unknowns, params, f, kind="downlock")


def with_sensitivity_columns(system: EquationSystem, branch, params: Iterable[str], of: str | None = None):
    """A copy of ``branch`` with ``d<of>_d<p>`` columns: the exact derivative at every row (SI units).

    ``of`` is an unknown of the branch (default: a downlock branch's force), differentiated
    with the continuation parameter held (:func:`equilibrium_sensitivity` at each row). The
    units of the new columns are those of the derivatives (``N/(N/m)``).
    """
    import copy

    from ..continuation import Branch
    from .downlock import DownlockBranch

    of = of or (branch.downlock_force if isinstance(branch, DownlockBranch) else None)
    if of is None:
        raise InputError("sensitivity", "name the unknown of the branch to differentiate")
    params = list(params)
    unknowns = list(branch.unknowns)
    check_parameters(system, params, unknowns)
    X = np.column_stack([branch.column(n) for n in system.names])  # the model's variables (other columns may follow)
    rows = [equilibrium_sensitivity(system, x, unknowns, params, of) for x in X]
    cols = {f"d{of}_d{p}": np.array([r[p] for r in rows]) for p in params}
    units = {f"d{of}_d{p}": rows[0].units[p] if rows else "" for p in params}
    out = copy.copy(branch)  # same type, a downlock branch's own attributes kept
    Branch.__init__(out, (*branch.names, *cols), np.column_stack([branch.values, *cols.values()]), branch.s,
                    branch.n_unstable, branch.labels, branch.special_points, branch.vary, branch.unknowns,
                    branch.status, branch.message, branch.model, {**branch.units, **units})
    return out
