"""The assembly of a compliant mechanism (issue 31, item 7): the released pose is the static one.

Held at a coordinate or condition, a mechanism at rest is in equilibrium with a reaction conjugate to
what is held; its compliant joints then deflect by the force they carry over their stiffness. Truth:

- tests/data/freefall_compliant_leg.toml (a 60 mm leg on a compliant hinge, held at its angle: a pure
  moment): the hinge carries the weight, so it deflects by ``m g / k`` downwards; released, the net
  force on the leg is zero (its cg does not accelerate) and it turns about its cg with
  ``alpha = -m g d sin(theta) / I_cg``; the hinge stays near its loaded deflection.
- tests/data/spatial/flap_compliant_tip.toml (mm and g in SI, frames away from the cgs, two coaxial
  rigid hinges: over-constrained, held by a cord length, a distance): the tip mass on its compliant
  weld deflects by ``m_tip g / k`` downwards whatever holds the flap; released, its cg does not accelerate.
- every compliant row's deflection equals the reaction the static equations (generated apart from the
  dynamics) give it at that pose, with the holding force solved for, over its stiffness.
- rigid mechanisms: the assembly is the kinematic one.
"""

import csv
import math

import numpy as np
import pytest
from cli_helpers import make_runner

from mechcont.dynamics import ConstrainedDynamics, assemble, simulate
from mechcont.dynamics.freefall import condition_value
from mechcont.models import load_model

LEG = "tests/data/freefall_compliant_leg.toml"
FLAP = "tests/data/spatial/flap_compliant_tip.toml"
M, K, D, IXX = 0.05, 2.0e4, 0.03, 1.5e-5          # the leg: mass, hinge stiffness, hinge to cg, inertia at the cg
M_TIP, K_TIP = 0.008, 500.0                        # the flap's tip mass and its weld's stiffness
M_FLAP, IXX_FLAP, IXX_TIP = 0.012, 1.6e-6, 3.0e-7  # the flap's mass; both bodies' inertias about x at their cgs
G = 9.81


@pytest.fixture(scope="module")
def leg():
    return load_model(LEG)


@pytest.fixture(scope="module")
def flap():
    return load_model(FLAP)


def static_reactions(model, x, held):
    """The reactions of every constraint row at the pose ``x`` from the static system's equilibrium rows
    (least squares, the holding force conjugate to each ``held`` condition solved for too): ``{name: value}``."""
    coords = model.mechanics.coordinates
    nq = len(coords)
    names = list(model.reaction_names)
    y = np.array(x, float)
    y[[model.index(n) for n in names]] = 0.0
    G_, J = model.residual_and_jacobian(y)
    qi = [model.index(c) for c in coords]
    rows = list(model.equation_names)
    grads = [J[rows.index(f"cond_{h}"), qi] for h in held]
    A = np.hstack([J[:nq][:, [model.index(n) for n in names]], np.array(grads).reshape(-1, nq).T])
    sol, *_ = np.linalg.lstsq(A, -G_[:nq], rcond=None)
    assert np.max(np.abs(A @ sol + G_[:nq])) < 1e-9 * max(1.0, np.max(np.abs(G_[:nq])))  # in equilibrium
    return dict(zip(names, sol[:len(names)]))


def spring_laws(model, x, held):
    """``(deflection, reaction / stiffness)`` of each compliant row at ``x``: its residual ``Phi - lambda/k``
    with lambda = 0 is ``Phi``; ``lambda`` from :func:`static_reactions`; ``1/k`` from the row's Jacobian."""
    from mechcont.mechanism import compliant_constraints as _compliant

    lam = static_reactions(model, x, held)
    y = np.array(x, float)
    y[[model.index(n) for n in model.reaction_names]] = 0.0
    res = model.residual(y)
    return [(res[row], -c * lam[r]) for row, r, c in _compliant(model, x)]


def point_accelerations(model, x, qdd, body):
    """World accelerations (m/s^2) of ``body``'s points at rest: ``J_p qdd`` (central differences of the scene)."""
    q = [model.index(c) for c in model.mechanics.coordinates]
    h = 1e-6

    def points(s):
        y = np.array(x, float)
        y[q] += s * qdd
        return dict(model.scene(y).bars)[body]

    return (points(h) - points(-h)) / (2 * h)


