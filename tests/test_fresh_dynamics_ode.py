"""A fresh user's ODE and algebraic files (tests/data/fresh/), written from docs/ode-format.md alone, against
closed forms and an independent SciPy integration: the Hopf normal form with a fold of cycles
(r' = r (mu + 2 r^2 - r^4): LPC at mu = -1, radii r^2 = 1 -+ sqrt(1 + mu), period pi, multiplier
exp(4 r^2 (1 - r^2) pi)), Rosenzweig-MacArthur (Hopf at K = (b + d)/(b - d), omega^2 = b x* y*/(1 + x*)^3)
and the cusp u^3 - a u - b."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import csv_rows, make_runner, one_line_error
from scipy.integrate import quad, solve_ivp

DATA = Path(__file__).parent / "data" / "fresh"



@pytest.fixture(scope="module")
def run():
    return make_runner()


@pytest.fixture(scope="module")
def lpc(run, tmp_path_factory):
    d = tmp_path_factory.mktemp("lpc")
    r = run("continue", DATA / "hopf_lpc.toml", "--vary", "mu", "--bounds", "mu=-2:1", "--out", d / "b.csv")
    assert r.exit_code == 0, r.output
    r = run("cycles", DATA / "hopf_lpc.toml", "--point", f"{d / 'b.csv'}:HB1", "--vary", "mu", "--bounds", "mu=-2:1",
            "--at", "mu=-0.5,0.5", "--out", d / "c.csv", "--orbits", d / "o.csv")
    assert r.exit_code == 0, r.output
    return d


def test_hopf_point_and_cycles_with_a_fold(lpc):
    hb = [row for row in csv_rows(lpc / "b.csv") if row["label"] == "HB"]
    assert len(hb) == 1 and abs(float(hb[0]["mu [1/s]"])) < 1e-12
    rows = csv_rows(lpc / "c.csv")
    fold = [row for row in rows if row["label"] == "LPC"]
    assert len(fold) == 1 and float(fold[0]["mu [1/s]"]) == pytest.approx(-1.0, abs=1e-8)
    assert float(fold[0]["max_x"]) == pytest.approx(1.0, abs=1e-8)
    uz = [row for row in rows if row["label"] == "UZ"]
    expected = [(-0.5, -1), (-0.5, 1), (0.5, 1)]  # inner unstable, then outer stable cycles after the fold
    assert [float(row["mu [1/s]"]) for row in uz] == pytest.approx([mu for mu, _ in expected], abs=1e-12)
    for row, (mu, side) in zip(uz, expected):
        r2 = 1 + side * math.sqrt(1 + mu)
        assert float(row["period [s]"]) == pytest.approx(math.pi, abs=1e-9)
        assert float(row["max_x"]) == pytest.approx(math.sqrt(r2), abs=1e-8)  # over the nodes: O(h^2) below r
        assert float(row["floquet_max"]) == pytest.approx(math.exp(4 * r2 * (1 - r2) * math.pi), rel=1e-6)
        assert row["stability"] == ("unstable" if side < 0 else "stable")


def test_simulation_converges_onto_the_outer_cycle(run, tmp_path):
    out = tmp_path / "s.csv"
    r = run("simulate", DATA / "hopf_lpc.toml", "--set", "mu=0.5", "--start", "x=0.3", "--until", "30",
            "--rtol", "1e-11", "--atol", "1e-12", "--out", out)
    assert r.exit_code == 0, r.output
    last = csv_rows(out)[-1]
    assert math.hypot(float(last["x"]), float(last["y"])) == pytest.approx(math.sqrt(1 + math.sqrt(1.5)), abs=1e-8)


def test_explore_names_the_cycles(run, lpc, tmp_path):
    page = tmp_path / "e.html"
    r = run("explore", DATA / "hopf_lpc.toml", "--branch", lpc / "b.csv", "--branch", lpc / "c.csv",
            "--orbits", lpc / "o.csv", "--out", page)
    assert r.exit_code == 0, r.output
    text = page.read_text()
    assert "LPC1" in text and "HB1" in text


@pytest.fixture(scope="module")
def rm(run, tmp_path_factory):
    d = tmp_path_factory.mktemp("rm")
    r = run("continue", DATA / "rosenzweig.toml", "--vary", "K", "--bounds", "K=1:4", "--out", d / "b.csv")
    assert r.exit_code == 0, r.output
    return d


def test_rosenzweig_hopf_point_cycle_and_curve(run, rm):
    hb = [row for row in csv_rows(rm / "b.csv") if row["label"] == "HB"]
    assert len(hb) == 1 and float(hb[0]["K"]) == pytest.approx(5 / 3, abs=1e-10)
    r = run("cycles", DATA / "rosenzweig.toml", "--point", f"{rm / 'b.csv'}:HB1", "--vary", "K", "--bounds", "K=1:3",
            "--at", "K=2", "--out", rm / "c.csv")
    assert r.exit_code == 0, r.output
    (uz,) = [row for row in csv_rows(rm / "c.csv") if row["label"] == "UZ"]

    def f(t, u):
        x, y = u
        return [x * (1 - x / 2) - x * y / (1 + x), 2 * x * y / (1 + x) - 0.5 * y]

    def up(t, u):
        return u[0] - 1 / 3

    up.direction = 1
    settled = solve_ivp(f, (0, 600), [0.5, 1.0], rtol=1e-10, atol=1e-12).y[:, -1]  # onto the stable cycle
    s = solve_ivp(f, (0, 60), settled, rtol=1e-12, atol=1e-14, events=up, dense_output=True)
    t0, t1 = s.t_events[0][-2:]
    assert float(uz["period [s]"]) == pytest.approx(t1 - t0, rel=1e-8)

    def div(t):  # the multiplier of a planar cycle: exp of the divergence integrated over a period
        x, y = s.sol(t)
        return 1 - x - y / (1 + x) ** 2 + 2 * x / (1 + x) - 0.5

    assert float(uz["floquet_max"]) == pytest.approx(math.exp(quad(div, t0, t1, limit=400)[0]), rel=1e-6)
    x = s.sol(np.linspace(t0, t1, 20001))[0]
    assert float(uz["max_x"]) == pytest.approx(x.max(), abs=1e-4)  # sampled at the nodes: O(h^2)
    r = run("folds", DATA / "rosenzweig.toml", "--point", f"{rm / 'b.csv'}:HB1", "--along", "b", "--bounds", "b=1:4",
            "--bounds", "K=0.5:10", "--out", rm / "h.csv")
    assert r.exit_code == 0, r.output
    for row in csv_rows(rm / "h.csv"):
        K, b = float(row["K"]), float(row["b"])
        xs = 0.5 / (b - 0.5)
        ys = (1 - xs / K) * (1 + xs)
        assert K == pytest.approx((b + 0.5) / (b - 0.5), abs=1e-10)
        assert float(row["omega [rad/s]"]) == pytest.approx(math.sqrt(b * xs * ys / (1 + xs) ** 3), abs=1e-10)


def test_cusp_fold_curve(run, tmp_path):
    r = run("continue", DATA / "cusp.toml", "--vary", "b", "--bounds", "b=-3:3", "--out", tmp_path / "b.csv")
    assert r.exit_code == 0, r.output
    lp = [row for row in csv_rows(tmp_path / "b.csv") if row["label"] == "LP"]
    assert sorted(float(row["b"]) for row in lp) == pytest.approx([-2.0, 2.0], abs=1e-10)
    r = run("folds", DATA / "cusp.toml", "--point", f"{tmp_path / 'b.csv'}:LP1", "--along", "a", "--bounds", "a=-1:4",
            "--bounds", "b=-4:4", "--out", tmp_path / "f.csv")
    assert r.exit_code == 0, r.output
    rows = csv_rows(tmp_path / "f.csv")
    for row in rows:
        u, a, b = float(row["u"]), float(row["a"]), float(row["b"])
        assert 3 * u * u == pytest.approx(a, abs=1e-10) and b == pytest.approx(-2 * u**3, abs=1e-10)
    (cp,) = [row for row in rows if row["label"] == "CP"]
    assert abs(float(cp["a"])) < 1e-10 and abs(float(cp["b"])) < 1e-10


def test_bad_input_is_one_line(run, rm, tmp_path):
    text = (DATA / "rosenzweig.toml").read_text()
    bad = tmp_path / "paren.toml"
    bad.write_text(text.replace('x = "x*(1 - x/K) - x*y/(1 + x)"', 'x = "x*(1 - x/K) - x*y/(1 + x"'))
    one_line_error(run("check", bad), "rates.x", "never closed")
    bad = tmp_path / "name.toml"
    bad.write_text(text.replace('y = "b*x*y/(1 + x) - d*y"', 'y = "b*x*z/(1 + x) - d*y"'))
    one_line_error(run("check", bad), "rates.y", "'z'")
    out = tmp_path / "o.csv"
    one_line_error(run("cycles", DATA / "rosenzweig.toml", "--point", f"{rm / 'b.csv'}:EP1", "--vary", "K",
                       "--bounds", "K=1:3", "--out", out), "EP1", "HB")
    one_line_error(run("folds", DATA / "rosenzweig.toml", "--point", f"{rm / 'b.csv'}:EP1", "--along", "b",
                       "--out", out), "EP1")
    assert not out.exists()


def test_cycles_at_a_value_never_reached_says_so(run, rm, tmp_path):
    """`continue --at` outside the bounds warns that no UZ row exists; `cycles --at` was silent."""
    out = tmp_path / "c.csv"
    r = run("cycles", DATA / "rosenzweig.toml", "--point", f"{rm / 'b.csv'}:HB1", "--vary", "K", "--bounds", "K=1:1.8",
            "--at", "K=5", "--out", out)
    assert r.exit_code == 0, r.output
    assert "warning: --at K=5: the family does not reach it (no UZ row)" in r.stderr
    assert not [row for row in csv_rows(out) if row["label"] == "UZ"]


def test_sensitivity_at_a_hopf_point_points_to_the_hopf_curve(run, rm):
    """It said '--keep: the point is not a fold: name the state that defines it', though keeping a state is not
    the Hopf condition."""
    one_line_error(run("sensitivity", DATA / "rosenzweig.toml", "--point", f"{rm / 'b.csv'}:HB1", "--params", "b"),
                   "Hopf point (HB)", "--along")


def test_sensitivity_of_the_cusp_fold(run, tmp_path):
    """b* = 2 (a/3)^(3/2) at LP1 (u = -1, a = 3): db*/da = (a/3)^(1/2) = 1."""
    r = run("continue", DATA / "cusp.toml", "--vary", "b", "--bounds", "b=-3:3", "--out", tmp_path / "b.csv")
    assert r.exit_code == 0, r.output
    r = run("sensitivity", DATA / "cusp.toml", "--point", f"{tmp_path / 'b.csv'}:LP1", "--params", "a")
    assert r.exit_code == 0, r.output
    (line,) = [ln.split() for ln in r.stdout.splitlines() if ln.split()[:1] == ["a"]]
    assert float(line[1]) == pytest.approx(1.0, abs=1e-9)
