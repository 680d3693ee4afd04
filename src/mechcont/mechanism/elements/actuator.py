"""Actuators: a two-force member between two points, driven by a force or by its length (``[actuators.NAME]``).

Sign convention: the actuator load is a **tension, positive** when it pulls its points
``a`` and ``b`` towards each other (negative: it pushes them apart, extending the
actuator). With ``l = |P_b - P_a|``:

* force mode (``force = F``, an expression in the parameters; a parameter name can be freed
  and solved for): the potential ``F l`` (J), i.e. the generalised force ``-F dl/dq``;
* length mode (``length = L``): the constraint row ``<NAME>_length: l - L = 0`` (m) whose
  reaction ``T_<NAME>`` (N) is the actuator tension. A length actuator removes one degree
  of freedom (declare ``dof`` accordingly); continuing in ``L`` drives the mechanism.

For a crank of angle ``theta`` under a moment ``M`` (counter-clockwise positive) the
virtual work gives ``F dl/dtheta = M`` in both modes.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from ...equations import Limit
from ...errors import InputError
from .._expr import Value
from .._plugin import Kinematics
from ..joints import ConstraintRow
from ._base import Draw, TwoPointElement

if TYPE_CHECKING:
    from .._description import Mechanism
    from ..loads import Loads

__all__ = ["Actuator"]


@dataclass(frozen=True)
class Actuator(TwoPointElement):
    """A straight actuator from point ``a`` to point ``b`` (see the module docstring).

    Exactly one of ``force`` (tension, N: a number or an expression in the parameters) and
    ``length`` (m, positive: a number or an expression in the parameters) is given.
    """

    name: str
    a: str
    b: str
    force: Value | None = None
    length: Value | None = None
    description: str = ""

    table: ClassVar[str] = "actuators"
    KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "force", "length", "description"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("a", "b")
    TEXT_KEYS: ClassVar[tuple[str, ...]] = ("description",)
    DRAWN: ClassVar[str] = "actuator"

    @property
    def mode(self) -> str:
        """``"force"`` or ``"length"``."""
        return "force" if self.force is not None else "length"

    @classmethod
    def required_message(cls, key: str) -> str:
        """The ends are point references."""
        return "is required (a point reference '<body>.<point>' or 'ground.<point>')"

    def check(self, mech: Mechanism) -> None:
        """Exactly one of force and length; two different points on two different bodies."""
        f = self.field()
        if (self.force is None) == (self.length is None):
            raise InputError(f, "give exactly one of force (N, tension positive) and length (m)"
                             + (", not both" if self.force is not None else ""))
        super().check(mech)
        if self.a == self.b:
            raise InputError(f + ".b", "an actuator needs two different points")
        if self.a.split(".")[0] == self.b.split(".")[0]:
            raise InputError(f + ".b", f"both ends are on {self.a.split('.')[0]!r}: an actuator joins two bodies "
                                       "(or a body and the ground)")

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its force or its length."""
        for key in ("force", "length"):
            if getattr(self, key) is not None:
                yield self.field(key), getattr(self, key)

    def limits(self, kin: Kinematics, solve: bool) -> list[Limit]:
        """A given length is positive."""
        return [self.value_limit(kin, "length", True, "actuator length (m)")] if self.length is not None else []

    def length_in(self, kin: Kinematics) -> sp.Expr:
        """``|P_b - P_a|`` (m) in the coordinates of ``kin``."""
        d = kin.point(self.b) - kin.point(self.a)
        return sp.sqrt(sum((c ** 2 for c in d), sp.S.Zero))

    def tension(self, mech: Mechanism) -> sp.Expr:
        """The actuator tension (N) as an expression in the system's variables."""
        if self.mode == "force":
            return mech.value(self.field("force"))
        return sp.Symbol(f"T_{self.name}", real=True)

    def apply(self, kin: Kinematics, out: Loads) -> None:
        """Force mode: the potential ``F l`` (J)."""
        if self.mode == "force":
            out.V += kin.mech.value(self.field("force")) * self.length_in(kin)

    def rows(self, kin: Kinematics) -> list:
        """Length mode: the row ``l - L`` (m), reaction ``T_<NAME>`` (N)."""
        if self.mode != "length":
            return []
        L = kin.mech.value(self.field("length"))
        return [ConstraintRow(self.name, f"{self.name}_length", f"T_{self.name}", "N", self.length_in(kin) - L)]

    def draw(self, kin: Kinematics, add: Draw) -> None:
        """Its ends, then its tension as the vector ``(T, 0, ...)`` (N)."""
        tension = sp.Matrix([self.tension(kin.mech)] + [0] * (len(kin.mech.AXES) - 1))
        add(self.DRAWN, self.name, [kin.point(self.a), kin.point(self.b), tension])