def release(model, x):
    """Accelerations of the coordinates just after release at rest at ``x`` (no Baumgarte terms: exact rows)."""
    dyn = ConstrainedDynamics(model, x, baumgarte=None)
    return dyn.acceleration(0.0, x[dyn.q_index], np.zeros(dyn.nq))


def test_leg_hinge_deflects_by_its_weight_over_k_and_is_released_without_a_snap(leg):
    theta = 1.2
    x = assemble(leg, {"angle": theta}, hold=["angle"])
    assert condition_value(leg, x, "angle") == theta
    hinge = np.array([x[leg.index(c)] for c in ("x_leg", "y_leg", "z_leg")])  # the leg's frame is at its hinge
    assert hinge == pytest.approx([0.0, 0.0, -M * G / K], rel=1e-6, abs=1e-6 * M * G / K)
    for phi, law in spring_laws(leg, x, ["angle"]):
        assert phi == pytest.approx(law, rel=1e-6, abs=1e-9 * M * G / K)
    a = point_accelerations(leg, x, release(leg, x), "leg")  # points O, act, tip; the cg halfway from O to tip
    assert np.linalg.norm((a[0] + a[2]) / 2) < 1e-8 * G      # the spring carries the weight: no net force
    r = dict(leg.scene(x).bars)["leg"][2] - dict(leg.scene(x).bars)["leg"][0]
    rel = a[2] - a[0]
    alpha = (rel[2] * r[1] - rel[1] * r[2]) / (r[1] ** 2 + r[2] ** 2)
    assert alpha == pytest.approx(-M * G * D * math.sin(theta) / IXX, rel=1e-6)
    # the first 5 ms: the hinge moves by what the changing reaction gives it; the kinematic assembly (the
    # old one, the compliant hinge moved freely) snaps it back by tens of millimetres
    t = np.linspace(0.0, 0.005, 201)
    swing = {}
    for kinematic in (False, True):
        y = assemble(leg, {"angle": theta}, hold=["angle"], kinematic=kinematic)
        run = simulate(leg, y, (0.0, 0.005), t_eval=t, rtol=1e-9, atol=1e-12)
        p = np.c_[run["x_leg"], run["y_leg"], run["z_leg"]]
        swing[kinematic] = float(np.max(np.linalg.norm(p - p[0], axis=1)))
    assert swing[False] < 2 * M * G / K < 1e-3 * swing[True]


def test_flap_tip_over_constrained_mm_scale_deflects_by_its_weight_over_k(flap):
    """Held by a distance (a cord): the holding force is a pair of forces along it. The tip's weld point sits
    ``m_tip g / k`` below the flap's, whatever the cord length; the hinges' split is indeterminate (dropped
    rows), the pose is not."""
    for cord in (0.025, 0.035):
        x = assemble(flap, {"cord": cord}, hold=["cord"])
        assert condition_value(flap, x, "cord") == pytest.approx(cord, abs=1e-15)
        assert np.max(np.abs(flap.mechanics.phi(x))) < 1e-12
        bars = dict(flap.scene(x).bars)
        assert bars["tip"][0] - bars["flap"][3] == pytest.approx([0.0, 0.0, -M_TIP * G / K_TIP], abs=1e-6 * M_TIP * G / K_TIP)
        for phi, law in spring_laws(flap, x, ["cord"]):
            assert phi == pytest.approx(law, rel=1e-6, abs=1e-9 * M_TIP * G / K_TIP)
        a = point_accelerations(flap, x, release(flap, x), "tip")
        assert np.linalg.norm(a[1]) < 1e-7 * G                # the tip's cg: its spring carries its weight
        y = assemble(flap, {"cord": cord}, hold=["cord"], kinematic=True)
        assert np.linalg.norm(point_accelerations(flap, y, release(flap, y), "tip")[1]) > 10 * G


