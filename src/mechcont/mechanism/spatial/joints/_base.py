"""The spatial joint protocol: the base every spatial joint derives from, its rows and registry.

Each joint joins point ``a`` (on a body or the ground) to point ``b`` and writes its scalar
constraint rows as "side a minus side b", so that a row's multiplier is the force (N) or
moment (N m) that the body of ``a`` exerts on the body of ``b`` along that row's direction.
A joint's vectors (``axis``, ``axis_a``, ``axis_b``) are given in the design pose, where every
body frame is parallel to the ground frame: the same vector then holds in both bodies' frames.
Rows "normal to an axis" ``u`` use the directions ``f``, ``g`` of
:func:`.._rotation.perpendiculars` (right-handed ``(f, g, u)``; axis x: f = y, g = z; axis y:
f = z, g = x; axis z: f = x, g = y), fixed in ``a``'s body: ``R_<name>_1`` acts along ``f``,
``R_<name>_2`` along ``g``, and ``T_<name>_1``, ``T_<name>_2`` keep ``f``, ``g`` of ``a``
perpendicular to the axis of ``b``.

A joint type is one module of :mod:`..joints` with one class (a :class:`~..._plugin.PlugIn` of the
family ``"joints"`` in space, written against ``SpatialKinematics``): its TOML ``kind`` and keys,
its rows (:meth:`SpatialJoint.rows`), whether it makes ``a`` and ``b`` coincide (used to place
bodies for the first assembly) and the axes drawn. Setting ``kind`` registers it in
:data:`JOINT_TYPES`.

Compliance: ``stiffness`` (N/m) turns the joint's translational rows, ``rotational_stiffness``
(N m/rad) its rotational rows, from rigid constraints ``Phi = 0`` into springs: the row
becomes ``Phi - lambda / k = 0`` (the deflection ``Phi`` (m or rad) equals the reaction over the
stiffness), and the mechanics sees the potential ``lambda^2 / (2 k)`` instead of a constraint.
Compliant rows never make a mechanism over-constrained: every reaction is then determinate.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from ....equations import Limit
from ....errors import InputError
from ..._expr import Value
from ..._plugin import Draw, PlugIn, Registry, registry
from ...joints._base import ConstraintRow, check_points
from .._rotation import dot, perpendiculars

if TYPE_CHECKING:
    from ..._description import Mechanism
    from .._kinematics import SpatialKinematics

__all__ = ["SpatialRow", "SpatialJoint", "JOINT_TYPES", "Vector", "vector3", "joint_keys"]

#: TOML ``type`` -> spatial joint class, in registration order.
JOINT_TYPES: Registry = registry("joints", "space")
Vector = tuple[Value, Value, Value]


@dataclass(frozen=True)
class SpatialRow(ConstraintRow):
    """A constraint row with its compliance: ``stiffness`` (N/m or N m/rad) or None (rigid)."""

    stiffness: sp.Expr | None = None


def vector3(v: Any, field: str) -> tuple[Any, ...]:
    """A 3-vector ``[x, y, z]`` of a description file (a one-line InputError naming ``field`` otherwise)."""
    if not isinstance(v, list) or len(v) != 3:
        raise InputError(field, f"must be a 3-vector [x, y, z], got {v!r}")
    return tuple(v)


@dataclass(frozen=True)
class SpatialJoint(PlugIn["SpatialKinematics"]):
    """Base of the spatial joints: ``a``, ``b`` point references and optional compliances."""

    name: str
    a: str
    b: str
    stiffness: Value | None = None
    rotational_stiffness: Value | None = None

    FAMILY: ClassVar[str] = "joints"
    SPACES: ClassVar[tuple[str, ...]] = ("space",)
    kind: ClassVar[str] = ""
    #: Keys of the joint's table besides ``type``, ``a``, ``b``, ``stiffness``, ``rotational_stiffness``.
    VECTORS: ClassVar[tuple[str, ...]] = ()
    #: Whether the joint makes ``a`` and ``b`` coincide (then it places ``b``'s body from ``a``'s).
    COINCIDENT: ClassVar[bool] = True
    #: Number of translational and rotational rows (for the degree-of-freedom bookkeeping).
    TRANSLATIONS: ClassVar[int] = 3
    ROTATIONS: ClassVar[int] = 0

    @classmethod
    def table_keys(cls) -> frozenset[str]:
        """The keys of its table besides ``type``."""
        return joint_keys(cls) - {"type"}

    @classmethod
    def from_table(cls, name: str, spec: Mapping, field: str) -> SpatialJoint:
        """The joint of a ``[joints.NAME]`` table ``spec`` (its keys already checked)."""
        for k in ("a", "b"):
            if k not in spec:
                raise InputError(f"{field}.{k}", "is required")
        kw: dict[str, Any] = {k: (vector3(v, f"{field}.{k}") if k in cls.VECTORS else v) for k, v in spec.items()}
        return cls(name, **kw)

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Value]]:
        """Every (key path, raw value) of the joint that is a number or an expression."""
        f = f"joints.{self.name}"
        for key in self.VECTORS:
            v = getattr(self, key)
            if not isinstance(v, (tuple, list)) or len(v) != 3:
                raise InputError(f"{f}.{key}", f"must be a 3-vector [x, y, z], got {v!r}")
            for c, comp in zip("xyz", v):
                yield f"{f}.{key}.{c}", comp
        if self.rotational_stiffness is not None and self.ROTATIONS == 0:
            holding = ", ".join(c.kind for c in JOINT_TYPES.values() if c.ROTATIONS)
            raise InputError(f"{f}.rotational_stiffness", f"a {self.kind} joint leaves the rotation free (it has no "
                                                          "rotational rows to make compliant): remove it, or use a "
                                                          f"joint that holds rotation ({holding})")
        for key in ("stiffness", "rotational_stiffness"):
            if getattr(self, key) is not None:
                yield f"{f}.{key}", getattr(self, key)

    def check(self, mech: Mechanism) -> None:
        """Check the point references ``a``, ``b`` against ``mech`` (a one-line InputError naming the key)."""
        check_points(self.name, [("a", self.a), ("b", self.b)], mech)

    def limits(self, kin: SpatialKinematics, solve: bool) -> list[Limit]:
        """The stiffnesses given must be positive."""
        return [self.value_limit(kin, key, True, what)
                for key, what in (("stiffness", "joint stiffness (N/m)"),
                                  ("rotational_stiffness", "joint rotational stiffness (N m/rad)"))
                if getattr(self, key) is not None]

    def perpendicular(self, mech: Mechanism) -> list[list[sp.Expr]]:
        """Pairs of vectors (six expressions) that must be perpendicular (default: none)."""
        return []

    def check_values(self, mech: Mechanism, values: Mapping[str, float]) -> None:
        """Reject values impossible for this joint at the parameter ``values`` (default: none)."""

    def vector(self, kin: SpatialKinematics, key: str) -> sp.Matrix:
        """The joint vector ``key`` (design pose) as a SymPy 3-vector."""
        return sp.Matrix([kin.mech.value(f"joints.{self.name}.{key}.{c}") for c in "xyz"])

    def _k(self, kin: SpatialKinematics, key: str) -> sp.Expr | None:
        return kin.mech.value(f"joints.{self.name}.{key}") if getattr(self, key) is not None else None

    def _point_rows(self, kin: SpatialKinematics) -> list[SpatialRow]:
        d = kin.point(self.a) - kin.point(self.b)
        k = self._k(kin, "stiffness")
        n = self.name
        return [SpatialRow(n, f"{n}_{c}", f"R_{n}_{c}", "N", d[i], k) for i, c in enumerate("xyz")]

    def _rotation_row(self, kin: SpatialKinematics, i: int, u_a: sp.Matrix, v_b: sp.Matrix) -> SpatialRow:
        """``(A_a u_a) . (A_b v_b) = 0``: zero while the two body vectors stay perpendicular."""
        n = self.name
        expr = dot(kin.turn(self.a, u_a), kin.turn(self.b, v_b))
        return SpatialRow(n, f"{n}_rot{i}", f"T_{n}_{i}", "N m", expr, self._k(kin, "rotational_stiffness"))

    def _axis_rows(self, kin: SpatialKinematics, axis: sp.Matrix) -> list[SpatialRow]:
        """Two rows keeping ``axis`` (design pose) parallel in both bodies."""
        u, f, g = perpendiculars(axis, kin.defaults)
        return [self._rotation_row(kin, 1, f, u), self._rotation_row(kin, 2, g, u)]

    def rows(self, kin: SpatialKinematics) -> list[SpatialRow]:
        """The joint's constraint rows in the coordinates of ``kin``."""
        raise NotImplementedError

    def drawn_axes(self, kin: SpatialKinematics) -> list[sp.Matrix]:
        """Global unit vectors to draw through the joint (pin axes)."""
        return []

    def draw(self, kin: SpatialKinematics, add: Draw) -> None:
        """A pin (``ground`` when it joins the ground) at ``b`` and its axes."""
        ground = "ground" in (self.a.split(".")[0], self.b.split(".")[0])
        add("ground" if ground else "pin", self.name, [kin.point(self.b)])
        for axis in self.drawn_axes(kin):
            add("axis", self.name, [kin.point(self.b), axis])


def joint_keys(cls: type[SpatialJoint]) -> frozenset[str]:
    """Keys accepted in a ``[joints.NAME]`` table of joint class ``cls`` (``type`` included)."""
    return frozenset({"type", "a", "b", "stiffness", "rotational_stiffness", *cls.VECTORS})
