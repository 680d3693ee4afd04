"""The first-order states of the force elements (:meth:`~.elements.Element.states`) in a generated system.

Each state ``s`` with rate ``ds/dt = r(q, qdot, s, p)`` becomes a variable of the system (after the
condition states, before the parameters) and its steady state at rest ``r(q, 0, s, p) = 0`` one of the
system's rows (``rate_<name>``): continuation follows equilibria with the element at its steady state,
while the mechanics (``MechanicalModel(state_rates=...)``) keeps the rate for the time simulation and
the dynamic analyses.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np
import sympy as sp

from ..equations import velocity_symbol
from ..errors import InputError
from .elements._base import ElementState

if TYPE_CHECKING:
    from ..equations import MechanicalModel
    from ._plugin import Kinematics

__all__ = ["collect_states", "rest_rows", "steady_states"]


def collect_states(kin: Kinematics, vel: Mapping[sp.Symbol, sp.Expr] | None = None,
                   subs: Mapping[sp.Symbol, sp.Expr] | None = None) -> list[ElementState]:
    """Every force element's states in the coordinates of ``kin``; with the reduced form's substitution
    ``subs`` of the eliminated coordinates and ``vel`` of their velocities, in the kept ones'."""
    out: list[ElementState] = []
    for el in kin.mech.force_elements():
        for s in el.states(kin):
            rate = sp.sympify(s.rate, strict=True)
            if subs:
                rate = rate.xreplace(subs)
            if vel:
                rate = rate.xreplace(vel)
            out.append(ElementState(s.name, s.unit, rate, s.scale, s.initial, s.description))
    names = [s.name for s in out]
    for n in names:
        if names.count(n) > 1 or not n.isidentifier():
            raise InputError(n, "element state names must be distinct identifiers")
    return out


def rest_rows(states: Sequence[ElementState], coords: Sequence[str]) -> list[sp.Expr]:
    """The rows ``r(q, 0, s, p)`` holding each state at its steady state (the mechanism at rest)."""
    at_rest = {velocity_symbol(c): 0 for c in coords}
    return [s.rate.xreplace(at_rest) for s in states]


def steady_states(mech: MechanicalModel, x: np.ndarray, max_iter: int = 30) -> np.ndarray:
    """``x`` with the element states of the mechanical model ``mech`` at their steady state at rest
    (Newton on ``r(q, 0, s) = 0`` with the exact ``dr/ds``); ``x`` itself when it has none or when
    ``dr/ds`` is singular (the solve of the whole system decides then)."""
    idx = mech.s_index
    if not len(idx):
        return x
    y = np.array(x, dtype=float)
    for _ in range(max_iter):
        r = mech.element_state_rates(y)
        Rs = mech.element_state_jacobians(y)[2]
        try:
            step = np.linalg.solve(Rs, -r)
        except np.linalg.LinAlgError:
            return x
        y[idx] += step
        if np.all(np.abs(step) <= 1e-14 * np.maximum(np.abs(y[idx]), 1.0)):
            break
    return y if np.all(np.isfinite(y)) else x
