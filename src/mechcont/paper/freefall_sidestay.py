"""Freefall of the dual-sidestay main gear from gear up: do both sidestays lock, and how far apart in time?

The generated gear (``examples/dual_sidestay.toml``) carries what a freefall needs: its retraction
actuator as a hydraulic damper (airframe point ``C`` to the fitting lug ``D``, ``c v + c2 v|v|``: the
hydraulics failed, the fluid still goes through the restrictor) and structural damping of the compliant
aft attachment (three dampers along x, y, z from the airframe to the aft upper arm's attachment point,
damping ratio ``zeta_att`` of the arm on its attachment).

The released pose is the gear retracted *quasi-statically* by its actuator (the equilibria with the
retraction angle held and the actuator force solved for, from gear down to gear up), so the aft
attachment carries its load with the deflection its stiffness gives. A purely kinematic assembly
(:func:`kinematic_offset`) treats the compliant attachment as free: it drags the aft upper arm
hundreds of millimetres off its airframe point and brings the aft lock links, seen in their fold
plane, to within a degree of alignment: a pose no gear reaches.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ._timing import timed

if TYPE_CHECKING:
    from ..dynamics.freefall import FreefallResult
    from ..equations import Model

#: A run of the table: (k_att N/m, lock-spring stretch, its freefall).
Run = tuple[float, float, "FreefallResult"]

__all__ = ["SIDESTAY_UP", "LOCKS", "description_text", "freefall_gear", "retracted", "kinematic_offset",
           "sidestay_freefall", "lines"]

#: Gear-up retraction angle (rad; docs/dual-sidestay.md) and the quasi-static retraction steps to it.
SIDESTAY_UP, STEPS = math.radians(85.0), 8
#: The lock stops.
LOCKS = ("fwd_stop", "aft_stop")
#: Longest simulated fall (s), the integrator's tolerances.
UNTIL, RTOL, ATOL = 4.0, 1e-6, 1e-8
#: Aft attachment stiffnesses (N/m) and lock-spring stretches (free over installed length: less is more
#: preload) of the table.
K_ATT, STRETCH = (5e7, 5e6), (0.5, 0.7, 0.9)


def description_text() -> str:
    """The generated dual-sidestay gear's description (``examples/dual_sidestay.toml``): it carries the actuator
    damper and the attachment's damping, which act only in time simulation."""
    from ..models.dual_sidestay_description import dual_sidestay_description

    return dual_sidestay_description()


def freefall_gear() -> Model:
    """The generated gear's model (:func:`~mechcont.paper.dual_sidestay.generated_gear`: built once, then from
    the disk cache, the entry the dual-sidestay section and ``load_model`` of the example share)."""
    from .dual_sidestay import generated_gear

    return generated_gear()


def retracted(model: Model, theta_up: float = SIDESTAY_UP, steps: int = STEPS, values: Mapping[str, float] | None = None,
              guess: np.ndarray | None = None) -> np.ndarray:
    """The gear ``model`` retracted quasi-statically to ``theta_up`` (rad) and released there.

    :func:`~mechcont.dynamics.freefall.held_pose` (what ``mechcont freefall --held-by F_act`` does): the
    equilibria with ``theta`` held and the actuator force ``F_act`` solved for, followed from gear down in
    ``steps`` steps, each from the last (or solved once from ``guess``, the retracted pose of a neighbouring
    parameter set); ``F_act`` is then back at its value, 0 (the hydraulics failed). ``values`` override
    parameters. Returns the full vector; :class:`~mechcont.errors.InputError` when a stop is violated there."""
    from ..dynamics.freefall import condition_value, held_pose
    from ..errors import InputError

    if values:
        model = model.with_values(dict(values))
    x = held_pose(model, {"theta": theta_up}, "F_act", guess=guess, steps=steps)
    for st in model.stops:
        value = condition_value(model, x, st.condition)
        if st.side * (value - st.limit) < 0:
            raise InputError("retracted", f"stop {st.name} is violated at gear up ({st.condition} = {value:.4g}, "
                                          f"limit {st.limit:.4g})")
    return x


