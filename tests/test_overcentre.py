"""The paper's overcentre (eq. 6) against the closed form derived from its potential energy."""

import numpy as np
import pytest
import sympy as sp

from mechcont.continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium, locate_fold
from mechcont.models import build_overcentre
from mechcont.models.overcentre import symmetric_cusp, symmetric_folds, symmetric_force, symmetric_stable

P = dict(L=1.5, m1=1.0, m2=1.0, g=9.81, k=127.0)


def branch_at(LU, theta_bound=1.3, **kw):
    s = build_overcentre(LU=LU, **kw)
    x0 = find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])
    return s, continuation(s, x0, "F", options=ContinuationOptions(bounds={"theta1": (-theta_bound, theta_bound)}))


@pytest.mark.parametrize("LU", [0.1, 0.4, 0.8, 1.2, 1.45])
def test_both_folds_match_closed_form(LU):
    s, b = branch_at(LU)
    expected = symmetric_folds(P["L"], P["m1"], P["m2"], P["g"], P["k"], LU)
    lps = sorted(b.special("LP"), key=lambda p: p["theta1"])
    assert len(lps) == 2
    for lp, (th, F) in zip(lps, expected):
        assert lp["theta1"] == pytest.approx(th, rel=1e-8)
        assert lp["F"] == pytest.approx(F, rel=1e-8)
        assert np.max(np.abs(s.residual(lp.x))) < 1e-10


def test_single_stable_branch_without_folds_at_long_spring():
    s, b = branch_at(2.0)
    assert not b.special("LP")
    assert np.all(b.stable)
    assert np.allclose(b["F"], symmetric_force(b["theta1"], P["L"], P["m1"], P["m2"], P["g"], P["k"], 2.0), rtol=1e-9, atol=1e-9)


def test_stability_on_all_three_branches_matches_energy():
    s, b = branch_at(0.4)
    th = b["theta1"]
    fold_rows = {p.index for p in b.special("LP")}
    rows = [i for i in range(len(b)) if i not in fold_rows]
    expected = symmetric_stable(th[rows], P["L"], 0.4)
    assert np.array_equal(b.stable[rows], expected)
    # all three branches present: lower stable, middle unstable, upper stable
    lp_th = sorted(p["theta1"] for p in b.special("LP"))
    assert b.stable[th < lp_th[0] - 1e-6].all() and b.stable[th > lp_th[1] + 1e-6].all()
    assert (~b.stable[(th > lp_th[0] + 1e-6) & (th < lp_th[1] - 1e-6)]).all()
    # stability changes exactly at the folds: between consecutive rows only across an LP
    changes = np.flatnonzero(np.diff(b.stable.astype(int)))
    for c in changes:
        assert {c, c + 1} & fold_rows


@pytest.mark.slow
def test_equilibrium_row_equals_virtual_work_for_general_geometry():
    # independent derivation: minimal coordinate theta1, potential energy, dV/dtheta1 = 0
    t1, F = sp.symbols("theta1 F", real=True)
    L1, L2, m1, m2, g, k, LU, m, n = 1.5, 1.2, 1.3, 0.7, 9.81, 127.0, 0.4, 0.2, -0.15
    t2 = sp.pi - sp.asin(L1 * sp.sin(t1) / L2)
    apex = sp.Matrix([L1 * sp.cos(t1), L1 * sp.sin(t1)])
    c1 = apex / 2
    c2 = apex - L2 / 2 * sp.Matrix([sp.cos(t2), sp.sin(t2)])
    d = (c2 + n * sp.Matrix([sp.cos(t2), sp.sin(t2)])) - (c1 + m * sp.Matrix([sp.cos(t1), sp.sin(t1)]))
    ell = sp.sqrt(d.dot(d))
    V = m1 * g * c1[1] + m2 * g * c2[1] + k / 2 * (ell - LU) ** 2 - F * apex[1]
    # V is linear in F: dV/dtheta1 = a(theta1) + F b(theta1) = 0 gives F = -a / b (sp.solve took ~9 s of CPU
    # simplifying the same expression)
    dV = sp.diff(V, t1)
    F_of = sp.lambdify(t1, -dV.subs(F, 0) / sp.diff(dV, F))
    s = build_overcentre(L1=L1, L2=L2, m1=m1, m2=m2, k=k, LU=LU, m=m, n=n)
    for th in (-0.8, -0.3, 0.2, 0.5, 0.75):  # |L1 sin(theta1)| < L2 so bar 2 reaches the ground line
        x = find_equilibrium(s, hold={"theta1": th}, free=["F"])
        assert x[s.index("F")] == pytest.approx(float(F_of(th)), rel=1e-10)


def test_fold_curve_and_cusp_match_closed_form():
    s, b = branch_at(0.1, theta_bound=1.45)
    lp = min(b.special("LP"), key=lambda p: p["F"])
    fc = continue_folds(s, lp, vary="F", free="LU", options=ContinuationOptions(bounds={"LU": (0.1, 2.0)}))
    LU, th, F = fc["LU"], fc["theta1"], fc["F"]
    assert np.max(np.abs(P["L"] * np.cos(th) ** 3 - LU)) < 1e-10  # folds at cos^3 = LU / L
    assert np.max(np.abs(symmetric_force(th, P["L"], P["m1"], P["m2"], P["g"], P["k"], LU) - F)) < 1e-8
    (cp,) = fc.special("CP")
    LUc, thc, Fc = symmetric_cusp(P["L"], P["m1"], P["m2"], P["g"], P["k"])
    assert cp["LU"] == pytest.approx(LUc, rel=1e-9)
    assert cp["theta1"] == pytest.approx(thc, abs=1e-7)
    assert cp["F"] == pytest.approx(Fc, rel=1e-9)
    # the curve covers both folds: from LU = 0.1 up to the cusp and back down
    assert fc["LU"].min() == pytest.approx(0.1) and (th > 0).any() and (th < 0).any()


