"""The one display rule for units: SI inside, radians inside; angles shown in degrees.

Every table, summary line, axis and warning shows a value through :func:`display`, so the rule
(``rad`` is shown as ``deg``, everything else as it is) is written once.
"""

from __future__ import annotations

import math
from typing import TypeVar

import numpy as np

__all__ = ["display", "display_unit", "display_scale", "shown", "derivative_unit", "dimension", "typical_scale"]

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
    ``by`` has no unit (a dimensionless parameter)."""
    if of == by:
        return "1"
    if not by:
        return of
    den = f"({by})" if any(c in by for c in "/* ") else by
    return f"{of or '1'}/{den}"


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

    Products are written with spaces or ``*``, one ``/`` divides by everything after it; a prefix
    (``mm``, ``km``, ``um``, ``kg``, ``kN`` ...) is part of the label, not of the dimension: a label never
    converts a value. Returns None for a label it cannot read (a dimensionless ``""`` is ``(0, 0, 0)``).
    """
    num, _, den = unit.replace("*", " ").partition("/")
    total = [0, 0, 0]
    for part, sign in ((num, 1), (den.replace("(", " ").replace(")", " "), -1)):
        for token in part.split():
            d = _symbol(token)
            if d is None:
                return None
            total = [t + sign * e for t, e in zip(total, d)]
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
    if "rad" in label.replace("/", " ").split():
        return None
    return {(1, 0, 0): length, (1, 1, -2): force, (2, 1, -2): force * length}.get(dimension(label) or (0, 0, 0))
