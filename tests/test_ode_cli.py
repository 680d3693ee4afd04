"""The commands on ODE files: simulate against analytic solutions, check, equations, continue, folds,
sensitivity, explore, and the mechanism analyses refused in one line."""

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
AB = EXAMPLES / "ab.toml"


@pytest.fixture(scope="module")
def run():
    return make_runner()


def _table(path):
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def test_simulate_a_linear_ode_against_its_exponential(tmp_path, run):
    """dx/dt = -a x from the file's x0 (metres): x = x0 e^(-a t); units reach the headers."""
    path = tmp_path / "decay.toml"
    path.write_text('[system]\nname = "decay"\n[parameters]\na = { value = 0.7, unit = "1/s" }\n'
                    '[states]\nx = { value = 2.0, unit = "m" }\n[rates]\nx = "-a*x"\n')
    out = tmp_path / "h.csv"
    res = run("simulate", path, "--until", "5", "--rtol", "1e-11", "--atol", "1e-13", "--out", out, "--no-progress")
    assert res.exit_code == 0, res.output
    header, data = _table(out)
    assert header == ["t [s]", "x [m]", "a [1/s]"]
    t, x = data[:, 0], data[:, 1]
    assert t[0] == 0 and t[-1] == pytest.approx(5.0, abs=1e-12) and len(t) > 10
    np.testing.assert_allclose(x, 2.0 * np.exp(-0.7 * t), rtol=1e-8)
    np.testing.assert_array_equal(data[:, 2], 0.7)


@pytest.mark.parametrize("method", ["RK45", "Radau", "LSODA"])
def test_simulate_the_logistic_equation_from_start_and_set(tmp_path, run, method):
    """dN/dt = r N (1 - N/K): N = K N0 e^(rt) / (K + N0 (e^(rt) - 1)), with --start N=... and --set r=..."""
    path = tmp_path / "logistic.toml"
    path.write_text('[system]\nname = "logistic"\n[parameters]\nr = 1.0\nK = 10.0\n[states]\nN = 1.0\n'
                    '[rates]\nN = "r*N*(1 - N/K)"\n')
    out = tmp_path / "h.csv"
    res = run("simulate", path, "--start", "N=0.5", "--set", "r=0.8", "--until", "12", "--method", method,
              "--rtol", "1e-10", "--atol", "1e-12", "--out", out, "--plot", tmp_path / "h.png", "--no-progress")
    assert res.exit_code == 0, res.output
    header, data = _table(out)
    assert header == ["t [s]", "N", "r", "K"]
    t, N = data[:, 0], data[:, 1]
    e = np.exp(0.8 * t)
    np.testing.assert_allclose(N, 10 * 0.5 * e / (10 + 0.5 * (e - 1)), rtol=1e-7)
    assert (tmp_path / "h.png").stat().st_size > 1000


def test_simulate_the_stuart_landau_cycle_radius(tmp_path, run):
    """The Hopf normal form at mu > 0: the orbit settles on the circle of radius sqrt(mu)."""
    out = tmp_path / "h.csv"
    res = run("simulate", EXAMPLES / "stuart_landau.toml", "--set", "mu=0.25", "--start", "x=0.05", "--until", "60",
              "--out", out, "--no-progress")
    assert res.exit_code == 0, res.output
    header, data = _table(out)
    assert header[:3] == ["t [s]", "x", "y"] and "mu [1/s]" in header
    r = np.hypot(data[-1, 1], data[-1, 2])
    assert r == pytest.approx(0.5, rel=1e-6)


def test_continue_writes_the_dynamic_stability_of_an_ode(tmp_path, run):
    out = tmp_path / "b.csv"
    res = run("continue", AB, "--vary", "D", "--bounds", "D=0:0.2", "--out", out)
    assert res.exit_code == 0, res.output
    with open(out) as fh:
        rows = list(csv.DictReader(fh))
    words = {r["stability"] for r in rows}
    assert words == {"stable", "unstable"}
    for r in rows:  # the count is that of df/du's eigenvalues with Re > 0 (closed form, see test_ode_continuation)
        u1 = float(r["u1"])
        lam = np.linalg.eigvals([[-1 / (1 - u1), u1], [-14 * u1 / (1 - u1), 14 * u1 - 4]])
        if np.min(np.abs(lam.real)) > 1e-6:
            assert int(r["n_unstable"]) == int(np.sum(lam.real > 0))


