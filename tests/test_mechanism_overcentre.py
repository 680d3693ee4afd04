"""The overcentre generated from its description against the hand model (eq. 6) and the closed form."""

import math

import numpy as np
import pytest

from mechcont.continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium
from mechcont.mechanism import assemble, load
from mechcont.models.overcentre import build_overcentre, symmetric_folds, symmetric_force, symmetric_stable

SYM = dict(L=1.5, m1=1.0, m2=1.0, g=9.81, k=127.0)
HAND_STATES = ("x1", "y1", "theta1", "x2", "y2", "theta2")


@pytest.fixture(scope="module")
def generated():
    return load("overcentre")


@pytest.fixture(scope="module")
def reduced():
    return load("overcentre", reduced=True)


def test_shipped_description_uses_the_hand_model_names(generated):
    hand = build_overcentre()
    assert set(hand.parameter_names) <= set(generated.parameter_names)
    assert set(HAND_STATES) <= set(generated.state_names)
    for p in hand.parameter_names:
        assert generated.variable(p).value == hand.variable(p).value
        assert generated.variable(p).unit == hand.variable(p).unit
    # one reaction per scalar constraint: two pins (x, y) and the slider (normal force)
    assert set(generated.reaction_names) == {"R_pin_x", "R_pin_y", "R_apex_x", "R_apex_y", "R_slider"}


@pytest.mark.parametrize("theta1", [-1.2, -0.5, 0.05, 0.4, 0.9, 1.3])
@pytest.mark.parametrize("LU", [0.4, 2.0])
def test_equilibrium_force_matches_closed_form(generated, reduced, theta1, LU):
    F = symmetric_force(theta1, SYM["L"], SYM["m1"], SYM["m2"], SYM["g"], SYM["k"], LU)
    for system in (generated, reduced):
        x = assemble(system, values={"LU": LU}, hold={"theta1": theta1}, free=["F"])
        assert x[system.index("F")] == pytest.approx(F, abs=1e-9 * max(1.0, abs(F)))
        assert x[system.index("theta2")] == pytest.approx(math.pi - theta1, abs=1e-12)
        n_unstable = system.mechanics.stability(x).n_unstable
        assert n_unstable == (0 if symmetric_stable(theta1, SYM["L"], LU) else 1)


@pytest.mark.parametrize("params", [dict(m=0.2, n=-0.1), dict(L2=1.2, m=0.3, n=0.25, m2=2.0), dict(L1=1.1, LU=1.0)])
def test_asymmetric_solutions_equal_the_hand_model(generated, reduced, params):
    """Hold theta1, free F: the hand model and both generated forms give the same pose and force."""
    hand = build_overcentre(**params)
    for theta1 in (-0.7, 0.2, 0.8):
        xh = find_equilibrium(hand, hold={"theta1": theta1}, free=["F"],
                              guess={"theta2": math.pi - theta1, "x1": 0.5, "y1": 0.3 * theta1,
                                     "x2": 1.5, "y2": 0.3 * theta1})
        for system in (generated, reduced):
            xg = assemble(system, values=params, hold={"theta1": theta1}, free=["F"])
            coords = system.coordinates_of(xg)
            for name in HAND_STATES:
                assert coords[name] == pytest.approx(xh[hand.index(name)], abs=1e-10)
            assert xg[system.index("F")] == pytest.approx(xh[hand.index("F")], abs=1e-9)
            assert system.mechanics.stability(xg).n_unstable == hand.mechanics.stability(xh).n_unstable


def test_reactions_balance_every_body(generated):
    """The named reactions are the inter-link forces: check the free body of bar 2 by hand."""
    x = assemble(generated, values={"LU": 0.4}, hold={"theta1": 0.6}, free=["F"])
    v = generated.as_dict(x)
    # spring force on bar 2 (tension positive pulls bar 2 towards bar 1); m = n = 0: CG to CG
    d = np.array([v["x2"] - v["x1"], v["y2"] - v["y1"]])
    length = np.linalg.norm(d)
    f_spring_on_2 = -v["k"] * (length - v["LU"]) * d / length
    # bar 2: apex force R_apex (bar 1 on bar 2), slider normal force (0, R_slider), weight, spring
    total = np.array([v["R_apex_x"], v["R_apex_y"]]) + np.array([0.0, v["R_slider"]]) \
        + np.array([0.0, -v["m2"] * v["g"]]) + f_spring_on_2
    assert np.allclose(total, 0.0, atol=1e-9)
    # the whole mechanism: ground pin + slider + weights + F balance vertically
    assert v["R_pin_y"] + v["R_slider"] - (v["m1"] + v["m2"]) * v["g"] + v["F"] == pytest.approx(0.0, abs=1e-9)