def test_flap_held_by_its_angle_or_not_held(flap):
    """Held by an angle (a moment) the tip deflects the same. Nothing held, the flap is not held either: it
    starts to fall from where the kinematic assembly puts it, with its tip loaded so that the two start as one
    rigid body turning about the hinge axis (x): the weld's two points accelerate together and
    ``alpha = M_x / I_x`` (gravity's moment and the inertia about the axis, the cgs where they are, to first
    order in the deflection); from the kinematic assembly the tip snaps on its spring instead."""
    x = assemble(flap, {"flap": 0.4}, hold=["flap"])
    assert condition_value(flap, x, "flap") == 0.4
    bars = dict(flap.scene(x).bars)
    assert bars["tip"][0] - bars["flap"][3] == pytest.approx([0.0, 0.0, -M_TIP * G / K_TIP], abs=1e-6 * M_TIP * G / K_TIP)
    snap, alpha, rigid = {}, {}, {}
    for kinematic in (False, True):
        y = assemble(flap, flap.defaults(), kinematic=kinematic)
        qdd = release(flap, y)
        a_flap, a_tip = point_accelerations(flap, y, qdd, "flap"), point_accelerations(flap, y, qdd, "tip")
        snap[kinematic] = np.linalg.norm(a_tip[0] - a_flap[3]) / np.linalg.norm(a_tip[0])
        bars = dict(flap.scene(y).bars)
        r, rel = bars["flap"][3] - bars["flap"][0], a_flap[3] - a_flap[0]  # tip and hinge points of the flap
        alpha[kinematic] = (rel[2] * r[1] - rel[1] * r[2]) / (r[1] ** 2 + r[2] ** 2)
        cg_flap, cg_tip = bars["flap"][4], bars["tip"][1]
        inertia = (IXX_FLAP + M_FLAP * (cg_flap[1] ** 2 + cg_flap[2] ** 2)
                   + IXX_TIP + M_TIP * (cg_tip[1] ** 2 + cg_tip[2] ** 2))
        rigid[kinematic] = -G * (M_FLAP * cg_flap[1] + M_TIP * cg_tip[1]) / inertia
    assert snap[False] < 1e-9 and snap[True] > 0.1
    # one rigid body to first order: the weld's rows keep their deflection (m_tip g / k) fixed in space
    # while the flap turns, so the tip's start differs from the rigid turn by that over its lever
    assert alpha[False] == pytest.approx(rigid[False], rel=2 * M_TIP * G / K_TIP / 0.04)
    assert alpha[True] != pytest.approx(rigid[True], rel=1e-2)


@pytest.mark.parametrize("path, hold", [("examples/freefall_leg.toml", {"angle": 3.0}),
                                        ("examples/main_gear.toml", {"theta4": 0.2}),
                                        ("tests/data/spatial/fourbar_3d.toml", {"theta_crank": 0.5}),
                                        ("tests/data/freefall_pendulum.toml", {"angle": 1.0})])
def test_rigid_mechanisms_keep_their_kinematic_assembly(path, hold):
    model = load_model(path)
    x = assemble(model, dict(hold), hold=list(hold))
    y = assemble(model, dict(hold), hold=list(hold), kinematic=True)
    assert np.max(np.abs(x - y)) <= 1e-12 * max(1.0, np.max(np.abs(y)))
    assert np.max(np.abs(model.mechanics.phi(x)), initial=0.0) < 1e-9


def test_cli_simulate_and_freefall_start_from_the_static_pose(tmp_path):
    run = make_runner()
    first = {}
    for cmd, opt in (("simulate", "--start"), ("freefall", "--start")):
        out = tmp_path / f"{cmd}.csv"
        args = [cmd, LEG, opt, "angle=1.2", "--until", "0.001", "--out", out]
        res = run(*(args + (["--lock", "downlock"] if cmd == "freefall" else ["--no-progress"])))
        assert res.exit_code == 0, res.output
        assert "compliant joints" not in res.output  # the warning of the kinematic assembly is gone
        with open(out) as fh:
            first[cmd] = next(csv.DictReader(fh))
    for row in first.values():
        assert float(row["z_leg [m]"]) == pytest.approx(-M * G / K, rel=1e-6)
        assert abs(float(row["y_leg [m]"])) < 1e-12