def test_folds_and_sensitivity_of_ab_against_the_closed_form(tmp_path, run):
    """B = 17: the first fold at u1 = (1 - sqrt(1 - 4/c))/2, c = B/(1 + beta); there dD/dB = -u1 D / (1 + beta)
    and dD/dbeta = u1 D B / (1 + beta)^2 (the envelope theorem: dD/du1 = 0 at the fold, d ln D / dc = -u1)."""
    branch = tmp_path / "b.csv"
    res = run("continue", AB, "--set", "B=17", "--vary", "D", "--bounds", "D=0:0.2", "--out", branch, "--quiet")
    assert res.exit_code == 0, res.output
    sens = tmp_path / "s.json"
    res = run("sensitivity", AB, "--set", "B=17", "--point", f"{branch}:LP1", "--params", "B,beta", "--out", sens)
    assert res.exit_code == 0, res.output
    got = json.loads(sens.read_text())
    c = 17 / 4
    u1 = (1 - np.sqrt(1 - 4 / c)) / 2
    D = u1 * np.exp(-c * u1) / (1 - u1)
    assert got["B"] == pytest.approx(-u1 * D / 4, rel=1e-8)
    assert got["beta"] == pytest.approx(u1 * D * 17 / 16, rel=1e-8)
    res = run("folds", AB, "--set", "B=17", "--vary", "D", "--along", "B", "--bounds", "D=0:0.2",
              "--bounds", "B=15:20")
    assert res.exit_code == 0, res.output
    assert "CP1                  16" in res.output


def test_check_reports_states_rates_residual_and_eigenvalues(run):
    res = run("check", EXAMPLES / "stuart_landau.toml", "--set", "mu=0.3")
    assert res.exit_code == 0, res.output
    text = res.output
    assert "ODE system du/dt = f(u, p) (AUTO's IPS = 1), 2 state(s), 2 parameter(s)" in text
    assert "mu = 0.3 1/s" in text and "dx/dt = mu*x - omega*y - x*(x**2 + y**2)" in text
    assert "rates at the initial state: 0, 0" in text
    assert "eigenvalues of df/du at the initial state: 0.3 + 1i, 0.3 - 1i" in text
    assert "UNSTABLE (2 eigenvalue(s) with positive real part)" in text


def test_check_finds_a_non_finite_rate(tmp_path, run):
    path = tmp_path / "bad.toml"
    path.write_text('[system]\nname = "lg"\n[states]\nx = 0.0\n[rates]\nx = "log(x)"\n')
    res = run("check", path)
    assert res.exit_code == 1
    assert "not finite at the initial state" in res.output
    one_line_error(run("simulate", path, "--until", "1"), "--start", "not finite at the initial state")


def test_equations_prints_the_rates_and_latex(run):
    res = run("equations", AB)
    assert res.exit_code == 0, res.output
    assert "du1/dt = D*(1 - u1)*exp(u2) - u1" in res.output
    res = run("equations", AB, "--latex")
    assert res.output.startswith("\\begin{align}") and "\\frac{d u_{1}}{dt} &=" in res.output


def test_explore_shows_the_branch_of_an_ode(tmp_path, run):
    branch = tmp_path / "b.csv"
    assert run("continue", AB, "--vary", "D", "--bounds", "D=0:0.2", "--out", branch, "--quiet").exit_code == 0
    page = tmp_path / "p.html"
    res = run("explore", AB, "--branch", branch, "--out", page)
    assert res.exit_code == 0, res.output
    text = page.read_text()
    assert '"title":"ab"' in text and '"bodies":[]' in text


@pytest.mark.parametrize("args", [
    ["downlock", "--vary", "D"], ["freefall", "--until", "1"], ["draw", "--out", "x.png"],
    ["animate", "--branch", "b.csv", "--out", "x.gif"], ["design", "--x", "D", "--y", "B", "--bounds", "D=0:1"],
    ["optimize", "--minimize", "D", "--design", "B=1:2"], ["sweep", "--ramp", "D=0:1:1", "--watch", "u1"],
])
def test_mechanism_analyses_refuse_an_ode_file(run, args):
    one_line_error(run(args[0], AB, *args[1:]), f"{args[0]} is a mechanism analysis", "is an ODE system")


