"""Hopf curves in two parameters (continue_hopf, `folds --point BRANCH.csv:HB1 --along P2`) against truth: AUTO's
ab demo in (D, beta) point by point against scipy's fsolve on f = 0, tr J = 0, its Bogdanov-Takens point against
f = 0, tr J = 0, det J = 0, l1 against SymPy's derivatives; the Bogdanov-Takens and Bautin normal forms (BT and GH
exactly at the origin); the stable side of the curve against eigenvalues off it; `continue --at` and the stability
chart from the command line."""

import math

import numpy as np
import pytest
import sympy as sp
from cli_helpers import make_runner, one_line_error
from hopf_models import S, ab_bt_independent, ab_hopf_independent, ab_jacobian, ab_model, l1_sympy

from mechcont.continuation import ContinuationOptions, continuation, continue_hopf, find_equilibrium, read_table
from mechcont.equations import ode_model


@pytest.fixture(scope="module")
def ab():
    return ab_model()


@pytest.fixture(scope="module")
def ab_curve(ab):
    hb = continuation(ab, ab.vector({}), "D", hopf=True,
                      options=ContinuationOptions(bounds={"D": (0.0, 0.2), "u2": (-1.0, 10.0)}))["HB1"]
    return continue_hopf(ab, hb, "D", "beta", options=ContinuationOptions(bounds={"beta": (0.5, 6.0), "D": (0.0, 1.0)}))


def test_ab_hopf_curve_points_solve_the_independent_system(ab_curve):
    omega = ab_curve.column("omega")
    rows = [i for i in range(0, len(ab_curve), 7) if np.isfinite(omega[i])]
    assert len(rows) >= 8
    for i in rows:
        v = ab_curve.point(i).values
        u1, u2, D = ab_hopf_independent([v["u1"], v["u2"], v["D"]], 14.0, v["beta"])
        assert (v["D"], v["u1"], v["u2"]) == pytest.approx((D, u1, u2), rel=1e-9)
        assert omega[i] == pytest.approx(math.sqrt(np.linalg.det(ab_jacobian(u1, u2, D, 14.0, v["beta"]))), rel=1e-9)
    for i in rows[::3]:
        assert ab_curve.column("l1")[i] == pytest.approx(l1_sympy(ab_curve.point(i).values, omega[i]), rel=1e-7)


def test_ab_bogdanov_takens_and_generalised_hopf_points(ab_curve):
    assert [p.label for p in ab_curve.special_points if p.label in ("BT", "GH")] == ["BT", "GH", "GH"]
    bt = ab_curve["BT1"]
    u1, u2, D, beta = ab_bt_independent([bt["u1"], bt["u2"], bt["D"], bt["beta"]], 14.0)
    assert (bt["D"], bt["beta"], bt["u1"]) == pytest.approx((D, beta, u1), rel=1e-8)
    for gh in ab_curve.special("GH"):
        # l1 (SymPy's derivatives) vanishes there: relative to its size a little way along the curve
        omega = math.sqrt(np.linalg.det(ab_jacobian(gh["u1"], gh["u2"], gh["D"], 14.0, gh["beta"])))
        assert abs(l1_sympy(gh.values, omega)) < 1e-9 and gh.located
    # past BT the curve is one of neutral saddles: no omega, no l1
    i = ab_curve["BT1"].index
    s = ab_curve.column("omega")
    assert np.isnan(s[:i]).all() != np.isnan(s[i + 1:]).all()


def test_the_stable_side_is_where_the_pair_turns_stable(ab, ab_curve):
    omega = ab_curve.column("omega")
    for i in [j for j in range(3, len(ab_curve), 11) if np.isfinite(omega[j])][:4]:
        v = ab_curve.point(i).values
        d = np.array([ab_curve.column("stable_D")[i], ab_curve.column("stable_beta")[i]])
        assert ab_curve.column("n_unstable_other")[i] == 0
        for sign in (1.0, -1.0):
            step = sign * 1e-4 * d / np.linalg.norm(d) * np.array([1.0, 1.0])
            x = find_equilibrium(ab, {"D": v["D"] + step[0], "beta": v["beta"] + step[1]},
                                 guess={"u1": v["u1"], "u2": v["u2"]})
            lam = np.linalg.eigvals(ab_jacobian(x[0], x[1], x[2], 14.0, x[4]))
            assert (lam.real.max() < 0) == (sign > 0)


