"""A spatial (3-D) mechanism described as objects: bodies, points, joints, springs, loads.

Conventions (SI units, radians):

* **Design pose.** Every body frame is parallel to the ground frame in the design pose; a
  body's points, centre of gravity, inertia and its joints' axes are given in that pose. Give
  a landing gear's hard points in aircraft coordinates and leave the body origins at the
  global origin, or give each body's points about its own origin: both describe the same
  mechanism. The design pose need not be assembled: the first assembly closes the loops from
  it (``initial`` moves a body's guess).
* **Coordinates** of body ``b``: the position of its frame origin ``x_b, y_b, z_b`` (m) and
  its orientation as Euler parameters ``e0_b, e1_b, e2_b, e3_b`` (``x1, ..., e3_1`` for a body
  named ``"1"``), with the normalisation row ``norm_b: e.e - 1 = 0`` whose multiplier
  ``mu_b`` carries no physical meaning (see :mod:`._rotation` for why Euler parameters).
* A *bar* is a body with a ``length``: its ends ``a = (-length/2, 0, 0)`` and
  ``b = (length/2, 0, 0)`` lie on its x axis about its origin.
* Point references are ``"<body>.<point>"`` or ``"ground.<point>"``; every body has the
  points ``origin`` and ``cg``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Self

from ...errors import InputError
from .._bodies import INERTIA_KEYS, SpatialBody, normalisation_row, spatial_coordinate_names
from .._description import Mechanism
from .._expr import Value
from .._plugin import Kinematics
from ..loads import SpatialCustomLoad, SpatialDrag, SpatialGravity, SpatialMoment
from ._kinematics import SpatialKinematics
from .joints import JOINT_TYPES, SpatialJoint

if TYPE_CHECKING:
    from ...equations import Model

__all__ = ["SpatialBody", "SpatialGravity", "SpatialMoment", "SpatialCustomLoad", "SpatialDrag", "SpatialMechanism",
           "spatial_coordinate_names", "INERTIA_KEYS"]


class SpatialMechanism(Mechanism[SpatialJoint, SpatialBody]):
    """A spatial mechanism: everything needed to generate its equations.

    Same fields and validation as :class:`~mechcont.mechanism.Mechanism` (``parameters``,
    ``bodies`` of :class:`SpatialBody`, ``joints`` of the :mod:`.joints` classes, ``ground``
    points ``{name: (x, y, z)}``, ``springs``, ``dampers``, ``actuators``, ``loads`` of
    :class:`~mechcont.mechanism.PointForce` (3-vector ``direction``), :class:`SpatialMoment`
    :class:`SpatialDrag` and :class:`SpatialCustomLoad`, ``gravity`` a :class:`SpatialGravity`, ``conditions``,
    ``dof``, ``redundant``, ``hold``, ``downlock``). ``redundant = "drop"`` removes dependent
    rows (reactions then indeterminate: one particular solution, the dropped rows chosen again
    along a branch where the kept ones lose rank); a joint ``stiffness`` makes
    them determinate instead (see :mod:`.joints`).
    """

    dimension = 3
    space = "space"
    AXES = "xyz"
    _UNKNOWN_LOAD = "load type {} is not available for spatial mechanisms (force, moment, drag, custom)"
    UNAVAILABLE_CONDITIONS = {"angle": "an angle condition is planar; in a spatial mechanism use an expression, "
                                       "distance or collinear condition"}
    COLLINEAR_NORMAL = True

    def _validate(self) -> None:
        for j in self.joints:
            if isinstance(j.name, str) and j.name.startswith("norm_"):
                raise InputError(f"joints.{j.name}", "names starting with 'norm_' are reserved for the Euler-parameter "
                                                     "normalisation rows (norm_<body>); rename the joint")
            if not isinstance(j, SpatialJoint):
                raise InputError(f"joints.{j.name}", f"{type(j).__name__} is a planar joint; a spatial mechanism "
                                                     f"takes {', '.join(JOINT_TYPES)} joints")
        if self.gravity is not None and self.space not in self.gravity.SPACES:
            raise InputError("gravity", "a spatial mechanism takes gravity as {g, direction = [x, y, z]}")
        super()._validate()

    def _coordinate_names(self, body: str) -> tuple[str, ...]:
        return spatial_coordinate_names(body)

    def kinematics_class(self) -> Callable[[Self], Kinematics]:
        """The kinematics strategy of space (:class:`._kinematics.SpatialKinematics`: origin and Euler parameters)."""
        return SpatialKinematics

    def normalisation_rows(self) -> frozenset[str]:
        """``norm_<body>``: each body's Euler-parameter normalisation row (no joint's)."""
        return frozenset(normalisation_row(b.name) for b in self.bodies)

    def summary(self) -> None:
        """None: a spatial description's variables are read from a build."""
        return None

    def direction_values(self, field: str, v: Any) -> list[tuple[str, Value]]:
        """The (key path, raw value) of each component of a direction ``[x, y, z]``."""
        return self.vector_values(field, v)

    def _generator(self) -> Callable[..., Model]:
        from ._generate import generate
        return generate
