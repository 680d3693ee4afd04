"""Where a freefall run that has nearly stopped is going, decided by statics.

A run that ends slow is *at rest* only where nothing more can happen: at a stable equilibrium it is
already at, with the static forces pointing back to it on the way (:func:`settled`). Near the ghost of a
fold (an airspeed just past the stall branch's fold) a gear creeps as slowly as it likes with no
equilibrium anywhere near: that run is still moving, its outcome undecided. A run that struck its lock
and left it may be bouncing back (:func:`lock_reactions`: the lock's static reaction at the locked pose is
positive, so the stop holds once the bounces decay) or may have left for good (it is negative).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..equations import StopLimit
from ..errors import ConvergenceError, InputError
from ._checks import check_simulable
from ._events import LOCK_GAP

if TYPE_CHECKING:
    from ..equations import Model
    from ._contact import StopConstraints
    from ._udwadia_kalaba import ConstrainedDynamics

__all__ = ["Settling", "settled", "lock_reactions"]

#: Points on the segment from the run's end to the equilibrium where the static force must point to it.
_SAMPLES = 33


class Settling:
    """The verdict of :func:`settled`: ``at_rest`` and, either way, ``why`` (one phrase with numbers)."""

    def __init__(self, at_rest: bool, why: str, distance: float = float("nan")) -> None:
        self.at_rest, self.why, self.distance = at_rest, why, distance


def settled(model: Model, x_end: np.ndarray, touching: Sequence[StopLimit]) -> Settling:
    """Whether the full vector ``x_end`` (a run's end, nearly at rest) lies at a stable equilibrium.

    The equilibrium is solved from ``x_end`` (Newton) with the stops ``touching`` held at their limits
    (their reactions solved for, which must push) and the other stops free (their reactions 0, their gaps
    kept open); it must be stable (:meth:`~mechcont.equations.MechanicalModel.stability`, the held stops'
    gradients held) and the static generalised force must point towards it all along the straight path
    from ``x_end`` (:data:`_SAMPLES` points): the run slides there and stays. Returns a :class:`Settling`
    whose ``distance`` is the largest coordinate change to that equilibrium (rad, m)."""
    from ..continuation import find_equilibrium

    mech = check_simulable(model, model.name)
    x = np.array(x_end, float)
    stops = list(model.stops)
    for s in stops:
        x[model.index(s.reaction)] = 0.0
    hold = {s.condition: float(s.limit) for s in touching}
    try:
        eq = find_equilibrium(model, hold=hold, free=[s.reaction for s in touching], guess=x, max_iter=30)
    except (ConvergenceError, InputError, np.linalg.LinAlgError):
        return Settling(False, "no equilibrium found near where it is")
    q = np.array([model.index(c) for c in mech.coordinates])
    dq = eq[q] - x[q]
    distance = float(np.max(np.abs(dq), initial=0.0))
    for s in stops:
        gap = s.side * (eq[model.index(s.condition)] - s.limit)
        if s in touching and eq[model.index(s.reaction)] <= 0:
            return Settling(False, f"its stop {s.name} would pull to hold it", distance)
        if s not in touching and gap < -1e-9 * max(1.0, abs(s.limit)):
            return Settling(False, f"the nearest equilibrium lies past stop {s.name}", distance)
    rows = np.array([list(model.equation_names).index(f"cond_{s.condition}") for s in touching], dtype=int)
    held = model.jacobian(eq)[np.ix_(rows, q)] if rows.size else None
    if mech.stability(eq, held=held).n_unstable:
        return Settling(False, f"the nearest equilibrium ({distance:.3g} away) is unstable", distance)
    for s in np.linspace(0.0, 1.0, _SAMPLES)[:-1]:
        y = x + s * (eq - x)
        Z = mech.allowed_motions(y)  # the force along the motions the joints allow: the joints' reactions drop out
        forces = mech.applied_forces(y)
        step = Z.T @ dq
        # pushed away from it somewhere on the way (beyond the forces' rounding): a barrier
        if float((Z.T @ forces) @ step) < -1e-12 * float(np.linalg.norm(forces) * np.linalg.norm(step)):
            return Settling(False, f"a barrier lies between it and the equilibrium {distance:.3g} away", distance)
    return Settling(True, f"at a stable equilibrium {distance:.3g} away", distance)


def lock_reactions(model: Model, stops: Sequence[StopLimit], x_end: np.ndarray) -> np.ndarray | None:
    """The static reactions (units of each ``R_NAME``) of the lock ``stops`` all held at their limits, solved
    from ``x_end``; None when that equilibrium cannot be found. Positive: the locked state exists, so a gear
    that struck the lock and bounced off comes back and its bounces decay onto it."""
    from ..continuation import find_equilibrium

    x = np.array(x_end, float)
    for s in model.stops:
        x[model.index(s.reaction)] = 0.0
    try:
        eq = find_equilibrium(model, hold={s.condition: float(s.limit) for s in stops},
                              free=[s.reaction for s in stops], guess=x, max_iter=30)
    except (ConvergenceError, InputError, np.linalg.LinAlgError):
        return None
    return np.array([eq[model.index(s.reaction)] for s in stops])


class SettledOffLock:
    """Terminal event of a freefall run: at rest short of its lock where nothing more can change.

    Once every coordinate speed is below ``rest_speed`` and no lock stop is in contact, :func:`settled` is asked
    (at times spaced geometrically, ``t``, then at least ``1.5 t`` on, so a long run at rest costs a few dozen
    static solves); when it says the run is at a stable equilibrium, within :data:`~._events.LOCK_GAP` of it
    in every coordinate, the event falls from +1 to -1 there. A
    freefall has no time-varying loads, so the rest of a long ``until`` would only repeat that state."""

    terminal, direction = True, -1

    def __init__(self, model: Model, lock_stops: Sequence[StopLimit], rest_speed: float) -> None:
        self.model, self.rest_speed = model, rest_speed
        self.lock = {s.name for s in lock_stops}
        self.contacts: StopConstraints | None = None
        self.t_settled: float | None = None
        self.next_check = 0.0

    def bind(self, dyn: ConstrainedDynamics) -> None:
        """Read the stops in contact from the simulation's ``dyn.contacts``."""
        self.contacts = dyn.contacts

    def __call__(self, t: float, x: np.ndarray, qd: np.ndarray) -> float:
        if self.t_settled is not None:
            return -1.0 if t >= self.t_settled else 1.0
        if t < self.next_check or float(np.max(np.abs(qd), initial=0.0)) > self.rest_speed:
            return 1.0
        c = self.contacts
        touching: list[StopLimit] = [c.stops[k] for k in c.active] if c is not None else []
        if any(s.name in self.lock for s in touching):
            return 1.0  # on the lock: the lock's own event decides
        self.next_check = 1.5 * t
        verdict = settled(self.model, np.asarray(x, float), touching)
        if verdict.at_rest and verdict.distance <= LOCK_GAP:  # as close to it as a lock to its stop
            self.t_settled = t
            return -1.0
        return 1.0
