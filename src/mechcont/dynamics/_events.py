"""Events during a simulation: a named quantity crossing a value, or any callable."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._roots import brentq
from ..equations import StopLimit, velocity_coordinate
from ..errors import InputError

if TYPE_CHECKING:
    from scipy.integrate import DenseOutput

    from ..equations import Model
    from ._contact import StopConstraints
    from ._udwadia_kalaba import ConstrainedDynamics

__all__ = ["Crossing", "EventTracker", "AtRestOnStops", "ConditionCrossing", "LOCK_GAP"]

#: A lock stop counts as on its limit within this gap (condition units) for the end of a run at the lock: far
#: below any gap a free stop has at rest, far above the contact's drift.
LOCK_GAP = 1e-6

#: ``g(t, x, qdot) -> value``: an event's function of the time (s), the full variable vector and the coordinate rates.
EventCallable = Callable[[float, np.ndarray, np.ndarray], float]


@dataclass(frozen=True)
class Crossing:
    """The event "column ``name`` passes through ``value``".

    Parameters
    ----------
    name:
        A variable name of the model (e.g. ``"theta1"``), or ``"<coordinate>_dot"``.
    value:
        The level (units of that variable).
    direction:
        +1: only upward crossings; -1: only downward; 0: both.
    terminal:
        Stop the simulation at the first such crossing.
    """

    name: str
    value: float = 0.0
    direction: int = 0
    terminal: bool = False

    def __post_init__(self) -> None:
        if self.direction not in (-1, 0, 1):
            raise InputError("direction", "must be -1, 0 or +1")


#: An event of :func:`~mechcont.dynamics.simulate`: a :class:`Crossing` or a callable ``g(t, x, qdot)`` (optional
#: attributes ``terminal``, ``direction``, method ``bind(dyn)``).
EventFunction = Crossing | EventCallable


def _level(i: int, value: float, rates: bool) -> EventCallable:
    """``g(t, x, qdot)``: entry ``i`` of ``qdot`` (``rates``) or of ``x``, less ``value``."""
    if rates:
        return lambda t, x, qd: qd[i] - value
    return lambda t, x, qd: x[i] - value


class EventTracker:
    """Evaluates events at each accepted step and locates sign changes on the dense output.

    Each event is a :class:`Crossing` or a callable ``g(t, x, qdot) -> float`` (``x`` the full
    variable vector) with optional attributes ``terminal`` and ``direction`` like SciPy's, and an
    optional method ``bind(dyn)``, called with the dynamics at the start (an event that needs the
    stops in contact reads ``dyn.contacts``).
    """

    def __init__(self, events: Sequence[EventFunction] | None, system: Model, coordinates: Sequence[str]) -> None:
        self._fns: list[EventCallable] = []
        self.terminal: list[bool] = []
        self.direction: list[int] = []
        nq = len(coordinates)
        for ev in events or ():
            if isinstance(ev, Crossing):
                if ev.name in system.names:
                    i = system.index(ev.name)
                    fn = _level(i, ev.value, rates=False)
                elif (c := velocity_coordinate(ev.name, coordinates)) is not None:
                    j = list(coordinates).index(c)
                    fn = _level(j, ev.value, rates=True)
                else:
                    raise InputError(ev.name, "event quantity is not a variable or <coordinate>_dot of the model")
                self._fns.append(fn)
                self.terminal.append(ev.terminal)
                self.direction.append(ev.direction)
            elif callable(ev):
                self._fns.append(ev)
                self.terminal.append(bool(getattr(ev, "terminal", False)))
                self.direction.append(int(np.sign(getattr(ev, "direction", 0))))
            else:
                raise InputError("events", "each event must be a Crossing or a callable g(t, x, qdot)")
        self.nq = nq
        self.n_names = len(system.names)
        self.t_events: list[list[float]] = [[] for _ in self._fns]
        self.x_events: list[list[np.ndarray]] = [[] for _ in self._fns]
        self._last: np.ndarray | None = None  # the event values at the last accepted state (start() sets them)

    def __bool__(self) -> bool:
        return bool(self._fns)

    def _values(self, dyn: ConstrainedDynamics, t: float, y: np.ndarray) -> np.ndarray:
        x = dyn.full_of(t, y)
        qd = y[self.nq:2 * self.nq]
        return np.array([fn(t, x, qd) for fn in self._fns], float)

    def start(self, dyn: ConstrainedDynamics, t: float, y: np.ndarray) -> None:
        """Record the event values at the initial state."""
        for fn in self._fns:
            bind = getattr(fn, "bind", None)
            if bind is not None:
                bind(dyn)
        if self._fns:
            self._last = self._values(dyn, t, y)

    def step(self, dyn: ConstrainedDynamics, t_old: float, t_new: float, y_new: np.ndarray,
             sol: DenseOutput) -> float | None:
        """Check the step ``[t_old, t_new]``; returns the terminal time if one fired, else None."""
        if not self._fns:
            return None
        g_new = self._values(dyn, t_new, y_new)
        g_old, self._last = self._last, g_new
        assert g_old is not None, "EventTracker.start() first"
        t_stop = None
        for k, (a, b) in enumerate(zip(g_old, g_new)):
            up, down = a < 0 <= b, a > 0 >= b
            if not ((up and self.direction[k] >= 0) or (down and self.direction[k] <= 0)):
                continue
            if b == 0:
                te = t_new
            else:
                def g(tt: float, k: int = k) -> float:
                    return self._values(dyn, tt, sol(tt))[k]
                te = brentq(g, t_old, t_new, xtol=1e-12 * max(1.0, abs(t_new)))
            self.t_events[k].append(te)
            self.x_events[k].append(dyn.full_of(te, sol(te)))
            if self.terminal[k]:
                t_stop = te if t_stop is None else min(t_stop, te)
        return t_stop

    def jump(self, dyn: ConstrainedDynamics, t: float, y: np.ndarray) -> float | None:
        """Restart after a velocity jump at ``t`` (an impact) to the state ``y``: an event whose value the jump
        carried across zero (in its direction) occurs at ``t``. Returns ``t`` if a terminal one did, else None."""
        if not self._fns:
            return None
        before, after = self._last, self._values(dyn, t, y)
        assert before is not None, "EventTracker.start() first"
        self._last = after
        t_stop = None
        for k, (a, b) in enumerate(zip(before, after)):
            up, down = a < 0 <= b, a > 0 >= b
            if (up and self.direction[k] >= 0) or (down and self.direction[k] <= 0):
                self.t_events[k].append(t)
                self.x_events[k].append(dyn.full_of(t, y))
                t_stop = t if self.terminal[k] else t_stop
        return t_stop

    def results(self) -> tuple[list[np.ndarray], list[np.ndarray]]:
        """``(t_events, x_events)``: lists of arrays, one per event."""
        n = len(self._fns)
        return ([np.array(self.t_events[k]) for k in range(n)],
                [np.array(self.x_events[k], float).reshape(-1, self.n_names) for k in range(n)])


class AtRestOnStops:
    """Terminal event: every stop of ``stops`` in contact (a constraint of the simulation, or a compliant stop
    pressed) and on its limit (gap below :data:`LOCK_GAP`), and every coordinate speed below ``rest_speed``:
    ``max(max |qdot| - rest_speed, max gap - LOCK_GAP)`` falls through 0 (1 while a stop is out of contact:
    a plastic impact whose reaction would pull stops the gear on the stop for an instant, then it leaves)."""

    terminal, direction = True, -1

    def __init__(self, model: Model, stops: Sequence[StopLimit], rest_speed: float) -> None:
        rows = list(model.equation_names)
        self.names = [s.name for s in stops]
        self.contacts: StopConstraints | None = None
        self.model, self.rest_speed = model, rest_speed
        self.rows = np.array([rows.index(f"cond_{s.condition}") for s in stops])
        self.index = np.array([model.index(s.condition) for s in stops])
        self.side = np.array([float(s.side) for s in stops])
        self.limit = np.array([float(s.limit) for s in stops])

    def bind(self, dyn: ConstrainedDynamics) -> None:
        """Read the stops in contact from the simulation's ``dyn.contacts``."""
        self.contacts = dyn.contacts
        if self.contacts is not None:
            self.stop_index = [self.contacts.names.index(n) for n in self.names]

    def __call__(self, t: float, x: np.ndarray, qd: np.ndarray) -> float:
        c = self.contacts
        if c is not None and not all(k in c.active or k in c.pressed for k in self.stop_index):
            return 1.0
        speed = float(np.max(np.abs(qd), initial=0.0)) - self.rest_speed
        if speed > 0:  # moving: the gaps need not be computed
            return speed
        y = np.array(x, float)
        y[self.index] = 0.0
        gaps = self.side * (self.model.residual(y)[self.rows] - self.limit)
        return max(speed, float(np.max(gaps)) - LOCK_GAP)


class ConditionCrossing:
    """Terminal event: a description's condition (evaluated from the coordinates; the simulation
    fills the condition columns only afterwards) passes ``value`` in ``direction``."""

    terminal = True

    def __init__(self, model: Model, name: str, value: float, direction: int) -> None:
        self.model, self.value, self.direction = model, value, direction
        self.row = list(model.equation_names).index(f"cond_{name}")
        self.index = model.index(name)

    def __call__(self, t: float, x: np.ndarray, qd: np.ndarray) -> float:
        y = np.array(x, float)
        y[self.index] = 0.0
        return float(self.model.residual(y)[self.row]) - self.value
