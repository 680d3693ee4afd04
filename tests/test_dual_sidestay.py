"""Dual-sidestay main gear retraction: actuator load by virtual work against a moment balance about the
trunnion and against finite differences, lock-up folds against a hand-derived tangency condition,
3-D drawings of the gear, and a reduced run of the paper section."""

from __future__ import annotations

import math
import re
from dataclasses import replace

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from figure_checks import check_figure  # noqa: E402

from mechcont.models.dual_sidestay import build_dual_sidestay_kinematics, points_at  # noqa: E402
from mechcont.models.dual_sidestay_geometry import DEFAULT_GEOMETRY, trunnion_axis  # noqa: E402
from mechcont.paper import dual_sidestay as paper  # noqa: E402


@pytest.fixture(scope="module")
def base():
    return build_dual_sidestay_kinematics()


@pytest.fixture(scope="module")
def run_default(base):
    return paper.retraction(DEFAULT_GEOMETRY, base=base)


def test_branch_satisfies_the_constraints_by_hand(run_default):
    """Every branch point: arm and link lengths and the plane conditions, from the points alone."""
    r = run_default
    geo = DEFAULT_GEOMETRY
    for x in r.branch.values[::10]:
        p = points_at(r.system, x)
        for side, st in (("fwd", geo.forward), ("aft", geo.aft)):
            A, B, K, J, P = (p[f"{side}_{n}"] for n in "ABKJP")
            assert np.linalg.norm(K - A) == pytest.approx(st.upper, abs=1e-9)
            assert np.linalg.norm(K - B) == pytest.approx(st.lower, abs=1e-9)
            assert np.linalg.norm(J - K) == pytest.approx(st.link1, abs=1e-9)
            assert np.linalg.norm(J - P) == pytest.approx(st.link2, abs=1e-9)
            assert abs((K - A) @ st.normal) < 1e-9 and abs((J - A) @ st.normal) < 1e-9
    assert r.lock_up is None and r.branch.values[-1, r.system.index("theta")] == pytest.approx(geo.retracted)


def test_actuator_load_by_virtual_work_equals_the_moment_balance_about_the_trunnion(base):
    """Massless sidestays: T (C - D)/|C - D| at D and the weight at the cg have no net moment about the
    trunnion axis (statics of the fitting), independent of the branch-rate code."""
    geo = replace(DEFAULT_GEOMETRY, forward=replace(DEFAULT_GEOMETRY.forward, upper_mass=0.0, lower_mass=0.0),
                  aft=replace(DEFAULT_GEOMETRY.aft, upper_mass=0.0, lower_mass=0.0))
    r = paper.retraction(geo, base=base, arms=False)
    e = trunnion_axis(geo.delta)
    for x, t in zip(r.branch.values[::7], r.loads.tension[::7]):
        p = points_at(r.system, x)
        u = (p["C"] - p["D"]) / np.linalg.norm(p["C"] - p["D"])
        arm = np.cross(p["D"], u) @ e
        weight = np.cross(p["cg"], [0.0, 0.0, -geo.fitting_mass * geo.g]) @ e
        assert t == pytest.approx(-weight / arm, rel=1e-9)


def test_virtual_work_with_the_arms_weight_matches_finite_differences(run_default):
    """T = -dV/dl: central differences of V (all weights, points from the branch) over dl along the branch."""
    r = run_default
    geo = DEFAULT_GEOMETRY
    xs = r.branch.values

    def potential(x):
        p = points_at(r.system, x)
        v = geo.fitting_mass * geo.g * p["cg"][2]
        for side, st in (("fwd", geo.forward), ("aft", geo.aft)):
            v += st.upper_mass * geo.g * (p[f"{side}_A"][2] + p[f"{side}_K"][2]) / 2
            v += st.lower_mass * geo.g * (p[f"{side}_K"][2] + p[f"{side}_B"][2]) / 2
        return v

    from mechcont.continuation import find_equilibrium

    def length(x):
        p = points_at(r.system, x)
        return np.linalg.norm(p["D"] - p["C"])

    h = 1e-6
    it = r.system.index("theta")
    for x, t in zip(xs[::9], r.loads.tension[::9]):
        plus, minus = (find_equilibrium(r.system, values={"theta": x[it] + sgn * h}, guess=x, tol=1e-13,
                                        residual_tol=1e-13) for sgn in (1, -1))
        fd = -(potential(plus) - potential(minus)) / (length(plus) - length(minus))
        assert t == pytest.approx(fd, rel=1e-5)
    # work: the actuator lifts the gear; -integral T dl equals the rise of V to the accuracy of the trapezoid rule
    V = np.array([potential(x) for x in xs])
    assert r.loads.work == pytest.approx(V[-1] - V[0], rel=2e-2)
    assert 0 < r.loads.efficiency <= 1


