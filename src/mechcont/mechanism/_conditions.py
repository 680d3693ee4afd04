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
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp

from ..errors import InputError
from ..units import typical_scale
from ._expr import Value

__all__ = ["Condition", "DownlockSpec", "condition_expr", "check_conditions", "conditions_from_table",
           "downlock_from_table", "CONDITION_KEYS", "CONDITION_UNITS"]

#: Keys of a ``[conditions]`` entry per kind (an expression may also be a bare string).
CONDITION_KEYS: dict[str, frozenset[str]] = {
    "expression": frozenset({"type", "expr", "unit", "target", "description"}),
    "collinear": frozenset({"type", "points", "normal", "target", "description"}),
    "distance": frozenset({"type", "points", "target", "description"}),
    "angle": frozenset({"type", "bodies", "target", "description"}),
}
#: Unit of each kind's value (an expression's is declared with ``unit``).
CONDITION_UNITS = {"collinear": "", "distance": "m", "angle": "rad"}
_COUNT = {"collinear": 3, "distance": 2}


@dataclass(frozen=True)
class Condition:
    """A named relation of the configuration (see the module docstring for the kinds).

    Parameters
    ----------
    name:
        Identifier; also the name of the generated state variable.
    kind:
        ``"expression"``, ``"collinear"``, ``"distance"`` or ``"angle"``.
    expr:
        The expression (kind ``"expression"``): a string in coordinates and parameters.
    points:
        Point references (three for collinear, two for distance).
    bodies:
        Two body names (angle).
    normal:
        Collinear condition of a spatial mechanism: the direction (3 numbers) about which the
        sine is signed, ``((P2 - P1) x (P3 - P1)) . n / (|P2 - P1| |P3 - P1| |n|)``.
    target:
        Value held by the downlock analysis (None: default 0, none for a distance).
    unit:
        Unit of an expression's value (display and scaling: ``"m"``, ``"rad"``, ``"N"``).
    description:
        Free text.
    """

    name: str
    kind: str = "expression"
    expr: Value | None = None
    points: Sequence[str] = ()
    bodies: Sequence[str] = ()
    target: Value | None = None
    unit: str = ""
    description: str = ""
    normal: Sequence[float] = ()

    @property
    def value_unit(self) -> str:
        """The unit of the condition's value (SI)."""
        return self.unit if self.kind == "expression" else CONDITION_UNITS[self.kind]


@dataclass(frozen=True)
class DownlockSpec:
    """The downlock condition of a mechanism: the condition held (at its target) and the
    force (a parameter, N) freed and solved for; see :mod:`mechcont.analysis.downlock`."""

    condition: str
    force: str


def _cross(u: sp.Matrix, v: sp.Matrix, normal: Sequence = ()) -> sp.Expr:
    """Planar cross product, or (3-vectors) the triple product with the unit ``normal``."""
    if len(u) == 2:
        return u[0] * v[1] - u[1] * v[0]
    n = [sp.nsimplify(c) for c in normal]
    w = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    return sum((a * b for a, b in zip(w, n)), sp.S.Zero) / sp.sqrt(sum((c ** 2 for c in n), sp.S.Zero))


def _norm(u: sp.Matrix) -> sp.Expr:
    return sp.sqrt(sum((c ** 2 for c in u), sp.S.Zero))


def condition_expr(kin, cond: Condition) -> sp.Expr:
    """The value of ``cond`` as an expression in the coordinates and parameters of ``kin``."""
    mech = kin.mech
    if cond.kind == "expression":
        return mech.value(f"conditions.{cond.name}.expr")
    if cond.kind == "collinear":
        p1, p2, p3 = (kin.point(r) for r in cond.points)
        u, v = p2 - p1, p3 - p1
        return _cross(u, v, cond.normal) / (_norm(u) * _norm(v))
    if cond.kind == "distance":
        return _norm(kin.point(cond.points[1]) - kin.point(cond.points[0]))
    b1, b2 = cond.bodies
    return kin.angle(f"{b2}.origin") - kin.angle(f"{b1}.origin")


