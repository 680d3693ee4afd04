"""A description's points measured from where its bars are not: the trap of ``length``.

A body with a ``length`` is a bar whose frame origin is its **centre** (its ends ``a``, ``b`` at
-length/2 and +length/2 on its axis); a body without one has its origin wherever its points are
measured from. A bar whose points are measured from one end (a hinge) instead is a valid
mechanism, but not the one its author meant to draw: every drawing shows the bar centred on the
hinge, half of it on the wrong side, with the points beyond its end hanging in the air. The check
reports each point or centre of gravity of a bar that lies beyond the bar's ends along its axis.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

from ._bodies import Polar
from ._expr import evaluate

if TYPE_CHECKING:
    from ._description import Mechanism

__all__ = ["bar_point_warnings"]

#: A point counts as beyond a bar's end by more than this fraction of the bar's length.
_BEYOND = 1e-9


def bar_point_warnings(mech: Mechanism, values: Mapping[str, float]) -> tuple[str, ...]:
    """One line per declared point or centre of gravity (planar or spatial) of a bar (a body with a
    ``length``) lying beyond the bar's ends along its axis at the parameter ``values`` (the file's own
    units), saying where it is (in bar lengths from the bar's centre, so in any units) and what the
    description likely meant; empty when none."""
    out = []
    for b in mech.bodies:
        if b.length is None:
            continue
        f = f"bodies.{b.name}"
        half = evaluate(mech.value(f"{f}.length"), values, f"{f}.length") / 2
        along = {"cg": (f"{f}.cg", evaluate(mech.value(f"{f}.cg.x"), values, f"{f}.cg.x"))}
        for pn, spec in b.points.items():
            p = f"{f}.points.{pn}"
            if isinstance(spec, Polar):
                r, a = (evaluate(mech.value(f"{p}.{k}"), values, f"{p}.{k}") for k in ("r", "angle"))
                along[pn] = (p, r * math.cos(a))
            else:
                along[pn] = (p, evaluate(mech.value(f"{p}.x"), values, f"{p}.x"))
        beyond = [(field, x) for field, x in along.values() if abs(x) > half * (1 + _BEYOND)]
        for field, x in beyond:
            out.append(f"{field}: beyond the bar's end {'b' if x > 0 else 'a'}, at {x / (2 * half):+.4g} of its length "
                       "from its centre along its axis (its ends are at -0.5 and +0.5): a body with a length is a bar "
                       "centred on its origin, so it is drawn apart from this point; measure the points from the bar's "
                       f"centre (its ends are {b.name}.a and {b.name}.b), or leave out length (and give the inertia) "
                       "if they are measured from a hinge")
    return tuple(out)
