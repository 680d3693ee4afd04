"""The dual-sidestay main gear's retraction (issue 11): actuator load and efficiency, lock-up against
the aft sidestay plane angle, 3-D drawings and an animation.

Built on the hand-formulated kinematic model :mod:`mechcont.models.dual_sidestay` with the
representative A320-class geometry of :mod:`mechcont.models.dual_sidestay_geometry` (see
``docs/dual-sidestay.md``). Not part of the default ``mechcont paper`` run: ``mechcont paper
--only dual_sidestay``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np

from ..analysis.retraction import ActuatorLoads, actuator_loads, first_fold
from ..continuation import Branch, ContinuationOptions, continuation
from ..models.dual_sidestay import (
    actuator_length_rate,
    build_dual_sidestay_kinematics,
    geometry_values,
    gravity_rate,
    loaded_scene,
    start_values,
)
from ..models.dual_sidestay_geometry import DEFAULT_GEOMETRY, GearGeometry

__all__ = ["retraction", "lock_up_scan", "Retraction", "run", "PLANE_ANGLES"]

#: Aft sidestay plane angles (rad) of the lock-up study.
PLANE_ANGLES = np.radians(np.arange(-45.0, 60.1, 7.5))


@dataclass(frozen=True)
class Retraction:
    """One retraction run: the system (with the geometry's values), its branch from gear down, the
    lock-up angle (rad, ``None`` when it retracts fully) and the actuator loads up to there."""

    system: object
    branch: Branch
    lock_up: float | None
    loads: ActuatorLoads
    lock_side: str | None = None


def retraction(geo: GearGeometry = DEFAULT_GEOMETRY, *, base=None, max_steps: int = 300,
               arms: bool = True) -> Retraction:
    """Continue the gear from down (theta = 0) towards ``geo.retracted`` in the retraction angle.

    ``base`` is a built kinematic system to reuse (its compiled code); ``arms`` counts the sidestay
    arms' weight. Returns the :class:`Retraction`; the actuator loads cover the branch up to the
    first fold (lock-up) or the gear-up position.
    """
    base = base or build_dual_sidestay_kinematics(geo)
    system = base.with_values(geometry_values(geo))
    system.geometry = geo
    system.scene = partial(loaded_scene, system)
    x0 = system.vector(start_values(geo), base=system.defaults())
    branch = continuation(system, x0, "theta", direction=1,
                          options=ContinuationOptions(bounds={"theta": (-0.01, geo.retracted)}, max_steps=max_steps,
                                                      stability=False))
    lock = first_fold(branch, "theta")
    end = next((k for k, lab in enumerate(branch.labels) if lab.startswith("LP")), len(branch.values))
    rows = branch.values[:end]
    loads = actuator_loads(system, rows, "theta", partial(gravity_rate, system, arms=arms),
                           partial(actuator_length_rate, system))
    side = None
    if end < len(branch.values):  # the side whose points move in the fold's null vector
        states = [system.index(n) for n in system.state_names]
        null = np.linalg.svd(system.jacobian(branch.values[end])[:, states])[2][-1]
        side = system.state_names[int(np.argmax(np.abs(null)))].split("_")[0]
    return Retraction(system, branch, lock, loads, side)


def lock_up_scan(geo: GearGeometry = DEFAULT_GEOMETRY, angles=PLANE_ANGLES, *, base=None,
                 max_steps: int = 300) -> tuple[np.ndarray, np.ndarray, list[Retraction]]:
    """Lock-up angle (rad, ``nan`` = retracts fully) for each aft sidestay plane angle in ``angles`` (rad)."""
    base = base or build_dual_sidestay_kinematics(geo)
    runs = [retraction(geo.with_aft_plane(a), base=base, max_steps=max_steps) for a in angles]
    lock = np.array([np.nan if r.lock_up is None else r.lock_up for r in runs])
    return np.asarray(angles, float), lock, runs


def run(out_dir: Path, quiet: bool = False, timings: dict | None = None, quick: bool = False) -> list[str]:
    """Figures into ``out_dir`` and the Markdown summary lines; ``quick`` runs a reduced study (tests)."""
    from ..outputs.animation import animate
    from ..outputs.drawing3d import draw3d
    from ..outputs.plotting import save_figure
    from ..outputs.retraction_plots import plot_actuator_loads, plot_lock_up

    timings = timings if timings is not None else {}
    out_dir = Path(out_dir)
    geo = DEFAULT_GEOMETRY
    t0 = time.perf_counter()
    base = build_dual_sidestay_kinematics(geo)
    timings["dual_sidestay: build"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    ret = retraction(geo, base=base)
    timings["dual_sidestay: retraction"] = time.perf_counter() - t0
    loads = ret.loads
    save_figure(plot_actuator_loads(loads), out_dir / "sidestay_actuator.png")
    sys_ = ret.system
    draw3d(sys_, ret.branch.values[0], out_dir / "sidestay_down.png", annotate=("theta",))
    draw3d(sys_, ret.branch.values[-1], out_dir / "sidestay_up.png", annotate=("theta",))
    if not quick:
        animate(sys_, ret.branch, out_dir / "sidestay_retraction.gif", every=max(1, len(ret.branch.values) // 24),
                annotate=("theta",), dpi=80)
    t0 = time.perf_counter()
    angles = PLANE_ANGLES[::3] if quick else PLANE_ANGLES
    phi, lock, runs = lock_up_scan(geo, angles, base=base)
    timings["dual_sidestay: lock-up scan"] = time.perf_counter() - t0
    save_figure(plot_lock_up(phi, lock, geo.retracted, geo.aft.phi), out_dir / "sidestay_lock_up.png")

    def deg(v):
        return f"{math.degrees(v):.1f}"

    i_peak = int(np.argmax(np.abs(loads.tension)))
    locked = [(p, t, r.lock_side) for p, t, r in zip(phi, lock, runs) if not np.isnan(t)]
    common = min(r.loads.s[-1] for r in runs)   # loads compared up to the earliest lock-up
    at = [float(np.interp(common, r.loads.s, r.loads.tension)) for r in runs]
    free = [p for p, t in zip(phi, lock) if np.isnan(t)]
    lines = ["## Dual-sidestay main gear: retraction (representative A320-class geometry)", "",
             "Hand-formulated kinematic model (12 natural coordinates, ball-jointed lugs; docs/dual-sidestay.md), "
             f"continued in the retraction angle theta from gear down to {deg(geo.retracted)} deg.", "",
             f"- Retraction actuator: length {loads.length[0]:.3f} m (down) to {loads.length[-1]:.3f} m "
             f"(theta = {deg(loads.s[-1])} deg); peak load {loads.peak / 1e3:.1f} kN "
             f"({'tension' if loads.tension[i_peak] > 0 else 'compression'}) at theta = {deg(loads.s[i_peak])} deg; "
             f"work {loads.work / 1e3:.2f} kJ; mechanical efficiency {loads.efficiency:.3f} "
             "(work over peak load x stroke). Figure: sidestay_actuator.png; drawings sidestay_down.png, "
             "sidestay_up.png" + ("" if quick else ", animation sidestay_retraction.gif") + ".",
             f"- Geometric lock-up against the aft sidestay plane angle ({deg(phi[0])} to {deg(phi[-1])} deg): "
             + (", ".join(f"phi_aft = {deg(p)} deg locks at theta = {deg(t)} deg ({side} lock links)"
                       for p, t, side in locked) or "none")
             + "; retracts fully at phi_aft = " + (", ".join(deg(p) for p in free) or "none") + " deg. "
             "A lock-up is a fold (LP) of the retraction branch: the aft lock links reach alignment and would "
             "have to stretch (go into tension) to follow. Figure: sidestay_lock_up.png.",
             f"- The actuator load hardly depends on the aft plane angle: at theta = {deg(common)} deg it is "
             f"{min(at) / 1e3:.2f} to {max(at) / 1e3:.2f} kN over the scan (+ tension), because the sidestays fold "
             "passively and only their arms' weight changes with the plane.",
             "- Not yet computed (need the spatial statics layer): downlock/unlock forces of the lock links, "
             "their sensitivity to attachment misalignment with compliance, two-parameter fold curves.", ""]
    return lines