def attachment_offset(model: Model, x: np.ndarray) -> float:
    """How far (m) the aft upper arm's attachment point is from its airframe point ``A_aft`` at ``x`` (both from
    the model's scene, which names every ground point ``ground.NAME``)."""
    scene = model.scene(x) if model.scene is not None else None
    if scene is None:
        raise TypeError(f"model '{model.name}' has no scene to measure the aft attachment in")
    return float(np.linalg.norm(dict(scene.bars)["aft_upper"][0] - np.asarray(dict(scene.points)["ground.A_aft"])))


def kinematic_offset(model: Model, theta_up: float = SIDESTAY_UP, steps: int = STEPS) -> tuple[float, float]:
    """The gear assembled kinematically (:func:`~mechcont.dynamics.assemble` with ``kinematic=True``, ``theta``
    held, from gear down in ``steps`` steps) at ``theta_up``: ``(attachment offset (m), aft lock condition)``. The assembly moves
    every coordinate the joints do not fix, the compliant attachment's too."""
    from ..dynamics import assemble
    from ..dynamics.freefall import condition_value

    x = assemble(model, {"theta": 0.0}, hold=["theta"], kinematic=True)
    for t in np.linspace(0.0, theta_up, steps + 1)[1:]:
        x = assemble(model, model.vector({"theta": float(t)}, base=x), hold=["theta"], kinematic=True)
    return attachment_offset(model, x), condition_value(model, x, "aft_lock")


def sidestay_freefall(system: Model, x_up: np.ndarray, values: Mapping[str, float] | None = None, until: float = UNTIL,
                      **options: Any) -> FreefallResult:
    """The gear released at rest at ``x_up`` (:func:`retracted`) and simulated with its stops until both
    lock-link pairs rest on their stops (the run ends there) or ``until`` s. ``values`` override parameters
    (e.g. ``k_att`` N/m, ``stretch``); ``options`` go to :func:`~mechcont.dynamics.freefall.freefall`.
    Returns the :class:`~mechcont.dynamics.freefall.FreefallResult`.

    Explicit Runge-Kutta (RK45): the attachment's vibration (a few hundred hertz at 5e7 N/m) limits its step,
    but an implicit method (Radau, BDF) with its finite-difference Jacobian of 126 states, rebuilt after every
    stop event, took several times more evaluations for the same lock times."""
    from ..dynamics.freefall import freefall

    options = {"rtol": RTOL, "atol": ATOL, "end_at_lock": True, **options}
    return freefall(system, {"theta": SIDESTAY_UP}, lock=list(LOCKS), until=until, values=values, guess=x_up,
                    **options)


def _deg(model: Model, x: np.ndarray, name: str) -> float:
    """A lock-link pair's angle from aligned in its fold plane (deg), from its condition (a sine)."""
    from ..dynamics.freefall import condition_value

    return math.degrees(math.asin(condition_value(model, x, name)))


def _row(k: float, stretch: float, run: FreefallResult, limits: dict[str, float]) -> str:
    """One table row: the outcome, each pair's first strike (time, the lock links' angular speed in deg/s) and
    lock, the gap, the peak loads. ``limits``: each lock stop's limit (the sine of its angle past aligned)."""
    ev = run.history.stop_events
    first = {n: next((e for e in ev if e.stop == n and e.kind == "impact"), None) for n in LOCKS}
    strikes = {n: sum(1 for e in ev if e.stop == n and e.kind == "impact") for n in LOCKS}

    def ms(t: float | None) -> str:
        return "-" if t is None else f"{1e3 * t:.1f}"

    cells = [f"{k:.0e}", f"{stretch:g}", run.outcome]
    for n in LOCKS:
        hit = first[n]
        # the condition is the sine of the angle psi: psi' = (sin psi)' / cos psi, at the stop's angle
        rate = None if hit is None else math.degrees(abs(hit.speed) / math.sqrt(1.0 - limits[n] ** 2))
        cells.append("-" if hit is None else f"{ms(hit.time)} ({rate:.0f} deg/s)")
        cells.append(f"{ms(run.stops[n].time)} ({strikes[n]})")
    t_fwd, t_aft = (run.stops[n].time for n in LOCKS)
    cells.append("-" if t_fwd is None or t_aft is None else f"{1e3 * (t_aft - t_fwd):+.1f}")
    cells.append(f"{run.peak_damper.get('actuator', 0.0) / 1e3:.1f}")
    return "| " + " | ".join(cells) + " |"