@pytest.mark.slow
def test_dual_sidestay_released_from_gear_up_with_its_attachment_loaded():
    """examples/dual_sidestay.toml (63 coordinates; built once, then cached) released by ``freefall`` from gear
    up without ``held_by``: the aft attachment is off its airframe point by its force over its stiffness (the
    force from the static equations at that pose, the holding moment solved for), not dragged hundreds of
    millimetres as by the kinematic assembly; the lock links are where the actuator-held pose has them
    (the stays carry the same loads whatever holds the rigid fitting)."""
    from mechcont.dynamics.freefall import freefall
    from mechcont.paper import freefall_sidestay as fs

    model = load_model("examples/dual_sidestay.toml")
    run = freefall(model, {"theta": fs.SIDESTAY_UP}, lock=list(fs.LOCKS), until=1e-3, rtol=1e-6, atol=1e-8)
    x = run.history.values[0]
    assert condition_value(model, x, "theta") == pytest.approx(fs.SIDESTAY_UP, abs=1e-12)
    lam = static_reactions(model, x, ["theta"])
    force = np.linalg.norm([lam[f"R_aft_A_{c}"] for c in "xyz"])
    assert fs.attachment_offset(model, x) == pytest.approx(force / model.as_dict(x)["k_att"], rel=1e-6)
    assert fs.attachment_offset(model, x) < 1e-4 < 0.1 < fs.kinematic_offset(model)[0]
    held = fs.retracted(model)  # --held-by F_act
    for lock in ("fwd_lock", "aft_lock"):
        assert condition_value(model, x, lock) == pytest.approx(condition_value(model, held, lock), abs=1e-9)


ARM = """
[mechanism]
name = "arm_soft_hinge"
dimension = 3

[parameters]
g = { value = 9.81, unit = "m/s^2" }
k_rot = { value = 1000.0, unit = "N m/rad" }

[ground]
O = [0, 0, 0]

[bodies.arm]
mass = 0.1
inertia = [1e-5, 2e-5, 3e-5]
cg = [0.1, 0.05, 0]
points = { O = [0, 0, 0], end = [0.2, 0.1, 0] }

[joints.hinge]
type = "revolute"
a = "ground.O"
b = "arm.O"
axis = [1, 0, 0]
rotational_stiffness = "k_rot"

[gravity]
g = "g"

[conditions]
angle = { expr = "2*atan2(e1_arm, e0_arm)", unit = "rad" }
"""


def test_rotational_compliance_tilts_the_hinge_by_the_moment_over_k():
    """An arm on a hinge whose rotational rows are compliant, its cg off along the axis: held at its angle,
    the hinge tilts by the weight's moment across the axis over ``k_rot`` (0.1 kg at 0.1 m: 1e-4 rad; the
    lever moves by that much: 1e-3), each row by its reaction over its stiffness."""
    from mechcont.models import model_from_text

    arm = model_from_text(ARM, "arm_soft_hinge.toml")
    theta = 0.3
    x = assemble(arm, {"angle": theta}, hold=["angle"])
    e = np.array([x[arm.index(f"e{i}_arm")] for i in range(4)])
    tilt = 2 * math.asin(math.hypot(e[2], e[3]))           # rotation away from the hinge's axis x
    across = 0.1 * 9.81 * 0.1                               # the weight's moment about the perpendicular axis
    assert tilt == pytest.approx(across / 1000.0, rel=1e-3)
    for phi, law in spring_laws(arm, x, ["angle"]):
        assert phi == pytest.approx(law, rel=1e-6, abs=1e-9 * across / 1000.0)


def test_bennett_linkage_compliant_and_unheld_starts_with_its_deflections_kept():
    """tests/data/spatial/bennett_compliant.toml: the Bennett linkage, mobile only by its special geometry,
    with joint D compliant (translation and rotation): closed as if rigid it still has its one motion, which
    nothing holds. Released under gravity, the compliant rows' deflections start with no acceleration
    (``Phi_c'' = Phi_c,q qddot`` at rest, relative to ``qddot``); from the kinematic assembly (deflections
    zero, unloaded) they snap."""
    from mechcont.mechanism import compliant_constraints as _compliant

    model = load_model("tests/data/spatial/bennett_compliant.toml")
    q = [model.index(c) for c in model.mechanics.coordinates]
    rows = [row for row, _, _ in _compliant(model, model.defaults())]
    snap = {}
    for kinematic in (False, True):
        x = assemble(model, model.defaults(), kinematic=kinematic)
        qdd = release(model, x)
        snap[kinematic] = np.max(np.abs(model.jacobian(x)[rows][:, q] @ qdd)) / np.max(np.abs(qdd))
    # deflected by ~1e-7 m (k = 1e8 N/m) the linkage keeps its mobility only to that over its size (0.5 m)
    assert snap[False] < 1e-6 < 0.1 < snap[True]
