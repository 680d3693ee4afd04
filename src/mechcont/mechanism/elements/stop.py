"""Stops: one-sided limits of a condition (``[stops.NAME]``), planar and spatial.

The contact reaction ``R_NAME`` is a generated parameter; see :mod:`.._stops` for the model
(its generalised force ``side R dc/dq``, contact and release).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from ...equations import Limit
from ...errors import InputError
from .._expr import Gradient, Value, symbol
from .._plugin import Kinematics
from ._base import Element

if TYPE_CHECKING:
    from .._description import Mechanism

__all__ = ["Stop", "STOP_KEYS", "CONTACT_MODELS"]

#: Keys of a ``[stops.NAME]`` table.
STOP_KEYS = frozenset({"condition", "min", "max", "restitution", "contact", "stiffness", "damping", "description"})
#: Contact models of a stop in the time simulation.
CONTACT_MODELS = ("rigid", "compliant")


@dataclass(frozen=True)
class Stop(Element):
    """A one-sided limit of a condition (see the module docstring).

    Parameters
    ----------
    name:
        Identifier; the contact reaction is the parameter ``R_<name>``.
    condition:
        Name of the condition limited.
    limit:
        The limit value, in the condition's unit (a number or an expression in parameters).
    side:
        ``+1``: the condition stays at or above ``limit`` (``min``); ``-1``: at or below (``max``).
    description:
        Free text.
    restitution:
        Newton's coefficient of restitution ``e`` (0 to 1) used by the time simulation at an
        impact: the condition's rate after the impact is ``-e`` times its rate before. Default 0
        (a lock does not bounce); quasi-static analyses do not use it.
    contact:
        ``"rigid"`` (a unilateral constraint with impacts) or ``"compliant"`` (a penalty
        reaction ``max(0, stiffness p + damping p')`` on the penetration ``p``) in time simulation.
    stiffness, damping:
        Of a compliant stop: per unit of the condition (N/m or N m/rad; N s/m or N m s/rad),
        numbers or expressions in parameters; None for a rigid stop.
    """

    name: str
    condition: str
    limit: Value
    side: int = 1
    description: str = ""
    restitution: float = 0.0
    contact: str = "rigid"
    stiffness: Value | None = None
    damping: Value | None = None

    table: ClassVar[str] = "stops"
    KEYS: ClassVar[frozenset[str]] = STOP_KEYS

    @property
    def reaction(self) -> str:
        """Name of the contact reaction parameter (>= 0 in contact, 0 out of contact)."""
        return f"R_{self.name}"

    @property
    def key(self) -> str:
        """The key of the limit in the stop's table: ``"min"`` or ``"max"``."""
        return "min" if self.side > 0 else "max"

    @property
    def reaction_description(self) -> str:
        """The meaning of the contact reaction parameter, for its variable's description."""
        return f"contact reaction of stop {self.name} ({self.key} of {self.condition}), >= 0 in contact, 0 out of contact"

    @classmethod
    def from_table(cls, name: str, spec: Mapping, field: str) -> Stop:
        """The stop of a ``[stops.NAME]`` table ``spec`` at key path ``field`` (keys and types checked)."""
        f = field
        for k in spec:
            if k not in STOP_KEYS:
                raise InputError(f"{f}.{k}", f"unknown key for a stop; valid keys: {', '.join(sorted(STOP_KEYS))}")
        if not isinstance(spec.get("condition"), str):
            raise InputError(f + ".condition", "is required: the name of the condition the stop limits")
        sides = [k for k in ("min", "max") if k in spec]
        if len(sides) != 1:
            raise InputError(f, "needs exactly one of min = LIMIT (the condition stays at or above it) or "
                                "max = LIMIT (at or below it)")
        limit = spec[sides[0]]
        if isinstance(limit, bool) or not isinstance(limit, (int, float, str)):
            raise InputError(f"{f}.{sides[0]}", f"must be a number or an expression in parameters, got {limit!r}")
        desc = spec.get("description", "")
        if not isinstance(desc, str):
            raise InputError(f + ".description", f"must be a string, got {desc!r}")
        e = spec.get("restitution", 0.0)
        if isinstance(e, bool) or not isinstance(e, (int, float)) or not 0.0 <= e <= 1.0:
            raise InputError(f + ".restitution", f"must be a number from 0 (no bounce) to 1 (elastic), got {e!r}")
        return cls(name, spec["condition"], limit, 1 if sides[0] == "min" else -1, desc, float(e),
                   *_contact_model(spec, f))

    def check(self, mech: Mechanism) -> None:
        """It names a declared condition; at most one stop per condition side (the first declared keeps it)."""
        f = self.field()
        names = [c.name for c in mech.conditions]
        if self.condition not in names:
            valid = ", ".join(names) or "none declared under [conditions]"
            raise InputError(f + ".condition", f"unknown condition {self.condition!r}; conditions: {valid}")
        if self.side not in (1, -1):
            raise InputError(f, f"side must be +1 (min) or -1 (max), got {self.side!r}")
        first = next(s for s in mech.stops if (s.condition, s.side) == (self.condition, self.side))
        if first is not self:
            raise InputError(f, f"the condition {self.condition!r} already has a {self.key} stop ({first.name})")

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its limit and, for a compliant stop, its stiffness and damping."""
        yield self.field(self.key), self.limit
        if self.contact == "compliant":
            yield self.field("stiffness"), self.stiffness
            yield self.field("damping"), self.damping

    def limits(self, kin: Kinematics, solve: bool) -> list[Limit]:
        """A compliant stop's stiffness (> 0) and damping (>= 0)."""
        if self.contact != "compliant":
            return []
        return [self.value_limit(kin, "stiffness", True, "contact stiffness (per unit of the condition)"),
                self.value_limit(kin, "damping", False, "contact damping (per unit of the condition's rate)")]

    def generalised_force(self, c: sp.Expr, q: Sequence[sp.Symbol], gradient: Gradient | None = None) -> list[sp.Expr]:
        """``side R dc/dq`` per coordinate ``q`` for its condition ``c(q, p)`` (``gradient(expr, symbols)``
        differentiates; default SymPy). Its force is along its condition, so the generators add it once
        the conditions are written in the generated coordinates (the reduced form's included)."""
        ds = gradient(c, list(q)) if gradient is not None else [sp.diff(c, qi) for qi in q]
        if all(d == 0 for d in ds):
            raise InputError(self.field("condition"), f"the condition {self.condition!r} does not depend on the "
                                                      "coordinates, so nothing can move against the stop; limit "
                                                      "a condition of the configuration")
        R = symbol(self.reaction)
        return [self.side * R * d for d in ds]


def _contact_model(spec: Mapping, f: str) -> tuple[str, Value | None, Value | None]:
    """``(contact, stiffness, damping)`` of the stop table ``spec`` at key path ``f`` (checked;
    the values' signs are checked with the parameters, see :func:`~._values.physical_limits`)."""
    contact = spec.get("contact", "rigid")
    if contact not in CONTACT_MODELS:
        raise InputError(f + ".contact", f"must be one of {', '.join(map(repr, CONTACT_MODELS))}, got {contact!r}")
    if contact == "rigid":
        for k in ("stiffness", "damping"):
            if k in spec:
                raise InputError(f"{f}.{k}", 'is for a compliant stop: give contact = "compliant" (or remove it)')
        return contact, None, None
    if "stiffness" not in spec:
        raise InputError(f + ".stiffness", "is required for a compliant stop: a positive number or expression "
                                           "(N/m, or N m/rad for an angle or collinear condition)")
    if "restitution" in spec:
        raise InputError(f + ".restitution", "is for a rigid stop; a compliant stop's bounce follows from its "
                                             "stiffness and damping")
    out = []
    for k in ("stiffness", "damping"):
        v = spec.get(k, 0.0)
        if isinstance(v, bool) or not isinstance(v, (int, float, str)):
            raise InputError(f"{f}.{k}", f"must be a number or an expression in parameters, got {v!r}")
        out.append(v)
    return contact, out[0], out[1]
