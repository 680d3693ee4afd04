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

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from ...errors import InputError
from .._description import BAR_POINTS, BUILTIN_POINTS, Mechanism, _check_name
from .._expr import Value
from ..loads import SpatialCustomLoad, SpatialDrag, SpatialGravity, SpatialMoment
from ._joints import SpatialJoint

__all__ = ["SpatialBody", "SpatialGravity", "SpatialMoment", "SpatialCustomLoad", "SpatialDrag", "SpatialMechanism",
           "spatial_coordinate_names", "INERTIA_KEYS"]

Vector = tuple[Value, Value, Value]
#: Components of a full inertia tensor, in the order of ``inertia = [...]`` with six values.
INERTIA_KEYS = ("xx", "yy", "zz", "xy", "xz", "yz")


def normalisation_row(body: str) -> str:
    """The name of ``body``'s Euler-parameter normalisation row (and its joint)."""
    return f"norm_{body}"


def spatial_coordinate_names(body: str) -> tuple[str, ...]:
    """``x_b, y_b, z_b, e0_b, e1_b, e2_b, e3_b`` for body ``b`` (``x1, y1, z1, e0_1, ...`` for ``"1"``)."""
    sep = "" if body.isdigit() else "_"
    return (f"x{sep}{body}", f"y{sep}{body}", f"z{sep}{body}", *(f"e{i}_{body}" for i in range(4)))


@dataclass(frozen=True)
class SpatialBody:
    """A rigid body in space.

    Parameters
    ----------
    name:
        Identifier (letters, digits, underscore; may be all digits).
    mass:
        Mass (kg), positive.
    length:
        For a bar: its length (m); adds the end points ``a``, ``b`` on the body's x axis.
    inertia:
        About the centre of gravity, design-pose axes (kg m^2): ``[Ixx, Iyy, Izz]`` or
        ``[Ixx, Iyy, Izz, Ixy, Ixz, Iyz]`` (products of inertia as the tensor's off-diagonal
        entries). Default: a bar is a thin rod (``m L^2/12`` across, ``m r^2/2`` along it,
        ``r = L/20``); another body a uniform sphere ``2/5 m r^2`` whose radius is half the
        largest distance between its declared points and centre of gravity (not its frame
        origin, at least 1 mm). Statics never uses the inertia; the time
        simulation and non-conservative stability do: give it for those.
    cg:
        Centre of gravity in body coordinates (m).
    points:
        Named points in body coordinates ``[x, y, z]`` (m).
    initial:
        Guess for the first assembly: ``x``, ``y``, ``z`` (m) of the frame origin and
        ``rotation = [rx, ry, rz]`` (rad, a rotation vector from the design pose).
    """

    name: str
    mass: Value
    length: Value | None = None
    inertia: Sequence[Value] | None = None
    cg: Vector = (0, 0, 0)
    points: Mapping[str, Vector] = field(default_factory=dict)
    initial: Mapping[str, object] = field(default_factory=dict)
    description: str = ""


class SpatialMechanism(Mechanism):
    """A spatial mechanism: everything needed to generate its equations.

    Same fields and validation as :class:`~mechcont.mechanism.Mechanism` (``parameters``,
    ``bodies`` of :class:`SpatialBody`, ``joints`` of the :mod:`._joints` classes, ``ground``
    points ``{name: (x, y, z)}``, ``springs``, ``dampers``, ``actuators``, ``loads`` of
    :class:`~mechcont.mechanism.PointForce` (3-vector ``direction``), :class:`SpatialMoment`
    :class:`SpatialDrag` and :class:`SpatialCustomLoad`, ``gravity`` a :class:`SpatialGravity`, ``conditions``,
    ``dof``, ``redundant``, ``hold``, ``downlock``). ``redundant = "drop"`` removes dependent
    rows (reactions then indeterminate: one particular solution, the dropped rows chosen again
    along a branch where the kept ones lose rank); a joint ``stiffness`` makes
    them determinate instead (see :mod:`._joints`).
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
                from ._joints import JOINT_TYPES
                raise InputError(f"joints.{j.name}", f"{type(j).__name__} is a planar joint; a spatial mechanism "
                                                     f"takes {', '.join(JOINT_TYPES)} joints")
        if self.gravity is not None and self.space not in self.gravity.SPACES:
            raise InputError("gravity", "a spatial mechanism takes gravity as {g, direction = [x, y, z]}")
        super()._validate()

    def _coordinate_names(self, body: str) -> tuple[str, ...]:
        return spatial_coordinate_names(body)

    def _values(self):
        for b in self.bodies:
            f = f"bodies.{b.name}"
            yield f + ".mass", b.mass
            if b.length is not None:
                yield f + ".length", b.length
            if b.inertia is not None:
                if isinstance(b.inertia, (str, int, float)) or len(b.inertia) not in (3, 6):
                    raise InputError(f + ".inertia", "is [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (kg m^2)")
                for key, v in zip(INERTIA_KEYS, b.inertia):
                    yield f"{f}.inertia.{key}", v
            yield from _vector(f + ".cg", b.cg)
            for pn, ps in b.points.items():
                _check_name(pn, f"{f}.points.{pn}")
                if pn in BUILTIN_POINTS or (pn in BAR_POINTS and b.length is not None):
                    raise InputError(f"{f}.points.{pn}", f"'{pn}' is a built-in point; name the declared point "
                                                         "differently")
                yield from _vector(f"{f}.points.{pn}", ps)
            for k, v in b.initial.items():
                if k == "rotation":
                    yield from _vector(f"{f}.initial.rotation", v)
                elif k in ("x", "y", "z"):
                    yield f"{f}.initial.{k}", v
                else:
                    raise InputError(f"{f}.initial.{k}", "initial values are x, y, z (m) and rotation = [rx, ry, rz] "
                                                         "(rad)")
        for gname, gp in self.ground.items():
            yield from _vector(f"ground.{gname}", gp)
        for j in self.joints:
            yield from j.values()
        if self.gravity is not None:
            yield from self.gravity.values(self)
        for ld in self.loads:
            yield from ld.values(self)
        yield from self._common_values()

    def normalisation_rows(self) -> frozenset[str]:
        """``norm_<body>``: each body's Euler-parameter normalisation row (no joint's)."""
        return frozenset(normalisation_row(b.name) for b in self.bodies)

    def summary(self) -> None:
        """None: a spatial description's variables are read from a build."""
        return None

    def direction_values(self, field: str, v) -> list[tuple[str, Value]]:
        """The (key path, raw value) of each component of a direction ``[x, y, z]``."""
        return _vector(field, v)

    def vector_values(self, field: str, v) -> list[tuple[str, Value]]:
        """The (key path, raw value) of each component of the vector ``v`` (``[x, y, z]``)."""
        return _vector(field, v)

    def _generator(self):
        from ._generate import generate
        return generate


def _vector(field_: str, v) -> list[tuple[str, Value]]:
    if not isinstance(v, (tuple, list)) or len(v) != 3:
        raise InputError(field_, f"must be a 3-vector [x, y, z], got {v!r}")
    return [(f"{field_}.{c}", comp) for c, comp in zip("xyz", v)]
