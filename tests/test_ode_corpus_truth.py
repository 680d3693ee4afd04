"""ODE files written from the docs alone (tests/corpus/ode), run through the CLI against truth derived by hand:
the Bogdanov-Takens normal form (its Hopf curve b1 = 0 meets the fold curve at the BT point, the origin), the
Bautin normal form (l1 = 2 beta, GH at beta = 0, its fold of cycles at mu = -beta^2/4 with radius, period and
multiplier in closed form), the Brusselator (Hopf curve b = 1 + a^2, omega = a; a cycle against a long
integration), FitzHugh-Nagumo (Hopf points in closed form; a planar system has no period doubling; its
relaxation cycle against a long integration) and Lorenz (subcritical Hopf at r = sigma (sigma + b + 3) /
(sigma - b - 1), the Hopf curve in (sigma, r))."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner
from scipy.integrate import solve_ivp

ODE = Path(__file__).resolve().parent / "corpus" / "ode"


@pytest.fixture(scope="module")
def run():
    return make_runner()


def _rows(path) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _col(row: dict[str, str], name: str) -> float:
    """The value of the column whose header starts with ``name`` (units follow it)."""
    key = next(k for k in row if k == name or k.startswith(name + " "))
    return float(row[key])


def _labelled(rows, prefix: str) -> list[dict[str, str]]:
    return [r for r in rows if r["label"].startswith(prefix)]


def _ok(result):
    assert result.exit_code == 0, result.output
    return result


def _continue(run, tmp_path, name, vary, lo, hi, *extra):
    out = tmp_path / f"{name}.csv"
    _ok(run("continue", ODE / f"{name}.toml", "--vary", vary, "--bounds", f"{vary}={lo}:{hi}", "--out", out, *extra))
    return out


def test_bogdanov_takens_point_where_the_hopf_curve_meets_the_fold_curve(run, tmp_path):
    branch = _continue(run, tmp_path, "bogdanov_takens", "b1", -0.5, 0.24)
    (hb,) = _labelled(_rows(branch), "HB")
    assert abs(_col(hb, "b1")) < 1e-12 and abs(_col(hb, "x")) < 1e-12
    curve = tmp_path / "hopf.csv"
    result = _ok(run("folds", ODE / "bogdanov_takens.toml", "--point", f"{branch}:HB1", "--along", "b2",
                     "--bounds", "b2=-1:1", "--out", curve))
    rows = _rows(curve)
    # the Hopf curve is b1 = 0 (x = 0) with omega^2 = -b2 while b2 < 0; the BT point is the origin
    for r in rows:
        assert abs(_col(r, "b1")) < 1e-12 and abs(_col(r, "x")) < 1e-12
        if _col(r, "b2") < -1e-9:
            assert _col(r, "omega") == pytest.approx(math.sqrt(-_col(r, "b2")), rel=1e-10)
    (bt,) = _labelled(rows, "BT")
    assert abs(_col(bt, "b2")) < 1e-10 and _col(bt, "omega") == 0.0
    assert "BT1" in result.output


def test_bautin_lyapunov_coefficient_generalised_hopf_and_fold_of_cycles(run, tmp_path):
    for beta in (1.0, -1.0):
        branch = _continue(run, tmp_path, "bautin", "mu", -0.5, 0.5, "--set", f"beta={beta}")
        res = run("continue", ODE / "bautin.toml", "--set", f"beta={beta}", "--vary", "mu", "--bounds", "mu=-0.5:0.5")
        line = next(ln for ln in res.output.splitlines() if ln.startswith("HB1 at"))
        l1 = float(line.split("l1 = ")[1].split(":")[0])
        assert l1 == pytest.approx(2 * beta, rel=1e-6)  # printed to 6 digits
        assert ("subcritical" if beta > 0 else "supercritical") in line
    branch = _continue(run, tmp_path, "bautin", "mu", -0.5, 0.5)
    curve = tmp_path / "gh.csv"
    _ok(run("folds", ODE / "bautin.toml", "--point", f"{branch}:HB1", "--along", "beta", "--bounds", "beta=-1:2",
            "--out", curve))
    rows = _rows(curve)
    (gh,) = _labelled(rows, "GH")
    assert abs(_col(gh, "beta")) < 1e-9 and abs(_col(gh, "mu")) < 1e-12
    for r in rows:
        if r["label"] == "":
            assert _col(r, "l1") == pytest.approx(2 * _col(r, "beta"), rel=1e-9)
    cycles = tmp_path / "c.csv"
    _ok(run("cycles", ODE / "bautin.toml", "--point", f"{branch}:HB1", "--vary", "mu", "--bounds", "mu=-0.5:0.5",
            "--at", "mu=-0.1", "--out", cycles))
    rows = _rows(cycles)
    (lpc,) = _labelled(rows, "LPC")
    assert _col(lpc, "mu") == pytest.approx(-0.25, abs=1e-8)
    assert _col(lpc, "max_x") == pytest.approx(math.sqrt(0.5), rel=8e-4)
    uz = _labelled(rows, "UZ")
    assert len(uz) == 2
    roots = [(1 - math.sqrt(0.6)) / 2, (1 + math.sqrt(0.6)) / 2]  # r^2 of the two cycles at mu = -0.1
    assert len(uz) == 2
    for r in uz:
        # the largest x over the nodes and collocation points (at most 2 pi / 80 apart in angle) is the radius
        # to within 1 - cos(pi / 80) = 7.7e-4; period and multiplier are exact
        r2 = min(roots, key=lambda q: abs(q - _col(r, "max_x") ** 2))
        assert _col(r, "max_x") == pytest.approx(math.sqrt(r2), rel=8e-4)
        assert _col(r, "period") == pytest.approx(2 * math.pi, rel=1e-10)
        assert _col(r, "floquet_max") == pytest.approx(math.exp(2 * math.pi * (2 * r2 - 4 * r2**2)), rel=1e-5)
        assert r["stability"] == ("stable" if r2 > 0.5 else "unstable")


def _long_run(f, z0, t_end):
    """Period, max of the first state and the Liouville multiplier exp(int div f dt) of the cycle a long
    integration from z0 settles on (rates f(z) -> (rates, div f))."""
    def rhs(t, z):
        dz, div = f(z[:-1])
        return [*dz, div]
    up = lambda t, z: z[0] - z0[0]  # noqa: E731
    up.direction = 1
    sol = solve_ivp(rhs, [0, t_end], [*z0, 0.0], method="DOP853", rtol=1e-12, atol=1e-12, events=up,
                    dense_output=True)
    t0, t1 = sol.t_events[0][-2:]
    ts = np.linspace(t0, t1, 20001)
    Z = sol.sol(ts)
    return t1 - t0, float(Z[0].max()), math.exp(Z[-1][-1] - Z[-1][0])


def test_brusselator_hopf_curve_and_a_cycle_against_integration(run, tmp_path):
    branch = _continue(run, tmp_path, "brusselator", "b", 1.5, 3)
    (hb,) = _labelled(_rows(branch), "HB")
    assert _col(hb, "b") == pytest.approx(2.0, rel=1e-12)
    curve = tmp_path / "hopf.csv"
    _ok(run("folds", ODE / "brusselator.toml", "--point", f"{branch}:HB1", "--along", "a", "--bounds", "a=0.3:3",
            "--out", curve))
    for r in _rows(curve):
        a = _col(r, "a")
        assert _col(r, "b") == pytest.approx(1 + a * a, rel=1e-10)
        assert _col(r, "omega") == pytest.approx(a, rel=1e-10)
    cycles = tmp_path / "c.csv"
    _ok(run("cycles", ODE / "brusselator.toml", "--point", f"{branch}:HB1", "--vary", "b", "--bounds", "b=1.5:3",
            "--at", "b=2.5", "--out", cycles))
    (uz,) = _labelled(_rows(cycles), "UZ")
    a, b = 1.0, 2.5
    T, umax, mult = _long_run(lambda z: ([a - (b + 1) * z[0] + z[0] ** 2 * z[1], b * z[0] - z[0] ** 2 * z[1]],
                                         -(b + 1) + 2 * z[0] * z[1] - z[0] ** 2), [1.0, 2.6], 400.0)
    assert _col(uz, "period") == pytest.approx(T, rel=1e-6)
    assert _col(uz, "max_u") == pytest.approx(umax, rel=1e-4)  # nodes and collocation points, not the true max
    assert _col(uz, "floquet_max") == pytest.approx(mult, rel=1e-4)


def test_fitzhugh_nagumo_hopf_points_and_no_period_doubling_in_the_plane(run, tmp_path):
    a, b, eps = 0.7, 0.8, 0.08
    branch = _continue(run, tmp_path, "fitzhugh_nagumo", "I", 0, 1.5)
    hbs = _labelled(_rows(branch), "HB")
    assert len(hbs) == 2
    for hb, sign in zip(hbs, (-1, 1)):
        v = sign * math.sqrt(1 - eps * b)
        assert _col(hb, "v") == pytest.approx(v, rel=1e-12)
        assert _col(hb, "I") == pytest.approx(v**3 / 3 - v + (v + a) / b, rel=1e-12)
        assert _col(hb, "leading_frequency") == pytest.approx(math.sqrt(eps * (1 - eps * b * b)), rel=1e-12)
    cycles = tmp_path / "c.csv"
    _ok(run("cycles", ODE / "fitzhugh_nagumo.toml", "--point", f"{branch}:HB1", "--vary", "I", "--bounds", "I=0:1.5",
            "--at", "I=0.5", "--out", cycles))
    rows = _rows(cycles)
    # the one non-trivial multiplier of a planar cycle is exp(int div f dt) > 0: it never crosses -1 (the canard
    # orbits' multipliers, on 20 intervals, are not accurate enough to say anything, and must not say PD)
    assert not _labelled(rows, "PD") and not _labelled(rows, "NS")
    (uz,) = _labelled(rows, "UZ")
    T, vmax, _ = _long_run(lambda z: ([z[0] - z[0] ** 3 / 3 - z[1] + 0.5, eps * (z[0] + a - b * z[1])],
                                      1 - z[0] ** 2 - eps * b), [0.0, 0.0], 400.0)
    assert _col(uz, "period") == pytest.approx(T, rel=1e-6)
    assert _col(uz, "max_v") == pytest.approx(vmax, rel=1e-4)
    assert uz["stability"] == "stable"


def test_lorenz_subcritical_hopf_and_its_curve(run, tmp_path):
    sigma, b = 10.0, 8.0 / 3.0
    branch = _continue(run, tmp_path, "lorenz", "r", 10, 30)
    (hb,) = _labelled(_rows(branch), "HB")
    r_h = sigma * (sigma + b + 3) / (sigma - b - 1)
    assert _col(hb, "r") == pytest.approx(r_h, rel=1e-12)
    assert _col(hb, "x") == pytest.approx(math.sqrt(b * (r_h - 1)), rel=1e-12)
    assert _col(hb, "leading_frequency") == pytest.approx(math.sqrt(b * (sigma + r_h)), rel=1e-12)
    res = run("continue", ODE / "lorenz.toml", "--vary", "r", "--bounds", "r=10:30")
    assert "subcritical (unstable cycles)" in next(ln for ln in res.output.splitlines() if ln.startswith("HB1 at"))
    curve = tmp_path / "hopf.csv"
    _ok(run("folds", ODE / "lorenz.toml", "--point", f"{branch}:HB1", "--along", "sigma", "--bounds", "sigma=5:20",
            "--out", curve))
    for r in _rows(curve):
        s = _col(r, "sigma")
        assert _col(r, "r") == pytest.approx(s * (s + b + 3) / (s - b - 1), rel=1e-10)


def test_the_pair_sum_gradient_is_its_derivative_and_finite_at_a_jordan_block():
    """dg/dx (g = lambda_1 + lambda_2 of the critical pair) against central differences of g at an ordinary
    point of a three-state system, and finite at the Bogdanov-Takens point of the normal form (a Jordan block,
    where each eigenvalue's own derivative divides by w^H v = 0)."""
    from mechcont.continuation._hopf_point import HopfTest
    from mechcont.equations import dynamics_of
    from mechcont.models import load_model

    lorenz = load_model(ODE / "lorenz.toml")
    test = HopfTest(dynamics_of(lorenz), lorenz)
    x = lorenz.vector({"x": 7.0, "y": 7.5, "z": 20.0, "r": 22.0})
    cols = np.arange(len(x))
    grad = test.gradient(x, cols, test.pair(x))
    for c in cols:
        h = 1e-5 * max(1.0, abs(x[c]))
        up, down = x.copy(), x.copy()
        up[c] += h
        down[c] -= h
        assert grad[c] == pytest.approx((test.pair(up).g - test.pair(down).g) / (2 * h), rel=1e-7, abs=1e-8)
    bt = load_model(ODE / "bogdanov_takens.toml")
    test = HopfTest(dynamics_of(bt), bt)
    x0 = bt.vector({"x": 0.0, "y": 0.0, "b1": 0.0, "b2": 0.0})
    # g = -x on the whole plane y = 0 (trace of [[0, 1], [b2 + 2x, -x]]): dg/dx = -1, dg/dy = 0, dg/db = 0
    assert test.gradient(x0, np.arange(4), test.pair(x0)) == pytest.approx([-1.0, 0.0, 0.0, 0.0], abs=1e-12)


def test_a_canard_explosion_is_not_taken_for_a_homoclinic_orbit(run, tmp_path):
    """FitzHugh-Nagumo has one equilibrium, never a saddle (the v-nullcline's slope 1 - v^2 stays below 1/b), so
    no homoclinic orbit: through its canard explosion the period triples while I moves in its 7th digit, but the
    orbit grows with it. The family goes on to the second Hopf point."""
    a, b, eps = 0.7, 0.8, 0.08
    branch = _continue(run, tmp_path, "fitzhugh_nagumo", "I", 0, 1.5)
    cycles = tmp_path / "c.csv"
    result = _ok(run("cycles", ODE / "fitzhugh_nagumo.toml", "--point", f"{branch}:HB1", "--vary", "I",
                     "--bounds", "I=0:1.5", "--ntst", "60", "--out", cycles))
    assert "homoclinic" not in result.output
    rows = _rows(cycles)
    assert max(_col(r, "period") for r in rows) > 60.0  # through the explosion
    v = math.sqrt(1 - eps * b)
    assert rows[-1]["label"] == "HB" and _col(rows[-1], "I") == pytest.approx(v**3 / 3 - v + (v + a) / b, rel=1e-6)


def test_lorenz_cycles_end_at_the_homoclinic_explosion(run, tmp_path):
    """The unstable cycles born at the subcritical Hopf point grow towards the homoclinic orbit of the origin at
    r = 13.9266 (Sparrow 1982, The Lorenz equations, sec. 3)."""
    branch = _continue(run, tmp_path, "lorenz", "r", 10, 30)
    cycles = tmp_path / "c.csv"
    result = _ok(run("cycles", ODE / "lorenz.toml", "--point", f"{branch}:HB1", "--vary", "r", "--bounds", "r=10:30",
                     "--bounds", "period=0:50", "--out", cycles))
    assert "approaching a homoclinic orbit" in result.output
    rows = _rows(cycles)
    assert _col(rows[-1], "r") == pytest.approx(13.9266, abs=1e-4)
    # saddle cycles; the first, 2e-5 from the Hopf point, has its unstable multiplier within 1 + 1e-6 (the
    # documented margin of "stable") of the circle
    assert all(r["stability"] == "unstable" for r in rows[2:])


def test_the_brusselator_in_thousandths_gives_the_same_hopf_point_and_cycles(run, tmp_path):
    """States and a in units 1000 times smaller: the same Hopf point and period, orbits 1000 times larger. (The
    states' default arclength scale of 1 took 2000 steps of 0.1 to reach b = 1.7 and never found the Hopf point.)"""
    found = {}
    for name in ("brusselator", "brusselator_mm"):
        branch = _continue(run, tmp_path, name, "b", 1.5, 3)
        (hb,) = _labelled(_rows(branch), "HB")
        assert _col(hb, "b") == pytest.approx(2.0, rel=1e-12)
        cycles = tmp_path / f"{name}_c.csv"
        _ok(run("cycles", ODE / f"{name}.toml", "--point", f"{branch}:HB1", "--vary", "b", "--bounds", "b=1.5:3",
                "--at", "b=2.5", "--out", cycles))
        (found[name],) = _labelled(_rows(cycles), "UZ")
    si, mm = found["brusselator"], found["brusselator_mm"]
    assert _col(mm, "period") == pytest.approx(_col(si, "period"), rel=1e-8)  # meshes differ: O(h^8) each
    assert _col(mm, "floquet_max") == pytest.approx(_col(si, "floquet_max"), rel=1e-6)
    for key in ("max_u", "min_u", "max_v", "min_v"):  # sampled at each mesh's own nodes
        assert _col(mm, key) == pytest.approx(1000 * _col(si, key), rel=1e-3)
