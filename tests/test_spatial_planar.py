"""Planar mechanisms described with spatial elements give the planar results.

The overcentre of the paper (Fig. 2), described in 3-D (``tests/data/spatial/overcentre_3d.toml``:
revolute joints about z, its slider an inline joint, gravity along -y), against the planar
description and the closed form: equilibria, stability, folds, the fold curve and its cusp.
"""

from pathlib import Path

import numpy as np
import pytest

from mechcont.continuation import ContinuationOptions, continuation, continue_folds
from mechcont.mechanism import assemble, load
from mechcont.models.overcentre import symmetric_folds, symmetric_force, symmetric_stable
from tests.derivative_checks import check_derivatives

DATA = Path(__file__).parent / "data" / "spatial"
SYM = dict(L=1.5, m1=1.0, m2=1.0, g=9.81, k=127.0)
BOUNDS = {"F": (-150.0, 150.0), "theta1": (-1.45, 1.45)}


@pytest.fixture(scope="module")
def spatial():
    return load(DATA / "overcentre_3d.toml")


@pytest.fixture(scope="module")
def planar():
    return load("overcentre")


def test_out_of_plane_rows_are_found_redundant_and_dropped(spatial):
    assert spatial.dof.dof == 1
    # one out-of-plane row repeats the others: the slider's normal out of the plane (along z)
    assert spatial.dropped_constraints == ("slider_n2",)
    assert set(spatial.dof.redundant_joints) == {"slider", "pin", "apex"}


def test_every_derivative_matches_finite_differences(spatial):
    check_derivatives(spatial)


@pytest.mark.parametrize("theta1", [-1.2, -0.5, 0.05, 0.4, 0.9, 1.3])
@pytest.mark.parametrize("LU", [0.4, 2.0])
def test_equilibria_and_stability_equal_closed_form(spatial, theta1, LU):
    F = symmetric_force(theta1, SYM["L"], SYM["m1"], SYM["m2"], SYM["g"], SYM["k"], LU)
    x = assemble(spatial, values={"LU": LU}, hold={"theta1": theta1}, free=["F"])
    assert x[spatial.index("F")] == pytest.approx(F, abs=1e-9 * max(1.0, abs(F)))
    assert x[spatial.index("theta2")] == pytest.approx(np.pi - theta1, abs=1e-12)
    assert spatial.mechanics.stability(x).n_unstable == (0 if symmetric_stable(theta1, SYM["L"], LU) else 1)
    # the mechanism stays in its plane
    for name in ("z1", "z2", "e1_1", "e2_1", "e1_2", "e2_2"):
        assert x[spatial.index(name)] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("params", [dict(m=0.2, n=-0.1), dict(L2=1.2, m=0.3, n=0.25, m2=2.0)])
def test_asymmetric_equilibria_and_reactions_equal_planar(spatial, planar, params):
    for theta1 in (-0.7, 0.2, 0.8):
        xs = assemble(spatial, values=params, hold={"theta1": theta1}, free=["F"])
        xp = assemble(planar, values=params, hold={"theta1": theta1}, free=["F"])
        vs, vp = spatial.as_dict(xs), planar.as_dict(xp)
        for name in ("x1", "y1", "x2", "y2", "F", "R_pin_x", "R_pin_y", "R_apex_x", "R_apex_y"):
            assert vs[name] == pytest.approx(vp[name], abs=1e-9), name
        assert vs["R_slider_1"] == pytest.approx(vp["R_slider"], abs=1e-9)  # along y
        assert spatial.mechanics.stability(xs).n_unstable == planar.mechanics.stability(xp).n_unstable


def _branch(system, LU=0.4):
    x0 = assemble(system, values={"LU": LU}, hold={"theta1": 0.3}, free=["F"])
    return continuation(system, x0, "F", options=ContinuationOptions(bounds=BOUNDS))


def test_folds_equal_planar_and_closed_form(spatial, planar):
    bs, bp = _branch(spatial), _branch(planar)
    assert bs.success
    ls = sorted((p["theta1"], p["F"]) for p in bs.special("LP"))
    lp = sorted((p["theta1"], p["F"]) for p in bp.special("LP"))
    lc = sorted(symmetric_folds(SYM["L"], SYM["m1"], SYM["m2"], SYM["g"], SYM["k"], 0.4))
    assert len(ls) == len(lp) == 2
    for a, b, c in zip(ls, lp, lc):
        assert a == pytest.approx(b, abs=1e-9)
        assert a == pytest.approx(c, abs=1e-9)
    regular = np.array([lab != "LP" for lab in bs.labels])
    assert np.array_equal(bs.stable[regular], symmetric_stable(bs["theta1"], SYM["L"], 0.4)[regular])


