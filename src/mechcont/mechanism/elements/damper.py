"""Hydraulic dampers between two points (planar and spatial): ``[dampers.NAME]``.

A damper of length ``l`` (m) between its points ``a`` and ``b`` carries the tension (N, positive
pulling its ends together, as springs and actuators)

    T = c v + c2 v |v|,     v = dl/dt (m/s),

``c`` (N s/m) the linear (laminar) term and ``c2`` (N s^2/m^2) the quadratic one of a restrictor
orifice. Its generalised force is ``-T dl/dq``. The tension depends on the velocity symbols only,
so it vanishes at rest: every continuation (an equilibrium is at rest) sees no damper; the time
simulation does.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from ...equations import Limit, velocity_symbol
from .._expr import Value
from .._plugin import Kinematics
from ._base import TwoPointElement

if TYPE_CHECKING:
    from .._description import Mechanism
    from ..loads import Loads

__all__ = ["Damper", "damper_tension"]


def damper_tension(c: sp.Expr, c2: sp.Expr, rate: sp.Expr) -> sp.Expr:
    """Tension ``c v + c2 v |v|`` (N) of a damper stroking at ``rate`` = ``v`` (m/s)."""
    return c * rate + c2 * rate * sp.Abs(rate)


@dataclass(frozen=True)
class Damper(TwoPointElement):
    """A hydraulic damper between points ``a`` and ``b``: tension ``c v + c2 v |v|`` (N) with
    ``v = dl/dt`` (m/s), ``c`` >= 0 (N s/m, linear), ``c2`` >= 0 (N s^2/m^2, quadratic: a restrictor
    orifice). Only the dynamic model feels it (zero at rest); see the module docstring."""

    name: str
    a: str
    b: str
    c: Value
    c2: Value = 0

    table: ClassVar[str] = "dampers"
    KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "c", "c2"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("a", "b", "c")
    DRAWN: ClassVar[str] = "damper"

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its linear and quadratic damping."""
        yield self.field("c"), self.c
        yield self.field("c2"), self.c2

    def limits(self, kin: Kinematics, solve: bool) -> list[Limit]:
        """Both coefficients non-negative."""
        return [self.value_limit(kin, "c", False, "damping (N s/m)"),
                self.value_limit(kin, "c2", False, "quadratic damping (N s^2/m^2)")]

    def apply(self, kin: Kinematics, out: Loads) -> None:
        """Generalised forces ``-T dl/dq`` with ``v = dl/dq . qdot`` (the velocity symbols of ``kin.coords``)."""
        length = kin.distance(self.a, self.b)
        grad = [sp.diff(length, qi) for qi in kin.q]
        rate = sum((gi * velocity_symbol(n) for gi, n in zip(grad, kin.coords)), sp.S.Zero)
        v = kin.mech.value
        T = damper_tension(v(self.field("c")), v(self.field("c2")), rate)
        out.add([-T * gi for gi in grad])