def test_lock_up_is_the_hand_derived_tangency_of_the_lock_links(base):
    """At a lock-up fold the lock links' circle in the fold plane touches the sphere about P: with P' the
    projection of P onto the plane and d its distance, |K - P'| = L4 + sqrt(L5^2 - d^2)."""
    geo = DEFAULT_GEOMETRY.with_aft_plane(math.radians(-30.0))
    r = paper.retraction(geo, base=base)
    assert r.lock_up is not None and (r.lock_side, r.lock_member) == ("aft", "lock links")
    lp = next(p for p in r.branch.special_points if p.label.startswith("LP"))
    p = points_at(r.system, lp.x)
    st = geo.aft
    K, P = p["aft_K"], p["aft_P"]
    d = (P - st.A) @ st.normal
    P_in = P - d * st.normal
    assert np.linalg.norm(K - P_in) == pytest.approx(st.link1 + math.sqrt(st.link2**2 - d**2), abs=1e-7)
    # with the gear down the links are not yet aligned (their joint sits lock_sag off the line)
    early = points_at(r.system, r.branch.values[0])
    K, P = early["aft_K"], early["aft_P"]
    d = (P - st.A) @ st.normal
    assert np.linalg.norm(K - (P - d * st.normal)) < st.link1 + math.sqrt(st.link2**2 - d**2) - 1e-4


def test_gear_drawing_three_view(run_default, tmp_path):
    from mechcont.outputs.drawing3d import draw3d

    axes = draw3d(run_default.system, run_default.branch.values[-1], tmp_path / "up.png", annotate=("theta",))
    fig = axes["front"].figure
    check_figure(fig, "dual sidestay")
    (legend,) = fig.legends   # bodies named by their colour in the 3-D view, by labels in the others
    assert {"fitting", "fwd lock links", "aft upper"} <= {t.get_text() for t in legend.get_texts()}
    assert {"fitting", "fwd lock links", "aft upper"} <= {t.get_text() for t in axes["front"].texts}
    loads = axes["3d"].get_title()   # the loads under the 3-D panel's title, not in a box over its axes
    assert not axes["3d"].texts
    assert any(part.startswith("actuator = ") and "compression" in part
               for line in loads.splitlines() for part in line.split(", "))


@pytest.mark.slow
def test_paper_section_quick(shared):
    """The section's quick run: the one tests/test_figure_review.py reviews, made once per session."""
    from test_figure_review import section_run

    run = section_run("dual_sidestay", shared)
    text = "\n".join(run.lines)
    assert "mechanical efficiency" in text and "kN" in text and "locks at theta" in text
    # the generated gear, both lock-link pairs held: the locked-in load grows with the attachment stiffness
    held = re.findall(r"attachment reaction ([0-9.]+) kN, deflection ([0-9.]+) mm", text)
    assert len(held) == 3
    loads = [float(r) for r, _ in held]
    assert loads[0] < loads[1] < loads[2]
    for name in ("sidestay_actuator.png", "sidestay_down.png", "sidestay_up.png", "sidestay_lock_up.png",
                 "sidestay_rigging.png", "sidestay_downlock.png", "sidestay_fold_curve.png",
                 "sidestay_generated.png"):
        assert run.sizes[name] > 0


def test_cli_continue_draw_animate_the_spatial_gear(tmp_path):
    """The built-in spatial model through the ordinary commands: a branch, a three-view, an animation."""
    from cli_helpers import make_runner, one_line_error
    from PIL import Image

    run = make_runner()
    branch = tmp_path / "b.csv"
    r = run("continue", "dual_sidestay_kinematics", "--vary", "theta", "--bounds", "theta=0:0.6", "--out", branch,
            "--quiet")
    assert r.exit_code == 0, r.output
    r = run("draw", "dual_sidestay_kinematics", "--point", f"{branch}:EP2", "--out", tmp_path / "d.png")
    assert r.exit_code == 0, r.output
    with Image.open(tmp_path / "d.png") as im:
        assert im.size[0] >= 800
    r = run("animate", "dual_sidestay_kinematics", "--branch", branch, "--every", 20, "--out", tmp_path / "a.gif",
            "--no-progress")
    assert r.exit_code == 0, r.output
    one_line_error(run("draw", "dual_sidestay_kinematics", "--set", "bogus=1", "--out", tmp_path / "e.png"),
                   "bogus")