def lines(timings: dict, out_dir: Path | None = None) -> list[str]:
    """The summary lines of the dual-sidestay freefall (pose, model, the table against ``k_att`` and ``stretch``);
    with ``out_dir``, its figure ``freefall_sidestay.png`` there (each pair's lock links against their stop)."""
    from ._freefall_figures import sidestay_figure

    with timed(timings, "freefall: dual-sidestay gear built, retracted quasi-statically"):
        model = freefall_gear()
        x_up = retracted(model)
    with timed(timings, "freefall: dual-sidestay gear assembled kinematically"):
        offset, aft_kin = kinematic_offset(model)
    cases = [(K_ATT[0], STRETCH[1])] + [(k, STRETCH[1]) for k in K_ATT[1:]] + [(K_ATT[0], s) for s in STRETCH if s != STRETCH[1]]
    runs: list[Run] = []
    for k, st in cases:
        values = {"k_att": k, "stretch": st}
        with timed(timings, f"freefall: dual-sidestay gear, k_att = {k:.0e} N/m, stretch {st:g}"):
            x = x_up if (k, st) == cases[0] else retracted(model, values=values, guess=x_up)
            runs.append((k, st, sidestay_freefall(model, x, values=values)))
    base = runs[0][2]
    if out_dir is not None:
        stops = {st.name: st for st in model.stops}
        sidestay_figure(runs, {f"{n.split('_')[0]} pair": (stops[n].condition, stops[n].limit) for n in LOCKS},
                        Path(out_dir) / "freefall_sidestay.png")
    p = model.as_dict(x_up)
    out = ["### Dual-sidestay main gear: freefall from gear up", "",
           "The generated gear (`examples/dual_sidestay.toml`: two sidestays with lock links, each pair with an "
           "overcentre stop 2 deg past aligned and a lock spring, the aft sidestay on a compliant airframe "
           f"attachment) at gear up, theta = {math.degrees(SIDESTAY_UP):.0f} deg. Assembled kinematically (theta held, "
           "every other coordinate moved as little as the joints allow) the compliant attachment is free to move: "
           f"the aft upper arm ends {1e3 * offset:.0f} mm off its airframe point and the aft lock links, seen in "
           f"their fold plane, {abs(math.degrees(math.asin(aft_kin))):.1f} deg from aligned, where they could go over "
           "centre onto their stop and hold the gear up. No gear gets there: retracted quasi-statically by its "
           "actuator (the equilibria with theta held and the actuator force solved for, from gear down) the "
           f"attachment deflects {1e6 * attachment_offset(model, x_up):.0f} um under its load and the lock links are "
           f"folded fwd {_deg(model, x_up, 'fwd_lock'):+.1f} deg, aft {_deg(model, x_up, 'aft_lock'):+.1f} deg "
           "from aligned in their fold planes, far from their stops.", "",
           "Released there at rest (the actuator force 0: the hydraulics failed) under gravity, with the retraction "
           f"actuator as a hydraulic damper (c = {p['c_ret']:.0e} N s/m, c2 = {p['c2_ret']:.0e} N s^2/m^2) and the "
           f"aft attachment damped ({100 * p['zeta_att']:.0f} % of critical for the aft upper arm on it: without "
           "structural damping its vibration never dies out and the aft pair chatters on its stop), simulated with "
           f"both stops (restitution 0) until both pairs rest on their stops (RK45, rtol {RTOL:g}). Times from the "
           "release; a pair's first strike (and the lock links' angular speed then, deg/s) and when it comes to rest "
           "on its stop (strikes in brackets); the gap is aft minus fwd:", "",
           "| k_att (N/m) | lock-spring stretch | outcome | fwd first strike (ms, deg/s) | fwd locked (ms) | "
           "aft first strike (ms, deg/s) | aft locked (ms) | gap (ms) | peak actuator damper load (kN) |",
           "|---|---|---|---|---|---|---|---|---|"]
    limits = {st.name: st.limit for st in model.stops}
    out += [_row(k, st, r, limits) for k, st, r in runs]
    out += [""] + _findings(runs, base) + [""]
    if out_dir is not None:
        out += ["![dual-sidestay freefall: each lock-link pair against its stop](freefall_sidestay.png)", ""]
    return out


