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

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp

from ..errors import InputError
from ._expr import Value, symbol

__all__ = ["Stop", "stops_from_table", "check_stops", "stop_reaction_unit", "stop_forces",
           "STOP_KEYS", "stop_value_limits"]

#: Keys of a ``[stops.NAME]`` table.
STOP_KEYS = frozenset({"condition", "min", "max", "restitution", "contact", "stiffness", "damping", "description"})
#: Contact models of a stop in the time simulation.
CONTACT_MODELS = ("rigid", "compliant")


@dataclass(frozen=True)
class Stop:
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


def stop_reaction_unit(condition_unit: str) -> str:
    """Unit of a stop reaction on a condition of unit ``condition_unit``: energy per unit of the condition."""
    u = condition_unit.strip()
    return {"": "N m", "rad": "N m", "m": "N"}.get(u, f"J/({u})")


def stops_from_table(tab: Mapping, field: str = "stops") -> list[Stop]:
    """``[stops.NAME]`` tables as parsed TOML -> :class:`Stop` objects (keys and types checked)."""
    out = []
    for name, spec in tab.items():
        f = f"{field}.{name}"
        if not isinstance(spec, Mapping):
            raise InputError(f, "a stop is a table {condition = \"NAME\", min = LIMIT} (or max = LIMIT), "
                                f"got {type(spec).__name__}")
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
        out.append(Stop(name, spec["condition"], limit, 1 if sides[0] == "min" else -1, desc, float(e),
                        *_contact_model(spec, f)))
    return out


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


def stop_value_limits(mech) -> list[tuple[str, bool, str]]:
    """``(key path, positive, what)`` of the stops' values with a physical range: a compliant
    stop's stiffness (> 0) and damping (>= 0); shared by the planar and spatial value checks."""
    out = []
    for st in mech.stops:
        if st.contact == "compliant":
            out += [(f"stops.{st.name}.stiffness", True, "contact stiffness (per unit of the condition)"),
                    (f"stops.{st.name}.damping", False, "contact damping (per unit of the condition's rate)")]
    return out


def check_stops(mech) -> None:
    """Each stop names a declared condition, at most one stop per condition side (one-line InputError)."""
    names = {c.name: c for c in mech.conditions}
    seen: dict[tuple[str, int], str] = {}
    for s in mech.stops:
        f = f"stops.{s.name}"
        if s.condition not in names:
            valid = ", ".join(names) or "none declared under [conditions]"
            raise InputError(f + ".condition", f"unknown condition {s.condition!r}; conditions: {valid}")
        if s.side not in (1, -1):
            raise InputError(f, f"side must be +1 (min) or -1 (max), got {s.side!r}")
        if (s.condition, s.side) in seen:
            raise InputError(f, f"the condition {s.condition!r} already has a "
                                f"{s.key} stop ({seen[(s.condition, s.side)]})")
        seen[(s.condition, s.side)] = s.name


def stop_forces(mech, conditions, q: Sequence[sp.Symbol], gradient=None) -> list[sp.Expr]:
    """``sum_s side_s R_s dc_s/dq`` per coordinate: the stops' generalised forces.

    ``conditions`` are the ``(Condition, c(q, p))`` pairs of the generated system (eliminated
    coordinates already substituted); ``gradient(expr, symbols)`` differentiates (default SymPy)."""
    out = [sp.S.Zero] * len(q)
    exprs = {c.name: e for c, e in conditions}
    for s in mech.stops:
        c = exprs[s.condition]
        ds = gradient(c, list(q)) if gradient is not None else [sp.diff(c, qi) for qi in q]
        if all(d == 0 for d in ds):
            raise InputError(f"stops.{s.name}.condition", f"the condition {s.condition!r} does not depend on the "
                                                          "coordinates, so nothing can move against the stop; limit "
                                                          "a condition of the configuration")
        R = symbol(s.reaction)
        out = [o + s.side * R * d for o, d in zip(out, ds)]
    return out
