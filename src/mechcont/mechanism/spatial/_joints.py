"""Joints of spatial mechanisms: one class per joint type.

Each joint joins point ``a`` (on a body or the ground) to point ``b`` and writes its scalar
constraint rows as "side a minus side b", so that a row's multiplier is the force (N) or
moment (N m) that the body of ``a`` exerts on the body of ``b`` along that row's direction.
A joint's vectors (``axis``, ``axis_a``, ``axis_b``) are given in the design pose, where every
body frame is parallel to the ground frame: the same vector then holds in both bodies' frames.
Rows "normal to an axis" ``u`` use the directions ``f``, ``g`` of
:func:`._rotation.perpendiculars` (right-handed ``(f, g, u)``; axis x: f = y, g = z; axis y:
f = z, g = x; axis z: f = x, g = y), fixed in ``a``'s body: ``R_<name>_1`` acts along ``f``,
``R_<name>_2`` along ``g``, and ``T_<name>_1``, ``T_<name>_2`` keep ``f``, ``g`` of ``a``
perpendicular to the axis of ``b``.

A joint type is one class: its TOML ``kind`` and keys, its rows (:meth:`SpatialJoint.rows`),
whether it makes ``a`` and ``b`` coincide (used to place bodies for the first assembly) and
the axes drawn. Adding a joint type is adding a class to :data:`JOINT_TYPES`.

Compliance: ``stiffness`` (N/m) turns the joint's translational rows, ``rotational_stiffness``
(N m/rad) its rotational rows, from rigid constraints ``Phi = 0`` into springs: the row
becomes ``Phi - lambda / k = 0`` (the deflection ``Phi`` (m or rad) equals the reaction over the
stiffness), and the mechanics sees the potential ``lambda^2 / (2 k)`` instead of a constraint.
Compliant rows never make a mechanism over-constrained: every reaction is then determinate.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import sympy as sp

from ...errors import InputError
from .._expr import Value
from .._kinematics import ConstraintRow
from ..joints._base import check_points
from ._rotation import dot, perpendiculars

__all__ = ["SpatialRow", "SpatialJoint", "Spherical", "Revolute3", "Universal", "Inline", "Cylindrical", "Prismatic3",
           "Weld3", "JOINT_TYPES"]

Vector = tuple[Value, Value, Value]


@dataclass(frozen=True)
class SpatialRow(ConstraintRow):
    """A constraint row with its compliance: ``stiffness`` (N/m or N m/rad) or None (rigid)."""

    stiffness: sp.Expr | None = None


def vector3(v, field: str) -> tuple:
    """A 3-vector ``[x, y, z]`` of a description file (a one-line InputError naming ``field`` otherwise)."""
    if not isinstance(v, list) or len(v) != 3:
        raise InputError(field, f"must be a 3-vector [x, y, z], got {v!r}")
    return tuple(v)


@dataclass(frozen=True)
class SpatialJoint:
    """Base of the spatial joints: ``a``, ``b`` point references and optional compliances."""

    name: str
    a: str
    b: str
    stiffness: Value | None = None
    rotational_stiffness: Value | None = None

    kind: ClassVar[str] = ""
    #: Keys of the joint's table besides ``type``, ``a``, ``b``, ``stiffness``, ``rotational_stiffness``.
    VECTORS: ClassVar[tuple[str, ...]] = ()
    #: Whether the joint makes ``a`` and ``b`` coincide (then it places ``b``'s body from ``a``'s).
    COINCIDENT: ClassVar[bool] = True
    #: Number of translational and rotational rows (for the degree-of-freedom bookkeeping).
    TRANSLATIONS: ClassVar[int] = 3
    ROTATIONS: ClassVar[int] = 0

    @classmethod
    def from_table(cls, name: str, spec: Mapping, field: str) -> SpatialJoint:
        """The joint of a ``[joints.NAME]`` table ``spec`` (its keys already checked)."""
        for k in ("a", "b"):
            if k not in spec:
                raise InputError(f"{field}.{k}", "is required")
        kw: dict[str, Any] = {k: (vector3(v, f"{field}.{k}") if k in cls.VECTORS else v) for k, v in spec.items()}
        return cls(name, **kw)

    def values(self) -> Iterator[tuple[str, Value]]:
        """Every (key path, raw value) of the joint that is a number or an expression."""
        f = f"joints.{self.name}"
        for key in self.VECTORS:
            v = getattr(self, key)
            if not isinstance(v, (tuple, list)) or len(v) != 3:
                raise InputError(f"{f}.{key}", f"must be a 3-vector [x, y, z], got {v!r}")
            for c, comp in zip("xyz", v):
                yield f"{f}.{key}.{c}", comp
        if self.rotational_stiffness is not None and self.ROTATIONS == 0:
            holding = ", ".join(c.kind for c in _rotation_holding())
            raise InputError(f"{f}.rotational_stiffness", f"a {self.kind} joint leaves the rotation free (it has no "
                                                          "rotational rows to make compliant): remove it, or use a "
                                                          f"joint that holds rotation ({holding})")
        for key in ("stiffness", "rotational_stiffness"):
            if getattr(self, key) is not None:
                yield f"{f}.{key}", getattr(self, key)

    def check(self, mech) -> None:
        """Check the point references ``a``, ``b`` against ``mech`` (a one-line InputError naming the key)."""
        check_points(self.name, [("a", self.a), ("b", self.b)], mech)

    def limits(self, kin) -> list[tuple[str, sp.Expr, bool, str]]:
        """``(key path, quantity, strict, what)``: the stiffnesses given must be positive."""
        out = []
        for key, what in (("stiffness", "joint stiffness (N/m)"),
                          ("rotational_stiffness", "joint rotational stiffness (N m/rad)")):
            if getattr(self, key) is not None:
                out.append((f"joints.{self.name}.{key}", kin.mech.value(f"joints.{self.name}.{key}"), True, what))
        return out

    def perpendicular(self, mech) -> list[list[sp.Expr]]:
        """Pairs of vectors (six expressions) that must be perpendicular (default: none)."""
        return []

    def check_values(self, mech, values) -> None:
        """Reject values impossible for this joint at the parameter ``values`` (default: none)."""

    def vector(self, kin, key: str) -> sp.Matrix:
        """The joint vector ``key`` (design pose) as a SymPy 3-vector."""
        return sp.Matrix([kin.mech.value(f"joints.{self.name}.{key}.{c}") for c in "xyz"])

    def _k(self, kin, key: str) -> sp.Expr | None:
        return kin.mech.value(f"joints.{self.name}.{key}") if getattr(self, key) is not None else None

    def _point_rows(self, kin) -> list[SpatialRow]:
        d = kin.point(self.a) - kin.point(self.b)
        k = self._k(kin, "stiffness")
        n = self.name
        return [SpatialRow(n, f"{n}_{c}", f"R_{n}_{c}", "N", d[i], k) for i, c in enumerate("xyz")]

    def _rotation_row(self, kin, i: int, u_a: sp.Matrix, v_b: sp.Matrix) -> SpatialRow:
        """``(A_a u_a) . (A_b v_b) = 0``: zero while the two body vectors stay perpendicular."""
        n = self.name
        expr = dot(kin.turn(self.a, u_a), kin.turn(self.b, v_b))
        return SpatialRow(n, f"{n}_rot{i}", f"T_{n}_{i}", "N m", expr, self._k(kin, "rotational_stiffness"))

    def _axis_rows(self, kin, axis: sp.Matrix) -> list[SpatialRow]:
        """Two rows keeping ``axis`` (design pose) parallel in both bodies."""
        u, f, g = perpendiculars(axis, kin.defaults)
        return [self._rotation_row(kin, 1, f, u), self._rotation_row(kin, 2, g, u)]

    def rows(self, kin) -> list[SpatialRow]:
        """The joint's constraint rows in the coordinates of ``kin``."""
        raise NotImplementedError

    def drawn_axes(self, kin) -> list[sp.Matrix]:
        """Global unit vectors to draw through the joint (pin axes)."""
        return []