def test_bogdanov_takens_normal_form():
    """x' = y, y' = b1 + b2 x + x^2 - x y: the Hopf curve is b1 = 0, b2 < 0; BT at b1 = b2 = 0."""
    x, y, b1, b2 = S["x"], S["y"], sp.Symbol("b1", real=True), sp.Symbol("b2", real=True)
    m = ode_model("bt", {"x": 0.0, "y": 0.0}, {"b1": 0.0, "b2": -1.0}, {"x": y, "y": b1 + b2 * x + x**2 - x * y})
    x0 = (1 - math.sqrt(1.8)) / 2
    hb = continuation(m, m.vector({"x": x0, "b1": -0.2}), "b1", hopf=True,
                      options=ContinuationOptions(bounds={"b1": (-0.5, 0.5), "x": (-3, 3)}))["HB1"]
    assert abs(hb["b1"]) < 1e-15 and hb.extra["hopf"].frequency == pytest.approx(1.0, rel=1e-14)
    curve = continue_hopf(m, hb, "b1", "b2", options=ContinuationOptions(bounds={"b2": (-2, 1)}))
    assert np.abs(curve.column("b1")).max() < 1e-14
    bt = curve["BT1"]
    assert abs(bt["b2"]) < 1e-12 and bt.located
    omega, b2 = curve.column("omega"), curve.column("b2")
    assert np.isnan(omega[b2 > 1e-9]).all() and omega[b2 < -1e-9] == pytest.approx(np.sqrt(-b2[b2 < -1e-9]), rel=1e-13)


def test_bautin_normal_form_generalised_hopf_at_zero():
    """z' = (b1 + i) z + b2 z|z|^2 - z|z|^4: Hopf curve b1 = 0, l1 = 2 b2 (Kuznetsov's normalisation), GH at b2 = 0."""
    x, y, b1, b2 = S["x"], S["y"], sp.Symbol("b1", real=True), sp.Symbol("b2", real=True)
    r2 = x**2 + y**2
    m = ode_model("bautin", {"x": 0.0, "y": 0.0}, {"b1": -1.0, "b2": -1.0},
                  {"x": b1 * x - y + b2 * x * r2 - x * r2**2, "y": x + b1 * y + b2 * y * r2 - y * r2**2})
    hb = continuation(m, m.vector({}), "b1", hopf=True, options=ContinuationOptions(bounds={"b1": (-1, 1)}))["HB1"]
    curve = continue_hopf(m, hb, "b1", "b2", options=ContinuationOptions(bounds={"b2": (-1, 1)}))
    assert curve.column("l1") == pytest.approx(2 * curve.column("b2"), abs=1e-11)
    gh = curve["GH1"]
    assert abs(gh["b2"]) < 1e-11 and gh.located and len(curve.special("GH")) == 1


@pytest.fixture
def run_ab(monkeypatch, ab):
    """The command line with model name `ab` served by the ODE model built here (the ODE file reader is another
    part of the project)."""
    import mechcont.models as models

    real = models.model_at
    monkeypatch.setattr(models, "model_at", lambda name, values=None, **kw: (
        ab.with_values(values or {}) if str(name) == "ab" else real(name, values, **kw)))
    return make_runner()


