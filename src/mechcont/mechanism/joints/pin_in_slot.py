"""The pin-in-slot joint: a pin on one body slides in a straight slot on another.

The slot is the segment between two points ``slot = [start, end]`` of one body (or two ground
points); the pin is a point of another body. One row: the pin's signed distance from the slot's
line is zero,

    n . (start - pin) = 0,    n = the unit left normal of end - start (turned +90 degrees),

so the reaction ``R_<name>`` is the force (N) that the slot's body exerts on the pin's body
along ``n``; the pin slides along the slot and turns freely. The slot's ends only draw it:
the pin may leave the segment (end limits are not modelled). Unlike ``slider`` (a line
through one point at an ``angle``), the slot is given by two points of its body, so it
follows the body's geometry (and its parameters) and is drawn where it is.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar

import sympy as sp

from ...equations import Limit
from ...errors import InputError
from ._base import ConstraintRow, Draw, PlanarJoint, check_points

if TYPE_CHECKING:
    from .._description import Mechanism
    from .._kinematics import PlanarKinematics

__all__ = ["PinInSlot"]


@dataclass(frozen=True)
class PinInSlot(PlanarJoint):
    """Point ``pin`` slides in the straight slot from ``slot[0]`` to ``slot[1]`` (two points of
    one other body, or two ground points); rotation free. Reaction ``R_<name>``: the force (N)
    on the pin's body along the slot's left normal. Row ``<name>_n`` (m)."""

    name: str
    pin: str
    slot: tuple[str, str]
    a: str = field(init=False, repr=False)
    b: str = field(init=False, repr=False)
    kind: ClassVar[str] = "pin_in_slot"
    KEYS: ClassVar[frozenset[str]] = frozenset({"pin", "slot"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("pin", "slot")

    @classmethod
    def from_table(cls, name: str, spec: Mapping, field: str) -> PinInSlot:
        for k in cls.REQUIRED:
            if k not in spec:
                raise InputError(f"{field}.{k}", "is required")
        slot = spec["slot"]
        return cls(name, spec["pin"], tuple(slot) if isinstance(slot, list) else slot)

    def __post_init__(self) -> None:
        # side a is the slot's start (its body exerts the reaction), side b the pin; a malformed
        # slot is reported by check(), so nothing is indexed here that may not exist
        ok = isinstance(self.slot, (tuple, list)) and len(self.slot) == 2
        object.__setattr__(self, "a", self.slot[0] if ok else "")
        object.__setattr__(self, "b", self.pin)

    def refs(self) -> list[tuple[str, str]]:
        return [("slot", self.slot[0]), ("pin", self.pin), ("slot", self.slot[1])]

    def check(self, mech: Mechanism) -> None:
        f = f"joints.{self.name}"
        slot = self.slot
        if not (isinstance(slot, (tuple, list)) and len(slot) == 2 and all(isinstance(s, str) for s in slot)):
            raise InputError(f + ".slot", f"is [start, end]: two point references of one body, got {slot!r}")
        check_points(self.name, self.refs(), mech)
        if slot[0].split(".")[0] != slot[1].split(".")[0]:
            raise InputError(f + ".slot", f"both ends must be on one body (or both on the ground), got {slot[0]} and "
                                          f"{slot[1]}")
        if slot[0] == slot[1]:
            raise InputError(f + ".slot", f"needs two different points, got {slot[0]} twice")

    def _local_direction(self, kin: PlanarKinematics) -> sp.Matrix:
        """``end - start`` in the slot body's frame (m): depends on the parameters only."""
        body = self.slot[0].split(".")[0]
        frame = {} if body == "ground" else dict.fromkeys(kin.body_q[body], 0)
        return (kin.point(self.slot[1]) - kin.point(self.slot[0])).xreplace(frame)

    def length(self, kin: PlanarKinematics) -> sp.Expr:
        """Length (m) of the slot."""
        d = self._local_direction(kin)
        return sp.sqrt(d[0] ** 2 + d[1] ** 2)

    def rows(self, kin: PlanarKinematics) -> list[ConstraintRow]:
        d = (kin.point(self.slot[1]) - kin.point(self.slot[0])) / self.length(kin)
        normal = sp.Matrix([-d[1], d[0]])
        n = self.name
        return [ConstraintRow(n, f"{n}_n", f"R_{n}", "N", normal.dot(kin.point(self.slot[0]) - kin.point(self.pin)))]

    def draw(self, kin: PlanarKinematics, add: Draw) -> None:
        add("slot", self.name, [kin.point(self.slot[0]), kin.point(self.slot[1])])
        add("pin", self.name, [kin.point(self.pin)])

    def limits(self, kin: PlanarKinematics, solve: bool) -> list[Limit]:
        """A positive slot length."""
        return [Limit(self.field("slot"), self.length(kin), True, "slot length (m)")]
