"""Freefall extension of the paper's nose gear: released from the uplock, does it fall out and lock?

The shipped nose gear (``nose_gear.toml``, paper Fig. 6) is given, in code, what a freefall needs:
the retraction actuator as a hydraulic damper (airframe point ``R`` to the drag-stay lug of the main
fitting, ``c v + c2 v|v|``), an uplock stop on the main fitting's angle (retracted at
``theta_up``), and a downlock stop on the lock links' overcentre angle, ``over`` past aligned.
The gear retracts forward, so gravity and the eq. 12 drag both extend it; the lock spring must
pull the lock links over centre. Released at rest from the uplock at several airspeeds, the
outcome, time to lock, the lock links' impact speed, the peak actuator load and the downlock
reaction are tabulated; the quasi-static predictor (the equilibria the gear could hang in on its
way, with the airspeed solved for) says whether any airspeed can stall it.

The dual-sidestay gear's freefall from gear up (both lock-link pairs as its lock, against the aft
attachment stiffness and the lock-spring preload) is :mod:`.freefall_sidestay`.

Run times go to ``timings``, never into the summary, which is the same on every run.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from . import freefall_sidestay
from ._freefall_figures import nose_gear_figure
from ._timing import timed

if TYPE_CHECKING:
    from ..dynamics.freefall import CriticalAirspeed
    from ..equations import Model

__all__ = ["run", "description_text", "AIRSPEEDS", "PENDULUM"]

#: Airspeeds (m/s) of the freefall runs.
AIRSPEEDS = (0.0, 25.0, 50.0, 75.0, 100.0, 125.0)
#: Simulated time (s) per run, the retracted angle (rad) of the main fitting at the uplock.
UNTIL, THETA_UP = 2.5, 0.2
#: Bracket and tolerance (m/s) of the critical airspeed's bisection; the end (rad) of the travel
#: searched for intermediate equilibria (short of the lock links' kinematic fold at aligned).
CRITICAL, TOL, TRAVEL_END = (100.0, 125.0), 0.05, 1.3
#: The bisection bracket (m/s) about the quasi-static release (SR) of the lock, from SR - 0.77 to SR + 0.83:
#: not centred, so that no bisection point falls on SR itself, where the reaction at rest is zero; the longest
#: simulated time (s) of a bisection run (the gear locks within 1.3 s at every airspeed of the table; a run
#: that locks ends there, one that does not runs this long).
SR_BRACKET, CRITICAL_UNTIL = (-0.77, 0.83), 2.5

_PARAMETERS = '''c_ret = { value = 2000.0, unit = "N s/m", description = "retraction actuator, laminar term" }
c2_ret = { value = 5000.0, unit = "N s^2/m^2", description = "retraction actuator restrictor, quadratic term" }
theta_up = { value = 0.2, unit = "rad", description = "main fitting angle at the uplock (retracted)" }
over = { value = 0.035, unit = "rad", description = "lock links' stop past aligned" }

[ground]
R = [-0.3, 0.4]
'''

_ELEMENTS = '''
[dampers.retraction]
a = "ground.R"
b = "3.lug2"
c = "c_ret"
c2 = "c2_ret"

[conditions]
fitting = { type = "angle", bodies = ["ground", "3"] }
overcentre = { type = "angle", bodies = ["4", "5"] }

[stops.uplock]
condition = "fitting"
min = "theta_up"

[stops.downlock]
condition = "overcentre"
max = "over"
'''

#: The bodies' first guesses in the retracted pose (rad; from the kinematic path of the gear
#: driven from down to theta3 = 0.2), so that the assembly finds the retracted branch.
_RETRACTED = (('initial = { theta = -0.678 }', 'initial = { theta = 0.15 }'),
              ('initial = { theta = -1.075 }', 'initial = { theta = -2.42 }'),
              ('initial = { theta = 1.396 }', 'initial = { theta = 0.2 }'),
              ('points = { spring = ["-l_sp1", 0] }\ninitial = { theta = 0.0 }',
               'points = { spring = ["-l_sp1", 0] }\ninitial = { theta = -0.76 }'),
              ('mass = "m5"\ninitial = { theta = 0.0 }', 'mass = "m5"\ninitial = { theta = -2.07 }'),
              ('hold = { theta4 = 0.0 }', 'hold = { theta3 = 0.2 }'))


#: A gear leg as a pendulum with a closed-form stall fold (the same file as tests/data/freefall_pendulum.toml,
#: whose header derives U_c = sqrt(2 m g / (rho C_D d L))): the critical airspeed against damping.
PENDULUM = '''# A gear leg as a pendulum: a uniform bar (mass m, length L) hinged at O, held up by an uplock at
# theta = beta (rad) and released at rest, falls under gravity to the downlock at theta = -beta.
# The air moves up at U (alpha = pi/2), so the drag on the bar, 1/2 rho C_D d L U^2 cos^2(theta) at
# its midpoint, opposes the fall. The net moment about O is
#   (L/2) cos(theta) (k U^2 cos(theta) - m g),   k = rho C_D d L / 2,
# so the equilibria the leg could hang in satisfy cos(theta) = m g / (k U^2): a branch with a fold
# at theta = 0, U_c = sqrt(2 m g / (rho C_D d L)) (the quasi-static critical airspeed). A hydraulic
# damper from the ground point G = (0, 2L) to the tip slows the fall (tests/test_freefall.py).
[mechanism]
name = "freefall_pendulum"
description = "a gear leg released from its uplock, falling against an upward airflow onto its downlock"

[parameters]
m = { value = 10.0, unit = "kg" }
L = { value = 1.0, unit = "m" }
g = { value = 9.81, unit = "m/s^2" }
beta = { value = 1.0, unit = "rad", description = "uplock angle; the downlock is at -beta" }
rho = { value = 1.225, unit = "kg/m^3" }
C_D = { value = 1.2, unit = "1" }
d = { value = 0.2, unit = "m" }
U = { value = 20.0, unit = "m/s", description = "airspeed" }
alpha = { value = 1.5707963267948966, unit = "rad", description = "the air moves up" }
c = { value = 0.0, unit = "N s/m", description = "damper coefficient" }

[ground]
O = [0, 0]
G = [0, "2*L"]

# leg is a bar (it has a length): its frame origin is its centre, its ends leg.a (the hinge) and leg.b, so its
# points are measured from the centre (`mechcont check` warns about a point beyond a bar's ends).
[bodies.leg]
mass = "m"
length = "L"
points = { tip = ["L/2", 0] }   # its end b: L from the hinge a
initial = { theta = 0.3 }

[joints.pin]
type = "revolute"
a = "ground.O"
b = "leg.a"

[dampers.retraction]
a = "ground.G"
b = "leg.tip"
c = "c"

[gravity]
g = "g"

[loads.air]
type = "drag"
body = "leg"
start = "a"
end = "tip"

[conditions]
angle = { type = "angle", bodies = ["ground", "leg"] }

[stops.uplock]
condition = "angle"
max = "beta"

[stops.downlock]
condition = "angle"
min = "-beta"
'''
#: Damper coefficients (N s/m) of the study, the bisection bracket (m/s), tolerance and run length (s).
DAMPERS, PENDULUM_BRACKET, PENDULUM_TOL, PENDULUM_UNTIL = (1.0, 2.0, 5.0, 10.0, 20.0), (24.0, 30.0), 0.01, 100.0
#: The integrator's tolerances of the damping study's runs (at 1e-8 / 1e-10 every bisection gave the same
#: brackets, at 1.6 to 3.4 times the cost).
PENDULUM_RTOL, PENDULUM_ATOL = 1e-6, 1e-8


def description_text() -> str:
    """The nose gear's description with the damper, the stops and the retracted pose (TOML)."""
    from ..mechanism import find_description

    path = find_description("nose_gear")
    assert path is not None
    text = path.read_text(encoding="utf-8").replace("[ground]\n", _PARAMETERS, 1)
    for a, b in _RETRACTED:
        if a not in text:  # pragma: no cover - guards the shipped file's layout
            raise RuntimeError(f"nose_gear.toml changed: {a!r} not found")
        text = text.replace(a, b, 1)
    return text + _ELEMENTS


