"""Rigid bodies, planar (:class:`Body`) and spatial (:class:`SpatialBody`), and the rules for names.

A body gives every number of its own (:meth:`~_RigidBody.values`: mass, length, inertia, centre
of gravity, points, initial guess) and the ranges of its inertia; the description classes
collect them.
"""

from __future__ import annotations

import keyword
import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ..equations import VELOCITY_SUFFIX
from ..errors import InputError
from ._expr import FUNCTIONS, Value, evaluate

if TYPE_CHECKING:
    from ._description import Mechanism

__all__ = ["Polar", "Body", "SpatialBody", "INERTIA_KEYS", "BUILTIN_POINTS", "BAR_POINTS", "BRANCH_COLUMNS",
           "check_inertia", "coordinate_names", "spatial_coordinate_names", "normalisation_row"]

Vector = tuple[Value, Value, Value]
#: Components of a full inertia tensor, in the order of ``inertia = [...]`` with six values.
INERTIA_KEYS = ("xx", "yy", "zz", "xy", "xz", "yz")


def coordinate_names(body: str) -> tuple[str, str, str]:
    """The names of a body's coordinates: ``x1, y1, theta1`` for ``"1"``, ``x_b, y_b, theta_b`` for ``"b"``."""
    if body.isdigit():
        return f"x{body}", f"y{body}", f"theta{body}"
    return f"x_{body}", f"y_{body}", f"theta_{body}"


def normalisation_row(body: str) -> str:
    """The name of ``body``'s Euler-parameter normalisation row (and its joint)."""
    return f"norm_{body}"


def spatial_coordinate_names(body: str) -> tuple[str, ...]:
    """``x_b, y_b, z_b, e0_b, e1_b, e2_b, e3_b`` for body ``b`` (``x1, y1, z1, e0_1, ...`` for ``"1"``)."""
    sep = "" if body.isdigit() else "_"
    return (f"x{sep}{body}", f"y{sep}{body}", f"z{sep}{body}", *(f"e{i}_{body}" for i in range(4)))


_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*|[0-9]+")
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
#: Columns of every branch table (see ``Branch.to_csv``): no variable may take these names.
BRANCH_COLUMNS = ("s", "stability", "n_unstable", "label", "vary")
#: Points every body has (``a``, ``b`` also for bars): they cannot be declared.
BUILTIN_POINTS = ("origin", "cg")
BAR_POINTS = ("a", "b")


def _check_name(name: str, field: str, *, digits: bool = True) -> None:
    """``name`` must be ASCII letters, digits and underscores not starting with a digit, or
    (``digits``) all ASCII digits. Non-ASCII names are refused: Python and SymPy would treat
    look-alikes differently (NFKC turns ``ｋ`` into ``k``), so two names could collide."""
    pattern = _NAME if digits else _IDENTIFIER
    if not isinstance(name, str) or not pattern.fullmatch(name):
        shown = repr(name) if isinstance(name, str) else type(name).__name__
        what = "ASCII letters, digits and underscores, not starting with a digit" + (", or all digits" if digits
                                                                                     else "")
        raise InputError(field, f"name {shown} must be an identifier: {what}")


def _check_variable_name(name: str, field: str, what: str) -> None:
    """A parameter or condition name: also a variable of the system and a branch-table column."""
    if name in BRANCH_COLUMNS:
        raise InputError(field, f"'{name}' is reserved: every branch table has a column of that name "
                                f"({', '.join(BRANCH_COLUMNS)}); rename the {what}")
    if name.endswith(VELOCITY_SUFFIX):
        raise InputError(field, f"names ending in '_dot' are reserved for the velocities of the time simulation "
                                f"(theta1_dot); rename the {what}")
    if keyword.iskeyword(name):  # the compiled code names every variable: a keyword cannot be one
        raise InputError(field, f"'{name}' is a Python keyword and cannot name a variable; rename the {what} "
                                f"(e.g. {name}_)")
    if name in FUNCTIONS:
        kind = "constant" if name == "pi" else "function"
        raise InputError(field, f"'{name}' is the expression {kind} {name}; rename the {what}")


@dataclass(frozen=True)
class Polar:
    """A point at distance ``r`` (m) from the body frame origin, at ``angle`` (rad) from the body axis."""

    r: Value
    angle: Value


PointSpec = tuple[Value, Value] | Polar