@dataclass(frozen=True)
class Spherical(SpatialJoint):
    """A ball joint: ``a`` and ``b`` coincide. Reactions ``R_<name>_x/y/z`` (N, global axes)."""

    kind: ClassVar[str] = "spherical"

    def rows(self, kin) -> list[SpatialRow]:
        return self._point_rows(kin)


@dataclass(frozen=True)
class Revolute3(SpatialJoint):
    """A hinge: ``a`` and ``b`` coincide and ``axis`` stays common to both bodies.
    Reactions ``R_<name>_x/y/z`` (N) and ``T_<name>_1``, ``T_<name>_2`` (N m, about two
    directions normal to the axis)."""

    axis: Vector = (0, 0, 1)
    kind: ClassVar[str] = "revolute"
    VECTORS: ClassVar[tuple[str, ...]] = ("axis",)
    ROTATIONS: ClassVar[int] = 2

    def rows(self, kin) -> list[SpatialRow]:
        return self._point_rows(kin) + self._axis_rows(kin, self.vector(kin, "axis"))

    def drawn_axes(self, kin) -> list[sp.Matrix]:
        return [kin.turn(self.a, perpendiculars(self.vector(kin, "axis"), kin.defaults)[0])]


@dataclass(frozen=True)
class Universal(SpatialJoint):
    """A Cardan joint: ``a`` and ``b`` coincide; ``axis_a`` (fixed in ``a``'s body) stays
    perpendicular to ``axis_b`` (fixed in ``b``'s body); the two must be perpendicular in the
    design pose. Reactions ``R_<name>_x/y/z`` (N) and ``T_<name>_1`` (N m)."""

    axis_a: Vector = (1, 0, 0)
    axis_b: Vector = (0, 1, 0)
    kind: ClassVar[str] = "universal"
    VECTORS: ClassVar[tuple[str, ...]] = ("axis_a", "axis_b")
    ROTATIONS: ClassVar[int] = 1

    def perpendicular(self, mech) -> list[list[sp.Expr]]:
        """``axis_a`` and ``axis_b`` must be perpendicular in the design pose."""
        return [[mech.value(f"joints.{self.name}.{axis}.{c}") for axis in ("axis_a", "axis_b") for c in "xyz"]]

    def check_values(self, mech, values) -> None:
        """``axis_a`` perpendicular to ``axis_b`` at ``values`` (one-line InputError)."""
        from .._values import evaluate

        a = [evaluate(mech.value(f"joints.{self.name}.axis_a.{c}"), values, "") for c in "xyz"]
        b = [evaluate(mech.value(f"joints.{self.name}.axis_b.{c}"), values, "") for c in "xyz"]
        c = sum(p * q for p, q in zip(a, b)) / (sum(p * p for p in a) * sum(q * q for q in b)) ** 0.5
        if abs(c) > 1e-9:
            raise InputError(f"joints.{self.name}.axis_b", f"must be perpendicular to axis_a in the design pose "
                                                           f"(cosine of the angle between them {c:.3g})")

    def rows(self, kin) -> list[SpatialRow]:
        ua = perpendiculars(self.vector(kin, "axis_a"), kin.defaults)[0]
        ub = perpendiculars(self.vector(kin, "axis_b"), kin.defaults)[0]
        return self._point_rows(kin) + [self._rotation_row(kin, 1, ua, ub)]

    def drawn_axes(self, kin) -> list[sp.Matrix]:
        return [kin.turn(self.a, perpendiculars(self.vector(kin, "axis_a"), kin.defaults)[0]),
                kin.turn(self.b, perpendiculars(self.vector(kin, "axis_b"), kin.defaults)[0])]


