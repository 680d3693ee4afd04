"""A planar mechanism described as objects: bodies, points, joints, springs, dampers, loads.

(Longer than most modules: :class:`Mechanism` checks every element's names and references in
one place, so that an error names the key path whatever the element.)

Conventions (SI units, radians):

* Every body has a frame; its coordinates are ``x<b>, y<b>, theta<b>`` when the body
  name ``b`` is all digits (``"1"`` gives ``x1, y1, theta1`` as in the paper) and
  ``x_<b>, y_<b>, theta_<b>`` otherwise: the position of the frame origin and the angle of
  the frame's x-axis from the global +x axis.
* A *bar* is a body with a ``length``: its frame origin is the bar's centre, the points
  ``a = (-length/2, 0)`` and ``b = (length/2, 0)`` are its ends, its centre of gravity is
  the origin and its default inertia is ``mass*length^2/12``.
* Points are given in body coordinates, either Cartesian ``(x, y)`` or polar
  ``Polar(r, angle)`` (the paper's psi offsets: a point at distance ``r`` from the frame
  origin at ``angle`` from the body axis). Every body has the points ``origin`` and ``cg``.
* A point reference is ``"<body>.<point>"``, or ``"ground.<point>"`` for a ground point.
* Every number may be an expression string in the parameter names (``"L1/2"``); custom
  loads may also use the coordinates.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar, Generic, Protocol, Self, TypeVar

import sympy as sp

from ..errors import InputError
from ..units import SI, UnitSystem
from ._bodies import (
    Body,
    Polar,
    _check_name,
    _check_variable_name,
    _RigidBody,
    coordinate_names,
)
from ._conditions import Condition, DownlockSpec, check_conditions
from ._elements import Parameter, StopReaction
from ._expr import Value, symbol, to_expr
from ._kinematics import PlanarKinematics
from ._locate import locate_error
from ._plugin import Kinematics
from ._stops import stop_reaction_unit
from .elements import Actuator, Damper, Element, Spring, Stop
from .joints import PlanarJoint, Prismatic, Revolute, Slider, Weld
from .loads import LOAD_TYPES, CustomLoad, Drag, Gravity, Load, Moment, PointForce, SpatialGravity

if TYPE_CHECKING:
    from ..equations import Model

__all__ = [
    "Parameter", "Polar", "Body", "Revolute", "Slider", "Prismatic", "Weld", "Spring", "Damper",
    "Gravity", "PointForce", "Moment", "Drag", "CustomLoad", "Mechanism", "coordinate_names",
]


#: A planar joint: any registered joint class (see :mod:`.joints`).
Joint = PlanarJoint


class _Named(Protocol):
    """A named element of a description."""

    @property
    def name(self) -> str:
        """Its name."""


class _Joint(_Named, Protocol):
    """What a description asks of any joint, planar or spatial (see :mod:`.joints`, :mod:`.spatial.joints`)."""

    #: Whether it makes its points ``a`` and ``b`` coincide (a pin, a weld: it places one body from the other).
    COINCIDENT: ClassVar[bool]

    @property
    def a(self) -> str:
        """The point reference of side a."""

    @property
    def b(self) -> str:
        """The point reference of side b."""

    def check(self, mech: Mechanism[Any, Any]) -> None:
        """Check its references against ``mech``."""

    def values(self, mech: Mechanism[Any, Any]) -> Iterator[tuple[str, Value]]:
        """Its (key path, raw value) pairs."""


#: The joint and body types of a description: planar (:class:`PlanarJoint`, :class:`Body`) or spatial.
JointT = TypeVar("JointT", bound=_Joint)
BodyT = TypeVar("BodyT", bound=_RigidBody)


@dataclass
class Mechanism(Generic[JointT, BodyT]):
    """A planar mechanism: everything needed to generate its equations.

    Parameters
    ----------
    name:
        Model name.
    parameters:
        Named parameters with defaults (SI) and units.
    bodies:
        The moving rigid bodies.
    joints:
        Joints: instances of the registered joint classes (:mod:`.joints`: revolute, slider,
        prismatic, weld, pin_in_slot, ...).
    ground:
        Named ground points ``{name: (x, y)}`` (m).
    springs, dampers, loads:
        Force elements.
    elements:
        Force elements of the other registered tables (:data:`~.elements.ELEMENT_TYPES`).
    gravity:
        Uniform gravity, or None.
    dof:
        The intended number of degrees of freedom; assembly reports any other count.
    redundant:
        What to do with an over-constrained mechanism (redundant constraints, e.g. a
        parallelogram with a third parallel link): ``"error"`` (default) refuses it with a
        one-line message naming the joints involved; ``"drop"`` removes each dependent
        constraint row (the later-declared one) so the system is square again, lists the
        dropped rows in ``system.dropped_constraints`` and their residual in
        ``system.dropped_residual(x)``. The reactions of the joints involved are then one
        particular solution of a statically indeterminate problem (the dropped rows carry
        none), and the dropped rows stay satisfied only while the geometry keeps them
        consistent (check ``dropped_residual`` after continuing in a geometric parameter).
    hold:
        Coordinates held during the first assembly, ``{name: value}`` (expressions allowed).
    description:
        Free text.
    conditions:
        Named relations of the configuration that analyses watch or hold (:mod:`._conditions`).
    stops:
        One-sided limits of conditions (:mod:`._stops`); each adds the contact reaction parameter
        ``R_<stop>`` (default 0) to :attr:`parameters`.
    units:
        The units every number of the description is in (``[mechanism] units``; SI by default): the
        generated names (coordinates, reactions, condition values, ...) are labelled in them
        (:meth:`unit`).

    Raises
    ------
    InputError
        Bad names, duplicate names, unknown body/point/parameter references, bodies not
        connected to the ground through joints. Values are checked by :meth:`build`.
    """

    name: str
    parameters: Sequence[Parameter]
    bodies: Sequence[BodyT]
    joints: Sequence[JointT]
    ground: Mapping[str, tuple[Value, Value]] = field(default_factory=dict)
    springs: Sequence[Spring] = ()
    dampers: Sequence[Damper] = ()
    loads: Sequence[Load[Any]] = ()
    gravity: Gravity | SpatialGravity | None = None
    dof: int = 1
    hold: Mapping[str, Value] = field(default_factory=dict)
    description: str = ""
    source: tuple[str, str] | None = field(default=None, repr=False)
    redundant: str = "error"
    conditions: Sequence[Condition] = ()
    actuators: Sequence[Actuator] = ()
    downlock: DownlockSpec | None = None
    stops: Sequence[Stop] = ()
    elements: Sequence[Element] = ()
    units: UnitSystem = SI
    # the value-independent part of each generated form, made by the first build (never pickled)
    _generated: dict[str, Any] = field(default_factory=dict, init=False, repr=False, compare=False)

    #: 2 for a planar mechanism, 3 for a spatial one (for readers of a description; the code asks
    #: :attr:`space`, :attr:`AXES` and the kinematics instead).
    dimension: ClassVar[int] = 2
    #: The registry key of the elements this mechanism takes (:data:`~.loads.LOAD_TYPES`).
    space: ClassVar[str] = "plane"
    #: The registered element tables with a field of their own (others go to ``elements``).
    ELEMENT_FIELDS: ClassVar[tuple[str, ...]] = ("springs", "dampers", "actuators", "stops")
    #: The components of a vector (a point, a direction).
    AXES: ClassVar[str] = "xy"
    #: The message for a load of a type not registered for this space (``{}``: its class name).
    _UNKNOWN_LOAD: ClassVar[str] = "unknown load type {}"
    #: Condition types this space has not, with the message that refuses them.
    UNAVAILABLE_CONDITIONS: ClassVar[Mapping[str, str]] = {}
    #: Whether a collinear condition is signed about a given ``normal`` (in space) rather than
    #: counter-clockwise (in the plane).
    COLLINEAR_NORMAL: ClassVar[bool] = False

    def __post_init__(self) -> None:
        self.parameters = tuple(self.parameters)
        self.bodies = tuple(self.bodies)
        self.joints = tuple(self.joints)
        self.springs, self.dampers, self.loads = tuple(self.springs), tuple(self.dampers), tuple(self.loads)
        self.ground = dict(self.ground)
        self.hold = dict(self.hold)
        self.conditions, self.actuators = tuple(self.conditions), tuple(self.actuators)
        self.stops, self.elements = tuple(self.stops), tuple(self.elements)
        # a copy (dataclasses.replace) passes the generated reactions back in: made anew here
        units = {c.name: self.condition_unit(c) for c in self.conditions}
        self.parameters = (*(p for p in self.parameters if not p.GENERATED),
                           *(StopReaction(s.reaction, 0.0, stop_reaction_unit(units.get(s.condition, ""), self.units),
                                          s.reaction_description) for s in self.stops))
        self._validate()

    def unit(self, si: str) -> str:
        """The label, in the description's :attr:`units`, of a generated quantity whose SI label is ``si``
        (``"N"`` -> ``"g mm/s^2"`` in mm and g; ``si`` itself in SI)."""
        return self.units.label(si)

    def condition_unit(self, cond: Condition) -> str:
        """The unit of condition ``cond``'s value: an expression's as declared, a built-in kind's (a
        distance, an angle) in the description's :attr:`units`."""
        return cond.value_unit if cond.kind == "expression" else self.unit(cond.value_unit)

    def __getstate__(self) -> dict[str, Any]:
        # the generated structures hold compiled code and the models made from them: a pickled
        # description is the description only (a copy generates its own on first build)
        return {k: v for k, v in self.__dict__.items() if k != "_generated"}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self.__dict__["_generated"] = {}

    # -- validation -----------------------------------------------------------------
    def _validate(self) -> None:
        if not isinstance(self.dof, int) or isinstance(self.dof, bool) or self.dof < 0:
            raise InputError("mechanism.dof", f"must be a non-negative integer, got {self.dof!r}")
        if self.redundant not in ("error", "drop"):
            raise InputError("mechanism.redundant", f"must be 'error' or 'drop', got {self.redundant!r}")
        self.param_symbols: dict[str, sp.Symbol] = {}
        for p in self.parameters:
            f = f"parameters.{p.name}"
            _check_name(p.name, f, digits=False)
            _check_variable_name(p.name, f, "parameter")
            if p.name in self.param_symbols:
                if p.GENERATED:
                    raise InputError(f, f"clashes with the contact reaction {p.name} of a stop: rename the parameter "
                                        "or the stop")
                raise InputError(f, "parameter defined more than once")
            if isinstance(p.value, bool) or not isinstance(p.value, (int, float)):
                raise InputError(f, f"value must be a number, got {p.value!r}")
            if p.scale is not None and not (isinstance(p.scale, (int, float)) and p.scale > 0):
                raise InputError(f, f"scale must be a positive number, got {p.scale!r}")
            self.param_symbols[p.name] = symbol(p.name)
        if not self.bodies:
            raise InputError("bodies", "a mechanism needs at least one body")
        self.body_map: dict[str, BodyT] = {}
        coords: dict[str, str] = {}
        for b in self.bodies:
            _check_name(b.name, f"bodies.{b.name}")
            if b.name == "ground":
                raise InputError("bodies.ground", "'ground' is reserved for the ground points")
            if b.name in self.body_map:
                raise InputError(f"bodies.{b.name}", "body defined more than once")
            self.body_map[b.name] = b
            for c in self._coordinate_names(b.name):
                if c in self.param_symbols:
                    raise InputError(f"parameters.{c}", f"clashes with a coordinate of body '{b.name}'")
                coords[c] = b.name
        self.coordinate_symbols = {c: symbol(c) for c in coords}
        for name in self.ground:
            _check_name(name, f"ground.{name}")
        seen: dict[str, str] = {}
        groups: list[tuple[str, Sequence[_Named]]] = [
            ("joints", self.joints), ("springs", self.springs), ("dampers", self.dampers), ("loads", self.loads),
            ("actuators", self.actuators), ("conditions", self.conditions), ("stops", self.stops),
            *((el.table, (el,)) for el in self.elements)]
        for group, items in groups:
            for it in items:
                _check_name(it.name, f"{group}.{it.name}")
                if group == "conditions":
                    _check_variable_name(it.name, f"{group}.{it.name}", "condition")
                if it.name in seen:
                    raise InputError(f"{group}.{it.name}", f"name already used in {seen[it.name]}")
                seen[it.name] = group
        # parse every value once: unknown parameters are reported now, with the key path
        self._exprs: dict[str, sp.Expr] = {}
        for key, v in self._values():
            self._exprs[key] = self.expr(v, key)
        for j in self.joints:
            j.check(self)
        for el in self.force_elements():
            el.check(self)
        self._check_loads()
        check_conditions(self)
        for name in self.hold:
            if name not in self.coordinate_symbols:
                raise InputError(f"assembly.hold.{name}",
                                 f"not a coordinate; coordinates: {', '.join(self.coordinate_symbols)}")
        self._check_connected()

    def force_elements(self) -> tuple[Element, ...]:
        """Every force element (:mod:`.elements`): springs, dampers, actuators, stops, then the other registered kinds."""
        return (*self.springs, *self.dampers, *self.actuators, *self.stops, *self.elements)

    def _coordinate_names(self, body: str) -> tuple[str, ...]:
        """The coordinate names of ``body`` (see :func:`coordinate_names`)."""
        return coordinate_names(body)

    def _check_loads(self) -> None:
        """Check every load's type and references (raises a one-line InputError)."""
        known = tuple(LOAD_TYPES[self.space].values())
        for ld in self.loads:
            if type(ld) not in known:
                raise InputError(f"loads.{getattr(ld, 'name', '?')}", self._UNKNOWN_LOAD.format(type(ld).__name__))
            ld.check(self)

    def direction_values(self, field: str, v: Any) -> list[tuple[str, Value]]:
        """The (key path, raw value) of a direction: ``[x, y]`` or an angle (rad)."""
        if not isinstance(v, (tuple, list)):
            return [(field, v)]
        if len(v) != 2:
            raise InputError(field, "a direction is [x, y] or an angle (rad)")
        return [(f"{field}.x", v[0]), (f"{field}.y", v[1])]

    def vector_values(self, field: str, v: Any) -> list[tuple[str, Value]]:
        """The (key path, raw value) of each component of the vector ``v`` (``[x, y]``)."""
        if not isinstance(v, (tuple, list)) or len(v) != len(self.AXES):
            raise InputError(field, f"must be a {len(self.AXES)}-vector [{', '.join(self.AXES)}], got {v!r}")
        return [(f"{field}.{c}", comp) for c, comp in zip(self.AXES, v)]

    def _values(self) -> Iterator[tuple[str, Any]]:
        """Every (key path, raw value) of the description that is a number or expression."""
        for b in self.bodies:
            yield from b.values(self)
        for gname, gp in self.ground.items():
            yield from self.vector_values(f"ground.{gname}", gp)
        for j in self.joints:
            yield from j.values(self)
        if self.gravity is not None:
            yield from self.gravity.values(self)
        for ld in self.loads:
            yield from ld.values(self)
        yield from self._common_values()

    def _common_values(self) -> Iterator[tuple[str, Any]]:
        """The (key path, raw value) pairs of the elements planar and spatial descriptions share:
        force elements (stops included), held coordinates and conditions."""
        for el in self.force_elements():
            yield from el.values(self)
        for k, v in self.hold.items():
            yield f"assembly.hold.{k}", v
        for c in self.conditions:
            yield from c.values(self)

    def kinematics_class(self) -> Callable[[Self], Kinematics]:
        """The kinematics strategy of this space (:class:`~._kinematics.PlanarKinematics`: x, y, theta per body)."""
        return PlanarKinematics

    def kinematics(self) -> Kinematics:
        """The kinematics of this description (:meth:`kinematics_class`), made once (it depends on no value) and
        kept with the generated structures."""
        kin = self._generated.get("kinematics")
        if kin is None:
            kin = self._generated["kinematics"] = self.kinematics_class()(self)
        return kin

    def normalisation_rows(self) -> frozenset[str]:
        """The names of the constraint rows that normalise coordinates (no joint's): none in the plane."""
        return frozenset()

    def summary(self) -> tuple[str, list[tuple[str, str, str, str, float | None]]] | None:
        """What a full build declares, without generating its equations (see :func:`._generate.summary`)."""
        from ._generate import summary
        return summary(self)

    def expr(self, value: Value, field: str) -> sp.Expr:
        """Parse ``value`` over the parameters (and, for custom loads and conditions, the coordinates)."""
        if isinstance(value, sp.Basic):
            return value
        known = dict(self.param_symbols)
        coordinate_keys = {k for cls in LOAD_TYPES[self.space].values() for k in cls.COORDINATE_KEYS}
        if (field.startswith("loads.") and field.rsplit(".", 1)[-1] in coordinate_keys) or (
                field.startswith("conditions.") and field.endswith(".expr")):
            known.update(self.coordinate_symbols)
        return to_expr(value, field, known)

    def value(self, field: str) -> sp.Expr:
        """The parsed expression of the value at key path ``field``."""
        return self._exprs[field]

    def _body_of(self, ref: str) -> str:
        return ref.split(".", 1)[0]

    def point_ref(self, ref: str, field: str) -> tuple[str, str]:
        """Split and check a point reference ``"<body>.<point>"`` / ``"ground.<point>"``."""
        if not isinstance(ref, str) or ref.count(".") != 1:
            raise InputError(field, f"a point reference is '<body>.<point>' or 'ground.<point>', got {ref!r}")
        body, point = ref.split(".")
        if body == "ground":
            if point not in self.ground:
                declared = ", ".join(self.ground) or "none declared"
                raise InputError(field, f"unknown ground point '{point}'; ground points: {declared}")
            return body, point
        if body not in self.body_map:
            raise InputError(field, f"unknown body '{body}'; bodies: {', '.join(self.body_map)}")
        valid = self.point_names(body)
        if point not in valid:
            raise InputError(field, f"unknown point '{point}' of body '{body}'; points: {', '.join(valid)}")
        return body, point

    def point_names(self, body: str) -> list[str]:
        """All point names of ``body`` (``a``, ``b`` for bars, declared points, ``cg``, ``origin``)."""
        b = self.body_map[body]
        names = ["a", "b"] if b.length is not None else []
        return names + [p for p in b.points if p not in names] + ["cg", "origin"]

    def _check_connected(self) -> None:
        adj: dict[str, set[str]] = {b: set() for b in self.body_map}
        adj["ground"] = set()
        for j in self.joints:
            ba, bb = self._body_of(j.a), self._body_of(j.b)
            adj[ba].add(bb)
            adj[bb].add(ba)
        for name, nbrs in adj.items():
            if name != "ground" and not nbrs:
                raise InputError(f"bodies.{name}", "is attached to nothing: no joint connects it to another body or the ground")
        reached, todo = {"ground"}, ["ground"]
        while todo:
            for nb in adj[todo.pop()]:
                if nb not in reached:
                    reached.add(nb)
                    todo.append(nb)
        loose = [b for b in self.body_map if b not in reached]
        if loose:
            raise InputError(f"bodies.{loose[0]}", "is not connected to the ground through joints (it would float freely)")

    # -- generation -----------------------------------------------------------------
    def build(self, **overrides: float) -> Model:
        """Generate the full static system: coordinates, joint reactions and every equation.

        Keyword arguments override parameter defaults (SI). Returns a
        :class:`~mechcont.equations.Model` (with ``mechanics``, ``scene``,
        ``potential_energy``, ``dof``, ...) whose state values are an assembled configuration.
        The equations are generated and compiled by the first build of this description; a
        build at other values reuses them and only assembles the mechanism again.
        Raises :class:`InputError` for impossible values, loops that cannot close and a
        wrong number of degrees of freedom.
        """
        return self._generate(overrides, reduced=False)

    def build_reduced(self, **overrides: float) -> Model:
        """Generate the reduced static system (see :mod:`mechcont.mechanism._reduce`)."""
        return self._generate(overrides, reduced=True)

    def _generator(self) -> Callable[..., Model]:
        """The function that generates this kind of mechanism's equations (imported on the first build: reading
        or checking a description needs neither the generator nor what it compiles with)."""
        from ._generate import generate
        return generate

    def _generate(self, overrides: Mapping[str, float], reduced: bool) -> Model:
        try:
            return self._generator()(self, overrides, reduced=reduced)
        except InputError as exc:
            raise locate_error(self.source, exc) from None
