"""How ``mechcont check`` shows its numbers: a value, a value in its unit (radians as degrees), aligned lines."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

__all__ = ["short", "shown", "aligned"]


def short(v: float | None) -> str:
    """A value to 4 significant digits, ``-`` for none."""
    return "-" if v is None else f"{v:.4g}"


def shown(v: float | None, unit: str) -> str:
    """A value for display: radians as degrees, others with their unit."""
    if v is None:
        return "-"
    if unit == "rad":
        return f"{round(math.degrees(v), 4) + 0.0:.4f} deg"   # no "-0.0000"
    return f"{v:.6g} {unit}".rstrip()


def aligned(entries: Iterable[Sequence[object]]) -> list[str]:
    """The ``entries`` as indented lines, their columns but the last aligned."""
    rows = [tuple(str(c) for c in r) for r in entries]
    if not rows:
        return ["  (none)"]
    n = max(len(r) for r in rows)
    widths = [max(len(r[i]) for r in rows if i < len(r)) for i in range(n - 1)]
    return ["  " + "  ".join([*(c.ljust(w) for c, w in zip(r[:-1], widths)), r[-1]]).rstrip() for r in rows]
