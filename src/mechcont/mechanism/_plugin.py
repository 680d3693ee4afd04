"""The plug-in protocol of a description: the typed kinematics every plug-in is written against,
the base every plug-in shares and the one registry that finds a plug-in by its table name.

A *plug-in* is one entry of a description file that a class reads and turns into equations: a
force element (``[springs.NAME]``, ...), a load (``[loads.NAME] type = ...``), a joint
(``[joints.NAME] type = ...``, planar or spatial) or a condition (``[conditions.NAME] type = ...``).
Every plug-in class derives from :class:`PlugIn` and has the same shape:

* ``FAMILY`` (``"elements"``, ``"loads"``, ``"joints"``, ``"conditions"``) and its key (the TOML
  ``type``, or an element's table name): defining a subclass with a key registers it in
  :func:`registry` ``(FAMILY, space)`` for each of its ``SPACES``; ``KEYS``/``REQUIRED``: the keys
  of its table;
* :meth:`~PlugIn.check` (references), :meth:`~PlugIn.values` (numbers and expressions by key
  path), :meth:`~PlugIn.limits` (the physical ranges of its quantities, each a
  :class:`~mechcont.equations.Limit`), :meth:`~PlugIn.check_values` (values impossible for it);
* :meth:`~PlugIn.rows` (constraint rows, each with its reaction) and :meth:`~PlugIn.apply`
  (potential and generalised forces), written once against a :class:`Kinematics`;
* :meth:`~PlugIn.ends` (the points to draw it from: a ground one is drawn as an anchor),
  :meth:`~PlugIn.line_of_action` (the two points whose line its force acts along, if it has
  one: the diagnostics refuse an assembly where they coincide) and :meth:`~PlugIn.draw`.

:class:`Kinematics` is the strategy of a space: the planar ``PlanarKinematics`` (x, y, theta per
body) and the spatial ``SpatialKinematics`` (origin and Euler parameters) both satisfy it; a
plug-in written for both spaces is annotated with it, so that the type checker refuses a call of a
method only one space has (``kin.angle``, ``kin.moment_work``). A plug-in of one space takes its
space's class (``PlugIn[PlanarKinematics]``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any, ClassVar, Generic, Protocol, TypeVar

import sympy as sp

from ..equations import Limit

if TYPE_CHECKING:
    from ._description import Mechanism
    from .joints._base import ConstraintRow
    from .loads._base import Loads

__all__ = ["Kinematics", "PlugIn", "Registry", "registry", "SPACES", "Draw"]

#: The spaces a description is written in (a description class's ``space``).
SPACES = ("plane", "space")
#: ``add(kind, name, points)``: one drawing primitive (see the scene functions).
Draw = Callable[[str, str, list[sp.Matrix]], None]


class Kinematics(Protocol):
    """What a plug-in may ask of the kinematics of either space (SymPy expressions; SI units, radians).

    Point references are ``"<body>.<point>"`` or ``"ground.<point>"``; vectors have ``dimension``
    components in global axes."""

    @property
    def mech(self) -> Mechanism[Any, Any]:
        """The description."""

    @property
    def dimension(self) -> int:
        """2 in the plane, 3 in space."""

    @property
    def coords(self) -> list[str]:
        """The generated coordinates' names, in order."""

    @property
    def q(self) -> list[sp.Symbol]:
        """The generated coordinates' symbols, in order."""

    def local_point(self, body: str, point: str) -> sp.Matrix:
        """Body coordinates (m) of ``point`` on ``body``."""

    def point(self, ref: str) -> sp.Matrix:
        """Global position (m) of the point reference ``ref``."""

    def cg(self, body: str) -> sp.Matrix:
        """Global position (m) of ``body``'s centre of gravity."""

    def origin(self, body: str) -> list[sp.Symbol]:
        """The coordinates of ``body``'s frame origin (m)."""

    def distance(self, a: str, b: str) -> sp.Expr:
        """Distance (m) between the point references ``a`` and ``b``."""

    def direction(self, field: str, raw: Any) -> sp.Matrix:
        """The unit vector of the direction at key path ``field`` (``raw``: the value as described)."""

    def turn(self, ref: str, v: sp.Matrix) -> sp.Matrix:
        """The body vector ``v`` of the frame ``ref`` belongs to, in global axes."""

    def relative_rotation(self, a: str, b: str, axis: sp.Matrix | None) -> sp.Expr:
        """The rotation (rad) of the frame of ``b`` relative to that of ``a`` (point references),
        about ``axis`` (design pose; in space only, where it is required)."""

    def body_mass(self, b: Any) -> sp.Expr:
        """Mass (kg) of the body ``b``."""

    def force_work(self, P: sp.Matrix, f: sp.Matrix) -> list[sp.Expr]:
        """Generalised forces (one per coordinate) of the force ``f`` (N) at ``P``: ``f . dP/dq``."""

    def constraints(self) -> Sequence[ConstraintRow]:
        """Every scalar constraint row of the mechanism."""

    def mass_matrix(self) -> sp.Matrix:
        """The mass matrix of the coordinates."""


K = TypeVar("K", bound=Kinematics)