class _RigidBody:
    """What every body has and does: a name, a mass (kg), for a bar a length (m), a centre of
    gravity, points and an initial guess (the subclasses' fields, their types differ in the plane
    and in space); its values."""

    name: str
    mass: Value
    length: Value | None
    cg: Sequence[Value]
    points: Mapping[str, object]
    initial: Mapping[str, object]

    def field(self, key: str) -> str:
        """The key path of the body's ``key``."""
        return f"bodies.{self.name}.{key}"

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Every (key path, raw value) of the body that is a number or an expression."""
        yield self.field("mass"), self.mass
        if self.length is not None:
            yield self.field("length"), self.length
        yield from self._inertia_values(mech)
        yield from mech.vector_values(self.field("cg"), self.cg)
        for pn, ps in self.points.items():
            _check_name(pn, self.field(f"points.{pn}"))
            if pn in BUILTIN_POINTS or (pn in BAR_POINTS and self.length is not None):
                meaning = {"a": "the bar's end at -length/2", "b": "the bar's end at +length/2",
                           "origin": "the body's frame origin", "cg": "the centre of gravity (key cg)"}[pn]
                raise InputError(self.field(f"points.{pn}"), f"'{pn}' is a built-in point ({meaning}); "
                                                             "name the declared point differently")
            yield from self._point_values(mech, self.field(f"points.{pn}"), ps)
        yield from self._initial_values(mech)

    def _inertia_values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        raise NotImplementedError

    def _point_values(self, mech: Mechanism, field: str, spec: object) -> Iterator[tuple[str, Any]]:
        raise NotImplementedError

    def _initial_values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        raise NotImplementedError

    def check_values(self, mech: Mechanism, values: Mapping[str, float]) -> None:
        """Reject values impossible for this body at the parameter ``values`` (default: none)."""


@dataclass(frozen=True)
class Body(_RigidBody):
    """A rigid planar body.

    Parameters
    ----------
    name:
        Identifier (letters, digits, underscore; may be all digits).
    mass:
        Mass (kg), positive.
    length:
        For a bar: its length (m), positive; adds the end points ``a`` and ``b``.
    inertia:
        Moment of inertia about the centre of gravity (kg m^2), positive; default
        ``mass*length^2/12`` for a bar (required for other bodies).
    cg:
        Centre of gravity in body coordinates (m); default the frame origin.
    points:
        Named points in body coordinates: ``(x, y)`` or :class:`Polar`.
    initial:
        Approximate configuration for assembly: any of ``x``, ``y``, ``theta``
        (numbers or expressions in the parameters).
    """

    name: str
    mass: Value
    length: Value | None = None
    inertia: Value | None = None
    cg: tuple[Value, Value] = (0, 0)
    points: Mapping[str, PointSpec] = field(default_factory=dict)
    initial: Mapping[str, Value] = field(default_factory=dict)
    description: str = ""

    def inertia_limits(self) -> list[tuple[str, str]]:
        """``(key path, what)`` of the inertia given, which must be positive."""
        return [(self.field("inertia"), "inertia (kg m^2)")] if self.inertia is not None else []

    def _inertia_values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        if self.inertia is not None:
            yield self.field("inertia"), self.inertia

    def _point_values(self, mech: Mechanism, field: str, spec: object) -> Iterator[tuple[str, Any]]:
        if isinstance(spec, Polar):
            yield f"{field}.r", spec.r
            yield f"{field}.angle", spec.angle
            return
        if not isinstance(spec, (tuple, list)) or len(spec) != 2:
            raise InputError(field, "a point is [x, y] or {r = ..., angle = ...}")
        yield f"{field}.x", spec[0]
        yield f"{field}.y", spec[1]

    def _initial_values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        for k, v in self.initial.items():
            if k not in ("x", "y", "theta"):
                raise InputError(self.field(f"initial.{k}"), "initial values are x, y, theta")
            yield self.field(f"initial.{k}"), v
        if self.inertia is None and self.length is None:
            raise InputError(self.field("inertia"), "a body without a length needs an inertia (kg m^2)")


@dataclass(frozen=True)
class SpatialBody(_RigidBody):
    """A rigid body in space (``name``, ``mass`` and ``description`` as for :class:`Body`).

    Parameters
    ----------
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

    def inertia_limits(self) -> list[tuple[str, str]]:
        """``(key path, what)`` of the principal moments given, which must be positive."""
        if self.inertia is None:
            return []
        return [(self.field(f"inertia.{k}"), "principal moment of inertia (kg m^2)") for k in ("xx", "yy", "zz")]

    def _inertia_values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        if self.inertia is None:
            return
        if isinstance(self.inertia, (str, int, float)) or len(self.inertia) not in (3, 6):
            raise InputError(self.field("inertia"), "is [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (kg m^2)")
        for key, v in zip(INERTIA_KEYS, self.inertia):
            yield self.field(f"inertia.{key}"), v

    def _point_values(self, mech: Mechanism, field: str, spec: object) -> Iterator[tuple[str, Any]]:
        yield from mech.vector_values(field, spec)

    def _initial_values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        for k, v in self.initial.items():
            if k == "rotation":
                yield from mech.vector_values(self.field("initial.rotation"), v)
            elif k in ("x", "y", "z"):
                yield self.field(f"initial.{k}"), v
            else:
                raise InputError(self.field(f"initial.{k}"), "initial values are x, y, z (m) and rotation = [rx, ry, rz] "
                                                             "(rad)")

    def check_values(self, mech: Mechanism, values: Mapping[str, float]) -> None:
        """An inertia tensor given must be positive definite and obey the triangle inequality."""
        if self.inertia is not None:
            check_inertia(mech, values, self.field("inertia"), len(self.inertia))


def check_inertia(mech: Mechanism, values: Mapping[str, float], field: str, n: int) -> None:
    """An inertia tensor about the CG must be positive definite and its principal moments obey the
    triangle inequality (each at most the sum of the other two: a real body's mass distribution)."""
    import numpy as np

    keys = ("xx", "yy", "zz", "xy", "xz", "yz")[:n]
    v = dict(zip(keys, (evaluate(mech.value(f"{field}.{k}"), values, f"{field}.{k}") for k in keys)))
    xy, xz, yz = v.get("xy", 0.0), v.get("xz", 0.0), v.get("yz", 0.0)
    tensor = np.array([[v["xx"], xy, xz], [xy, v["yy"], yz], [xz, yz, v["zz"]]])
    scale = float(np.max(np.abs(tensor)))
    moments = np.linalg.eigvalsh(tensor / scale) * scale
    shown = ", ".join(f"{m:.6g}" for m in moments)
    if moments[0] <= 1e-12 * scale:
        raise InputError(field, f"is not positive definite (principal moments {shown} kg m^2); a body's inertia "
                                "tensor has positive principal moments")
    if moments[2] > (moments[0] + moments[1]) * (1 + 1e-9):
        raise InputError(field, f"principal moments {shown} kg m^2 violate the triangle inequality (the largest must "
                                "not exceed the sum of the other two): no body has this mass distribution")