def test_alignment_angle_is_the_continuation_fold_of_the_locked_links(base):
    """The closed-form alignment angle (knee from circle-sphere intersection, misfit root) equals the fold
    (LP) that continuation finds when the forward lock links start on their locked side."""
    from mechcont.continuation import ContinuationOptions, continuation
    from mechcont.models.dual_sidestay import geometry_values

    geo = DEFAULT_GEOMETRY
    x = base.defaults()
    st = geo.forward
    v = (st.P - st.K) / np.linalg.norm(st.P - st.K)
    locked = st.K + 2 * ((st.J - st.K) @ v) * v - (st.J - st.K)   # J mirrored across the K-P line
    for i, c in enumerate("xyz"):
        x[base.index(f"fwd_J_{c}")] = locked[i]
    b = continuation(base, x, "theta", direction=-1,
                     options=ContinuationOptions(bounds={"theta": (-0.01, 0.01)}, max_steps=100, stability=False))
    lp = next(p for p in b.special_points if p.label.startswith("LP"))
    theta = paper.alignment_angle(geometry_values(geo), "fwd")
    assert lp.x[base.index("theta")] == pytest.approx(theta, abs=1e-12)
    assert paper.lock_misfit({**geometry_values(geo), "theta": theta}, "fwd") == pytest.approx(0.0, abs=1e-12)


def test_rigging_offset_moves_the_misfit_the_way_a_longer_stay_must():
    """Offsets of opposite sign give misfits of opposite sign about the nominal one, and zero offset leaves the
    aft alignment where the unperturbed closed form puts it."""
    from mechcont.models.dual_sidestay import geometry_values

    aft, fwd, misfit = paper.rigging_scan([-5e-4, 0.0, 5e-4])
    assert aft[1] == pytest.approx(paper.alignment_angle(geometry_values(DEFAULT_GEOMETRY), "aft"), abs=1e-15)
    assert (misfit[0] - misfit[1]) * (misfit[2] - misfit[1]) < 0
    assert misfit[1] == pytest.approx(paper.lock_misfit({**geometry_values(DEFAULT_GEOMETRY), "theta": fwd[0]},
                                                        "aft"), abs=1e-15)


def test_compliant_downlock_is_the_constrained_energy_minimum():
    """The KKT solution equals an independent constrained minimisation (SLSQP) of the potential
    V(theta) + sum k delta^2 / 2 subject to both misfits <= 0, and its tensions balance the load moment
    (virtual work in theta)."""
    from scipy.optimize import brentq, minimize, minimize_scalar

    from mechcont.models.dual_sidestay import geometry_values
    from mechcont.models.dual_sidestay_geometry import rotation

    geo, k, S, off = DEFAULT_GEOMETRY, paper.STAY_STIFFNESS, paper.SIDE_LOAD, 4e-4
    r = paper.downlock_loads(off)
    values = geometry_values(geo)
    values.update({f"aft_A_{c}": float(a + off * uc) for c, a, uc in zip("xyz", geo.aft.A, geo.aft.u)})
    e = trunnion_axis(geo.delta)

    R0 = rotation(e, 0.0)
    v0 = geo.fitting_mass * geo.g * (R0 @ geo.cg)[2] - S * (R0 @ geo.axle)[1]

    def potential(z):   # J above gear down; theta in mrad, stretches in mm for a well-scaled problem
        R = rotation(e, z[0] * 1e-3)
        return (geo.fitting_mass * geo.g * (R @ geo.cg)[2] - S * (R @ geo.axle)[1] - v0
                + 0.5 * k * ((z[1] * 1e-3) ** 2 + (z[2] * 1e-3) ** 2))

    cons = [{"type": "ineq", "fun": (lambda z, s=s, i=i: -1e3 * paper._g(values, s, z[0] * 1e-3, z[i] * 1e-3,
                                                                          geo))}
            for i, s in ((1, "fwd"), (2, "aft"))]
    z0 = [r.theta * 1e3 + 0.1, 1.0, 1.0]
    best = minimize(potential, z0, constraints=cons, method="SLSQP", options={"ftol": 1e-14, "maxiter": 500})
    # SLSQP stops at the optimum either cleanly (0) or when no line search can improve it further (8)
    assert best.status in (0, 8), best.message
    assert all(c["fun"](best.x) > -1e-6 for c in cons)
    ours = [r.theta * 1e3, r.stretch["fwd"] * 1e3, r.stretch["aft"] * 1e3]
    assert potential(ours) <= potential(best.x) + 1e-6
    assert best.x[0] * 1e-3 == pytest.approx(r.theta, abs=1e-7)
    assert best.x[1] * 1e-3 == pytest.approx(r.stretch["fwd"], rel=1e-4)
    assert best.x[2] * 1e-3 == pytest.approx(r.stretch["aft"], rel=1e-4)
    # SLSQP ends with "positive directional derivative" anywhere within ~2e-5 of the stretches (where
    # depends on the BLAS's rounding), so it only confirms the active set: both pairs aligned. Along
    # that set each stretch is the root of its misfit and the potential a function of theta alone:
    # minimised by Brent's method it fixes the stretches to ~4e-8.
    active = [c["fun"](best.x) < 1e-6 for c in cons]
    assert active == [True, True]

    def stretch(side, theta):
        return brentq(lambda u: paper._g(values, side, theta, u, geo), 0.0, 5e-3, xtol=1e-16)

    def along(theta):
        return potential([theta * 1e3, stretch("fwd", theta) * 1e3, stretch("aft", theta) * 1e3])

    th = minimize_scalar(along, bracket=(r.theta - 1e-5, r.theta + 1e-5), tol=1e-12).x
    assert th == pytest.approx(r.theta, abs=1e-9)
    assert stretch("fwd", th) == pytest.approx(r.stretch["fwd"], rel=1e-6)
    assert stretch("aft", th) == pytest.approx(r.stretch["aft"], rel=1e-6)
    assert all(t > 0 for t in r.tension.values()) and all(abs(m) < 1e-9 for m in r.misfit.values())


