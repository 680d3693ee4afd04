"""The dual-sidestay main gear: retraction actuator load and efficiency, lock-up against the aft
sidestay plane angle, the rigid downlock's rigging sensitivity, downlock loads with compliant and rigid
sidestays, unlock forces with overcentre stops and their fold curve with a cusp, 3-D drawings and an
animation.

Built on the hand-formulated kinematic model :mod:`mechcont.models.dual_sidestay` with the
representative A320-class geometry of :mod:`mechcont.models.dual_sidestay_geometry` (see
``docs/dual-sidestay.md``). Not part of the default ``mechcont paper`` run: ``mechcont paper
--only dual_sidestay``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np

from ..analysis.retraction import ActuatorLoads, actuator_loads, first_fold
from ..continuation import Branch, ContinuationOptions, continuation, continue_folds
from ..equations import Model
from ..models.dual_sidestay import (
    GearDescription,
    actuator_length_rate,
    build_dual_sidestay_kinematics,
    geometry_values,
    gravity_rate,
    loaded_scene,
    start_values,
)
from ..models.dual_sidestay_geometry import DEFAULT_GEOMETRY, GearGeometry
from ._dual_sidestay_rigging import (
    SIDE_LOAD,
    STAY_STIFFNESS,
    DownlockLoads,
    _g,  # noqa: F401 - the misfit constraint, used by the tests through this module
    alignment_angle,
    downlock_loads,
    lock_misfit,
    rigging_scan,
)
from ._timing import timed

__all__ = ["retraction", "lock_up_scan", "Retraction", "run", "PLANE_ANGLES", "lock_misfit", "alignment_angle",
           "rigging_scan", "lock_up_fold_curve", "downlock_loads", "DownlockLoads", "STAY_STIFFNESS", "SIDE_LOAD",
           "generated_gear", "locked_gear", "LockedGear", "ATTACHMENT_STIFFNESS", "UnlockStudy", "unlock_study",
           "UNLOCK_FORCES"]

#: The unlock forces of the generated gear (N, at the lock-link joints J, + towards unlocking).
UNLOCK_FORCES = {"F_fwd": "forward pair alone", "F_aft": "aft pair alone", "F_lock": "both pairs together"}

#: Aft airframe attachment stiffnesses (N/m) of the locked generated gear.
ATTACHMENT_STIFFNESS = (5e6, 5e7, 5e8)

#: Aft sidestay plane angles (rad) of the lock-up study.
PLANE_ANGLES = np.radians(np.arange(-45.0, 60.1, 7.5))


@dataclass(frozen=True)
class Retraction:
    """One retraction run: the system (with the geometry's values), its branch from gear down, the
    lock-up angle (rad, ``None`` when it retracts fully), the actuator loads up to there, and at a
    lock-up the sidestay (``fwd``/``aft``) and member that jams: ``lock links`` (aligned links, the
    knee at rest in the fold's null vector) or ``knee`` (the arms aligned)."""

    system: Model
    branch: Branch
    lock_up: float | None
    loads: ActuatorLoads
    lock_side: str | None = None
    lock_member: str | None = None


def retraction(geo: GearGeometry = DEFAULT_GEOMETRY, *, base: Model | None = None, max_steps: int = 300,
               arms: bool = True) -> Retraction:
    """Continue the gear from down (theta = 0) towards ``geo.retracted`` in the retraction angle.

    ``base`` is a built kinematic system to reuse (its compiled code); ``arms`` counts the sidestay
    arms' weight. Returns the :class:`Retraction`; the actuator loads cover the branch up to the
    first fold (lock-up) or the gear-up position.
    """
    base = base or build_dual_sidestay_kinematics(geo)
    system = base.with_values(geometry_values(geo)).evolve(mechanism=GearDescription(geo))
    system = system.evolve(scene=partial(loaded_scene, system))
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
        knee = [k for k, n in enumerate(system.state_names) if n.startswith(f"{side}_K_")]
        member = "knee" if np.max(np.abs(null[knee])) > 1e-6 else "lock links"
        return Retraction(system, branch, lock, loads, side, member)
    return Retraction(system, branch, lock, loads)


def lock_up_fold_curve(geo: GearGeometry, *, base: Model | None = None, span: tuple[float, float] = (0.5, 2.0),
                       max_steps: int = 300) -> tuple[Model, Branch]:
    """The lock-up fold of ``geo``'s retraction continued in two parameters, ``theta`` and the aft first
    lock-link length ``aft_L4`` (within ``span`` times its nominal value). Returns ``(system, curve)``: the
    equation system with ``geo``'s values and the fold-curve Branch (CP at cusps).

    Raises
    ------
    ValueError
        When ``geo`` retracts fully (no lock-up fold to continue).
    """
    ret = retraction(geo, base=base)
    lp = next((p for p in ret.branch.special_points if p.label.startswith("LP")), None)
    if lp is None:
        raise ValueError("this geometry retracts fully: no lock-up fold to continue")
    l4 = ret.system.as_dict(lp.x)["aft_L4"]
    opts = ContinuationOptions(bounds={"aft_L4": (span[0] * l4, span[1] * l4), "theta": (-0.1, 1.6)},
                               max_steps=max_steps)
    return ret.system, continue_folds(ret.system, lp, "theta", "aft_L4", options=opts)


def lock_up_scan(geo: GearGeometry = DEFAULT_GEOMETRY, angles: Sequence[float] | np.ndarray = PLANE_ANGLES, *,
                 base: Model | None = None,
                 max_steps: int = 300) -> tuple[np.ndarray, np.ndarray, list[Retraction]]:
    """Lock-up angle (rad, ``nan`` = retracts fully) for each aft sidestay plane angle in ``angles`` (rad)."""
    base = base or build_dual_sidestay_kinematics(geo)
    runs = [retraction(geo.with_aft_plane(a), base=base, max_steps=max_steps) for a in angles]
    lock = np.array([np.nan if r.lock_up is None else r.lock_up for r in runs])
    return np.asarray(angles, float), lock, runs


#: Frames of the retraction animation, at least (about 8 s at its frame rate).
ANIMATION_FRAMES = 48


def _fine(system: Model, branch: Branch, retracted: float) -> Branch:
    """``branch`` continued again from its first row with steps short enough for :data:`ANIMATION_FRAMES` rows
    (a step moves theta by at most the step length), for a smooth animation."""
    opts = ContinuationOptions(bounds={"theta": (-0.01, retracted)}, dsmax=retracted / ANIMATION_FRAMES,
                               ds=retracted / ANIMATION_FRAMES, max_steps=4 * ANIMATION_FRAMES, stability=False)
    return continuation(system, branch.values[0], "theta", direction=1, options=opts)


def run(out_dir: Path, quiet: bool = False, timings: dict | None = None, quick: bool = False) -> list[str]:
    """Figures into ``out_dir`` and the Markdown summary lines; ``quick`` runs a reduced study (tests)."""
    timings = timings if timings is not None else {}
    out_dir = Path(out_dir)
    geo = DEFAULT_GEOMETRY
    with timed(timings, "dual_sidestay: build"):
        base = build_dual_sidestay_kinematics(geo)
    lines = ["## Dual-sidestay main gear: retraction (representative A320-class geometry)", "",
             "Hand-formulated kinematic model (12 natural coordinates, ball-jointed lugs; docs/dual-sidestay.md), "
             f"continued in the retraction angle theta from gear down to {_deg(geo.retracted)} deg.", ""]
    lines += _retraction_part(out_dir, geo, base, timings, quick)
    lines += _rigging_part(out_dir, geo, quick)
    lines += _downlock_part(out_dir, quick)
    lines.append(_fold_curve_part(out_dir, geo, base))
    lines += _generated_part(out_dir, geo, timings, quick)
    shown = [*FIGURES, *([] if quick else [ANIMATION])]
    return [*lines, "", *(f"![{what}]({name})" for name, what in shown), ""]


#: The section's figures, shown in the summary in this order: file, what it shows.
FIGURES = (("sidestay_actuator.png", "retraction actuator load and length"),
           ("sidestay_down.png", "the gear down: three views and 3-D"),
           ("sidestay_up.png", "the gear up: three views and 3-D"),
           ("sidestay_lock_up.png", "lock-up angle against the aft sidestay plane angle"),
           ("sidestay_rigging.png", "rigid downlock against rigging error"),
           ("sidestay_downlock.png", "downlock loads, compliant and rigid sidestays"),
           ("sidestay_fold_curve.png", "the lock-up fold continued in the aft lock-link length"),
           ("sidestay_unlock.png", "unlock with overcentre stops and the unlock fold curve"),
           ("sidestay_generated.png", "the generated gear held locked"))
ANIMATION = ("sidestay_retraction.gif", "the retraction")


def _deg(v: float) -> str:
    return f"{math.degrees(v):.1f}"


def retraction_animation(ret: Retraction, geo: GearGeometry, path: Path) -> int:
    """Write the section's animation of the retraction ``ret`` (of the geometry ``geo``) to ``path`` (GIF): the gear
    in three views and 3-D beside the branch; returns the number of frames."""
    from ..outputs.animation import animate

    return animate(ret.system, _fine(ret.system, ret.branch, geo.retracted), path, annotate=("theta",),
                   diagram=("theta", "aft_J_z"), dpi=80)


def _retraction_part(out_dir: Path, geo: GearGeometry, base: Model, timings: dict, quick: bool) -> list[str]:
    """The retraction's actuator load, drawings and animation, and the lock-up against the aft plane angle."""
    from ..outputs.drawing3d import draw3d
    from ..outputs.plotting import save_figure
    from ..outputs.retraction_plots import plot_actuator_loads, plot_lock_up

    with timed(timings, "dual_sidestay: retraction"):
        ret = retraction(geo, base=base)
    loads = ret.loads
    save_figure(plot_actuator_loads(loads), out_dir / "sidestay_actuator.png")
    sys_ = ret.system
    with timed(timings, "dual_sidestay: 3-D drawings, gear down and up"):
        draw3d(sys_, ret.branch.values[0], out_dir / "sidestay_down.png", annotate=("theta",))
        draw3d(sys_, ret.branch.values[-1], out_dir / "sidestay_up.png", annotate=("theta",))
    if not quick:
        with timed(timings, "dual_sidestay: retraction animation (GIF)"):
            retraction_animation(ret, geo, out_dir / ANIMATION[0])
    angles = PLANE_ANGLES[::3] if quick else PLANE_ANGLES
    with timed(timings, "dual_sidestay: lock-up scan"):
        phi, lock, runs = lock_up_scan(geo, angles, base=base)
    save_figure(plot_lock_up(phi, lock, geo.retracted, geo.aft.phi), out_dir / "sidestay_lock_up.png")
    i_peak = int(np.argmax(np.abs(loads.tension)))
    locked = [(p, t, f"{r.lock_side} {r.lock_member}") for p, t, r in zip(phi, lock, runs) if not np.isnan(t)]
    common = min(r.loads.s[-1] for r in runs)   # loads compared up to the earliest lock-up
    at = [float(np.interp(common, r.loads.s, r.loads.tension)) for r in runs]
    free = [p for p, t in zip(phi, lock) if np.isnan(t)]
    return [f"- Retraction actuator: length {loads.length[0]:.3f} m (down) to {loads.length[-1]:.3f} m "
            f"(theta = {_deg(loads.s[-1])} deg); peak load {loads.peak / 1e3:.1f} kN "
            f"({'tension' if loads.tension[i_peak] > 0 else 'compression'}) at theta = {_deg(loads.s[i_peak])} deg; "
            f"work {loads.work / 1e3:.2f} kJ; mechanical efficiency {loads.efficiency:.3f} "
            "(work over peak load x stroke). Figure: sidestay_actuator.png; drawings sidestay_down.png, "
            "sidestay_up.png" + ("" if quick else ", animation sidestay_retraction.gif") + ".",
            f"- Geometric lock-up against the aft sidestay plane angle ({_deg(phi[0])} to {_deg(phi[-1])} deg): "
            + (", ".join(f"phi_aft = {_deg(p)} deg locks at theta = {_deg(t)} deg ({side})"
                         for p, t, side in locked) or "none")
            + "; retracts fully at phi_aft = " + (", ".join(_deg(p) for p in free) or "none") + " deg. "
            "A lock-up is a fold (LP) of the retraction branch: a lock-link pair reaches alignment and would "
            "have to stretch (go into tension) to follow. Figure: sidestay_lock_up.png.",
            f"- The actuator load hardly depends on the aft plane angle: at theta = {_deg(common)} deg it is "
            f"{min(at) / 1e3:.2f} to {max(at) / 1e3:.2f} kN over the scan (+ tension), because the sidestays fold "
            "passively and only their arms' weight changes with the plane."]


def _rigging_part(out_dir: Path, geo: GearGeometry, quick: bool) -> list[str]:
    """The rigid downlock's sensitivity to the aft attachment's rigging."""
    from ..outputs.plotting import save_figure
    from ..outputs.retraction_plots import plot_rigging

    offsets = np.linspace(-1e-3, 1e-3, 5 if quick else 9)
    aft_align, fwd_align, misfit = rigging_scan(offsets, geo)
    save_figure(plot_rigging(offsets, aft_align, fwd_align[0], misfit), out_dir / "sidestay_rigging.png")
    per_mm = float(np.polyfit(offsets * 1e3, misfit * 1e3, 1)[0])
    per_mm_angle = float(np.polyfit(offsets * 1e3, np.degrees(aft_align), 1)[0])
    nominal = 1e3 * float(np.interp(0.0, offsets, misfit))  # mm
    return [f"- Rigid downlock, rigging tolerance: the forward lock links align at theta = "
            f"{math.degrees(fwd_align[0]):.4f} deg, the aft ones at "
            f"{math.degrees(float(np.interp(0.0, offsets, aft_align))):.4f} deg; "
            f"moving the aft airframe attachment along its stay moves the aft alignment by {per_mm_angle:.4f} deg/mm "
            f"and leaves the aft links {per_mm:.2f} mm off alignment per mm of offset when the forward ones are "
            f"aligned (nominal geometry: {nominal:.3f} mm). Both pairs can be aligned at once only for one exact "
            "rigging: the rigid over-constrained downlock is highly sensitive, and its loads are set by how the "
            "structure absorbs this misfit (compliance). Figure: sidestay_rigging.png."]


def _downlock_part(out_dir: Path, quick: bool) -> list[str]:
    """The downlock loads with compliant and rigid sidestays against the aft attachment's offset."""
    from ..outputs.plotting import save_figure
    from ..outputs.retraction_plots import plot_downlock

    dl_offsets = np.linspace(-1e-3, 1e-3, 5 if quick else 11)
    compliant = [downlock_loads(o) for o in dl_offsets]
    rigid = [downlock_loads(o, stiffness=None) for o in dl_offsets]
    save_figure(plot_downlock(dl_offsets, compliant, rigid, STAY_STIFFNESS, SIDE_LOAD),
                out_dir / "sidestay_downlock.png")
    nom_c, nom_r = downlock_loads(0.0), downlock_loads(0.0, stiffness=None)
    return [f"- Downlock loads (gear down, {SIDE_LOAD / 1e3:.0f} kN outboard side load at the axle plus gravity, "
            f"sidestays as axial springs of {STAY_STIFFNESS:.1e} N/m): nominal rigging, fwd lock links "
            f"{nom_c.tension['fwd'] / 1e3:.2f} kN, aft {nom_c.tension['aft'] / 1e3:.2f} kN (both together "
            f"{(nom_c.tension['fwd'] + nom_c.tension['aft']) / 1e3:.2f} kN); over aft attachment offsets of "
            f"-1 to +1 mm the fwd load goes {compliant[0].tension['fwd'] / 1e3:.2f} to "
            f"{compliant[-1].tension['fwd'] / 1e3:.2f} kN and the aft {compliant[0].tension['aft'] / 1e3:.2f} to "
            f"{compliant[-1].tension['aft'] / 1e3:.2f} kN. Rigid sidestays: one pair carries everything "
            f"(nominal: fwd {nom_r.tension['fwd'] / 1e3:.2f} kN, aft {nom_r.tension['aft'] / 1e3:.2f} kN) and the "
            f"load jumps to the other pair within a fraction of a millimetre of rigging "
            f"(-1 mm: aft {rigid[0].tension['aft'] / 1e3:.2f} kN); only at the one exact rigging do both pairs "
            "touch alignment, and there the split is indeterminate. Compliance makes it determinate and "
            "continuous. Figure: sidestay_downlock.png. (Lock springs and overcentre stops are not "
            "modelled: loads are at lock-link alignment.)"]


def _fold_curve_part(out_dir: Path, geo: GearGeometry, base: Model) -> str:
    """The lock-up fold continued in the retraction angle and the aft first lock-link length."""
    from ..outputs.plotting import save_figure
    from ..outputs.retraction_plots import plot_fold_curve

    curve_plane = math.radians(-30.0)
    cs, curve = lock_up_fold_curve(geo.with_aft_plane(curve_plane), base=base)
    lengths, angles = curve.values[:, cs.index("aft_L4")], curve.values[:, cs.index("theta")]
    nominal_l4 = geo.with_aft_plane(curve_plane).aft.link1
    save_figure(plot_fold_curve(lengths, angles, geo.retracted, nominal_l4, curve_plane),
                out_dir / "sidestay_fold_curve.png")
    order = np.argsort(angles)
    l4_full = float(np.interp(geo.retracted, angles[order], lengths[order]))
    cusps = [p for p in curve.special_points if p.label.startswith("CP")]
    return (f"- Two-parameter fold curve (aft plane angle {_deg(curve_plane)} deg): the lock-up fold continued in "
            f"the retraction angle and the aft first lock-link length aft_L4 runs from theta = {_deg(angles.min())} "
            f"deg at {lengths[np.argmin(angles)]:.3f} m to {_deg(angles.max())} deg at "
            f"{lengths[np.argmax(angles)]:.3f} m; the lock-up moves past gear up ({_deg(geo.retracted)} deg) at "
            f"aft_L4 = {l4_full:.3f} m (nominal {nominal_l4:.3f} m). Cusps (CP) on it: {len(cusps)}. Figure: "
            "sidestay_fold_curve.png.")


def _generated_part(out_dir: Path, geo: GearGeometry, timings: dict, quick: bool) -> list[str]:
    """The gear from its spatial description: held locked with a compliant attachment, and unlocked on its stops."""
    from ..mechanism import Mechanism
    from ..outputs.drawing3d import draw3d
    from ..outputs.plotting import save_figure
    from ..outputs.retraction_plots import plot_unlock_with_stops

    with timed(timings, "dual_sidestay: generated model build"):
        gen = generated_gear(geo)
    with timed(timings, "dual_sidestay: locked generated gear"):
        held = locked_gear(gen, ATTACHMENT_STIFFNESS)
    with timed(timings, "dual_sidestay: unlock with stops"):
        unlock = unlock_study(gen, stretch=None if quick else (0.5, 1.0))
    save_figure(plot_unlock_with_stops(unlock.runs, unlock.fold_curve, UNLOCK_FORCES), out_dir / "sidestay_unlock.png")
    mid = held[len(held) // 2]
    with timed(timings, "dual_sidestay: 3-D drawing of the generated gear"):
        draw3d(gen.with_values({"k_att": mid.k_att}), mid.x, out_dir / "sidestay_generated.png",
               annotate=("F_fwd", "F_aft"))
    mech, mechanics, dof = gen.mechanism, gen.mechanics, gen.dof
    if not isinstance(mech, Mechanism) or mechanics is None or dof is None:  # a generated model has all three
        raise TypeError(f"model '{gen.name}' is not generated from a mechanism description")
    n_coords = len(mechanics.coordinates)
    return [f"- The same gear from its spatial description (examples/dual_sidestay.toml: {len(mech.bodies)} "
            f"rigid bodies, {n_coords} coordinates, {len(gen.names) - len(gen.parameter_names)} unknowns, equations "
            "generated; lock springs; tests/test_dual_sidestay_generated.py checks its retraction against the hand "
            f"model to 1e-9): {dof.dof} degree of freedom, no redundant row while the lock links are free. "
            "Holding both lock-link pairs aligned adds two conditions to one degree of freedom: with rigid "
            "attachments there is no solution (the rigging misfit above); with the aft airframe attachment "
            "compliant every reaction is determinate: "
            + "; ".join(f"k_att = {h.k_att:.0e} N/m: holding forces fwd {h.F_fwd:.1f} N, aft {h.F_aft:.1f} N, "
                        f"attachment reaction {h.reaction / 1e3:.2f} kN, deflection {h.deflection * 1e3:.4f} mm"
                        for h in held)
            + ". The deflection tends to the geometric misfit the attachment must take up, so the locked-in load "
            "grows with the stiffness: in the rigid limit it is unbounded, the highly sensitive downlock of the "
            "paper. Figure: sidestay_generated.png.",
            _unlock_line(unlock, gen)]


def _unlock_line(study: UnlockStudy, gen: Model) -> str:
    """The summary line of the unlock study (numbers in N, N m, deg)."""
    R = study.contact
    parts = []
    for f, what in UNLOCK_FORCES.items():
        rel = study.release(f)
        released = ", ".join(f"the {s.split('_')[0]} pair leaves its stop at {v:.1f} N" for s, v in rel.items())
        run = study.runs[f]
        if math.isnan(study.unlock(f)):
            end = run.branch.values[-1]
            held_by = [s for s in ("fwd_stop", "aft_stop") if end[gen.index(f"R_{s}")] > 0]
            parts.append(f"{what} ({f}): {released}; no unlock fold up to {end[gen.index(f)]:.0f} N, the "
                         + (f"{held_by[0].split('_')[0]} pair still on its stop carrying "
                            f"{end[gen.index('R_' + held_by[0])]:.0f} N m" if held_by else "links turning")
                         + " (the aft attachment deflects): one pair cannot unlock the gear alone")
        else:
            lp = run.first_fold()
            still = [s for s in ("fwd_stop", "aft_stop") if lp[f"R_{s}"] > 0]
            holds = "".join(f", the {s.split('_')[0]} pair still on its stop ({lp['R_' + s]:.0f} N m) holding the gear"
                            for s in still)
            parts.append(f"{what} ({f}): {released}; snaps through at {study.unlock(f):.1f} N (LP; fwd links "
                         f"{math.degrees(math.asin(lp['fwd_lock'])):+.2f} deg, aft "
                         f"{math.degrees(math.asin(lp['aft_lock'])):+.2f} deg past aligned{holds})")
    text = ("- Unlock with overcentre stops (generated gear; each lock-link pair rests on a stop 2 deg past aligned, "
            "`[stops]` in examples/dual_sidestay.toml; mechcont.analysis.continuation_with_stops switches a stop "
            "off where its reaction reaches zero, SR, and on where its links reach it, SC): locked under gravity "
            f"and the lock springs with stop reactions fwd {R.get('R_fwd_stop', 0.0):.1f} N m, aft "
            f"{R.get('R_aft_stop', 0.0):.1f} N m. " + "; ".join(parts) + ".")
    curve = study.fold_curve
    if curve is not None:
        st = curve.values[:, curve.names.index("stretch")]
        F = curve.values[:, curve.names.index("F_lock")]
        cusps = [p for p in curve.special_points if p.label == "CP"]
        text += (f" Two-parameter fold curve: the unlock fold of both pairs continued in the lock-spring stretch "
                 f"(free length / installed length) over {st.min():.2f} to {st.max():.2f}, unlock force "
                 f"{F.min():.1f} to {F.max():.1f} N; cusps (CP): {len(cusps)}"
                 + "".join(f", at stretch = {p['stretch']:.4f}, F_lock = {p['F_lock']:.1f} N" for p in cusps)
                 + (": with less preload than that the lock no longer snaps open (no fold, no hysteresis)"
                    if cusps else "") + ".")
    return text + " Figure: sidestay_unlock.png."


@dataclass(frozen=True)
class LockedGear:
    """The generated gear (``examples/dual_sidestay.toml``) with both lock-link pairs held aligned, at an aft
    attachment stiffness ``k_att`` (N/m): the forces holding each pair aligned (N, + towards unlocking), the
    attachment's reaction (N, on the upper arm) and deflection (m), and the full solution ``x``."""

    k_att: float
    F_fwd: float
    F_aft: float
    reaction: float
    deflection: float
    x: np.ndarray


@dataclass
class UnlockStudy:
    """Unlocking the generated gear from its downlocked state (both lock-link pairs on their overcentre stops).

    ``locked``: the downlocked full vector; ``contact``: the stop reactions there (N m, ``R_<side>_stop``);
    ``runs``: per unlock force (:data:`UNLOCK_FORCES`) its :class:`~mechcont.analysis.StopRun`, pushed from 0 up
    to its first fold (the unlock load) or ``force_bound``; ``fold_curve``: the unlock fold of both pairs
    together continued in the lock-spring ``stretch`` (cusps ``CP``), or None."""

    locked: np.ndarray
    contact: dict
    runs: dict
    fold_curve: Branch | None

    def release(self, force: str) -> dict[str, float]:
        """``{stop: force (N) at which it leaves its stop}`` along the run of ``force``."""
        b = self.runs[force].branch
        return {p.stop: p[force] for p in b.special_points if p.label == "SR"}

    def unlock(self, force: str) -> float:
        """The unlock load (N): ``force`` at the run's first fold; nan when none up to the bound."""
        lp = self.runs[force].first_fold()
        return float(lp[force]) if lp is not None else float("nan")


def unlock_study(gen: Model, *, force_bound: float = 1000.0,
                 stretch: tuple[float, float] | None = (0.5, 1.0)) -> UnlockStudy:
    """Unlock the generated gear ``gen`` with each of :data:`UNLOCK_FORCES` (N) and continue the joint unlock
    fold in the lock-spring ``stretch`` over ``stretch`` (None: no fold curve).

    The downlocked state holds both lock-link pairs on their stops (conditions ``fwd_lock``/``aft_lock`` at
    the stops' limits, the contact reactions solved for, checked >= 0 by
    :func:`~mechcont.analysis.equilibrium_on_stops`); each run is
    :func:`~mechcont.analysis.continuation_with_stops` from there, ended at its first fold."""
    from ..analysis import continuation_with_stops, equilibrium_on_stops

    model = gen
    x, contact = equilibrium_on_stops(gen, gen.defaults(), contact=[s.name for s in model.stops])
    runs = {f: continuation_with_stops(gen, x, f, direction=1, stop_at_fold=True,
                                       options=ContinuationOptions(bounds={f: (-1.0, force_bound)}, max_steps=200))
            for f in UNLOCK_FORCES}
    curve = None
    lp = runs["F_lock"].first_fold()
    if stretch is not None and lp is not None:
        curve = continue_folds(gen, lp, "F_lock", "stretch",
                               options=ContinuationOptions(bounds={"stretch": stretch, "F_lock": (0.0, 5e3)},
                                                           max_steps=100))
    return UnlockStudy(x, {s.reaction: float(x[gen.index(s.reaction)]) for s in model.stops if s.name in contact},
                       runs, curve)


def generated_gear(geo: GearGeometry = DEFAULT_GEOMETRY) -> Model:
    """The gear generated from its spatial description (:mod:`mechcont.models.dual_sidestay_description`),
    compliant aft attachment.

    The built model is kept in the disk cache under the description's text, the same entry as
    :func:`~mechcont.models.load_model` of ``examples/dual_sidestay.toml`` (the same text)."""
    from ..models import model_from_text
    from ..models.dual_sidestay_description import dual_sidestay_description

    return model_from_text(dual_sidestay_description(geo), "dual_sidestay.toml")


def locked_gear(system: Model, stiffnesses: Iterable[float]) -> list[LockedGear]:
    """Hold both lock-link pairs of the generated ``system`` aligned (conditions ``fwd_lock = aft_lock = 0``) and
    solve for the two forces ``F_fwd``, ``F_aft`` at each aft attachment stiffness (N/m). With one degree of
    freedom the two alignments are two conditions: the attachment's deflection takes up the rigging misfit."""
    from ..continuation import find_equilibrium

    out = []
    for k in stiffnesses:
        sys_k = system.with_values({"k_att": float(k)})
        x = find_equilibrium(sys_k, hold={"fwd_lock": 0.0, "aft_lock": 0.0}, free=["F_fwd", "F_aft"])
        v = sys_k.as_dict(x)
        R = float(np.linalg.norm([v[f"R_aft_A_{c}"] for c in "xyz"]))
        out.append(LockedGear(v["k_att"], v["F_fwd"], v["F_aft"], R, R / v["k_att"], x))
    return out
