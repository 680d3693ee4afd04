"""The kinds of condition (``[conditions.NAME] type = ...``): one registered class each.

A :class:`Condition` is a :class:`~._plugin.PlugIn` of the family ``"conditions"``, written once for
both spaces against the kinematics protocol; its ``kind`` registers it in :data:`CONDITION_TYPES`
(see :mod:`._conditions` for what a condition is and the kinds' meanings). A kind gives its keys,
checks, expression, unit, default target and meaning.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from ..errors import InputError
from ._expr import Value
from ._plugin import Kinematics, PlugIn, Registry, registry

if TYPE_CHECKING:
    from ._description import Mechanism

__all__ = ["Condition", "ExpressionCondition", "CollinearCondition", "DistanceCondition", "AngleCondition",
           "CONDITION_TYPES"]

#: ``type`` -> condition class, in registration order (both spaces).
CONDITION_TYPES: Registry = registry("conditions", "plane")


@dataclass(frozen=True)
class Condition(PlugIn[Kinematics]):
    """Base of the conditions (see the module docstring for the kinds): a :class:`~._plugin.PlugIn`
    of the family ``"conditions"``, registered by its ``kind`` (the ``type`` of its table).

    ``name``: identifier, also the name of the generated state variable; ``target``: the value held
    by the downlock analysis (None: :meth:`default_target`); ``description``: free text."""

    name: str
    target: Value | None = field(default=None, kw_only=True)
    description: str = field(default="", kw_only=True)

    FAMILY: ClassVar[str] = "conditions"
    kind: ClassVar[str] = ""
    #: Unit of its value (SI; an expression declares its own).
    UNIT: ClassVar[str] = ""
    #: Keys of its table that are lists of point references or body names.
    LISTS: ClassVar[tuple[str, ...]] = ()

    @classmethod
    def table_keys(cls) -> frozenset[str]:
        """The keys of its table besides ``type``."""
        return cls.KEYS | {"target", "description"}

    @classmethod
    def from_table(cls, name: str, spec: Mapping, field: str) -> Condition:
        """The condition of a ``[conditions.NAME]`` table ``spec`` (keys besides ``type`` already checked)."""
        for k in cls.LISTS:
            if k in spec and not (isinstance(spec[k], list) and all(isinstance(r, str) for r in spec[k])):
                raise InputError(f"{field}.{k}", f"must be a list of strings, got {spec[k]!r}")
        for k in ("unit", "description"):
            if k in spec and not isinstance(spec[k], str):
                raise InputError(f"{field}.{k}", f"must be a string, got {spec[k]!r}")
        return cls(name, **cls._keywords(spec, field))

    @classmethod
    def _keywords(cls, spec: Mapping, field: str) -> dict[str, Any]:
        """The constructor's keywords of a checked table ``spec``."""
        return {k: (tuple(v) if k in cls.LISTS else v) for k, v in spec.items()}

    @property
    def value_unit(self) -> str:
        """The unit of the condition's value (SI)."""
        return self.UNIT

    def default_target(self) -> float | None:
        """The target held when none is given (None: a target is required to hold it)."""
        return 0.0

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its target, when given."""
        if self.target is not None:
            yield self.field("target"), self.target

    def expression(self, kin: Kinematics) -> sp.Expr:
        """Its value as an expression in the coordinates and parameters of ``kin``."""
        raise NotImplementedError

    def meaning(self) -> str:
        """A one-line meaning of its value (when it has no description)."""
        return ""

    def _check_points(self, mech: Mechanism, points: Sequence[str], n: int) -> None:
        f = self.field("points")
        if isinstance(points, str) or len(points) != n:
            raise InputError(f, f"a {self.kind} condition needs {n} point references, got {points!r}")
        for ref in points:
            mech.point_ref(ref, f)
        if len(set(points)) != n:
            raise InputError(f, f"the {n} points must be different, got {list(points)}")


@dataclass(frozen=True)
class ExpressionCondition(Condition):
    """Any expression ``expr`` in the coordinates and parameters (unit ``unit``, as declared)."""

    expr: Value | None = None
    unit: str = ""

    kind: ClassVar[str] = "expression"
    KEYS: ClassVar[frozenset[str]] = frozenset({"expr", "unit"})

    @property
    def value_unit(self) -> str:
        """The declared unit."""
        return self.unit

    def check(self, mech: Mechanism) -> None:
        """An expression is required; its unit is text."""
        if self.expr is None:
            raise InputError(self.field("expr"), "is required: an expression in coordinates and parameters")
        if not isinstance(self.unit, str):
            raise InputError(self.field("unit"), f"must be a string, got {self.unit!r}")

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its expression and target."""
        if self.expr is not None:
            yield self.field("expr"), self.expr
        yield from super().values(mech)

    def expression(self, kin: Kinematics) -> sp.Expr:
        """The parsed expression."""
        return kin.mech.value(self.field("expr"))

    def meaning(self) -> str:
        """The expression as written."""
        return f"{self.expr}"