def test_fold_curve_and_cusp_equal_closed_form(spatial):
    b = _branch(spatial)
    curve = continue_folds(spatial, b.special("LP")[0], "F", "LU",
                           options=ContinuationOptions(bounds={"LU": (0.1, 2.0)}, max_steps=400))
    LU, th, F = curve["LU"], curve["theta1"], curve["F"]
    assert len(LU) > 20
    assert np.allclose(np.cos(th) ** 3, LU / SYM["L"], atol=1e-9)
    assert np.allclose(F, symmetric_force(th, SYM["L"], SYM["m1"], SYM["m2"], SYM["g"], SYM["k"], LU), atol=1e-8)
    cusp = curve.special("CP")
    assert len(cusp) == 1
    assert cusp[0]["LU"] == pytest.approx(SYM["L"], abs=1e-7)


# -- the four-bar linkage and the paper's nose gear --------------------------------------------
def _folds(system, hold, value, free, bounds):
    x = assemble(system, hold={hold: value}, free=[free])
    b = continuation(system, x, free, options=ContinuationOptions(bounds=bounds))
    assert b.success
    return b, sorted((p[hold], p[free]) for p in b.special("LP"))


def test_fourbar_folds_and_stability_equal_planar():
    spatial, planar = load(DATA / "fourbar_3d.toml"), load("fourbar")
    assert spatial.dropped_constraints == ("D_z", "D_rot1", "D_rot2")
    # one revolution of the crank (the conditions' 2 atan2 of Euler parameters wraps at +-2 pi)
    bounds = {"T": (-30.0, 30.0), "theta_crank": (-1.5, 4.7)}
    bs, ls = _folds(spatial, "theta_crank", 1.2, "T", bounds)
    bp, lp = _folds(planar, "theta_crank", 1.2, "T", bounds)
    assert len(ls) == len(lp) == 4
    for a, b in zip(ls, lp):
        assert a == pytest.approx(b, abs=1e-9)
    assert bs["theta_crank"][bs.stable].size > 0
    # the same equilibria have the same stability (away from the folds)
    for row, label in zip(bs.values[::5], bs.labels[::5]):
        if label == "LP":
            continue
        v = spatial.as_dict(row)
        xp = assemble(planar, values={"T": v["T"]}, hold={"theta_crank": v["theta_crank"]}, free=["T"])
        assert xp[planar.index("T")] == pytest.approx(v["T"], abs=1e-9)
        assert planar.mechanics.stability(xp).n_unstable == spatial.mechanics.stability(row).n_unstable


@pytest.fixture(scope="module")
def nose_3d():
    return load(DATA / "nose_gear_3d.toml")


@pytest.mark.slow
def test_nose_gear_derivatives_with_drag_match_finite_differences(nose_3d):
    check_derivatives(nose_3d.with_values({"U": 40.0, "alpha": 0.3}))


def test_nose_gear_unlock_fold_and_fold_curve_equal_planar(nose_3d):
    spatial, planar = nose_3d, load("nose_gear")
    assert spatial.dof.dof == 1 and len(spatial.dropped_constraints) == 6  # 3 per planar loop
    bounds = {"F": (-3e4, 3e4), "theta4": (-0.5, 0.5)}
    for values in ({}, {"U": 60.0, "alpha": 0.3}, {"psi2": -0.1, "U": 40.0}):
        xs = assemble(spatial, values=values, hold={"theta4": 0.05}, free=["F"])
        xp = assemble(planar, values=values, hold={"theta4": 0.05}, free=["F"])
        assert xs[spatial.index("F")] == pytest.approx(xp[planar.index("F")], rel=1e-9)
        for name in ("x3", "y3", "R_pivot_x", "R_pivot_y", "R_joint45_x", "R_joint45_y"):
            assert xs[spatial.index(name)] == pytest.approx(xp[planar.index(name)], rel=1e-9, abs=1e-9), name
        assert spatial.mechanics.stability(xs).n_unstable == planar.mechanics.stability(xp).n_unstable
    bs, ls = _folds(spatial, "theta4", 0.0, "F", bounds)
    bp, lp = _folds(planar, "theta4", 0.0, "F", bounds)
    assert len(ls) == len(lp) == 1
    assert ls[0] == pytest.approx(lp[0], rel=1e-9)
    assert ls[0][1] == pytest.approx(10403.721131432, rel=1e-9)   # the paper's unlock force, as planar
    # the spatial fold curve in (l_sp1, F): each of its points is the planar gear's fold at that l_sp1
    opts = ContinuationOptions(bounds={"l_sp1": (0.0, 0.2)}, max_steps=60)
    cs = continue_folds(spatial, bs.special("LP")[0], "F", "l_sp1", options=opts)
    assert len(cs.values) > 20 and cs["l_sp1"].max() == pytest.approx(0.2, abs=1e-12)
    for i in (len(cs.values) // 3, 2 * len(cs.values) // 3, len(cs.values) - 1):
        l_sp1 = cs["l_sp1"][i]
        x = assemble(planar, values={"l_sp1": l_sp1}, hold={"theta4": 0.0}, free=["F"])
        fold = continuation(planar, x, "F", options=ContinuationOptions(bounds=bounds)).special("LP")[0]
        assert fold["F"] == pytest.approx(cs["F"][i], rel=1e-9)
        assert fold["theta4"] == pytest.approx(cs["theta4"][i], abs=1e-9)
