"""The one display rule for units: SI inside, radians inside; angles shown in degrees.

Every table, summary line, axis and warning shows a value through :func:`display`, so the rule
(``rad`` is shown as ``deg``, everything else as it is) is written once.
"""

from __future__ import annotations

import math
from typing import TypeVar

import numpy as np

__all__ = ["display", "display_unit", "display_scale", "shown", "derivative_unit"]

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