def test_rigid_downlock_load_switches_pairs_at_the_exact_rigging():
    """Rigid sidestays: all the load on the pair that aligns first; it moves to the other pair where the
    closed-form misfit of the aft pair at the forward alignment changes sign."""
    from scipy.optimize import brentq

    exact = brentq(lambda o: paper.rigging_scan([o])[2][0], -1e-3, 1e-3, xtol=1e-12)
    below, above = (paper.downlock_loads(exact + d, stiffness=None) for d in (-2e-5, 2e-5))
    assert below.tension["fwd"] == 0.0 and below.tension["aft"] > 0
    assert above.tension["aft"] == 0.0 and above.tension["fwd"] > 0


def test_lock_up_fold_curve_points_are_lock_link_alignments(base):
    """Every point of the two-parameter lock-up fold curve (theta, aft_L4) satisfies the hand-derived
    tangency of the aft lock links, and the curve moves the lock-up with the link length."""
    geo = DEFAULT_GEOMETRY.with_aft_plane(math.radians(-30.0))
    system, curve = paper.lock_up_fold_curve(geo, base=base, span=(0.9, 1.2), max_steps=60)
    assert len(curve.values) > 3
    for x in curve.values:   # the hint only picks which of the two closed-form knee positions
        hint = points_at(system, x)["aft_K"]
        assert paper.lock_misfit(system.as_dict(x), "aft", geo, knee_hint=hint) == pytest.approx(0.0, abs=1e-8)
    th, l4 = curve.values[:, system.index("theta")], curve.values[:, system.index("aft_L4")]
    assert np.ptp(l4) > 0.05 and np.ptp(th) > math.radians(1.0)


def test_the_model_is_rebuilt_from_its_description(base):
    """The model's description (``mechanism``) holds the geometry it was built from and builds the same gear at
    other values: the gear-down knee of the rebuilt model solves the rebuilt equations."""
    from dataclasses import replace

    from mechcont.models.dual_sidestay import geometry_of
    from mechcont.models.overcentre import build_overcentre

    assert geometry_of(base) is DEFAULT_GEOMETRY
    geo = DEFAULT_GEOMETRY.with_aft_plane(DEFAULT_GEOMETRY.aft.phi + 0.05)
    moved = replace(base.mechanism, geometry=geo).build(delta=DEFAULT_GEOMETRY.delta + 0.01)
    assert geometry_of(moved) is geo and moved.variable("delta").value == pytest.approx(DEFAULT_GEOMETRY.delta + 0.01)
    assert np.max(np.abs(moved.residual(moved.defaults()))) < 1e-9   # gear-down pose of geo, delta moved: theta = 0
    with pytest.raises(TypeError, match="GearGeometry"):
        geometry_of(build_overcentre())
