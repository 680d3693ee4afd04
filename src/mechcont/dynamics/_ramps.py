"""Sweep segments: a ramped parameter's linear segments, read from their several spellings, and their schedule."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, TypeAlias

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from typing_extensions import TypeIs

__all__ = ["Ramp", "RampSpec", "parse_ramps", "MAX_SWEEP_SECONDS"]


#: Longest time (s) a sweep may simulate (about 11.6 days of slowly ramped loads).
MAX_SWEEP_SECONDS = 1e6


@dataclass(frozen=True)
class Ramp:
    """One sweep segment: parameter ``name`` goes linearly from ``start`` to ``stop``.

    ``rate`` is the speed of the ramp, positive, in units of the parameter per second.
    """

    name: str
    start: float
    stop: float
    rate: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.start) and math.isfinite(self.stop)):
            raise InputError("ramp", f"{self.name}: start and stop must be finite numbers")
        if not (math.isfinite(self.rate) and self.rate > 0):
            raise InputError("ramp", f"{self.name}: rate must be a positive number (units per second)")
        if self.start == self.stop:
            raise InputError("ramp", f"{self.name}: start and stop must differ")
        if self.duration > MAX_SWEEP_SECONDS:
            raise InputError("ramp", f"{self.name}: at {self.rate:g} per second the segment {self.start:g} -> "
                                     f"{self.stop:g} lasts {self.duration:.3g} s; at most {MAX_SWEEP_SECONDS:g} s "
                                     f"may be simulated: raise the rate")

    @property
    def duration(self) -> float:
        """Time the segment takes (s)."""
        return abs(self.stop - self.start) / self.rate

    @property
    def direction(self) -> int:
        """+1 for an increasing ramp, -1 for a decreasing one."""
        return 1 if self.stop > self.start else -1


#: What :func:`parse_ramps` reads: a :class:`Ramp`, a sequence of them or of ``(name, from, to, rate)`` tuples, or a
#: mapping ``{name: (from, to, rate)}`` / ``{name: [(from, to, rate), ...]}``.
RampSpec: TypeAlias = (Ramp | Sequence[Ramp | tuple[str, float, float, float]]
                       | Mapping[str, Sequence[float] | Sequence[Sequence[float]]])


def _one_segment(spec: Sequence[float] | Sequence[Sequence[float]]) -> TypeIs[Sequence[float]]:
    """True for one segment ``(from, to, rate)`` of a ramp mapping's value, False for a sequence of them."""
    return not (len(spec) and isinstance(spec[0], (tuple, list)))


def parse_ramps(ramp: RampSpec) -> tuple[Ramp, ...]:
    """Normalise a ramp description to a tuple of :class:`Ramp`.

    Accepts a :class:`Ramp`, a sequence of ``Ramp`` or ``(name, from, to, rate)`` tuples, or a
    mapping ``{name: (from, to, rate)}`` / ``{name: [(from, to, rate), ...]}`` (segments in
    order).
    """
    out: list[Ramp] = []
    if isinstance(ramp, Ramp):
        return (ramp,)
    if isinstance(ramp, Mapping):
        for name, spec in ramp.items():
            segs = [spec] if _one_segment(spec) else spec
            for seg in segs:
                if len(seg) != 3:
                    raise InputError("ramp", f"{name}: give (from, to, rate)")
                out.append(Ramp(name, float(seg[0]), float(seg[1]), float(seg[2])))
    elif isinstance(ramp, Sequence):
        for item in ramp:
            if isinstance(item, Ramp):
                out.append(item)
            elif len(item) == 4:
                out.append(Ramp(str(item[0]), float(item[1]), float(item[2]), float(item[3])))
            else:
                raise InputError("ramp", "give Ramp objects or (name, from, to, rate) tuples")
    if not out:
        raise InputError("ramp", "at least one segment (name, from, to, rate) is needed")
    return tuple(out)


def _schedule(ramps: Sequence[Ramp], settle: float) -> tuple[np.ndarray, dict[str, Callable[[float], float]]]:
    """Segment time windows and a piecewise-linear load function per ramped parameter."""
    times, t = [], settle
    for r in ramps:
        times.append((t, t + r.duration))
        t += r.duration
    loads: dict[str, Callable[[float], float]] = {}
    for name in dict.fromkeys(r.name for r in ramps):
        segs = tuple((a, b, r.start, r.stop) for (a, b), r in zip(times, ramps) if r.name == name)
        loads[name] = _piecewise(segs)
    return np.array(times, float).reshape(-1, 2), loads


def _piecewise(segs: Sequence[tuple[float, float, float, float]]) -> Callable[[float], float]:
    """Load function: linear within each segment, held between and after them."""
    def value(t: float) -> float:
        v = segs[0][2]
        for a, b, v0, v1 in segs:
            if t < a:
                return v
            if t <= b:
                return v0 + (t - a) * (v1 - v0) / (b - a)
            v = v1
        return v
    return value