def _damping_study(out_dir: Path, timings: dict) -> list[str]:
    """Dynamic critical airspeed of :data:`PENDULUM` against its damper, beside the closed-form fold."""
    from ..dynamics.freefall import quasi_static_critical
    from ..models import model_from_text
    from ..outputs.critical_plots import critical_figure
    from ..outputs.plotting import legend_below, save_figure

    system = model_from_text(PENDULUM, "freefall_pendulum.toml")
    closed = math.sqrt(2 * 10.0 * 9.81 / (1.225 * 1.2 * 0.2 * 1.0))
    qs = quasi_static_critical(system, "angle", 1.0, -1.0, "U")
    crits = []
    lo, hi = PENDULUM_BRACKET
    for c in DAMPERS:  # lightest first: more damping locks at no higher an airspeed, so each bracket is the last's
        with timed(timings, f"freefall: pendulum critical airspeed at c = {c:g} N s/m"):
            crits.append(_bisect(system, {"angle": 1.0}, "U", (max(lo, qs.value - 0.5), hi), PENDULUM_BRACKET,
                                 tol=PENDULUM_TOL, lock="downlock", until=PENDULUM_UNTIL, values={"c": c},
                                 rtol=PENDULUM_RTOL, atol=PENDULUM_ATOL))
        hi = crits[-1].high  # (upper end: it failed with less damping, checked again by the next bisection)
    fig = critical_figure(DAMPERS, crits, qs.value, damping_label="damper c (N s/m)",
                          airspeed_label="critical airspeed U (m/s)",
                          title="Gear leg (pendulum) freefall: dynamic vs quasi-static")
    fig.set_layout_engine("constrained")
    fig.set_size_inches(6.4, 5.0)
    legend_below(fig, ncols=1)   # in the axes it lay over the curves
    save_figure(fig, out_dir / "freefall_critical_vs_damping.png")
    import matplotlib.pyplot as plt

    plt.close(fig)   # critical_figure makes it with pyplot
    lines = ["### Critical airspeed against damping (a gear leg with a closed-form fold)", "",
             "A gear leg as a pendulum (the description `freefall_pendulum`, `mechcont.paper.freefall.PENDULUM`: "
             "10 kg, 1 m, released at 57 deg above "
             "the horizontal, locked at 57 deg below) falls against the drag of an upward airflow, which holds it up "
             "best at the horizontal: its stall equilibria fold at U_c = sqrt(2 m g / (rho C_D d L)) = "
             f"{closed:.4f} m/s. Continuation finds the fold at {qs.value:.4f} m/s. Bisection on freefall runs "
             f"(up to {PENDULUM_UNTIL:g} s each, ended once locked, rtol {PENDULUM_RTOL:g}; each bracket from the last, "
             f"to {PENDULUM_TOL:g} m/s; the two ends of each bracket are runs made, the difference from the fold "
             "counted from the run that locked and significant only beyond the bracket's width):", "",
             "| damper c (N s/m) | largest U that locked (m/s) | smallest U that did not (m/s) | above the fold (%) |",
             "|---|---|---|---|"]
    lines += [f"| {c:g} | {k.locked:.3f} | {k.failed:.3f} | {100 * k.compare(qs.value)[0] / qs.value:+.2f}"
              f"{'' if k.compare(qs.value)[1] else ' (within the bracket)'} |" for c, k in zip(DAMPERS, crits)]
    lines += ["", "Lightly damped, the leg's momentum carries it over the airload's hump: it locks above the "
              "quasi-static critical airspeed. Heavily damped, it creeps through the hump and the dynamic value "
              "converges to the fold (a run near it creeps for a time growing without bound, so a finite run "
              "length leaves it a little below).", "", "![critical vs damping](freefall_critical_vs_damping.png)", ""]
    return lines


