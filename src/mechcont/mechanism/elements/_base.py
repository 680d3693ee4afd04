"""The element protocol of the force elements: one class per table, registered by its table name.

A force element is an entry ``[TABLE.NAME]`` of a description file (``[springs.NAME]``,
``[dampers.NAME]``, ``[actuators.NAME]``), planar or spatial: the same class serves both, its
maths written once against the kinematics object (``kin.point``, ``kin.distance``, ``kin.q``,
...). An element class gives

* ``table``: its table name (setting it registers the class in :data:`ELEMENT_TYPES`);
  ``KEYS``: the keys of its table; ``REQUIRED``: the keys a file must give; ``TEXT_KEYS``: the
  keys that are free text; :meth:`~Element.from_table`: the element of one parsed table;
* :meth:`~Element.check`: its references, with one-line errors naming the key;
  :meth:`~Element.values`: every number or expression of it (key path, raw value);
  :meth:`~Element.limits`: the physical ranges of its values; ``LENGTH_KEYS`` and
  ``STIFFNESS_KEYS``: the values that set the mechanism's typical length (m) and force (N/m times
  that length);
* :meth:`~Element.apply`: its potential or generalised forces, added to a :class:`~.loads.Loads`;
  :meth:`~Element.rows`: its constraint rows (with their reactions' names), if any;
* :meth:`~Element.states`: its first-order states (:class:`ElementState`, a tyre's lateral
  deflection), if any: each becomes a variable of the generated system held at its steady state
  in continuation, and is integrated or linearised with the coordinates in dynamics;
* :meth:`~Element.ends`: the point references it attaches to; :meth:`~Element.draw`: its
  drawing primitives.

The description keeps the built-in kinds in their own fields (``springs``, ``dampers``,
``actuators``) and any other registered kind in ``elements``; :meth:`Mechanism.force_elements`
gives them all. Adding an element kind is adding one module to this package with one such class.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from ...errors import InputError

if TYPE_CHECKING:
    from .._description import Mechanism
    from ..loads import Loads

__all__ = ["Element", "ElementState", "TwoPointElement", "ELEMENT_TYPES", "element_rows"]

#: table name (``"springs"``, ...) -> element class, in registration order.
ELEMENT_TYPES: dict[str, type[Element]] = {}
#: ``add(kind, name, points)``: one drawing primitive (see the scene functions).
Draw = Callable[[str, str, list[sp.Matrix]], None]


@dataclass(frozen=True)
class ElementState:
    """A first-order state of a force element: ``d(name)/dt = rate``.

    ``name``: the state variable (``y_<element>``); ``unit``: its unit label (SI); ``rate``: a SymPy
    expression in the generated coordinates, their velocity symbols
    (:func:`~mechcont.equations.velocity_symbol`), the parameters and the state symbols
    (``sympy.Symbol(name, real=True)``); ``scale``: its typical magnitude (for the arclength);
    ``initial``: its value before any solve."""

    name: str
    unit: str
    rate: sp.Expr
    scale: float = 1.0
    initial: float = 0.0
    description: str = ""


class Element:
    """Base of the force elements (see the module docstring for the protocol).

    Subclasses are frozen dataclasses whose first field is ``name``."""

    name: str
    table: ClassVar[str] = ""
    KEYS: ClassVar[frozenset[str]] = frozenset()
    REQUIRED: ClassVar[tuple[str, ...]] = ()
    TEXT_KEYS: ClassVar[tuple[str, ...]] = ()
    LENGTH_KEYS: ClassVar[tuple[str, ...]] = ()
    STIFFNESS_KEYS: ClassVar[tuple[str, ...]] = ()

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        table = cls.__dict__.get("table")
        if table:
            known = ELEMENT_TYPES.get(table)
            if known is not None and known.__qualname__ != cls.__qualname__:
                raise TypeError(f"element table {table!r} registered twice ({known.__name__}, {cls.__name__})")
            ELEMENT_TYPES[table] = cls

    @classmethod
    def required_message(cls, key: str) -> str:
        """What a file missing the required ``key`` is told."""
        return "is required"

    @classmethod
    def from_table(cls, name: str, spec: Mapping, field: str) -> Element:
        """The element of a ``[TABLE.NAME]`` table ``spec`` (its keys checked against ``KEYS``)."""
        for k in spec:
            if k not in cls.KEYS:
                raise InputError(f"{field}.{k}", f"unknown key; valid keys: {', '.join(sorted(cls.KEYS))}")
        for k in cls.REQUIRED:
            if k not in spec:
                raise InputError(f"{field}.{k}", cls.required_message(k))
        for k in cls.TEXT_KEYS:
            if k in spec and not isinstance(spec[k], str):
                raise InputError(f"{field}.{k}", f"must be a string, got {spec[k]!r}")
        return cls(name, **spec)  # type: ignore[call-arg]

    def field(self, key: str = "") -> str:
        """The key path of this element (or of its ``key``)."""
        return f"{self.table}.{self.name}" + (f".{key}" if key else "")

    def check(self, mech: Mechanism) -> None:
        """Check the references against ``mech`` (a one-line InputError naming the key)."""

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Every (key path, raw value) of the element that is a number or an expression."""
        return iter(())

    def limits(self, solve: bool) -> list[tuple[str, bool, str]]:
        """``(key path, strict, what)``: values that must be positive (strict) or non-negative
        (``solve``: values given for one analysis rather than the file's defaults)."""
        return []

    def apply(self, kin, out: Loads) -> None:
        """Add the element's potential and generalised forces in the coordinates of ``kin`` to ``out``."""

    def rows(self, kin) -> list:
        """The element's constraint rows (:class:`~.._kinematics.ConstraintRow`) in the coordinates of ``kin``."""
        return []

    def states(self, kin) -> tuple[ElementState, ...]:
        """The element's first-order states in the coordinates of ``kin`` (none by default)."""
        return ()

    def ends(self) -> tuple[str, ...]:
        """The point references the element attaches to (a ground one is drawn as an anchor)."""
        return ()

    def draw(self, kin, add: Draw) -> None:
        """Add the element's drawing primitives."""


class TwoPointElement(Element):
    """An element between the points ``a`` and ``b`` (point references), drawn as ``DRAWN`` from ``a`` to ``b``."""

    a: str
    b: str
    DRAWN: ClassVar[str] = ""

    def check(self, mech: Mechanism) -> None:
        """Both ends must be points of the mechanism."""
        mech.point_ref(self.a, self.field("a"))
        mech.point_ref(self.b, self.field("b"))

    def ends(self) -> tuple[str, ...]:
        """``a`` and ``b``."""
        return (self.a, self.b)

    def draw(self, kin, add: Draw) -> None:
        """A ``DRAWN`` primitive from ``a`` to ``b``."""
        add(self.DRAWN, self.name, [kin.point(self.a), kin.point(self.b)])


def element_rows(kin) -> list:
    """The constraint rows of every force element of the mechanism of ``kin``, in declaration order."""
    return [r for el in kin.mech.force_elements() for r in el.rows(kin)]