def _findings(runs: Sequence[Run], base: FreefallResult) -> list[str]:
    """What the table says, in words (from the runs, not assumed)."""
    locked = [r for _, _, r in runs if r.locked]
    if len(locked) < len(runs):
        failed = [(k, st, r) for k, st, r in runs if not r.locked]
        return ["Not every run locks: " + "; ".join(
            f"k_att = {k:.0e} N/m, stretch {st:g}: {r.outcome}, "
            + ", ".join(f"{n.split('_')[0]} pair {'locked' if r.stops[n].time is not None else 'not locked'}"
                        for n in LOCKS) for k, st, r in failed) + "."]
    gaps = [_lock_time(r, LOCKS[1]) - _lock_time(r, LOCKS[0]) for r in locked]
    order = "the forward pair first" if all(g > 0 for g in gaps) else (
        "the aft pair first" if all(g < 0 for g in gaps) else "in either order")
    first = [min(e.time for e in r.history.stop_events if e.kind == "impact") for r in locked]
    return [f"Both sidestays lock in every run, {order}, {1e3 * min(map(abs, gaps)):.1f} to "
            f"{1e3 * max(map(abs, gaps)):.1f} ms apart; the nominal gear has locked {base.time_to_lock:.3f} s after "
            f"the release. The fall itself is set by the actuator damper: the first strike comes "
            f"{min(first):.3f} to {max(first):.3f} s after the release in every run. What the aft attachment and "
            "the lock springs change is the settling on the stops. Restitution is 0, so a pair leaves its stop "
            "again only when its reaction falls to zero, the rest of the gear still moving (the other pair's "
            "strike, the aft attachment's vibration), and its lock spring brings it back: the strikes in "
            "brackets. " + _changes(runs)]


def _lock_time(run: FreefallResult, stop: str) -> float:
    """When (s) the lock ``stop`` came to rest in ``run``, a run that locked (where every lock stop has its time)."""
    t = run.stops[stop].time
    if t is None:
        raise ValueError(f"the lock stop {stop} has no lock time in a run that locked")
    return t


def _changes(runs: Sequence[Run]) -> str:
    """The lock times and strike counts of each variant against the nominal run (the first)."""
    k0, s0, base = runs[0]

    def strikes(r: FreefallResult) -> int:
        return sum(1 for e in r.history.stop_events if e.kind == "impact")

    parts = []
    for k, st, r in runs[1:]:
        what = f"k_att = {k:.0e} N/m" if k != k0 else f"stretch {st:g}"
        moves = ", ".join(f"{n.split('_')[0]} lock {1e3 * (t - t0):+.1f} ms" for n in LOCKS
                          if (t := r.stops[n].time) is not None and (t0 := base.stops[n].time) is not None)
        parts.append(f"{what}: {moves}, {strikes(r)} strikes in all")
    return f"Against the nominal gear ({strikes(base)} strikes in all): " + "; ".join(parts) + "."