def check_conditions(mech) -> None:
    """Check every condition's kind, references and target (raises a one-line InputError)."""
    for c in mech.conditions:
        f = f"conditions.{c.name}"
        if c.name in mech.param_symbols or c.name in mech.coordinate_symbols:
            what = "parameter" if c.name in mech.param_symbols else "coordinate"
            raise InputError(f, f"clashes with the {what} {c.name!r}: a condition's name is a variable of the model")
        if c.kind not in CONDITION_KEYS:
            raise InputError(f + ".type", f"must be one of {', '.join(CONDITION_KEYS)}, got {c.kind!r}")
        if c.kind == "expression":
            if c.expr is None:
                raise InputError(f + ".expr", "is required: an expression in coordinates and parameters")
        elif c.kind in _COUNT:
            n = _COUNT[c.kind]
            if isinstance(c.points, str) or len(c.points) != n:
                raise InputError(f + ".points", f"a {c.kind} condition needs {n} point references, got {c.points!r}")
            for ref in c.points:
                mech.point_ref(ref, f"{f}.points")
            if len(set(c.points)) != n:
                raise InputError(f + ".points", f"the {n} points must be different, got {list(c.points)}")
            _check_normal(mech, c, f)
        else:
            if c.kind in mech.UNAVAILABLE_CONDITIONS:
                raise InputError(f + ".type", mech.UNAVAILABLE_CONDITIONS[c.kind])
            if isinstance(c.bodies, str) or len(c.bodies) != 2:
                raise InputError(f + ".bodies", f"an angle condition needs two body names, got {c.bodies!r}")
            for b in c.bodies:
                if b != "ground" and b not in mech.body_map:
                    raise InputError(f + ".bodies", f"unknown body {b!r}; bodies: {', '.join(mech.body_map)}")
            if c.bodies[0] == c.bodies[1]:
                raise InputError(f + ".bodies", "the two bodies must be different")
        if not isinstance(c.unit, str):
            raise InputError(f + ".unit", f"must be a string, got {c.unit!r}")
    spec = mech.downlock
    if spec is None:
        return
    names = {c.name: c for c in mech.conditions}
    if spec.condition not in names:
        valid = ", ".join(names) or "none declared under [conditions]"
        raise InputError("mechanism.downlock.condition", f"unknown condition {spec.condition!r}; conditions: {valid}")
    if names[spec.condition].kind == "distance" and names[spec.condition].target is None:
        raise InputError(f"conditions.{spec.condition}.target", "a distance condition held by the downlock needs "
                                                                "a target (m)")
    if spec.force not in mech.param_symbols:
        valid = ", ".join(mech.param_symbols) or "none"
        raise InputError("mechanism.downlock.force", f"must be a parameter (the force solved for), got "
                                                     f"{spec.force!r}; parameters: {valid}")


def _check_normal(mech, c: Condition, f: str) -> None:
    """A spatial collinear condition needs a non-zero ``normal``; a planar one takes none
    (``mech.COLLINEAR_NORMAL``: whether a collinear condition is signed about a given normal)."""
    spatial = mech.COLLINEAR_NORMAL
    if c.kind != "collinear":
        return
    if not spatial and c.normal:
        raise InputError(f + ".normal", "is for spatial mechanisms; a planar collinear condition is signed "
                                        "counter-clockwise in the plane")
    if spatial and (len(c.normal) != 3 or not any(c.normal)):
        raise InputError(f + ".normal", "a spatial collinear condition needs normal = [x, y, z] (non-zero): the "
                                        "direction about which its sine is signed")
    if spatial and not _normalisable(c.normal):
        raise InputError(f + ".normal", f"must be a finite direction whose length is between 1e-150 and 1e150 (it is "
                                        f"normalised), got {list(c.normal)!r}")


def _normalisable(v: Sequence[float]) -> bool:
    """Every component finite and the squared length a normal float (neither overflow nor underflow)."""
    if not all(math.isfinite(c) for c in v):
        return False
    n = math.hypot(*v)
    return 1e-150 <= n <= 1e150


