"""The one display rule for units: radians inside, angles shown in degrees; and the unit system of a description.

Every table, summary line, axis and warning shows a value through :func:`display`, so the rule
(``rad`` is shown as ``deg``, everything else as it is) is written once. A description written in other
units (millimetres and grams, ...) declares them (``[mechanism] units``, a :class:`UnitSystem`), and every
name it generates is labelled through :meth:`UnitSystem.label`: ``"N"`` becomes ``"g mm/s^2"``, so a label
always says the unit its value is in.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TypeVar

import numpy as np

__all__ = ["display", "display_unit", "display_scale", "shown", "derivative_unit", "dimension", "typical_scale",
           "UnitSystem", "SI", "LENGTH_UNITS", "MASS_UNITS", "undeclared_label"]

V = TypeVar("V", float, np.ndarray)


def display_unit(unit: str) -> str:
    """The unit a value of ``unit`` is shown in: ``"deg"`` for ``"rad"``, else ``unit`` itself."""
    return "deg" if unit == "rad" else unit


def display_scale(unit: str) -> float:
    """The factor from SI ``unit`` to its display unit (180/pi for ``rad``, else 1)."""
    return 180.0 / math.pi if unit == "rad" else 1.0


def display(value: V, unit: str) -> tuple[V, str]:
    """``(value, unit)`` as shown: an angle (``rad``) in degrees with unit ``"deg"``, any other value unchanged.

    ``value`` may be a float or an array (converted elementwise).
    """
    if unit != "rad":
        return value, unit
    return (np.degrees(value) if isinstance(value, np.ndarray) else math.degrees(value)), "deg"


def shown(value: float, unit: str, fmt: str = ".6g") -> str:
    """``"12.5 deg"``, ``"3 N"``, ``"0.5"`` (no unit): a value with its display unit, formatted with ``fmt``."""
    v, u = display(value, unit)
    return f"{v:{fmt}} {u}" if u else f"{v:{fmt}}"



def derivative_unit(of: str, by: str) -> str:
    """The unit of ``d(of)/d(by)``: ``"N/m"``, ``"N/(N/m)"``, ``"1/m"``, ``"1"`` when they cancel; ``of`` when
    ``by`` has no unit (a dimensionless parameter); a quotient ``of`` divided by a product ``by`` keeps one
    ``/``: ``"g mm/s^2"`` by ``"mm"`` is ``"g mm/(s^2 mm)"``, by a quotient both are grouped,
    ``"(g mm/s^2)/(g/s^2)"`` (as :func:`dimension` reads them)."""
    if of == by:
        return "1"
    if not by:
        return of
    num, slash, below = of.partition("/")
    if slash and "/" not in by and not any(c in of + by for c in "()*"):
        return f"{num or '1'}/({below.strip()} {by})"
    den = f"({by})" if any(c in by for c in "/* ") else by
    return f"{f'({of})' if '/' in of else of or '1'}/{den}"


#: the base of each unit symbol a description's labels use, as exponents of (length, mass, time); a
#: prefix (mm, km, um, g, t, kN, ...) changes the number a file writes, never the dimension
_BASE = {"m": (1, 0, 0), "g": (0, 1, 0), "t": (0, 1, 0), "s": (0, 0, 1), "N": (1, 1, -2), "rad": (0, 0, 0),
         "1": (0, 0, 0), "Pa": (-1, 1, -2), "J": (2, 1, -2), "W": (2, 1, -3)}
_PREFIXES = ("", "k", "M", "c", "m", "u", "\u00b5", "n")


def _symbol(token: str) -> tuple[int, int, int] | None:
    name, _, power = token.partition("^")
    try:
        n = int(power) if power else 1
    except ValueError:
        return None
    for pre in _PREFIXES:
        if name.startswith(pre) and name[len(pre):] in _BASE and (pre or name in _BASE):
            base = _BASE[name[len(pre):]]
            return (base[0] * n, base[1] * n, base[2] * n)
    return None


def dimension(unit: str) -> tuple[int, int, int] | None:
    """The exponents ``(length, mass, time)`` of a unit label such as ``"N m/rad"``, ``"mm"`` or ``"g mm/s^2"``.

    Products are written with spaces or ``*``, one ``/`` divides by everything after it, a parenthesised
    group is one factor (``"N/(N/m)"``, ``"(g mm/s^2)/(g/s^2)"``); a prefix (``mm``, ``km``, ``um``,
    ``kg``, ``kN`` ...) is part of the label, not of the dimension: a label never converts a value.
    Returns None for a label it cannot read (a dimensionless ``""`` is ``(0, 0, 0)``).
    """
    return _quotient(unit.replace("*", " "), 0)


def _quotient(text: str, depth: int) -> tuple[int, int, int] | None:
    """:func:`dimension` of ``text``: its factors before the first ``/`` outside parentheses over those after."""
    level, cut = 0, -1
    for i, c in enumerate(text):
        level += (c == "(") - (c == ")")
        if level < 0:
            return None
        if c == "/" and level == 0 and cut < 0:
            cut = i
    if level != 0 or depth > 8:
        return None
    num, den = (text, "") if cut < 0 else (text[:cut], text[cut + 1:])
    total = [0, 0, 0]
    for part, sign in ((num, 1), (den, -1)):
        d = _product(part, depth)
        if d is None:
            return None
        total = [t + sign * e for t, e in zip(total, d)]
    return (total[0], total[1], total[2])


def _product(text: str, depth: int) -> tuple[int, int, int] | None:
    """The dimension of a product of symbols and parenthesised groups (no ``/`` outside the groups)."""
    total, level, start = [0, 0, 0], 0, 0
    factors = []
    for i, c in enumerate(text + " "):
        if c == "(":
            if level == 0:
                factors.append(text[start:i])
                start = i
            level += 1
        elif c == ")":
            level -= 1
            if level == 0:
                factors.append(text[start:i + 1])
                start = i + 1
        elif c == " " and level == 0:
            factors.append(text[start:i])
            start = i + 1
    for f in (f.strip() for f in factors):
        if not f:
            continue
        d = _quotient(f[1:-1], depth + 1) if f.startswith("(") else _symbol(f)
        if d is None:
            return None
        total = [t + e for t, e in zip(total, d)]
    return (total[0], total[1], total[2])


def typical_scale(unit: str, length: float, force: float) -> float | None:
    """The typical magnitude of a value labelled ``unit`` on a mechanism whose typical length is ``length``
    and typical force ``force`` (both in the file's own units, whatever they are): 1 for ``"rad"``,
    ``length`` for a length (``"m"``, ``"mm"``, ``"km"`` ...), ``force`` for a force (``"N"``, ``"kN"``,
    ``"g mm/s^2"`` ...), ``force*length`` for a moment (``"N m"`` ...); None for any other label (a
    stiffness per radian included: its size is not a moment's), and the caller falls back on the value."""
    label = unit.replace("*", " ").replace(".", " ").strip()
    if label == "rad":
        return 1.0
    if "rad" in label.replace("/", " ").replace("(", " ").replace(")", " ").split():
        return None
    return {(1, 0, 0): length, (1, 1, -2): force, (2, 1, -2): force * length}.get(dimension(label) or (0, 0, 0))


#: the length and mass units a description may declare, with their size in metres and kilograms
LENGTH_UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "km": 1e3, "um": 1e-6, "\u00b5m": 1e-6}
MASS_UNITS = {"kg": 1.0, "g": 1e-3, "t": 1e3, "mg": 1e-6}


def _angle_power(unit: str) -> int:
    """How many times ``rad`` divides (negative) or multiplies a label such as ``"N m/rad"``."""
    num, _, den = unit.replace("*", " ").replace("(", " ").replace(")", " ").partition("/")
    return num.split().count("rad") - den.split().count("rad")


@dataclass(frozen=True)
class UnitSystem:
    """The consistent units a description's numbers are in: ``length`` (a key of :data:`LENGTH_UNITS`),
    ``mass`` (a key of :data:`MASS_UNITS`), seconds and radians; force is then mass length/s^2 and
    energy (a moment) force length. The default is SI (m, kg)."""

    length: str = "m"
    mass: str = "kg"

    @property
    def is_si(self) -> bool:
        """True for metres and kilograms (the labels are then SI's own: N, N m, J)."""
        return self.length == "m" and self.mass == "kg"

    @property
    def newtons(self) -> bool:
        """True when the system's force is exactly a newton (mm with t, m with kg): forces are labelled
        ``N``, moments ``N mm``, stiffnesses ``N/mm`` (a mass or an inertia keeps ``t``, ``t mm^2``)."""
        return math.isclose(MASS_UNITS[self.mass] * LENGTH_UNITS[self.length], 1.0, rel_tol=1e-12)

    def label(self, si: str) -> str:
        """The label in this system of a quantity whose SI label is ``si``: for mm and g, ``"N"`` ->
        ``"g mm/s^2"``, ``"N m/rad"`` -> ``"g mm^2/(s^2 rad)"``, ``"m/s"`` -> ``"mm/s"``, ``"rad"`` and
        ``""`` unchanged; for mm and t, ``"N"`` stays and ``"J"`` -> ``"N mm"``. In SI ``si`` itself.
        A label :func:`dimension` cannot read is returned unchanged."""
        dim = dimension(si)
        if self.is_si or dim is None or dim == (0, 0, 0):
            return si
        return self.of(dim, _angle_power(si))

    def of(self, dim: tuple[int, int, int], angle: int = 0) -> str:
        """The label of dimension ``dim`` (length, mass, time exponents) times ``rad^angle`` in this
        system (see :meth:`label`); ``"1"`` for a pure number."""
        length, mass, time = dim
        factors: list[tuple[str, int]]
        if self.newtons and mass != 0 and time < 0:  # N, N mm, N/mm, N s/mm: what users of mm/t expect
            factors = [("N", mass), (self.length, length - mass), ("s", time + 2 * mass)]
        else:
            factors = [(self.mass, mass), (self.length, length), ("s", time)]
        factors.append(("rad", angle))
        num = [n if e == 1 else f"{n}^{e}" for n, e in factors if e > 0]
        den = [n if e == -1 else f"{n}^{-e}" for n, e in factors if e < 0]
        if not den:
            return " ".join(num) or "1"
        below = den[0] if len(den) == 1 else f"({' '.join(den)})"
        return f"{' '.join(num) or '1'}/{below}"

    def from_si(self, unit: str) -> float:
        """How many of this system's units make one SI unit of the quantity labelled ``unit`` (by its
        dimension, :func:`dimension`): 1e6 for a force in mm and g (1 N = 1e6 g mm/s^2), 1 in SI or for a
        label it cannot read. An absolute number in SI (a default bound) is worth this many in the file's units."""
        dim = dimension(unit)
        if dim is None:
            return 1.0
        return 1.0 / (LENGTH_UNITS[self.length] ** dim[0] * MASS_UNITS[self.mass] ** dim[1])

    def __str__(self) -> str:
        return f"{self.length}, {self.mass}, s"


#: metres, kilograms, seconds
SI = UnitSystem()


def undeclared_label(label: str, units: UnitSystem) -> str | None:
    """The first length or mass symbol of the label ``label`` that is not ``units``' own (``"mm"`` in a
    description declared, or by default, in metres), or None: a parameter labelled in units the description
    does not declare, so its generated names' labels would not be the units its numbers are in."""
    for token in label.replace("/", " ").replace("*", " ").replace("(", " ").replace(")", " ").split():
        name = token.partition("^")[0]
        if name in LENGTH_UNITS and name != units.length or name in MASS_UNITS and name != units.mass:
            return name
    return None

