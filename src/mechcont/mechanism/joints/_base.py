"""The planar joint protocol: one class per joint type, registered by its TOML ``type``.

A joint joins a point of one body (or the ground), side ``a``, to a point of another, side
``b``, and writes its scalar constraint rows as "side a minus side b", so that a row's
multiplier is the force (N) or moment (N m) that the body of ``a`` exerts on the body of ``b``
along that row's direction. A joint class gives

* ``kind``: its ``type`` in a description file (setting it registers the class in
  :data:`JOINT_TYPES`, the planar ``"joints"`` registry of :mod:`.._plugin`); ``KEYS``,
  ``REQUIRED``: its table's keys besides ``type``;
  ``VALUES``: the keys holding numbers or expressions (parsed over the parameters);
* :meth:`~PlanarJoint.check`: the point references, with one-line errors naming the key;
* :meth:`~PlanarJoint.rows`: its constraint rows against the planar kinematics (``kin.point``,
  ``kin.angle``, ``kin.local_point``), each with its reaction's name and unit;
* ``COINCIDENT`` and :meth:`~PlanarJoint.locked_angle`: whether it makes ``a`` and ``b``
  coincide (and fixes ``theta_b - theta_a``), used to place bodies for the first assembly and
  to eliminate coordinates in the reduced form;
* :meth:`~PlanarJoint.draw`: its drawing primitives; :meth:`~PlanarJoint.limits`: the
  physical ranges of its values.

The class is a :class:`~.._plugin.PlugIn` of the family ``"joints"`` written against the planar
kinematics (``PlugIn[PlanarKinematics]``). Adding a joint type is adding one module to this
package with one such class.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import sympy as sp

from ...errors import InputError
from .._plugin import Draw, PlugIn, Registry, registry

if TYPE_CHECKING:
    from .._description import Mechanism
    from .._kinematics import PlanarKinematics

__all__ = ["ConstraintRow", "PlanarJoint", "JOINT_TYPES", "Draw", "check_points", "point_rows", "line_row", "angle_row"]

#: TOML ``type`` -> planar joint class, in registration order.
JOINT_TYPES: Registry = registry("joints", "plane")


@dataclass(frozen=True)
class ConstraintRow:
    """One scalar constraint: its joint, equation name, reaction name, unit, expression."""

    joint: str
    equation: str
    reaction: str
    unit: str
    expr: sp.Expr


class PlanarJoint(PlugIn["PlanarKinematics"]):
    """Base of the planar joints (see the module docstring for the protocol).

    Subclasses are frozen dataclasses whose first field is ``name``; ``a`` and ``b`` are the
    point references of side a and side b (fields, or properties of the joint's own keys)."""

    name: str
    a: str
    b: str
    FAMILY: ClassVar[str] = "joints"
    SPACES: ClassVar[tuple[str, ...]] = ("plane",)
    kind: ClassVar[str] = ""
    KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("a", "b")
    VALUES: ClassVar[tuple[str, ...]] = ()
    #: Keys of the joint's vectors that must not be zero (none so far in the plane).
    VECTORS: ClassVar[tuple[str, ...]] = ()
    COINCIDENT: ClassVar[bool] = False

    @classmethod
    def from_table(cls, name: str, spec: Mapping, field: str) -> PlanarJoint:
        """The joint of a ``[joints.NAME]`` table ``spec`` (its keys already checked against ``KEYS``)."""
        for k in cls.REQUIRED:
            if k not in spec:
                raise InputError(f"{field}.{k}", "is required")
        return cls(name, **spec)  # type: ignore[call-arg]

    def refs(self) -> list[tuple[str, str]]:
        """``(key, point reference)`` of every point the joint names."""
        return [("a", self.a), ("b", self.b)]

    def check(self, mech: Mechanism) -> None:
        """Check the point references against ``mech`` (a one-line InputError naming the key)."""
        check_points(self.name, self.refs(), mech)

    def values(self, mech: Mechanism) -> Iterator[tuple[str, object]]:
        """Every (key path, raw value) of the joint that is a number or an expression."""
        for key in self.VALUES:
            yield f"joints.{self.name}.{key}", getattr(self, key)

    def value(self, kin: PlanarKinematics, key: str) -> sp.Expr:
        """The parsed expression of the joint's value ``key``."""
        return kin.mech.value(f"joints.{self.name}.{key}")

    def grounded(self) -> bool:
        """Whether either side is a ground point."""
        return "ground" in (self.a.split(".")[0], self.b.split(".")[0])

    def locked_angle(self, kin: PlanarKinematics) -> sp.Expr | None:
        """The fixed ``theta_b - theta_a`` (rad) of a coincident joint that locks rotation, else None."""
        return None

    def rows(self, kin: PlanarKinematics) -> list[ConstraintRow]:
        """The joint's constraint rows in the coordinates of ``kin``."""
        raise NotImplementedError

    def perpendicular(self, mech: Mechanism) -> list[list[sp.Expr]]:
        """Pairs of vectors (six expressions) that must be perpendicular (default: none)."""
        return []

    def check_values(self, mech: Mechanism, values: Mapping[str, float]) -> None:
        """Reject values impossible for this joint at the parameter ``values`` (default: none)."""


def check_points(name: str, refs: list[tuple[str, str]], mech: Mechanism) -> None:
    """Check joint ``name``'s point references ``(key, ref)`` against ``mech``; the first two
    (sides a and b) must be on different bodies. Raises a one-line InputError naming the key."""
    for key, ref in refs:
        mech.point_ref(ref, f"joints.{name}.{key}")
    if refs[0][1].split(".")[0] == refs[1][1].split(".")[0]:
        raise InputError(f"joints.{name}", "joins a body to itself")


def point_rows(joint: PlanarJoint, kin: PlanarKinematics) -> list[ConstraintRow]:
    """``a - b = 0``: reactions ``R_<name>_x``, ``R_<name>_y`` (N, global axes)."""
    n = joint.name
    d = kin.point(joint.a) - kin.point(joint.b)
    return [ConstraintRow(n, f"{n}_x", f"R_{n}_x", "N", d[0]), ConstraintRow(n, f"{n}_y", f"R_{n}_y", "N", d[1])]


def line_row(joint: PlanarJoint, kin: PlanarKinematics, phi: sp.Expr) -> ConstraintRow:
    """``b`` on the line through ``a`` at global angle ``phi``: reaction ``R_<name>`` (N) along its left normal."""
    n = joint.name
    normal = sp.Matrix([-sp.sin(phi), sp.cos(phi)])
    return ConstraintRow(n, f"{n}_n", f"R_{n}", "N", normal.dot(kin.point(joint.a) - kin.point(joint.b)))


def angle_row(joint: PlanarJoint, kin: PlanarKinematics, relative: sp.Expr) -> ConstraintRow:
    """``theta_a + relative - theta_b = 0``: reaction ``T_<name>`` (N m, on ``b``'s body)."""
    n = joint.name
    return ConstraintRow(n, f"{n}_angle", f"T_{n}", "N m", kin.angle(joint.a) + relative - kin.angle(joint.b))