class Registry(dict[str, Any]):
    """Key (TOML ``type``, or an element's table name) -> plug-in class of one family in one space,
    in registration order. Filled by :class:`PlugIn` subclasses; read by the file reader, the
    generators and the documentation checks (:meth:`keyed`)."""

    def __init__(self, family: str, space: str):
        super().__init__()
        self.family, self.space = family, space

    def add(self, key: str, cls: type) -> None:
        """Register ``cls`` under ``key`` (a TypeError when another class has it: two plug-ins, one name)."""
        known = self.get(key)
        if known is not None and known.__qualname__ != cls.__qualname__:
            raise TypeError(f"{self.family} key {key!r} registered twice in {self.space} "
                            f"({known.__name__}, {cls.__name__})")
        self[key] = cls

    def keyed(self) -> dict[str, tuple[Any, frozenset[str]]]:
        """``key`` -> (class, the keys of its table besides ``type``), every class registered."""
        return {key: (cls, cls.table_keys()) for key, cls in self.items()}

    def first(self, keys: Sequence[str]) -> None:
        """Put ``keys`` first, in that order (the order error messages list them), the others after."""
        rest = dict(self)
        self.clear()
        self.update({k: rest[k] for k in keys if k in rest}, **rest)


_REGISTRIES: dict[tuple[str, str], Registry] = {}
#: The families whose every plug-in serves both spaces (one class, written against :class:`Kinematics`):
#: one registry for both.
BOTH_SPACES = frozenset({"elements", "conditions"})


def registry(family: str, space: str) -> Registry:
    """The registry of the plug-ins of ``family`` (``"elements"``, ``"loads"``, ``"joints"``,
    ``"conditions"``) in ``space`` (``"plane"`` or ``"space"``; the same one for both in the families
    of :data:`BOTH_SPACES`)."""
    key = (family, "both" if family in BOTH_SPACES else space)
    if key not in _REGISTRIES:
        _REGISTRIES[key] = Registry(family, key[1])
    return _REGISTRIES[key]


class PlugIn(Generic[K]):
    """Base of every plug-in (see the module docstring): defaults that do nothing.

    Subclasses are frozen dataclasses whose first field is ``name``."""

    name: str
    FAMILY: ClassVar[str] = ""
    #: The class attribute that holds the plug-in's registry key.
    KEY: ClassVar[str] = "kind"
    SPACES: ClassVar[tuple[str, ...]] = SPACES
    KEYS: ClassVar[frozenset[str]] = frozenset()
    REQUIRED: ClassVar[tuple[str, ...]] = ()

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        key = cls.__dict__.get(cls.KEY)
        if key:
            for space in cls.SPACES:
                registry(cls.FAMILY, space).add(key, cls)

    @classmethod
    def table_keys(cls) -> frozenset[str]:
        """The keys of its table (besides ``type``)."""
        return cls.KEYS

    def section(self) -> str:
        """The table the plug-in is an entry of (``"joints"``, ``"loads"``, ...)."""
        return self.FAMILY

    def field(self, key: str = "") -> str:
        """The key path of this plug-in (or of its ``key``)."""
        return f"{self.section()}.{self.name}" + (f".{key}" if key else "")

    def check(self, mech: Mechanism[Any, Any]) -> None:
        """Check the references against ``mech`` (a one-line InputError naming the key)."""

    def values(self, mech: Mechanism[Any, Any]) -> Iterator[tuple[str, Any]]:
        """Every (key path, raw value) that is a number or an expression."""
        return iter(())

    def limits(self, kin: K, solve: bool) -> list[Limit]:
        """The physical ranges of its quantities in the coordinates of ``kin`` (none by default): each a
        :class:`~mechcont.equations.Limit` named by its key path, the quantity positive (``strict``) or
        non-negative. ``solve``: the values are given for one analysis rather than being the file's
        defaults (a spring's stiffness may then be zero)."""
        return []

    def value_limit(self, kin: K, key: str, strict: bool, what: str) -> Limit:
        """The :class:`~mechcont.equations.Limit` of its value at ``key``: positive (``strict``) or
        non-negative; ``what`` names the quantity with its unit (``"stiffness (N/m)"``)."""
        field = self.field(key)
        return Limit(field, kin.mech.value(field), strict, what)

    def check_values(self, mech: Mechanism[Any, Any], values: Mapping[str, float]) -> None:
        """Reject values impossible for it at the parameter ``values`` (one-line InputError)."""

    def rows(self, kin: K) -> Sequence[ConstraintRow]:
        """Its constraint rows in the coordinates of ``kin`` (none by default)."""
        return []

    def apply(self, kin: K, out: Loads) -> None:
        """Add its potential and generalised forces in the coordinates of ``kin`` to ``out`` (none by default)."""

    def ends(self) -> tuple[str, ...]:
        """The point references it is drawn from (a ground one is drawn as an anchor)."""
        return ()

    def line_of_action(self) -> tuple[str, str] | None:
        """The two point references whose line its force acts along (its direction is undefined where
        they coincide), or None when its force has no such line (a torsion spring, a moment)."""
        return None

    def draw(self, kin: K, add: Draw) -> None:
        """Add its drawing primitives (none by default)."""
