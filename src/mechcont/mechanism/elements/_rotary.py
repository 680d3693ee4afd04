"""What the rotary elements (``[torsion_springs.NAME]``, ``[torsion_dampers.NAME]``) share: the
relative angle of two bodies, its rate, their checks and their drawing.

In the plane the relative angle is ``theta_b - theta_a`` (rad, counter-clockwise positive; the
ground's angle is 0). In space it is the rotation of ``b`` relative to ``a`` about the axis of a
named revolute or cylindrical joint (``joint``), right-handed about that axis as the joint gives it
(design pose): the kinematics' ``relative_rotation`` (:meth:`..spatial._kinematics.SpatialKinematics.relative_rotation`),

    phi = atan2(u_a . (f_a x f_b), f_a . f_b),

zero in the design pose (every body frame parallel to the ground's) and equal to the planar
``theta_b - theta_a`` for a joint about +z. For a joint that keeps the axis common (its rows hold)
this is exactly the rotation about it; it is smooth for ``|phi| < pi``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import sympy as sp

from ...equations import velocity_symbol
from ...errors import InputError

if TYPE_CHECKING:
    from .._description import Mechanism
    from .._plugin import Kinematics
    from ..joints import PlanarJoint
    from ..spatial.joints import SpatialJoint


class Rotary(Protocol):
    """A rotary element: bodies ``a``, ``b`` (or ``"ground"``) and the joint it acts about."""

    @property
    def a(self) -> str: ...
    @property
    def b(self) -> str: ...
    @property
    def joint(self) -> str | None: ...
    def field(self, key: str = "") -> str: ...

__all__ = ["relative_angle", "angle_rate", "check_bodies", "pivot", "AXIS_JOINTS"]

#: Spatial joint kinds that have an ``axis`` a rotary element can act about.
AXIS_JOINTS = ("revolute", "cylindrical")


def _bodies(joint: PlanarJoint | SpatialJoint) -> set[str]:
    """The bodies (or ``"ground"``) of the joint's two sides."""
    return {joint.a.split(".")[0], joint.b.split(".")[0]}


def check_bodies(el: Rotary, mech: Mechanism) -> None:
    """``el.a`` and ``el.b`` must be bodies of ``mech`` (or ``"ground"``), different; ``el.joint``,
    required in space, a joint of ``mech`` joining them (in space with an ``axis``). One-line
    InputErrors naming the key."""
    for key in ("a", "b"):
        ref = getattr(el, key)
        if not isinstance(ref, str) or (ref != "ground" and ref not in mech.body_map):
            raise InputError(el.field(key), f"must be a body name or \"ground\", got {ref!r}; bodies: "
                                            f"{', '.join(mech.body_map)}")
    if el.a == el.b:
        raise InputError(el.field("b"), f"must differ from a ({el.a!r}): the element joins a body to itself")
    spatial = mech.space == "space"
    if el.joint is None:
        if spatial:
            raise InputError(el.field("joint"), "is required in a spatial description: the revolute or cylindrical "
                                                "joint whose axis the element acts about")
        return
    joint = next((j for j in mech.joints if j.name == el.joint), None)
    if joint is None:
        raise InputError(el.field("joint"), f"unknown joint {el.joint!r}; joints: {', '.join(j.name for j in mech.joints)}")
    if _bodies(joint) != {el.a, el.b}:
        raise InputError(el.field("joint"), f"joint {el.joint!r} joins {' and '.join(sorted(_bodies(joint)))}, "
                                            f"not {el.a} and {el.b}")
    if spatial and joint.kind not in AXIS_JOINTS:
        raise InputError(el.field("joint"), f"joint {el.joint!r} is {joint.kind}: a rotary element needs a joint with an "
                                            f"axis ({', '.join(AXIS_JOINTS)})")


def _joint(el: Rotary, mech: Mechanism) -> Any:
    """The joint ``el`` acts about (planar or spatial: the description's own joint type, which a bare
    :class:`Mechanism` leaves open; in space its ``vector(kin, "axis")`` is read)."""
    return next(j for j in mech.joints if j.name == el.joint)


def relative_angle(el: Rotary, kin: Kinematics) -> sp.Expr:
    """The rotation (rad) of body ``el.b`` relative to ``el.a`` (see the module docstring)."""
    axis = _joint(el, kin.mech).vector(kin, "axis") if kin.dimension == 3 else None
    return kin.relative_rotation(f"{el.a}.origin", f"{el.b}.origin", axis)


def angle_rate(angle: sp.Expr, kin: Kinematics) -> tuple[list[sp.Expr], sp.Expr]:
    """``(d angle/dq, d angle/dt)``: the gradient in the coordinates of ``kin`` and the rate (rad/s)
    in their velocity symbols."""
    grad = [sp.diff(angle, qi) for qi in kin.q]
    rate = sum((g * velocity_symbol(n) for g, n in zip(grad, kin.coords) if g != 0), sp.S.Zero)
    return grad, rate


def pivot(el: Rotary, kin: Kinematics) -> sp.Matrix:
    """Where a rotary element is drawn: its joint's point ``b``, else the first pin or weld joining
    ``a`` and ``b``, else the origin of body ``b`` (of ``a`` when ``b`` is the ground)."""
    mech = kin.mech
    if el.joint is not None:
        return kin.point(_joint(el, mech).b)
    for j in mech.joints:
        if getattr(j, "COINCIDENT", False) and _bodies(j) == {el.a, el.b}:
            return kin.point(j.b)
    return kin.point(f"{el.b if el.b != 'ground' else el.a}.origin")