@dataclass(frozen=True)
class CollinearCondition(Condition):
    """Three points ``[P1, P2, P3]``: the signed sine of the angle from ``P2 - P1`` to ``P3 - P1``
    (dimensionless; about ``normal`` in space)."""

    points: Sequence[str] = ()
    normal: Sequence[float] = ()

    kind: ClassVar[str] = "collinear"
    KEYS: ClassVar[frozenset[str]] = frozenset({"points", "normal"})
    LISTS: ClassVar[tuple[str, ...]] = ("points",)

    @classmethod
    def _keywords(cls, spec: Mapping, field: str) -> dict[str, Any]:
        """As any condition's, ``normal`` a list of numbers."""
        normal = spec.get("normal", [])
        if not (isinstance(normal, list) and all(isinstance(c, (int, float)) and not isinstance(c, bool)
                                                 for c in normal)):
            raise InputError(field + ".normal", f"must be a list of three numbers [x, y, z], got {normal!r}")
        return {**super()._keywords(spec, field), "normal": tuple(float(c) for c in normal)}

    def check(self, mech: Mechanism) -> None:
        """Three different points; a normal in space only (:func:`_check_normal`)."""
        self._check_points(mech, self.points, 3)
        _check_normal(mech, self, self.field())

    def expression(self, kin: Kinematics) -> sp.Expr:
        """``((P2 - P1) x (P3 - P1)) / (|P2 - P1| |P3 - P1|)`` (triple product with the unit normal in space)."""
        p1, p2, p3 = (kin.point(r) for r in self.points)
        u, v = p2 - p1, p3 - p1
        return _cross(u, v, self.normal) / (_norm(u) * _norm(v))

    def meaning(self) -> str:
        """Which sine, signed which way."""
        turn = "right-handed about the normal" if self.normal else "counter-clockwise"
        return (f"sine of the angle {self.points[0]}: {self.points[1]} -> {self.points[2]} (0: aligned, + {turn})"
                if len(self.points) == 3 else "")


@dataclass(frozen=True)
class DistanceCondition(Condition):
    """Two points ``[P, Q]``: ``|Q - P|`` (m); no default target."""

    points: Sequence[str] = ()

    kind: ClassVar[str] = "distance"
    UNIT: ClassVar[str] = "m"
    KEYS: ClassVar[frozenset[str]] = frozenset({"points"})
    LISTS: ClassVar[tuple[str, ...]] = ("points",)

    def default_target(self) -> float | None:
        """None: a distance held needs its target."""
        return None

    def check(self, mech: Mechanism) -> None:
        """Two different points."""
        self._check_points(mech, self.points, 2)

    def line_of_action(self) -> tuple[str, str] | None:
        """Its two points (``|Q - P|`` has no derivative where they coincide)."""
        return (self.points[0], self.points[1])

    def expression(self, kin: Kinematics) -> sp.Expr:
        """``|Q - P|``."""
        return _norm(kin.point(self.points[1]) - kin.point(self.points[0]))

    def meaning(self) -> str:
        """Between which points."""
        return f"distance {' - '.join(self.points)}"


@dataclass(frozen=True)
class AngleCondition(Condition):
    """Two bodies ``[b1, b2]``: ``theta_b2 - theta_b1`` (rad, not wrapped; planar only)."""

    bodies: Sequence[str] = ()

    kind: ClassVar[str] = "angle"
    UNIT: ClassVar[str] = "rad"
    KEYS: ClassVar[frozenset[str]] = frozenset({"bodies"})
    LISTS: ClassVar[tuple[str, ...]] = ("bodies",)

    def check(self, mech: Mechanism) -> None:
        """Planar only (``mech.UNAVAILABLE_CONDITIONS``); two different bodies (or the ground)."""
        f = self.field()
        if self.kind in mech.UNAVAILABLE_CONDITIONS:
            raise InputError(f + ".type", mech.UNAVAILABLE_CONDITIONS[self.kind])
        if isinstance(self.bodies, str) or len(self.bodies) != 2:
            raise InputError(f + ".bodies", f"an angle condition needs two body names, got {self.bodies!r}")
        for b in self.bodies:
            if b != "ground" and b not in mech.body_map:
                raise InputError(f + ".bodies", f"unknown body {b!r}; bodies: {', '.join(mech.body_map)}")
        if self.bodies[0] == self.bodies[1]:
            raise InputError(f + ".bodies", "the two bodies must be different")

    def expression(self, kin: Kinematics) -> sp.Expr:
        """``theta_b2 - theta_b1``."""
        b1, b2 = self.bodies
        return kin.relative_rotation(f"{b1}.origin", f"{b2}.origin", None)

    def meaning(self) -> str:
        """Of which bodies."""
        return f"theta of {self.bodies[-1]} minus theta of {self.bodies[0]}" if self.bodies else ""


def _cross(u: sp.Matrix, v: sp.Matrix, normal: Sequence = ()) -> sp.Expr:
    """Planar cross product, or (3-vectors) the triple product with the unit ``normal``."""
    if len(u) == 2:
        return u[0] * v[1] - u[1] * v[0]
    n = [sp.nsimplify(c) for c in normal]
    w = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    return sum((a * b for a, b in zip(w, n)), sp.S.Zero) / sp.sqrt(sum((c ** 2 for c in n), sp.S.Zero))


def _norm(u: sp.Matrix) -> sp.Expr:
    return sp.sqrt(sum((c ** 2 for c in u), sp.S.Zero))


def _check_normal(mech: Mechanism, c: CollinearCondition, f: str) -> None:
    """A spatial collinear condition needs a non-zero ``normal``; a planar one takes none
    (``mech.COLLINEAR_NORMAL``: whether a collinear condition is signed about a given normal)."""
    spatial = mech.COLLINEAR_NORMAL
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
