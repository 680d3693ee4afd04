"""Conditions: named relations of the configuration that analyses can watch or hold.

A condition ``NAME`` of a description becomes one extra *state* variable ``NAME`` and one
extra equation ``c(q, p) - NAME = 0`` of the generated system (the row ``cond_NAME``). Every
branch then carries the condition's value as a column, ``ValueEvent("NAME", 0)`` finds where
it is met, and "hold the condition" is just ``hold NAME = value`` with a force freed (the
downlock analysis). The rows are outputs, not constraints: the mechanics (coordinates,
constraints, stability, dynamics) never see them.

Kinds (all in SI units):

* ``"expression"``: any expression in the coordinates and parameters (unit as declared).
* ``"collinear"``, points ``[P1, P2, P3]``: ``((P2 - P1) x (P3 - P1)) / (|P2 - P1| |P3 - P1|)``,
  the sine of the angle from ``P2 - P1`` to ``P3 - P1`` (dimensionless, rad-like near 0):
  zero when the three points are aligned, positive when ``P3`` lies to the left of the line
  ``P1 -> P2`` (counter-clockwise), negative to its right.
* ``"distance"``, points ``[P, Q]``: ``|Q - P|`` (m).
* ``"angle"``, bodies ``[b1, b2]``: ``theta_b2 - theta_b1`` (rad), the angle of body 2's
  frame relative to body 1's (not wrapped).

``target`` is the value the downlock analysis holds: default 0 for expressions, collinear
and angle conditions; a distance has no default.

Each kind is one :class:`Condition` class in :mod:`._condition_kinds` (a
:class:`~._plugin.PlugIn` of the family ``"conditions"``), registered by its ``type`` in
:data:`CONDITION_TYPES`: its keys, checks, expression against the kinematics, unit, default
target and meaning.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import sympy as sp

from ..errors import InputError
from ..units import typical_scale
from ._condition_kinds import (
    CONDITION_TYPES,
    AngleCondition,
    CollinearCondition,
    Condition,
    DistanceCondition,
    ExpressionCondition,
)
from ._plugin import Kinematics

if TYPE_CHECKING:
    from ._description import Mechanism

__all__ = ["Condition", "ExpressionCondition", "CollinearCondition", "DistanceCondition", "AngleCondition",
           "CONDITION_TYPES", "DownlockSpec", "condition_expr", "check_conditions", "conditions_from_table",
           "downlock_from_table"]


@dataclass(frozen=True)
class DownlockSpec:
    """The downlock condition of a mechanism: the condition held (at its target) and the
    force (a parameter, N) freed and solved for; see :mod:`mechcont.analysis.downlock`."""

    condition: str
    force: str


def condition_expr(kin: Kinematics, cond: Condition) -> sp.Expr:
    """The value of ``cond`` as an expression in the coordinates and parameters of ``kin``."""
    return cond.expression(kin)


def check_conditions(mech: Mechanism) -> None:
    """Check every condition's name, references and target, and the downlock (a one-line InputError)."""
    for c in mech.conditions:
        f = f"conditions.{c.name}"
        if c.name in mech.param_symbols or c.name in mech.coordinate_symbols:
            what = "parameter" if c.name in mech.param_symbols else "coordinate"
            raise InputError(f, f"clashes with the {what} {c.name!r}: a condition's name is a variable of the model")
        c.check(mech)
    spec = mech.downlock
    if spec is None:
        return
    names = {c.name: c for c in mech.conditions}
    if spec.condition not in names:
        valid = ", ".join(names) or "none declared under [conditions]"
        raise InputError("mechanism.downlock.condition", f"unknown condition {spec.condition!r}; conditions: {valid}")
    held = names[spec.condition]
    if held.target is None and held.default_target() is None:
        raise InputError(f"conditions.{spec.condition}.target", "a distance condition held by the downlock needs "
                                                                "a target (m)")
    if spec.force not in mech.param_symbols:
        valid = ", ".join(mech.param_symbols) or "none"
        raise InputError("mechanism.downlock.force", f"must be a parameter (the force solved for), got "
                                                     f"{spec.force!r}; parameters: {valid}")


def conditions_from_table(tab: Mapping, field: str = "conditions") -> list[Condition]:
    """``[conditions]`` as parsed TOML -> :class:`Condition` objects, each read by the class its
    ``type`` names in :data:`CONDITION_TYPES` (keys checked)."""
    out: list[Condition] = []
    for name, spec in tab.items():
        f = f"{field}.{name}"
        if isinstance(spec, str):
            out.append(ExpressionCondition(name, expr=spec))
            continue
        if not isinstance(spec, Mapping):
            raise InputError(f, "a condition is an expression string or a table {type = ..., ...}, "
                                f"got {type(spec).__name__}")
        kind = spec.get("type", "expression")
        if kind not in CONDITION_TYPES:
            raise InputError(f + ".type", f"must be one of {', '.join(CONDITION_TYPES)}, got {kind!r}")
        cls = CONDITION_TYPES[kind]
        keys = cls.table_keys() | {"type"}
        for k in spec:
            if k not in keys:
                raise InputError(f"{f}.{k}", f"unknown key for a {kind} condition; valid keys: "
                                             f"{', '.join(sorted(keys))}")
        out.append(cls.from_table(name, {k: v for k, v in spec.items() if k != "type"}, f))
    return out


def downlock_from_table(spec: object, field: str = "mechanism.downlock") -> DownlockSpec:
    """``downlock = {condition = "NAME", force = "F"}`` -> :class:`DownlockSpec` (keys checked)."""
    if not isinstance(spec, Mapping):
        raise InputError(field, f"must be a table {{condition = \"NAME\", force = \"F\"}}, got {spec!r}")
    for k in spec:
        if k not in ("condition", "force"):
            raise InputError(f"{field}.{k}", "unknown key; valid keys: condition, force")
    for k, what in (("condition", "condition held"), ("force", "force parameter solved for")):
        if not isinstance(spec.get(k), str):
            raise InputError(f"{field}.{k}", f"is required: the name of the {what}")
    return DownlockSpec(spec["condition"], spec["force"])


# -- generation ---------------------------------------------------------------------------
def condition_rows(kin: Kinematics, subs: Mapping) -> list[tuple[Condition, sp.Expr]]:
    """``(condition, c(q, p))`` for every condition, eliminated coordinates substituted (``subs``)."""
    return [(c, sp.sympify(c.expression(kin), strict=True).xreplace(dict(subs))) for c in kin.mech.conditions]


def condition_scale(cond: Condition, Lc: float, Fc: float) -> float:
    """Typical magnitude of the condition's value: 1 (rad, sine), ``Lc`` (m), ``Fc`` (N), ``Fc Lc`` (N m)."""
    return typical_scale(cond.value_unit, Lc, Fc) or 1.0


def condition_description(cond: Condition) -> str:
    """A one-line meaning of the condition's value, for the variable's description."""
    return f"condition {cond.name}: {cond.description or cond.meaning()}"
