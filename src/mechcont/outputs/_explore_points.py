"""The special points and first axes of the explorer's documents (:mod:`.explore`): their names, buttons and labels."""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from ..units import dimension

if TYPE_CHECKING:
    from ..continuation import Branch
    from ._explore_cycles import CycleTable

__all__ = ["special_points", "default_axes", "event_words"]

#: A special point's label that is a code (``LP``, ``JUMP``, a user event's name) is numbered along the branch.
_CODE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
#: One stop event of a time history's label column (:func:`.tables.event_labels`): kind, stop, details.
_STOP_EVENT = re.compile(r"(impact|contact|release) (\S+)(?: .*)?\Z")

def event_words(label: str) -> str:
    """A time history's event label without its numbers, for the diagram (``"impact fwd_stop 75.3 1/s; contact
    fwd_stop"`` -> ``"impact + contact fwd_stop"``); any other label as it is."""
    parts = [_STOP_EVENT.match(p) for p in label.split("; ")]
    if not parts or not all(parts):
        return label
    kinds = [m.group(1) for m in parts if m]
    stops = list(dict.fromkeys(m.group(2) for m in parts if m))
    if len(stops) == 1:
        return " + ".join(kinds) + " " + stops[0]
    return "; ".join(f"{m.group(1)} {m.group(2)}" for m in parts if m)


def special_points(branch: Branch, rows: np.ndarray) -> list[dict]:
    """The special points of ``branch`` for the page: ``name`` (``branch.point_names()``: ``LP1``, what
    ``branch["LP1"]`` finds), ``tag`` (the buttons' text: the name of a code label, ``LP1``, ``LP2?`` when only
    approximately located; an event's own text otherwise, numbered ``(2)`` only when it repeats), ``short``
    (the diagram's label: an event without its numbers), ``label`` and ``row`` (index among the embedded rows)."""
    where = {int(r): k for k, r in enumerate(rows)}
    repeats = Counter(p.label for p in branch.special_points)
    seen: Counter = Counter()
    out = []
    for name, p in zip(branch.point_names(), branch.special_points):
        seen[p.label] += 1
        if _CODE.match(p.label):
            tag = short = name
        else:
            nth = f" ({seen[p.label]})" if repeats[p.label] > 1 else ""
            tag, short = p.label + nth, event_words(p.label)
        approx = "" if p.located else "?"
        out.append({"name": name, "tag": tag + approx, "short": short + approx, "label": p.label,
                    "row": where[p.index]})
    return out


def default_axes(doc: dict, kinds: Mapping[str, str] | None = None, cycle: CycleTable | None = None) -> list[str]:
    """The diagram's first axes: the continuation parameter (else the first changing column) against the
    first changing angle; else a changing force or moment the branch solved for (a parameter, such as a
    downlock's force); else the coordinate that moves most (a spatial gear's point coordinates: the part
    that travels furthest); else the last changing column. ``kinds`` maps a column to its variable's kind
    (``"state"``, ``"parameter"``) when the model is known. A family of cycles (``cycle``): its parameter
    against its first state (drawn as the max and min over each orbit)."""
    if cycle is not None and cycle.states:
        return [doc["vary"], cycle.states[0]]
    cols, units = doc["columns"], doc["units"]
    ptp = {n: float(np.ptp(v)) for n, v in cols.items()}
    changing = [n for n, v in cols.items() if ptp[n] > 1e-12 * max(1.0, float(np.max(np.abs(v))))] or list(cols)
    x = doc["vary"] if doc["vary"] in cols else changing[0]
    rest = [n for n in changing if n != x] or [n for n in cols if n != x] or [x]
    kind = (lambda n: kinds.get(n, "")) if kinds is not None else (lambda n: "")
    angle = next((n for n in rest if units.get(n) == "rad"), None)
    load = next((n for n in rest if dimension(units.get(n, "")) in ((1, 1, -2), (2, 1, -2)) and kind(n) == "parameter"),
                None)  # a force or a moment, in any units
    moves = [n for n in rest if dimension(units.get(n, "")) == (1, 0, 0) and kind(n) in ("state", "")]
    y = angle or load or (max(moves, key=lambda n: ptp[n]) if moves else rest[-1])
    return [x, y]