def test_cli_continue_at_rows_and_hopf_then_the_hopf_curve_and_its_chart(run_ab, tmp_path):
    branch = tmp_path / "ab.csv"
    r = run_ab("continue", "ab", "--vary", "D", "--start", "u1=0", "--bounds", "D=0:0.2", "--bounds", "u2=-1:10",
               "--at", "D=0.05,0.15", "--out", branch)
    assert r.exit_code == 0, r.output
    assert "HB1 at D = 0.16504" in r.output and "subcritical (unstable cycles)" in r.output
    header, rows = read_table(branch)
    col = header.index("label")
    uz = [float(row[header.index("D")]) for row in rows if row[col] == "UZ"]
    assert r.stderr == ""
    assert uz == pytest.approx([0.05, 0.15], rel=1e-15)
    assert [row[col] for row in rows if row[col]] == ["EP", "UZ", "UZ", "HB", "EP"]
    curve, chart = tmp_path / "hopf.csv", tmp_path / "chart.png"
    r = run_ab("folds", "ab", "--point", f"{branch}:HB1", "--along", "beta", "--bounds", "beta=1:5", "--out", curve,
               "--plot", chart)
    assert r.exit_code == 0, r.output
    assert "BT1" in r.output and chart.stat().st_size > 10_000
    header, rows = read_table(curve)
    assert {"omega [rad/s]", "l1", "stable_D", "stable_beta"} <= set(header)
    one_line_error(run_ab("folds", "ab", "--point", f"{branch}:UZ1", "--along", "beta"), "--point", "UZ1")
    one_line_error(run_ab("continue", "ab", "--vary", "D", "--start", "u1=0", "--at", "beta=1"), "--at")
    one_line_error(run_ab("continue", "ab", "--vary", "D", "--start", "u1=0", "--at", "D=0.1,abc"), "--at")
    r = run_ab("continue", "ab", "--vary", "D", "--start", "u1=0", "--bounds", "D=0:0.2", "--bounds", "u2=-1:10",
               "--at", "D=0.1,0.3", "--quiet")
    assert r.exit_code == 0 and r.stderr.strip() == "warning: --at D=0.3: the branch does not reach it (no UZ row)"
    one_line_error(run_ab("folds", "ab", "--point", f"{branch}:HB1", "--along", "D"), "--along")
    one_line_error(run_ab("folds", "ab", "--point", f"{branch}:HB1", "--vary", "B", "--along", "beta"), "--vary")


def test_cli_folds_from_a_fold_row_of_a_table(run_ab, tmp_path):
    """`folds --point BRANCH.csv:LP1 --along beta`: every row of the fold curve solves f = 0, det J = 0 (by hand)."""
    branch, curve = tmp_path / "ab.csv", tmp_path / "lp.csv"
    r = run_ab("continue", "ab", "--set", "beta=1.5", "--vary", "D", "--start", "u1=0", "--bounds", "D=0:0.3",
               "--bounds", "u2=-1:10", "--out", branch, "--quiet")
    assert r.exit_code == 0, r.output
    r = run_ab("folds", "ab", "--set", "beta=1.5", "--point", f"{branch}:LP1", "--along", "beta", "--bounds",
               "beta=1:2", "--out", curve, "--quiet")
    assert r.exit_code == 0, r.output
    header, rows = read_table(curve)
    col = {h.split(" ")[0]: k for k, h in enumerate(header)}
    assert len(rows) > 10
    for row in rows:
        u1, u2, D, beta = (float(row[col[n]]) for n in ("u1", "u2", "D", "beta"))
        e = math.exp(u2)
        assert abs(-u1 + D * (1 - u1) * e) < 1e-10 and abs(-u2 + D * 14 * (1 - u1) * e - beta * u2) < 1e-10
        J = ab_jacobian(u1, u2, D, 14.0, beta)
        assert abs(np.linalg.det(J)) < 1e-9 * np.abs(J).max() ** 2
    # the fold curve drawn on the Hopf curve's stability chart; refused where there is no chart
    hb_branch, chart = tmp_path / "hb.csv", tmp_path / "chart.svg"
    r = run_ab("continue", "ab", "--vary", "D", "--start", "u1=0", "--bounds", "D=0:0.2", "--bounds", "u2=-1:10",
               "--out", hb_branch, "--quiet")
    assert r.exit_code == 0, r.output
    r = run_ab("folds", "ab", "--point", f"{hb_branch}:HB1", "--along", "beta", "--bounds", "beta=1:5",
               "--fold-curve", curve, "--plot", chart, "--quiet")
    assert r.exit_code == 0, r.output
    assert "fold (LP) curve" in chart.read_text() and "Hopf (HB) curve" in chart.read_text()
    one_line_error(run_ab("folds", "ab", "--point", f"{hb_branch}:HB1", "--along", "beta", "--fold-curve", curve),
                   "--fold-curve")
    one_line_error(run_ab("folds", "ab", "--point", f"{hb_branch}:HB1", "--along", "beta", "--fold-curve",
                          hb_branch, "--plot", chart), "--fold-curve")


def test_bt_row_has_zero_frequency(ab_curve):
    bt = ab_curve["BT1"]
    assert ab_curve.column("omega")[bt.index] == 0.0 and np.isnan(ab_curve.column("l1")[bt.index])
