"""The columns a time history's rows derive from their state: the declared conditions' values
(:func:`fill_conditions`) and the live reactions (:func:`fill_reactions`), each at every row.

A joint's reaction ``R_*``/``T_*`` (and a length-mode actuator's tension) is the Lagrange multiplier of
its constraint row in ``M qddot = Q + Phi_q^T z`` with ``Phi_q qddot = b``, from the same solve as the
accelerations (:meth:`~._udwadia_kalaba.ConstrainedDynamics.multipliers`). The statics writes the
equilibrium rows ``Q - Phi_q^T lambda = 0``, so the reported reaction is ``lambda = -z``: at rest
(``qdot = 0``, ``qddot = 0``) it is the static reaction. A rigid stop in contact reports its contact
reaction (``+z`` of its row, the same multiplier the contact events watch); a compliant stop its
penalty reaction; a compliant joint (a spatial row ``Phi_k - lambda_k / k_k = 0``) ``lambda_k = k_k Phi_k``,
read off its row. With redundant constraints the multipliers are the minimum-norm ones (the solve leaves
the redundant rows out, :mod:`._redundant`; their self-stresses are taken out here).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from ..equations import Model
    from ._udwadia_kalaba import ConstrainedDynamics

__all__ = ["fill_conditions", "fill_reactions"]


def _elastic_rows(system: Model, nq_rows: int, names: list[str]) -> list[tuple[int, int, float]]:
    """``(variable index, row index, d row / d reaction)`` of the reactions ``names`` whose row (after the
    ``nq_rows`` equilibrium rows) is linear in them: a compliant row ``Phi - lambda / k``."""
    if not names:
        return []
    x = system.defaults()
    J = system.jacobian(x)
    out = []
    for n in names:
        j = system.index(n)
        col = J[nq_rows:, j]
        hit = np.flatnonzero(col)
        if len(hit) == 1:
            out.append((j, nq_rows + int(hit[0]), float(col[hit[0]])))
    return out


def fill_reactions(system: Model, dyn: ConstrainedDynamics, t: np.ndarray, y: np.ndarray, values: np.ndarray,
                   modes: Sequence[tuple[int, ...]], known: Sequence[Any] | None = None) -> int:
    """Write the live reactions into ``values`` (rows like ``t``, ``y``; ``modes``: the stops in contact at
    each row; ``known``: per row, the integrator's own solve there, :meth:`~._udwadia_kalaba.ConstrainedDynamics.recall`,
    or None). Returns the number of rows whose joint reactions are minimum-norm (redundant constraints)."""
    nq, nc = dyn.nq, dyn.mech.n_constraints
    names = list(system.reaction_names)
    joint = np.array([system.index(n) for n in names[:nc]], dtype=int) if len(names) >= nc else np.zeros(0, int)
    elastic = _elastic_rows(system, nq, names[nc:]) if len(names) > nc else []
    contacts = dyn.contacts
    indeterminate = 0
    for i, (ti, yi) in enumerate(zip(t, y)):
        if contacts is not None:
            contacts.active = list(modes[i])
        if known is not None and known[i] is not None and known[i][1] is not None:  # the integrator's solve here
            z, determinate = known[i][1], not dyn.indeterminate  # redundant rows: the dropped ones carry nothing
        else:
            _, z, determinate = dyn.multipliers(ti, yi[:nq], yi[nq:2 * nq], yi[2 * nq:])
        indeterminate += not determinate
        if dyn.kept is not None:  # the rows left out of the solve carried none: report the minimum-norm split
            z = dyn.kept.minimum_norm(dyn.mech.phi_q(dyn.full_of(ti, yi)), z)
        if joint.size:
            values[i, joint] = -z[:nc]
        if contacts is not None and modes[i]:
            values[i, contacts.reaction[list(modes[i])]] = z[nc:]
    if elastic:  # the compliant rows at zero reaction are their deflections Phi_k: lambda_k = -Phi_k / slope
        cols, rows = [j for j, _, _ in elastic], [row for _, row, _ in elastic]
        X = values.copy()
        X[:, cols] = 0.0
        residual = system.columns(()).residual_and_jacobian  # the residual alone: a batch would form every Jacobian
        G = np.array([residual(x)[0][rows] for x in X]).reshape(len(X), len(rows))
        for k, (j, _, slope) in enumerate(elastic):
            values[:, j] = -G[:, k] / slope
    if contacts is not None and contacts.law:
        idx = contacts.reaction[contacts.law.index]
        for i, (ti, yi) in enumerate(zip(t, y)):
            values[i, idx] = contacts.penalized(dyn.full_of(ti, yi), yi[nq:2 * nq])[idx]
    return indeterminate


def fill_conditions(system: Model, values: np.ndarray) -> None:
    """The description's conditions (rows ``cond_NAME: c(q) - NAME``) evaluated at every saved row."""
    rows = [(k, system.index(r[5:])) for k, r in enumerate(getattr(system, "equation_names", ()))
            if r.startswith("cond_") and r[5:] in system.names]
    if not rows:
        return
    k, j = (np.array(v) for v in zip(*rows))
    residual = system.columns(()).residual_and_jacobian  # the residual alone, without the Jacobian
    for x in values:
        x[j] = 0.0
        x[j] = residual(x)[0][k]
