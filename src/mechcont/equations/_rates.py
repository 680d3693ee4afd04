"""The rate of an equilibrium along a one-parameter family (the branch tangent, from the exact Jacobian)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from ._system import EquationSystem

__all__ = ["branch_rates"]


def branch_rates(system: EquationSystem, x: np.ndarray, vary: str) -> np.ndarray:
    """``dx/d(vary)`` (full vector, ordered like ``system.names``) at the equilibrium ``x`` of a
    one-parameter family in which every state moves and every other parameter is held.

    Raises
    ------
    InputError
        When the states' Jacobian is singular at ``x`` (a fold in ``vary``: the rate is infinite).
    """
    states = [system.index(n) for n in system.state_names]
    j = system.index(vary)
    jac = system.jacobian(np.asarray(x, float))
    ju = jac[:, states]
    if np.linalg.cond(ju) > 1e12:
        raise InputError(vary, "the states' Jacobian is singular here (a fold): no rate along the branch")
    rate = np.zeros(len(system.names))
    rate[states] = np.linalg.solve(ju, -jac[:, j])
    rate[j] = 1.0
    return rate