def test_fold_curve_starts_from_a_located_fold_as_from_a_rough_one():
    # a located LP starts the curve as it is; a plain vector, or an LP whose point no longer
    # solves the fold system, is polished first: the three curves are the same closed form
    from dataclasses import replace

    s, b = branch_at(0.1, theta_bound=1.45)
    lp = min(b.special("LP"), key=lambda p: p["F"])
    opts = ContinuationOptions(bounds={"LU": (0.1, 2.0)})
    stale = replace(lp, x=lp.x + 1e-3 * (np.array(s.names) == "theta1"))
    LUc = symmetric_cusp(P["L"], P["m1"], P["m2"], P["g"], P["k"])[0]
    for start in (lp, lp.x, stale):
        fc = continue_folds(s, start, vary="F", free="LU", options=opts, direction=1, stop_at_cusp=True)
        assert np.max(np.abs(P["L"] * np.cos(fc["theta1"]) ** 3 - fc["LU"])) < 1e-10
        assert fc["LU"][0] == 0.1 and fc.labels[-1] == "CP" and fc["LU"][-1] == pytest.approx(LUc, rel=1e-9)


def test_lower_fold_crosses_zero_force_near_1_2_m():
    s, b = branch_at(0.4)
    lp = min(b.special("LP"), key=lambda p: p["F"])
    fc = continue_folds(s, lp, vary="F", free="LU", options=ContinuationOptions(bounds={"LU": (0.1, 2.0)}),
                        stop_at_cusp=True, direction=1)
    lower = fc["theta1"] > 0
    LU0 = np.interp(0.0, fc["F"][lower], fc["LU"][lower])
    assert 1.1 < LU0 < 1.3


def test_locate_fold_polishes_a_rough_guess():
    s = build_overcentre(LU=0.4)
    th, F = symmetric_folds(P["L"], P["m1"], P["m2"], P["g"], P["k"], 0.4)[1]
    x0 = find_equilibrium(s, hold={"theta1": th + 0.01}, free=["F"])
    x, v, a = locate_fold(s, x0, "F")
    assert x[s.index("theta1")] == pytest.approx(th, rel=1e-10)
    assert x[s.index("F")] == pytest.approx(F, rel=1e-10)
    assert a != 0


def test_jacobians_agree_with_finite_differences(overcentre):
    s = build_overcentre(m=0.1, n=-0.2, L2=1.3)
    rng = np.random.default_rng(0)
    x = find_equilibrium(s, hold={"theta1": 0.4}, free=["F"]) + rng.normal(0, 1e-2, len(s.names))
    J = s.jacobian(x)
    h = 1e-6
    fd = np.array([(s.residual(x + h * e) - s.residual(x - h * e)) / (2 * h) for e in np.eye(len(x))]).T
    assert np.allclose(J, fd, rtol=1e-6, atol=1e-6 * np.abs(J).max())
    v = rng.normal(size=len(x))
    H = s.jacobian_derivative(x, v)
    fdH = (s.jacobian(x + h * v) - s.jacobian(x - h * v)) / (2 * h)
    assert np.allclose(H, fdH, rtol=1e-6, atol=1e-6 * np.abs(H).max())
    mech = s.mechanics
    q = mech.q_index
    Pq = mech.phi_q(x)
    fdP = np.array([(mech.phi(x + h * e) - mech.phi(x - h * e)) / (2 * h) for e in np.eye(len(x))[q]]).T
    assert np.allclose(Pq, fdP, atol=1e-7)


def test_fold_system_jacobian_agrees_with_finite_differences():
    from mechcont.continuation import FoldProblem

    s, b = branch_at(0.4)
    lp = b["LP1"]
    prob = FoldProblem(s, lp.x, "F", "LU", lp.info["unknowns"])
    u = prob.u0 + 1e-3
    J = prob.jacobian(u)
    h = 1e-6
    fd = np.array([(prob.residual(u + h * e) - prob.residual(u - h * e)) / (2 * h) for e in np.eye(len(u))]).T
    assert np.allclose(J, fd, rtol=1e-6, atol=1e-6 * np.abs(J).max())


def test_reduced_generated_form_locates_the_same_folds():
    # three unknowns in mixed units (rad, rad, N): the fold's null vector must come from the
    # scaled Jacobian, else a small singular value of another direction is picked
    from mechcont.mechanism import assemble, load

    s = load("overcentre", reduced=True, LU=0.4)
    x0 = assemble(s, hold={"theta1": 0.3}, free=["F"])
    b = continuation(s, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}))
    got = sorted((p["theta1"], p["F"]) for p in b.special("LP"))
    for (th, F), (th0, F0) in zip(got, symmetric_folds(P["L"], P["m1"], P["m2"], P["g"], P["k"], 0.4)):
        assert th == pytest.approx(th0, rel=1e-8) and F == pytest.approx(F0, rel=1e-8)
