"""A time integration bounded before it hangs: a step budget, and the stiff element named when it runs out.

An explicit Runge–Kutta method on a stiff mechanism (a damper of 1e12 N s/m, a mass of 1e-300 kg, a
mass-proportional damping of 1e308 1/s) takes steps set by its fastest time scale, however slow the motion:
it would run for hours. :class:`StepBudget` projects, every :data:`CHECK_EVERY` accepted steps, the steps to
the end at the recent step size, and ends the run when that exceeds the budget and the step is held by
stability, or exceeds it for :data:`PATIENCE` checks in a row, or the steps taken reach it; :func:`stiffest` names the
parameter (or the ``damping`` option) that sets that time scale, found by how much the fastest rate of the
linearised equations of motion falls when it is reduced.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..equations import Model
    from ._udwadia_kalaba import ConstrainedDynamics

__all__ = ["StepBudget", "stiffest", "MAX_STEPS", "CHECK_EVERY"]

#: Most integrator steps a run may take unless raised (``max_steps``): about a quarter of an hour of RK45 on a
#: small mechanism.
MAX_STEPS = 1_000_000
#: How often (accepted steps) the projection is made.
CHECK_EVERY = 200
#: Consecutive checks over the budget that end a run whose step is held by accuracy (not stiff): its step did not
#: grow enough in CHECK_EVERY * PATIENCE steps to bring the projection back under the budget.
PATIENCE = 5


class StepBudget:
    """Counts accepted steps from ``t0`` towards ``t1``; :meth:`exceeded` says when the steps so far plus those
    still needed at the recent step size would pass ``max_steps``."""

    def __init__(self, t0: float, t1: float, max_steps: int = MAX_STEPS):
        self.t1, self.max_steps = float(t1), int(max_steps)
        self.n, self.t_mark, self.n_mark = 0, float(t0), 0
        self.h = math.nan
        self.over = 0  # consecutive checks whose projection passed the budget

    def exceeded(self, t: float, dyn: ConstrainedDynamics, y: np.ndarray) -> bool:
        """Count one accepted step ending at ``(t, y)`` (s, state); True when the steps themselves reach the budget,
        or the projection passes it and either the step is held by stability (the step times the fastest rate of
        the linearised equations above 1: a stiff mode, which an explicit method never outgrows) or it has passed
        it at :data:`PATIENCE` checks in a row (a step held by accuracy grows as the motion dies out, so one
        projection alone ends nothing: a gear coming to rest is given the time to)."""
        self.n += 1
        if self.n >= self.max_steps:
            self.h = (t - self.t_mark) / max(self.n - self.n_mark, 1)
            return True
        if self.n - self.n_mark < CHECK_EVERY:
            return False
        self.h = (t - self.t_mark) / (self.n - self.n_mark)
        self.t_mark, self.n_mark = t, self.n
        if not self.h > 0:
            return True
        if self.n + (self.t1 - t) / self.h <= self.max_steps:
            self.over = 0
            return False
        self.over += 1
        return self.over >= PATIENCE or self.h * _fastest_rate(dyn, t, y) > 1.0

    def projected(self, t: float) -> float:
        """Steps the run would take in all at the recent step size."""
        return self.n + (self.t1 - t) / self.h if self.h > 0 else math.inf


def _fastest_rate(dyn: ConstrainedDynamics, t: float, y: np.ndarray) -> float:
    """Largest |eigenvalue| (1/s) of the linearised state equations at ``(t, y)`` (central differences)."""
    n = len(y)
    J = np.empty((n, n))
    with np.errstate(all="ignore"):
        for j in range(n):
            h = 1e-7 * max(1.0, abs(y[j]))
            e = np.zeros(n)
            e[j] = h
            J[:, j] = (np.asarray(dyn(t, y + e)) - np.asarray(dyn(t, y - e))) / (2 * h)
    if not np.all(np.isfinite(J)):
        return math.inf
    return float(np.max(np.abs(np.linalg.eigvals(J)), initial=0.0))


def stiffest(system: Model, dyn: ConstrainedDynamics, t: float, y: np.ndarray) -> str:
    """What sets the fastest time scale at ``(t, y)``: ``"the damping option (D 1/s)"`` when its rate dominates,
    else the parameters (up to four) whose change by a factor 1e3 either way lowers the fastest rate most (a
    damper's ``c`` made smaller, a mass made larger: ``"c = 1e+12 N s/m, m = 10 kg"``), with the rate. Returns a
    phrase for a message."""
    from ._udwadia_kalaba import ConstrainedDynamics

    rate = _fastest_rate(dyn, t, y)
    if dyn.damping and (not math.isfinite(dyn.damping) or dyn.damping >= 0.5 * rate or not math.isfinite(rate)):
        return f"the damping option ({dyn.damping:g} 1/s)"
    changes: list[tuple[float, str]] = []
    x = dyn.x
    for i, v in enumerate(system.variables):
        if v.kind != "parameter" or not (math.isfinite(x[i]) and x[i] != 0) or not (math.isfinite(rate) and rate > 0):
            continue
        if v.unit in ("rad", "1", ""):  # an angle or a ratio is not a size: a factor 1e3 says nothing
            continue
        drops = []
        for factor in (1e-3, 1e3):  # a damper or spring sets the rate by its size, a mass by its smallness
            xm = np.array(x, float)
            xm[i] = x[i] * factor
            try:
                other = ConstrainedDynamics(system, xm, baumgarte=(dyn.alpha, dyn.beta), damping=dyn.damping)
                other.contacts = dyn.contacts
                r = _fastest_rate(other, t, y)
            except Exception:  # noqa: BLE001 - a parameter whose change breaks the model says nothing here
                continue
            if math.isfinite(r) and r > 0:
                drops.append(math.log(rate / r))
        if drops and max(drops) > 0:
            changes.append((max(drops), f"{v.name} = {x[i]:g} {v.unit}".rstrip()))
    changes.sort(reverse=True)
    # the parameters that set it (rate ~ c / m: a damper and the mass it moves share the blame; a mass under an
    # airload, rate ~ U / sqrt(m) plus the load's own mass-free part, has a little under half the speed's share,
    # about as much as the air's density and the load's size: four names, else which three is decided by rounding)
    best = ", ".join(name for c, name in changes[:4] if c >= 0.4 * changes[0][0]) if changes else ""
    rate_text = f"fastest rate {rate:.3g} 1/s" if math.isfinite(rate) else "rates beyond the floats"
    return f"{best} ({rate_text})" if best else rate_text
