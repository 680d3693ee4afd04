"""The shimmy section's computations: the Hopf point in speed, the Hopf curves, the cycles, the simulations.

Everything here is the continuation answer and its independent checks; the figures and the summary
paragraph are :mod:`._shimmy_figures`. Speeds in m/s, angles in rad, damper rates in N m s/rad.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ._shimmy_gear import SPEEDS, gear_at, leading_eigenvalue

if TYPE_CHECKING:
    from ..continuation import Branch, ContinuationOptions, CycleBranch, SpecialPoint
    from ..equations import Model
    from ..mechanism import Mechanism

__all__ = ["CHART", "SIM_SPEEDS", "TORSION", "equilibria", "hopf_curve", "curve_check", "shimmy_cycles",
           "simulate_onto", "CycleSimulation"]

#: The second parameter of each stability chart and its range (SI): damper rate (N m s/rad), caster (m).
CHART = {"c_psi": (0.0, 100.0), "e": (0.0, 0.5)}
#: The speeds (m/s) of the two time simulations that should land on the computed cycles.
SIM_SPEEDS = (40.0, 60.0)
#: The torsion angle about the strut (the wheel's heading, rad): the amplitude shown.
TORSION = "theta_wheel"
#: The simulations' last seconds (s) kept as samples: at least eight periods of the cycles (about 19 ms at 60
#: m/s, 25 ms at 40 m/s), of which the last four give the amplitude, the period and the remaining transient.
WINDOW = 0.2
#: Typical sizes that set the steps (the speed's own scale is 1 m/s: hundreds of steps to 100 m/s).
_SCALES = {"V": 10.0, "c_psi": 10.0, "e": 0.05}


def _options(**bounds: tuple[float, float]) -> ContinuationOptions:
    from ..continuation import ContinuationOptions

    return ContinuationOptions(ds=0.1, dsmax=1.0, bounds=bounds, scales=_SCALES)


def equilibria(model: Model, x: np.ndarray) -> Branch:
    """Straight running continued in the speed ``V`` over :data:`SPEEDS` from the equilibrium ``x``, with
    Hopf points (``HB``) located: a :class:`~mechcont.continuation.Branch`."""
    from ..continuation import continuation

    return continuation(model, x, "V", options=_options(V=SPEEDS), hopf=True)


def hopf_curve(model: Model, hopf: SpecialPoint, parameter: str) -> Branch:
    """The Hopf curve through the point ``hopf`` (labelled ``HB`` in ``V``) in (``V``, ``parameter``),
    both ways, bounded by :data:`SPEEDS` and :data:`CHART`: a Branch with ``omega``, ``l1`` and the stable side."""
    from ..continuation import continue_hopf

    return continue_hopf(model, hopf, "V", parameter, options=_options(V=SPEEDS, **{parameter: CHART[parameter]}))


def curve_check(model: Model, curve: Branch, parameter: str, mech: Mechanism[Any, Any] | None = None) -> float:
    """The largest ``|Re lambda| / |Im lambda|`` of the leading eigenvalue, computed afresh (one
    linearisation of the gear built at the point's speed and ``parameter``) at each point of the Hopf
    ``curve``: 0 on an exact Hopf curve, about the Newton tolerance in practice."""
    worst = 0.0
    for x in curve.values:
        lam = leading_eigenvalue(float(x[model.index("V")]), mech, **{parameter: float(x[model.index(parameter)])})
        worst = max(worst, abs(lam.real) / max(abs(lam.imag), 1e-300))
    return worst


def shimmy_cycles(model: Model, hopf: SpecialPoint, at: Sequence[float] = SIM_SPEEDS) -> CycleBranch:
    """The limit cycles born at the Hopf point ``hopf`` (a Branch row labelled ``HB``), continued in ``V``
    up to :data:`SPEEDS`'s end, rows located at the speeds ``at``: a
    :class:`~mechcont.continuation.CycleBranch` (Floquet multipliers, stability per row)."""
    from ..continuation import ContinuationOptions, cycles_from_hopf

    options = ContinuationOptions(ds=0.1, dsmax=20.0, max_steps=80, bounds={"V": SPEEDS}, scales={"V": 10.0})
    return cycles_from_hopf(model, hopf.x, "V", options=options, ntst=10, ncol=4, at=at)


@dataclass(frozen=True)
class CycleSimulation:
    """A time simulation of the gear from a small disturbance, read as a periodic motion at its end.

    ``speed`` (m/s), ``disturbance`` (rad, the initial torsion angle), ``until`` (s, simulated);
    ``amplitude`` (rad): the largest torsion angle over the last period; ``period`` (s): between the last
    two upward zero crossings of the torsion angle; ``remaining`` (rad): the transient still to decay,
    estimated from the last three crests as a geometric series (a motion approaching a stable cycle
    closes the gap by the leading Floquet multiplier each period); ``t``, ``torsion``: the samples over the last
    :data:`WINDOW` seconds (s, rad)."""

    speed: float
    disturbance: float
    until: float
    amplitude: float
    period: float
    remaining: float
    t: np.ndarray
    torsion: np.ndarray


def simulate_onto(speed: float, mech: Mechanism[Any, Any] | None = None, disturbance: float = 0.01, until: float = 2.0,
                  rtol: float = 1e-8, **values: float) -> CycleSimulation:
    """Integrate the gear's equations of motion (the model's minimal-coordinate rates,
    :func:`~mechcont.equations.dynamics_of`, DOP853 at ``rtol``) at ``speed`` (m/s) from straight running
    with the torsion angle set to ``disturbance`` (rad) for ``until`` seconds; the motion's amplitude and
    period at its end (:class:`CycleSimulation`). A growing motion has not settled: the caller compares."""
    from scipy.integrate import DOP853, OdeSolution

    from ..equations import dynamics_of
    from ..errors import ConvergenceError

    model, x = gear_at(speed, mech, **values)
    dyn = dynamics_of(model)
    z0 = np.array(dyn.state_at(x), float)
    k = dyn.state_names.index(TORSION)
    z0[k] = disturbance
    # solve_ivp's loop, with the interpolants (three more rates per step) built only over the last
    # WINDOW seconds, where the motion is read: the same steps, the same values there
    solver = DOP853(lambda _t, z: dyn.rates(z, x), 0.0, z0, until, rtol=rtol, atol=1e-10)
    start = until - min(WINDOW, until)
    ts: list[float] = []
    interpolants: list = []
    while solver.status == "running":
        message = solver.step()
        if solver.status == "failed":
            raise ConvergenceError(f"the time simulation at {speed:g} m/s failed: {message}")
        if solver.t > start:
            if not ts:
                ts.append(solver.t_old)
            ts.append(solver.t)
            interpolants.append(solver.dense_output())
    sol = OdeSolution(ts, interpolants)
    # sampled finely from the integrator's interpolant (about 200 samples per period of 19 ms)
    t = np.linspace(0.0, until, int(until * 1e4) + 1)
    t = t[t >= ts[0]]
    th = sol(t)[k]
    up = np.nonzero((th[:-1] < 0) & (th[1:] >= 0))[0]
    cross = t[up] - th[up] * (t[up + 1] - t[up]) / (th[up + 1] - th[up])
    period = float(cross[-1] - cross[-2])
    crests = [_crest(t, th, cross[j], cross[j + 1]) for j in range(len(cross) - 4, len(cross) - 1)]
    d1, d2 = crests[1] - crests[0], crests[2] - crests[1]
    ratio = min(abs(d2 / d1), 0.99) if d1 != 0 else 0.0
    remaining = abs(d2) * ratio / (1 - ratio)
    return CycleSimulation(speed, disturbance, until, crests[-1], period, remaining, t, th)


def _crest(t: np.ndarray, th: np.ndarray, t0: float, t1: float) -> float:
    """The largest sample of ``th`` between ``t0`` and ``t1``, polished by a parabola through it and its neighbours."""
    inside = np.flatnonzero((t >= t0) & (t <= t1))
    i = int(inside[np.argmax(th[inside])])
    a, b, c = th[i - 1], th[i], th[i + 1]
    return float(b + 0.125 * (a - c) ** 2 / (2 * b - a - c)) if 2 * b - a - c > 0 else float(b)