def _bisect(system: Model, start: Mapping[str, float], vary: str, bracket: tuple[float, float],
            fallback: tuple[float, float], **options: Any) -> CriticalAirspeed:
    """:func:`~mechcont.dynamics.freefall.critical_airspeed` in ``bracket`` (runs ended at the lock), or in the
    wider ``fallback`` when the outcome does not change across ``bracket``."""
    from ..dynamics.freefall import critical_airspeed
    from ..errors import InputError

    try:
        return critical_airspeed(system, start, vary, *bracket, end_at_lock=True, **options)
    except InputError:
        return critical_airspeed(system, start, vary, *fallback, end_at_lock=True, **options)


def run(out_dir: Path, quiet: bool = True, timings: dict | None = None) -> list[str]:
    """Simulate the nose-gear freefall at :data:`AIRSPEEDS`; write the figure; return summary lines."""
    from ..analysis import continuation_with_stops, equilibrium_on_stops
    from ..continuation import ContinuationOptions
    from ..dynamics.freefall import freefall, quasi_static_critical
    from ..errors import InputError
    from ..models import model_from_text

    timings = {} if timings is None else timings
    out_dir = Path(out_dir)
    system = model_from_text(description_text(), "nose_gear_freefall.toml")
    runs = []
    for U in AIRSPEEDS:
        with timed(timings, f"freefall: nose gear at U = {U:g} m/s ({UNTIL:g} s simulated)"):
            runs.append((U, freefall(system, {"fitting": THETA_UP}, lock="downlock", until=UNTIL, values={"U": U})))
    downlock = next(st for st in system.stops if st.name == "downlock")
    nose_gear_figure(runs, downlock.limit, out_dir / "freefall_nose_gear.png")
    lines = ["## Freefall extension of the nose gear (beyond the 2010 paper)", "",
             f"The nose gear of Fig. 6 with its retraction actuator as a hydraulic damper (c = 2000 N s/m, "
             f"c2 = 5000 N s^2/m^2, from the airframe point (-0.3, 0.4) m to the drag-stay lug), an uplock at "
             f"theta3 = {math.degrees(THETA_UP):.1f} deg and a downlock stop 2.0 deg past aligned lock links "
             f"(restitution 0), released at rest from the uplock and simulated with its stops for up to "
             f"{UNTIL:g} s. The impact speed is the lock links' closing rate (overcentre angle) at the stop.", "",
             "| U (m/s) | outcome | time to lock (s) | lock-link impact (deg/s) | peak actuator load (kN) | "
             "downlock reaction at rest (N m) |", "|---|---|---|---|---|---|"]
    for U, r in runs:
        t = f"{r.time_to_lock:.3f}" if r.time_to_lock is not None else "-"
        v = f"{math.degrees(r.impact_speed):.0f}" if r.impact_speed is not None else "-"
        rest = f"{float(r.history['R_downlock'][-1]):.2f}" if r.locked else "-"
        lines.append(f"| {U:g} | {r.outcome} | {t} | {v} | {r.peak_damper['retraction'] / 1e3:.2f} | {rest} |")
    # -- the predictors: intermediate equilibria, and the locked state continued in U ---------------------
    try:
        qs = quasi_static_critical(system, "fitting", THETA_UP, TRAVEL_END, "U")
        hang = (f"it could hang at U >= {qs.value:.1f} m/s (theta3 = {math.degrees(qs.pose):.1f} deg)")
    except InputError:
        hang = (f"no equilibrium at a positive airspeed between the uplock and theta3 = {math.degrees(TRAVEL_END):.0f} "
                "deg: no airspeed can stop this forward-retracting gear on its way down")
    x = runs[0][1].history.values[-1].copy()
    x[system.index("R_downlock")] = 0.0
    locked, _ = equilibrium_on_stops(system, x, values={"U": 0.0}, contact=["downlock"])
    with timed(timings, "freefall: locked state continued in U"):
        sr = [p["U"] for p in continuation_with_stops(system, locked, "U", direction=1, options=ContinuationOptions(
            bounds={"U": (0.0, 2 * CRITICAL[1])})).branch.special_points if p.label == "SR"]
    t0 = time.perf_counter()
    bracket = (sr[0] + SR_BRACKET[0], sr[0] + SR_BRACKET[1]) if sr else CRITICAL
    crit = _bisect(system, {"fitting": THETA_UP}, "U", bracket, CRITICAL, tol=TOL, lock="downlock", until=CRITICAL_UNTIL)
    timings[f"freefall: critical airspeed by bisection ({len(crit.runs)} runs)"] = time.perf_counter() - t0
    static = []
    for U, r in runs:
        if r.locked:
            y = r.history.values[-1].copy()
            y[system.index("R_downlock")] = 0.0
            xe, _ = equilibrium_on_stops(system, y, values={"U": U}, contact=["downlock"])
            static.append(abs(float(xe[system.index("R_downlock")]) - float(r.history["R_downlock"][-1]))
                          / float(xe[system.index("R_downlock")]))
    lines += ["", f"Quasi-static: {hang}. But the airload unloads the lock: continued in U from the locked "
              f"state, the downlock stop releases (SR) at U = {sr[0]:.3f} m/s" if sr else
              f"Quasi-static: {hang}; the locked state holds up to U = {2 * CRITICAL[1]:g} m/s",
              ]
    lines[-1] += (f"; above it the lock spring cannot hold the lock links on their stop. Dynamic: bisection on "
                  f"freefall runs brackets the critical airspeed between the largest airspeed run that locked, "
                  f"{crit.locked:.3f} m/s, and the smallest that did not, {crit.failed:.3f} m/s ({crit.outcome(crit.failed)}; "
                  f"{len(crit.runs)} runs of up to {CRITICAL_UNTIL:g} s from a "
                  f"bracket from SR {SR_BRACKET[0]:+g} to SR {SR_BRACKET[1]:+g} m/s, to {TOL:g} m/s). Each locked run's "
                  f"reaction at rest equals the static reaction on the stop (`equilibrium_on_stops`) to "
                  + ("better than 1e-8 relative" if max(static) < 1e-8 else f"{max(static):.1e} relative")
                  + ". The airload shortens the fall and hits the lock harder; above the critical airspeed the "
                    "lock links strike their stop but do not stay on it: the airload pulls them off again (the "
                    "outcomes in the table and of the bracket's failing end say where the gear is at the end).")
    lines += ["", "![nose gear freefall](freefall_nose_gear.png)", ""]
    lines += _damping_study(out_dir, timings)
    lines += freefall_sidestay.lines(timings, out_dir)
    return lines