@dataclass(frozen=True)
class Inline(SpatialJoint):
    """Point ``b`` stays on the line through ``a`` along ``axis`` (fixed in ``a``'s body); every
    rotation is free (a ball in a slot: the planar slider's spatial form). Reactions
    ``R_<name>_1``, ``R_<name>_2`` (N, normal to the line)."""

    axis: Vector = (1, 0, 0)
    kind: ClassVar[str] = "inline"
    VECTORS: ClassVar[tuple[str, ...]] = ("axis",)
    COINCIDENT: ClassVar[bool] = False
    TRANSLATIONS: ClassVar[int] = 2

    def _line_rows(self, kin) -> list[SpatialRow]:
        _, f, g = perpendiculars(self.vector(kin, "axis"), kin.defaults)
        d = kin.point(self.a) - kin.point(self.b)
        k, n = self._k(kin, "stiffness"), self.name
        return [SpatialRow(n, f"{n}_n{i}", f"R_{n}_{i}", "N", dot(kin.turn(self.a, v), d), k)
                for i, v in ((1, f), (2, g))]

    def rows(self, kin) -> list[SpatialRow]:
        return self._line_rows(kin)


@dataclass(frozen=True)
class Cylindrical(Inline):
    """``b`` slides along and turns about the line through ``a`` along ``axis`` (fixed in
    ``a``'s body). Reactions ``R_<name>_1``, ``R_<name>_2`` (N, normal to the axis) and
    ``T_<name>_1``, ``T_<name>_2`` (N m)."""

    axis: Vector = (0, 0, 1)
    kind: ClassVar[str] = "cylindrical"
    ROTATIONS: ClassVar[int] = 2

    def rows(self, kin) -> list[SpatialRow]:
        return self._line_rows(kin) + self._axis_rows(kin, self.vector(kin, "axis"))

    def drawn_axes(self, kin) -> list[sp.Matrix]:
        return [kin.turn(self.a, perpendiculars(self.vector(kin, "axis"), kin.defaults)[0])]