def _branch(system, LU):
    x0 = assemble(system, values={"LU": LU}, hold={"theta1": 0.3}, free=["F"])
    opts = ContinuationOptions(bounds={"F": (-150.0, 150.0), "theta1": (-1.45, 1.45)})
    return continuation(system, x0, "F", options=opts)


def test_branch_folds_and_stability_equal_hand_model_and_closed_form(generated):
    hand = build_overcentre(LU=0.4)
    xh = find_equilibrium(hand, hold={"theta1": 0.3}, free=["F"])
    bh = continuation(hand, xh, "F", options=ContinuationOptions(bounds={"F": (-150.0, 150.0),
                                                                          "theta1": (-1.45, 1.45)}))
    bg = _branch(generated, 0.4)
    assert bg.success
    # every generated point solves the hand equations; stability agrees away from the
    # folds themselves (neutral there: V'' = 0 to rounding)
    regular = np.array([lab != "LP" for lab in bg.labels])
    for row, ok in zip(bg.values, regular):
        xhand = hand.vector({n: row[generated.index(n)] for n in (*HAND_STATES, "F")})
        assert np.max(np.abs(hand.residual(xhand))) < 1e-9
        if ok:
            assert hand.mechanics.stability(xhand).n_unstable == generated.mechanics.stability(row).n_unstable
    # stability along the branch agrees with the closed form V'' > 0
    th = bg["theta1"]
    assert np.array_equal(bg.stable[regular], symmetric_stable(th, SYM["L"], 0.4)[regular])
    # folds: hand model, generated model and closed form agree to 1e-8
    lg = sorted((p["theta1"], p["F"]) for p in bg.special("LP"))
    lh = sorted((p["theta1"], p["F"]) for p in bh.special("LP"))
    lc = sorted(symmetric_folds(SYM["L"], SYM["m1"], SYM["m2"], SYM["g"], SYM["k"], 0.4))
    assert len(lg) == len(lh) == len(lc) == 2
    for a, b, c in zip(lg, lh, lc):
        assert a == pytest.approx(b, abs=1e-8)
        assert a == pytest.approx(c, abs=1e-8)


def test_no_fold_for_long_spring(generated):
    b = _branch(generated, 2.0)
    assert not b.special("LP")
    assert b.stable.all()


def test_fold_curve_matches_closed_form(generated):
    b = _branch(generated, 0.4)
    curve = continue_folds(generated, b.special("LP")[0], "F", "LU",
                           options=ContinuationOptions(bounds={"LU": (0.1, 2.0)}, max_steps=400))
    LU, th, F = curve["LU"], curve["theta1"], curve["F"]
    assert len(LU) > 20
    assert np.allclose(np.cos(th) ** 3, LU / SYM["L"], atol=1e-8)
    assert np.allclose(F, symmetric_force(th, SYM["L"], SYM["m1"], SYM["m2"], SYM["g"], SYM["k"], LU), atol=1e-7)
    cusp = curve.special("CP")
    assert len(cusp) == 1
    assert cusp[0]["LU"] == pytest.approx(SYM["L"], abs=1e-6)


def test_reduced_branch_equals_full_branch(generated, reduced):
    """The reduced form's continued branch solves the full equations (after a linear solve
    for the eliminated reactions) and has the same stability."""
    br = _branch(reduced, 0.4)
    assert br.success
    for row, label in list(zip(br.values, br.labels))[::3]:
        if label == "LP":
            continue
        coords = reduced.coordinates_of(row)
        F = row[reduced.index("F")]
        xf = generated.vector({**coords, "F": F, "LU": 0.4})
        nq = len(generated.mechanics.coordinates)
        xf[nq:nq + len(generated.reaction_names)] = generated.mechanics.multipliers(xf)
        assert np.max(np.abs(generated.residual(xf))) < 1e-9
        assert generated.mechanics.stability(xf).n_unstable == reduced.mechanics.stability(row).n_unstable
    F_closed = symmetric_force(br["theta1"], SYM["L"], SYM["m1"], SYM["m2"], SYM["g"], SYM["k"], 0.4)
    assert np.allclose(br["F"], F_closed, atol=1e-9)
