"""Peaks located on the integrator's dense output, not sampled at the saved rows.

A simulation keeps, per accepted step, the integrator's interpolant of ``(q, qdot)`` over the step
(:class:`DenseHistory`, ``SimulationResult.dense``). The largest value of a quantity of the state (a
damper's tension, a stop's reaction, a speed) is then found where it is, not at the nearest saved
row: the rows pick the steps around their largest values, each step is scanned at a few points and
the best is polished by successive parabolic interpolation (safeguarded by bisection, as in Brent's
method) to a small fraction of the step. A quantity whose largest value falls at the end of a step (at an impact
the velocities jump) is found there: the ends of a step are among the points scanned.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np

from ._reactions import fill_conditions, fill_reactions

if TYPE_CHECKING:
    from ..equations import Model
    from ._result import SimulationResult
    from ._udwadia_kalaba import ConstrainedDynamics

__all__ = ["Peak", "DenseHistory", "locate_peak", "locate_peaks"]

#: Points per step scanned before the bounded search (ends included), and how many of the rows' largest
#: values (separate local maxima) have their neighbouring steps searched.
_SCAN, _CANDIDATES = 5, 3
#: Most parabolic steps in a step's search (it converges superlinearly: a handful reach 1e-7 of the step).
_ITERATIONS = 40


@dataclass(frozen=True)
class Peak:
    """The largest value of a quantity over a simulation (its unit) and when it occurs (s)."""

    value: float
    time: float


class DenseHistory:
    """The integrator's dense output of a simulation: per accepted step ``(t_start, t_end, interpolant of
    (q, qdot), the stops in contact)``; at a stop event one step ends and the next starts at the same time
    (an impact's velocity jump between them). Several simulations in sequence (a sweep's phases) are
    :meth:`joined`: each step keeps the dynamics it was integrated with."""

    def __init__(self, system: Model | None, dyn: ConstrainedDynamics | None,
                 segments: Iterable[tuple[float, float, Any, tuple[int, ...]]]) -> None:
        self.segments = list(segments)
        # (None, None: the empty history :meth:`joined` starts from)
        self._parts: list[tuple[Model, ConstrainedDynamics]] = [] if system is None or dyn is None else [(system, dyn)]
        self._part = [0] * len(self.segments)
        self._ends = [s[1] for s in self.segments]

    @classmethod
    def joined(cls, histories: Iterable[DenseHistory]) -> DenseHistory:
        """One dense output of consecutive simulations' (``histories`` in time order)."""
        out = cls(None, None, [])
        out._parts = []
        for h in histories:
            out._part += [len(out._parts) + i for i in h._part]
            out._parts += h._parts
            out.segments += h.segments
        out._ends = [s[1] for s in out.segments]
        return out

    def __len__(self) -> int:
        return len(self.segments)

    def segment_at(self, t: float) -> int:
        """Index of the first step whose interval contains ``t`` (the one before an event at ``t``)."""
        k = bisect.bisect_left(self._ends, t)
        return min(k, len(self.segments) - 1)

    def state(self, t: float, segment: int | None = None) -> np.ndarray:
        """``(q, qdot)`` at ``t`` (s) on step ``segment`` (default :meth:`segment_at`)."""
        k = self.segment_at(t) if segment is None else segment
        return np.asarray(self.segments[k][2](t), float)

    def row(self, t: float, segment: int | None = None, full: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """``(full variable vector, qdot)`` at ``t`` as a history row has them: coordinates, parameters, the
        description's conditions and the live reactions of the joints and, with stops simulated, of the stops
        (``full=False``: only the coordinates and parameters)."""
        k = self.segment_at(t) if segment is None else segment
        y = self.state(t, k)
        system, dyn = self._parts[self._part[k]]
        nq = dyn.nq
        values = np.array(dyn.full_of(t, y), float).reshape(1, -1)
        if not full:
            return values[0], y[nq:2 * nq]
        fill_conditions(system, values)
        contacts = dyn.contacts
        active = [] if contacts is None else list(contacts.active)
        fill_reactions(system, dyn, np.array([t]), y.reshape(1, -1), values, [self.segments[k][3]])
        if contacts is not None:
            contacts.active = active
        return values[0], y[nq:2 * nq]


def locate_peak(result: SimulationResult, quantity: Callable[[np.ndarray, np.ndarray], float], *, rows: np.ndarray | None = None,
                full: bool = True) -> Peak:
    """The largest value of ``quantity(x, qdot)`` (``x`` a full row of ``result``, its unit) over ``result``,
    located on its dense output, and the time (s) where it occurs (:func:`locate_peaks` for one quantity)."""
    return locate_peaks(result, lambda x, qd: [quantity(x, qd)], rows=None if rows is None else np.reshape(rows, (-1, 1)),
                        full=full)[0]


def locate_peaks(result: SimulationResult, quantities: Callable[[np.ndarray, np.ndarray], Sequence[float]], *,
                 rows: np.ndarray | None = None, full: bool = True) -> list[Peak]:
    """The largest value of each of ``quantities(x, qdot)`` (m values of a full row ``x`` of ``result``, their
    units) over ``result``, located on its dense output, with the time (s) of each; the evaluations at the
    points scanned are shared. ``rows``: the quantities at the saved rows (N x m) when already computed;
    ``full=False`` when they read only coordinates and parameters (the rows between are not completed). A
    result without a dense output, or a quantity constant over the rows, gives the largest row's value and
    time. The time is searched to ``1e-7`` of a step (the value, at a smooth maximum, then far better)."""
    v = np.array([quantities(x, qd) for x, qd in zip(result.values, result.qdot)], float) if rows is None \
        else np.asarray(rows, float)
    if not v.size:
        raise ValueError("an empty history has no peak")
    v = v.reshape(len(result.t), -1)
    dense: DenseHistory | None = getattr(result, "dense", None)
    cache: dict[tuple[int, float], np.ndarray] = {}

    def at(k: int, tt: float) -> np.ndarray:
        if (k, tt) not in cache:
            assert dense is not None  # called only with a dense output
            x, qd = dense.row(tt, k, full)
            values = np.asarray(quantities(x, qd), float)
            cache[(k, tt)] = np.where(np.isfinite(values), values, -math.inf)
        return cache[(k, tt)]

    out = []
    for m in range(v.shape[1]):
        column = v[:, m]
        i_best = int(np.argmax(column))
        best = Peak(float(column[i_best]), float(result.t[i_best]))
        if dense and column.min() < column.max():
            for k in _candidate_steps(result.t, column, dense):
                found = _on_step(dense, k, partial(_component, at, k, m))
                if found.value > best.value:
                    best = found
        out.append(best)
    return out


def _component(at: Callable[[int, float], np.ndarray], k: int, m: int, tt: float) -> float:
    """Quantity ``m`` at time ``tt`` on step ``k``."""
    return float(at(k, tt)[m])


def _candidate_steps(t: np.ndarray, v: np.ndarray, dense: DenseHistory) -> list[int]:
    """The steps about the rows' largest local maxima (at most :data:`_CANDIDATES`, those in the top quarter of
    the range): between the rows on either side of each."""
    n, top, bottom = len(v), float(v.max()), float(v.min())
    maxima = [i for i in range(n) if (i == 0 or v[i] >= v[i - 1]) and (i == n - 1 or v[i] > v[i + 1])]
    maxima = sorted((i for i in maxima if v[i] >= top - 0.25 * (top - bottom)), key=lambda i: -v[i])[:_CANDIDATES]
    steps: list[int] = []
    for i in maxima or [int(np.argmax(v))]:
        lo, hi = t[max(i - 1, 0)], t[min(i + 1, n - 1)]
        steps += [k for k, (a, b, *_) in enumerate(dense.segments) if b >= lo and a <= hi and b > a and k not in steps]
    return steps


def _on_step(dense: DenseHistory, k: int, g: Callable[[float], float]) -> Peak:
    """The largest value of ``g(t)`` on step ``k``: a scan of :data:`_SCAN` points (its ends included), then, when
    the best is inside, successive parabolic interpolation (safeguarded by bisection) on the three points about
    it until the bracket is ``1e-7`` of the step. A best at an end of the step is the step's largest value there
    (the next step, also scanned, has the peak if the quantity still rises)."""
    a, b = dense.segments[k][:2]
    ts = [float(tt) for tt in np.linspace(a, b, _SCAN)]
    gs = [g(tt) for tt in ts]
    j = int(np.argmax(gs))
    if j in (0, _SCAN - 1):  # a maximum between the end and its neighbour shows in the parabola of the last three
        e, n = (0, 1) if j == 0 else (_SCAN - 1, _SCAN - 2)
        x = _vertex(*ts[n - 1:n + 2], *gs[n - 1:n + 2]) if j else _vertex(*ts[0:3], *gs[0:3])
        if not (min(ts[e], ts[n]) < x < max(ts[e], ts[n])):
            return Peak(gs[j], ts[j])
        fx = g(x)
        if not fx > gs[j]:
            return Peak(gs[j], ts[j])
        (x0, f0), (x2, f2) = sorted([(ts[e], gs[e]), (ts[n], gs[n])])
        x1, f1 = x, fx
    else:
        (x0, x1, x2), (f0, f1, f2) = ts[j - 1:j + 2], gs[j - 1:j + 2]
    tol = 1e-7 * (b - a)
    for _ in range(_ITERATIONS):
        if x2 - x0 <= tol:
            break
        x = _vertex(x0, x1, x2, f0, f1, f2)
        if not (x0 < x < x2) or abs(x - x1) < 0.5 * tol:  # no usable vertex: bisect the larger side
            x = 0.5 * (x0 + x1) if x1 - x0 > x2 - x1 else 0.5 * (x1 + x2)
        fx = g(x)
        if fx >= f1:  # the new best: the bracket closes on it
            (x0, f0, x2, f2) = (x0, f0, x1, f1) if x < x1 else (x1, f1, x2, f2)
            x1, f1 = x, fx
        elif x < x1:
            x0, f0 = x, fx
        else:
            x2, f2 = x, fx
    return Peak(f1, x1)


def _vertex(x0: float, x1: float, x2: float, f0: float, f1: float, f2: float) -> float:
    """The abscissa of the vertex of the parabola through three points (nan when they are on a line)."""
    d = (x1 - x0) * (f1 - f2) - (x1 - x2) * (f1 - f0)
    return x1 - 0.5 * ((x1 - x0) ** 2 * (f1 - f2) - (x1 - x2) ** 2 * (f1 - f0)) / d if d != 0 else math.nan