@pytest.mark.parametrize("args,words", [
    (["simulate", "--until", "1", "--stops"], ["--stops", "ODE system"]),
    (["simulate", "--until", "1", "--start", "D=1"], ["--start", "D is not a state"]),
    (["simulate", "--until", "1", "--watch", "D"], ["--watch", "D is not a state"]),
    (["check", "--plot", "x.png"], ["--plot", "ODE system"]),
    (["equations", "--reduced"], ["--reduced", "ODE system"]),
    (["continue", "--vary", "D", "--set", "Q=1"], ["Q", "unknown variable"]),
])
def test_options_that_make_no_sense_for_an_ode_are_one_line(run, args, words):
    one_line_error(run(args[0], AB, *args[1:]), *words)


def test_continue_the_hopf_normal_form_units_and_exact_stability(tmp_path, run):
    """Stuart-Landau: the origin is the equilibrium for every mu; df/du there is [[mu, -omega], [omega, mu]],
    eigenvalues mu +- i omega: two unstable for mu > 0, none for mu < 0. The file's units reach the headers."""
    out = tmp_path / "b.csv"
    res = run("continue", EXAMPLES / "stuart_landau.toml", "--vary", "mu", "--bounds", "mu=-1:1", "--out", out)
    assert res.exit_code == 0, res.output
    with open(out) as fh:
        reader = csv.DictReader(fh)
        rows = list(reader)
    assert reader.fieldnames[:4] == ["x", "y", "mu [1/s]", "omega [rad/s]"]
    mu = np.array([float(r["mu [1/s]"]) for r in rows])
    assert mu.min() == pytest.approx(-1) and mu.max() == pytest.approx(1)
    assert max(abs(float(r["x"])) + abs(float(r["y"])) for r in rows) < 1e-12
    for m, r in zip(mu, rows):
        if abs(m) > 1e-9:
            assert int(r["n_unstable"]) == (2 if m > 0 else 0), (m, r)


def test_an_algebraic_file_is_checked_and_not_simulated(tmp_path, run):
    path = tmp_path / "square.toml"
    path.write_text('[system]\nname = "square"\n[parameters]\nmu = 4.0\n[states]\nx = 1.0\n[equations]\nx = "x^2 - mu"\n')
    res = run("check", path)
    assert res.exit_code == 0, res.output
    assert "algebraic system 0 = g(u, p) (AUTO's IPS = 0)" in res.output
    assert "residual at the initial state: -3" in res.output
    assert "equilibrium Newton reaches from the initial state: x = 2" in res.output
    assert "eigenvalues" not in res.output
    one_line_error(run("simulate", path, "--until", "1"), "algebraic")


def test_simulate_van_der_pol_settles_on_its_cycle_of_the_known_period(tmp_path, run):
    """mu = 1: the period of the limit cycle is 6.6632868593231... (the issue's truth); measured between
    upward zero crossings of x, found on the cubic Hermite interpolant (dx/dt = y is in the table)."""
    from scipy.interpolate import CubicHermiteSpline

    out = tmp_path / "vdp.csv"
    res = run("simulate", EXAMPLES / "van_der_pol.toml", "--until", "80", "--method", "DOP853", "--rtol", "1e-12",
              "--atol", "1e-13", "--out", out, "--no-progress")
    assert res.exit_code == 0, res.output
    _, data = _table(out)
    t, x, y = data[:, 0], data[:, 1], data[:, 2]
    roots = CubicHermiteSpline(t, x, y).roots(extrapolate=False)
    up = np.array([r for r in roots if r > 30 and np.interp(r, t, y) > 0])
    assert len(up) >= 5
    np.testing.assert_allclose(np.diff(up), 6.6632868593231, rtol=1e-10)  # measured: 7e-14


def test_a_step_budget_ends_the_run_in_one_line_keeping_the_history(tmp_path, run):
    out = tmp_path / "h.csv"
    res = run("simulate", EXAMPLES / "van_der_pol.toml", "--until", "50", "--step-budget", "5", "--out", out,
              "--no-progress")
    one_line_error(res, "--step-budget", "more than 5 steps", str(out))
    _, data = _table(out)
    assert 2 <= len(data) <= 6 and data[-1, 0] < 50