def conditions_from_table(tab: Mapping, field: str = "conditions") -> list[Condition]:
    """``[conditions]`` as parsed TOML -> :class:`Condition` objects (keys checked)."""
    out = []
    for name, spec in tab.items():
        f = f"{field}.{name}"
        if isinstance(spec, str):
            out.append(Condition(name, "expression", expr=spec))
            continue
        if not isinstance(spec, Mapping):
            raise InputError(f, "a condition is an expression string or a table {type = ..., ...}, "
                                f"got {type(spec).__name__}")
        kind = spec.get("type", "expression")
        if kind not in CONDITION_KEYS:
            raise InputError(f + ".type", f"must be one of {', '.join(CONDITION_KEYS)}, got {kind!r}")
        for k in spec:
            if k not in CONDITION_KEYS[kind]:
                raise InputError(f"{f}.{k}", f"unknown key for a {kind} condition; valid keys: "
                                             f"{', '.join(sorted(CONDITION_KEYS[kind]))}")
        for k in ("points", "bodies"):
            if k in spec and not (isinstance(spec[k], list) and all(isinstance(r, str) for r in spec[k])):
                raise InputError(f"{f}.{k}", f"must be a list of strings, got {spec[k]!r}")
        for k in ("unit", "description"):
            if k in spec and not isinstance(spec[k], str):
                raise InputError(f"{f}.{k}", f"must be a string, got {spec[k]!r}")
        normal = spec.get("normal", [])
        if not (isinstance(normal, list) and all(isinstance(c, (int, float)) and not isinstance(c, bool)
                                                 for c in normal)):
            raise InputError(f + ".normal", f"must be a list of three numbers [x, y, z], got {normal!r}")
        out.append(Condition(name, kind, expr=spec.get("expr"), points=tuple(spec.get("points", ())),
                             bodies=tuple(spec.get("bodies", ())), target=spec.get("target"),
                             unit=spec.get("unit", ""), description=spec.get("description", ""),
                             normal=tuple(float(c) for c in normal)))
    return out


def downlock_from_table(spec, field: str = "mechanism.downlock") -> DownlockSpec:
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
def condition_rows(kin, subs: Mapping) -> list[tuple[Condition, sp.Expr]]:
    """``(condition, c(q, p))`` for every condition, eliminated coordinates substituted (``subs``)."""
    return [(c, sp.sympify(condition_expr(kin, c), strict=True).xreplace(dict(subs))) for c in kin.mech.conditions]


def condition_scale(cond: Condition, Lc: float, Fc: float) -> float:
    """Typical magnitude of the condition's value: 1 (rad, sine), ``Lc`` (m), ``Fc`` (N), ``Fc Lc`` (N m)."""
    return typical_scale(cond.value_unit, Lc, Fc) or 1.0


def condition_targets(mech, values: Mapping[str, float]) -> dict[str, float | None]:
    """Each condition's target at the parameter ``values`` (0 by default; None for a distance without one)."""
    from ._values import evaluate

    out: dict[str, float | None] = {}
    for c in mech.conditions:
        f = f"conditions.{c.name}.target"
        out[c.name] = (evaluate(mech.value(f), values, f) if c.target is not None
                       else (None if c.kind == "distance" else 0.0))
    return out


def condition_description(cond: Condition) -> str:
    """A one-line meaning of the condition's value, for the variable's description."""
    turn = "right-handed about the normal" if cond.normal else "counter-clockwise"
    what = {"expression": f"{cond.expr}", "collinear": f"sine of the angle {cond.points[0]}: {cond.points[1]} -> "
                                                       f"{cond.points[2]} (0: aligned, + {turn})"
            if len(cond.points) == 3 else "", "distance": f"distance {' - '.join(cond.points)}",
            "angle": f"theta of {cond.bodies[-1]} minus theta of {cond.bodies[0]}" if cond.bodies else ""}[cond.kind]
    return f"condition {cond.name}: {cond.description or what}"
