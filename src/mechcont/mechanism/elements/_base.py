"""The element protocol of the force elements: one class per table, registered by its table name.

A force element is an entry ``[TABLE.NAME]`` of a description file (``[springs.NAME]``,
``[dampers.NAME]``, ``[actuators.NAME]``), planar or spatial: the same class serves both, its
maths written once against the kinematics object (``kin.point``, ``kin.distance``, ``kin.q``,
...). An element class gives

* ``table``: its table name (setting it registers the class in :data:`ELEMENT_TYPES`, the
  ``"elements"`` registry of :mod:`.._plugin`, shared by both spaces);
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
* :meth:`~Element.ends`: the point references it is drawn from (a ground one is drawn as an
  anchor); :meth:`~Element.line_of_action`: the two points whose line its force acts along, if
  any (the assembly diagnostics refuse a configuration where they coincide; a rotary element has
  none); :meth:`~Element.draw`: its drawing primitives.

The class is a :class:`~.._plugin.PlugIn` of the family ``"elements"``: its maths is written
against the :class:`~.._plugin.Kinematics` protocol, so that it serves both spaces.

The description keeps the built-in kinds in their own fields (``springs``, ``dampers``,
``actuators``) and any other registered kind in ``elements``; :meth:`Mechanism.force_elements`
gives them all. Adding an element kind is adding one module to this package with one such class.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import sympy as sp

from ...errors import InputError
from .._plugin import Draw, Kinematics, PlugIn, Registry, registry

if TYPE_CHECKING:
    from .._description import Mechanism
    from ..joints import ConstraintRow

__all__ = ["Element", "ElementState", "TwoPointElement", "ELEMENT_TYPES", "element_rows"]

#: table name (``"springs"``, ...) -> element class, in registration order (both spaces share it).
ELEMENT_TYPES: Registry = registry("elements", "plane")


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


class Element(PlugIn[Kinematics]):
    """Base of the force elements (see the module docstring for the protocol).

    Subclasses are frozen dataclasses whose first field is ``name``."""

    name: str
    FAMILY: ClassVar[str] = "elements"
    KEY: ClassVar[str] = "table"
    table: ClassVar[str] = ""
    TEXT_KEYS: ClassVar[tuple[str, ...]] = ()
    LENGTH_KEYS: ClassVar[tuple[str, ...]] = ()
    STIFFNESS_KEYS: ClassVar[tuple[str, ...]] = ()

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

    def section(self) -> str:
        """Its table (``"springs"``, ...)."""
        return self.table

    def states(self, kin: Kinematics) -> tuple[ElementState, ...]:
        """The element's first-order states in the coordinates of ``kin`` (none by default)."""
        return ()


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

    def line_of_action(self) -> tuple[str, str] | None:
        """Its force acts along ``a`` - ``b``."""
        return (self.a, self.b)

    def draw(self, kin: Kinematics, add: Draw) -> None:
        """A ``DRAWN`` primitive from ``a`` to ``b``."""
        add(self.DRAWN, self.name, [kin.point(self.a), kin.point(self.b)])


def element_rows(kin: Kinematics) -> list[ConstraintRow]:
    """The constraint rows of every force element of the mechanism of ``kin``, in declaration order."""
    return [r for el in kin.mech.force_elements() for r in el.rows(kin)]
