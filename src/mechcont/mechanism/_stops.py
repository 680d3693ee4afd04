"""Stops: one-sided limits of a condition, with the contact reaction as a named variable.

A stop ``NAME`` on the condition ``c`` (see :mod:`._conditions`) says that the mechanism cannot
move past ``c = limit``: ``c >= limit`` for ``min = limit``, ``c <= limit`` for ``max = limit``.
In contact the stop pushes back with a generalised force along the condition's gradient,

    Q_stop = s R_NAME dc/dq          (s = +1 for a min stop, -1 for a max stop; R_NAME >= 0),

added to the generalised forces ``Q`` of the equilibrium rows, the mechanics (tangent stiffness,
which gains ``s R d2c/dq2``) and the dynamic model. ``R_NAME`` is a generated *parameter*
(default 0: no contact). Its unit is energy per unit of the condition: N m for a collinear
(sine) or angle condition (a moment about the stop), N for a distance. Because the condition
depends only on the relative configuration of the bodies it names, the reaction is an internal
force: the joint reactions stay those of the real contact.

A stop in contact is the paper's swap of a state for a parameter: hold the condition at its limit
and solve for ``R_NAME`` (``hold={"c": limit}, free=["R_NAME"]``). Out of contact, ``R_NAME = 0``
and the condition is free. :func:`mechcont.analysis.continuation_with_stops` switches between the
two as the reaction reaches zero (the stop releases) or the condition reaches its limit (contact).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import sympy as sp

from ..units import SI, UnitSystem, dimension
from ._expr import Gradient
from .elements.stop import STOP_KEYS, Stop

if TYPE_CHECKING:
    from ._conditions import Condition
    from ._description import Mechanism

__all__ = ["Stop", "STOP_KEYS", "stop_reaction_unit", "stop_forces"]


def stop_reaction_unit(condition_unit: str, units: UnitSystem = SI) -> str:
    """Unit of a stop reaction on a condition of unit ``condition_unit``: energy per unit of the condition,
    in ``units`` (a moment on an angle or a number, a force on a length; ``J/(u)`` for a label it cannot read)."""
    u = condition_unit.strip()
    dim = dimension(u)
    if units.is_si or dim is None:
        return {"": "N m", "rad": "N m", "m": "N"}.get(u, f"{units.label('J')}/({u})")
    return units.of((2 - dim[0], 1 - dim[1], -2 - dim[2]))


def stop_forces(mech: Mechanism, conditions: Sequence[tuple[Condition, sp.Expr]], q: Sequence[sp.Symbol],
                gradient: Gradient | None = None) -> list[sp.Expr]:
    """``sum_s side_s R_s dc_s/dq`` per coordinate: the stops' generalised forces
    (:meth:`~.elements.stop.Stop.generalised_force` of each).

    ``conditions`` are the ``(Condition, c(q, p))`` pairs of the generated system (eliminated
    coordinates already substituted); ``gradient(expr, symbols)`` differentiates (default SymPy)."""
    out = [sp.S.Zero] * len(q)
    exprs = {c.name: e for c, e in conditions}
    for s in mech.stops:
        out = [o + g for o, g in zip(out, s.generalised_force(exprs[s.condition], q, gradient))]
    return out
