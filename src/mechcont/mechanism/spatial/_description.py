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
from .._description import BAR_POINTS, BUILTIN_POINTS, Mechanism, PointForce, _check_name
from .._expr import Value
from ._joints import SpatialJoint

__all__ = ["SpatialBody", "SpatialGravity", "SpatialMoment", "SpatialCustomLoad", "SpatialDrag", "SpatialMechanism",
           "spatial_coordinate_names", "INERTIA_KEYS"]

Vector = tuple[Value, Value, Value]
#: Components of a full inertia tensor, in the order of ``inertia = [...]`` with six values.
INERTIA_KEYS = ("xx", "yy", "zz", "xy", "xz", "yz")


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


@dataclass(frozen=True)
class SpatialGravity:
    """Uniform gravity of magnitude ``g`` (m/s^2) along ``direction`` (default ``-z``)."""

    g: Value = "g"
    direction: Vector = (0, 0, -1)


@dataclass(frozen=True)
class SpatialMoment:
    """A pure moment ``magnitude`` (N m) about the fixed global ``axis`` (right-hand rule) on a body."""

    name: str
    body: str
    magnitude: Value
    axis: Vector = (0, 0, 1)


@dataclass(frozen=True)
class SpatialCustomLoad:
    """A user-defined load: force ``(fx, fy, fz)`` (N, global axes) at point ``at`` and moment
    ``(mx, my, mz)`` (N m, global axes) on that point's body; expressions may use the
    parameters and the coordinates."""

    name: str
    at: str
    fx: Value = 0
    fy: Value = 0
    fz: Value = 0
    mx: Value = 0
    my: Value = 0
    mz: Value = 0


@dataclass(frozen=True)
class SpatialDrag:
    """Aerodynamic cross-flow drag on the segment from point ``start`` to point ``end`` of ``body``.

    With the air velocity ``U * direction / |direction|`` (m/s), the segment ``D = P_end -
    P_start`` of length ``L`` and the air velocity's component normal to it ``w_n``, the force
    ``1/2 rho C_D d L |w_n| w_n`` (N) acts at the segment's midpoint (the planar drag's model in
    space; ``|w_n|`` smoothed as ``sqrt(|w_n|^2 + (1e-6 m/s)^2)`` so the Jacobian exists at
    ``U = 0``).
    """

    name: str
    body: str
    rho: Value = "rho"
    U: Value = "U"
    direction: Vector = (1, 0, 0)
    d: Value = "d"
    CD: Value = "C_D"
    start: str = "a"
    end: str = "b"


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

    _COORDINATE_KEYS = ("fx", "fy", "fz", "mx", "my", "mz")
    dimension = 3

    def _validate(self) -> None:
        for j in self.joints:
            if isinstance(j.name, str) and j.name.startswith("norm_"):
                raise InputError(f"joints.{j.name}", "names starting with 'norm_' are reserved for the Euler-parameter "
                                                     "normalisation rows (norm_<body>); rename the joint")
            if not isinstance(j, SpatialJoint):
                from ._joints import JOINT_TYPES
                raise InputError(f"joints.{j.name}", f"{type(j).__name__} is a planar joint; a spatial mechanism "
                                                     f"takes {', '.join(JOINT_TYPES)} joints")
        if self.gravity is not None and not isinstance(self.gravity, SpatialGravity):
            raise InputError("gravity", "a spatial mechanism takes gravity as {g, direction = [x, y, z]}")
        super()._validate()

    def _coordinate_names(self, body: str) -> tuple[str, ...]:
        return spatial_coordinate_names(body)

    def _load_kinds(self) -> tuple[tuple[type, ...], tuple[type, ...], str]:
        return ((PointForce, SpatialCustomLoad), (SpatialMoment, SpatialDrag),
                "load type {} is not available for spatial mechanisms (force, moment, drag, custom)")

    def _check_loads(self) -> None:
        super()._check_loads()
        for ld in self.loads:
            if isinstance(ld, SpatialDrag) and ld.start == ld.end:
                raise InputError(f"loads.{ld.name}.end", "the drag segment needs two different points")

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
            yield "gravity.g", self.gravity.g
            yield from _vector("gravity.direction", self.gravity.direction)
        for ld in self.loads:
            f = f"loads.{ld.name}"
            if isinstance(ld, PointForce):
                yield f + ".magnitude", ld.magnitude
                yield from _vector(f + ".direction", ld.direction)
            elif isinstance(ld, SpatialMoment):
                yield f + ".magnitude", ld.magnitude
                yield from _vector(f + ".axis", ld.axis)
            elif isinstance(ld, SpatialCustomLoad):
                for attr in self._COORDINATE_KEYS:
                    yield f"{f}.{attr}", getattr(ld, attr)
            elif isinstance(ld, SpatialDrag):
                for attr in ("rho", "U", "d", "CD"):
                    yield f"{f}.{attr}", getattr(ld, attr)
                yield from _vector(f + ".direction", ld.direction)
        yield from self._common_values()

    def _generator(self):
        from ._generate import generate
        return generate


def _vector(field_: str, v) -> list[tuple[str, Value]]:
    if not isinstance(v, (tuple, list)) or len(v) != 3:
        raise InputError(field_, f"must be a 3-vector [x, y, z], got {v!r}")
    return [(f"{field_}.{c}", comp) for c, comp in zip("xyz", v)]