@dataclass(frozen=True)
class Prismatic3(Cylindrical):
    """A cylindrical joint that also locks the rotation about its axis. Reactions as the
    cylindrical joint's and ``T_<name>_3`` (N m, about the axis)."""

    kind: ClassVar[str] = "prismatic"
    ROTATIONS: ClassVar[int] = 3

    def rows(self, kin) -> list[SpatialRow]:
        _, f, g = perpendiculars(self.vector(kin, "axis"), kin.defaults)
        return super().rows(kin) + [self._rotation_row(kin, 3, f, g)]


@dataclass(frozen=True)
class Weld3(SpatialJoint):
    """A rigid connection: ``a`` and ``b`` coincide and the bodies keep their design-pose
    relative orientation. Reactions ``R_<name>_x/y/z`` (N) and ``T_<name>_1..3`` (N m, about
    the x, y, z axes of ``a``'s body)."""

    kind: ClassVar[str] = "weld"
    ROTATIONS: ClassVar[int] = 3

    def rows(self, kin) -> list[SpatialRow]:
        ex, ey, ez = (sp.Matrix([int(i == j) for j in range(3)]) for i in range(3))
        return self._point_rows(kin) + [self._rotation_row(kin, 1, ey, ez), self._rotation_row(kin, 2, ez, ex),
                                        self._rotation_row(kin, 3, ex, ey)]


#: TOML ``type`` -> joint class.
JOINT_TYPES: dict[str, type[SpatialJoint]] = {
    cls.kind: cls for cls in (Spherical, Revolute3, Universal, Inline, Cylindrical, Prismatic3, Weld3)}


def joint_keys(cls: type[SpatialJoint]) -> frozenset[str]:
    """Keys accepted in a ``[joints.NAME]`` table of joint class ``cls`` (``type`` included)."""
    return frozenset({"type", "a", "b", "stiffness", "rotational_stiffness", *cls.VECTORS})


def _rotation_holding() -> list[type[SpatialJoint]]:
    """The joint classes with rotational rows (those a ``rotational_stiffness`` applies to), in declaration order."""
    return [c for c in (Revolute3, Universal, Cylindrical, Prismatic3, Weld3) if c.ROTATIONS]
