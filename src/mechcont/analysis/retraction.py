"""Retraction of a one-degree-of-freedom mechanism: actuator load, stroke and efficiency along a branch.

Along a continuation branch in a driving coordinate ``s`` (e.g. the retraction angle) every
point's position is a function of ``s``; its rate ``dx/ds`` is the branch tangent, computed
exactly from the Jacobian (``G_u du/ds = -G_s``). With a potential ``V`` of the loads
(gravity) and an actuator of length ``l``, virtual work gives the actuator load that holds the
mechanism in quasi-static equilibrium:

    T = -(dV/ds) / (dl/ds)      (N, positive in tension: pulling its ends together).

The mechanical efficiency of the retraction is the work the actuator does over its stroke
divided by the work of an actuator giving its peak load over the whole stroke:

    eta = |integral of T dl| / (max |T| * |l_end - l_start|),

1 for a constant load, smaller the more peaked the load is.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..equations import Model, branch_rates  # re-exported here, where it is used most
from ..errors import InputError

if TYPE_CHECKING:
    from ..continuation import Branch

__all__ = ["branch_rates", "ActuatorLoads", "actuator_loads", "first_fold"]


@dataclass(frozen=True)
class ActuatorLoads:
    """Actuator load along a branch (one entry per branch point used).

    Attributes
    ----------
    s:
        The driving coordinate (e.g. the retraction angle, rad).
    length:
        Actuator length (m).
    tension:
        Actuator load (N), positive in tension.
    efficiency:
        Mechanical efficiency over the whole stroke (see the module docstring), 0..1.
    """

    s: np.ndarray
    length: np.ndarray
    tension: np.ndarray
    efficiency: float

    @property
    def work(self) -> float:
        """Work the actuator does on the mechanism over the stroke (J): -integral of T dl."""
        return float(-np.trapezoid(self.tension, self.length))

    @property
    def peak(self) -> float:
        """Largest |T| (N)."""
        return float(np.max(np.abs(self.tension)))


def actuator_loads(system: Model, rows: np.ndarray, vary: str,
                   potential_rate: Callable[[np.ndarray, np.ndarray], float],
                   length_and_rate: Callable[[np.ndarray, np.ndarray], tuple[float, float]]) -> ActuatorLoads:
    """Actuator load, length and efficiency along branch ``rows`` by virtual work.

    Parameters
    ----------
    system:
        The model of the branch.
    rows:
        Branch points (full vectors), ordered along the branch and free of folds.
    vary:
        The driving coordinate of the branch.
    potential_rate:
        ``(x, dx) -> dV`` (J per unit of ``vary``): rate of the load potential for the rate ``dx``.
    length_and_rate:
        ``(x, dx) -> (l, dl)``: actuator length (m) and its rate (m per unit of ``vary``).

    Returns
    -------
    ActuatorLoads
    """
    rows = np.atleast_2d(np.asarray(rows, float))
    rows_s: list[float] = []
    rows_length: list[float] = []
    rows_tension: list[float] = []
    for x in rows:
        dx = branch_rates(system, x, vary)
        dv = potential_rate(x, dx)
        ell, dl = length_and_rate(x, dx)
        if abs(dl) < 1e-12:
            raise InputError("actuator", f"its length does not change at {vary} = {x[system.index(vary)]:.6g}: "
                                         "it cannot drive the mechanism there")
        rows_s.append(float(x[system.index(vary)]))
        rows_length.append(ell)
        rows_tension.append(-dv / dl)
    s, length, tension = np.asarray(rows_s), np.asarray(rows_length), np.asarray(rows_tension)
    stroke = abs(length[-1] - length[0])
    peak = float(np.max(np.abs(tension)))
    eff = abs(float(np.trapezoid(tension, length))) / (peak * stroke) if peak > 0 and stroke > 0 else float("nan")
    return ActuatorLoads(s, length, tension, eff)


def first_fold(branch: Branch, vary: str) -> float | None:
    """Value of ``vary`` at the first fold (``LP``) of ``branch`` met from its start, else ``None``.

    A fold of a kinematic branch in its driving coordinate is a lock-up: the mechanism cannot
    follow the driver past it.
    """
    for p in branch.special_points:
        if p.label.rstrip("0123456789?") == "LP":
            return float(p.x[list(branch.names).index(vary)])
    return None
