"""Continuation with stops where the contact set is not obvious (issue 23, item 3).

Truth: a pendulum (mass m, length L, centre of mass at L/2) under gravity and an applied moment T,
angle theta from the horizontal (tests/data/pendulum_snap.toml). Free, it balances
T = a cos(theta) with a = m g L / 2, stable where sin(theta) < 0 (the potential a sin(theta) - T theta
has the curvature -a sin(theta)). A max stop at theta = 0.3 pushed by T carries R = T - a cos(0.3);
lowering T releases it at T = a cos(0.3) onto the *unstable* free branch (sin(0.3) > 0): a non-smooth
fold. At that moment the net moment T - a cos(theta) is negative for |theta| < 0.3, so the bar swings
down to the first equilibrium below, theta = -0.3 (stable), or onto a min stop on the way.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from mechcont.analysis import continuation_with_stops, equilibrium_on_stops
from mechcont.continuation import ContinuationOptions, find_equilibrium
from mechcont.mechanism import load_description, parse_description

DATA = Path(__file__).parent / "data"
A = 2.0 * 9.81 * 1.0 / 2          # m g L / 2 (N m)
TOP = 0.3
T_NSF = A * math.cos(TOP)
OPTIONS = ContinuationOptions(bounds={"T": (-5.0, 15.0)})


@pytest.fixture(scope="module")
def snap():
    return load_description(DATA / "pendulum_snap.toml").build()


@pytest.fixture(scope="module")
def snap_low():
    text = (DATA / "pendulum_snap.toml").read_text() + '\n[stops.low]\ncondition = "angle"\nmin = -0.2\n'
    return parse_description(text, "pendulum_snap_low.toml").build()


def _on_limit(m):
    """The free equilibrium exactly on the stop's limit (theta held, T solved for: R_top = 0 there)."""
    x = find_equilibrium(m, hold={"theta_bar": TOP}, free=["T"], guess={"theta_bar": TOP, "angle": TOP})
    assert m.as_dict(x)["T"] == pytest.approx(T_NSF, rel=1e-12)
    return x


def _check_landing(run, theta, contact):
    (nsf,) = run.branch.special("NSF")
    assert nsf["T"] == pytest.approx(T_NSF, rel=1e-9) and abs(nsf["R_top"]) < 1e-9 and nsf.stop == "top"
    fold = nsf.nonsmooth
    assert fold is not None and fold.jump is True and fold.sign in (1, -1)
    assert fold.vary == "T" and fold.value == pytest.approx(nsf["T"], rel=1e-15)
    land = fold.landing
    assert land is not None and land.stable is True
    d = dict(zip(run.branch.names, land.x))
    assert d["T"] == pytest.approx(T_NSF, rel=1e-12)
    assert d["theta_bar"] == pytest.approx(theta, abs=1e-9)
    assert land.contact == contact
    # the flat keys of before (the JSON's, the info view's) say the same
    info = nsf.info
    assert info["stop"] == "top" and info["jump"] is True and info["landing_stable"] is True
    assert info["T"] == fold.value and info["landing"] is land.x and info["landing_contact"] == contact
    return d


def test_release_onto_an_unstable_branch_is_a_non_smooth_fold_and_the_bar_lands_below(snap):
    x, contact = equilibrium_on_stops(snap, snap.defaults())
    assert contact == ["top"] and snap.as_dict(x)["R_top"] == pytest.approx(15.0 - T_NSF, rel=1e-12)
    run = continuation_with_stops(snap, x, "T", direction=-1, options=OPTIONS)
    assert "chattering" not in run.message
    assert [s[:2] for s in run.switches] == [("NSF", "top")]
    _check_landing(run, -TOP, ())
    b = run.branch
    i = b.special("NSF")[0].index
    # the connecting free branch: up to the free fold T = a at theta = 0, unstable, then stable again below
    (lp,) = b.special("LP")
    assert lp.index > i and lp["T"] == pytest.approx(A, rel=1e-9) and abs(lp["theta_bar"]) < 1e-6
    assert np.all(b.n_unstable[:i + 1] == 0)              # held by the stop up to the release
    after = np.arange(len(b)) > i
    th = b["theta_bar"]
    assert np.all(b.n_unstable[after & (th > 1e-6)] == 1)
    assert np.all(b.n_unstable[after & (th < -1e-6)] == 0)
    assert b["T"][-1] == pytest.approx(-5.0) and np.all(b["angle"] <= TOP + 1e-12)
    np.testing.assert_allclose(b["T"][after], A * np.cos(th[after]), rtol=1e-9, atol=1e-9)
    # the unlock load ends a run that stops at the first fold, smooth or not
    first = continuation_with_stops(snap, x, "T", direction=-1, options=OPTIONS, stop_at_fold=True).first_fold()
    assert first.label == "NSF" and first["T"] == pytest.approx(T_NSF, rel=1e-9)


def test_the_jump_lands_on_a_stop_on_the_way(snap_low):
    x, contact = equilibrium_on_stops(snap_low, snap_low.defaults())
    assert contact == ["top"]
    run = continuation_with_stops(snap_low, x, "T", direction=-1, options=OPTIONS)
    d = _check_landing(run, -0.2, ("low",))
    assert d["R_low"] == pytest.approx(A * (math.cos(0.2) - math.cos(TOP)), rel=1e-9)
    end = dict(zip(run.branch.names, run.branch.values[-1]))
    assert end["T"] == pytest.approx(-5.0) and end["R_low"] == pytest.approx(A * math.cos(0.2) + 5.0, rel=1e-10)


def test_a_start_exactly_on_the_limit_goes_into_contact_when_pushed_into_the_stop(snap):
    x0 = _on_limit(snap)
    for guess in (x0, equilibrium_on_stops(snap, x0)[0]):
        run = continuation_with_stops(snap, guess, "T", direction=1, options=OPTIONS)
        b = run.branch
        assert run.contact[0] == ("top",) and not b.special("LP")   # the free fold at T = a is not reached
        assert np.all(b["angle"] == TOP) and np.all(b.n_unstable == 0)
        np.testing.assert_allclose(b["R_top"], b["T"] - T_NSF, rtol=1e-10, atol=1e-9)
        assert b["T"][-1] == pytest.approx(15.0)


def test_a_start_exactly_on_the_limit_at_the_release_is_the_non_smooth_fold(snap):
    run = continuation_with_stops(snap, _on_limit(snap), "T", direction=-1, options=OPTIONS)
    assert run.branch.special("NSF")[0].index == 0
    _check_landing(run, -TOP, ())


def test_a_start_exactly_on_the_limit_of_a_stable_release(snap):
    # the resting pendulum (min stop at -1.2): started exactly on the limit with R = 0, pushing T down
    # presses it on the stop (R = a cos(1.2) - T), pushing T up lifts it off (free fold at T = a)
    m = load_description(DATA / "pendulum_stop.toml").build()
    x0 = find_equilibrium(m, hold={"theta_bar": -1.2}, free=["T"], guess={"theta_bar": -1.2, "angle": -1.2})
    down = continuation_with_stops(m, x0, "T", direction=-1, options=OPTIONS)
    assert down.contact == [("rest",)]
    np.testing.assert_allclose(down.branch["R_rest"], A * math.cos(1.2) - down.branch["T"], rtol=1e-10, atol=1e-9)
    up = continuation_with_stops(m, x0, "T", direction=1, options=OPTIONS, stop_at_fold=True)
    assert up.contact == [()] and up.first_fold()["T"] == pytest.approx(A, rel=1e-9)


def test_continue_on_the_command_line_from_the_limit(tmp_path):
    from mechcont.continuation import read_branch_table
    from tests.cli_helpers import make_runner

    out = tmp_path / "b.csv"
    r = make_runner()("continue", DATA / "pendulum_snap.toml", "--stops", "--start", "theta_bar=0.3", "--vary", "T",
                      "--bounds", "T=0:12", "--out", out)
    assert r.exit_code == 0, r.output
    assert "NSF1" in r.output and "chattering" not in r.output
    line = next(ln for ln in r.output.splitlines() if ln.startswith("NSF1") and "lands" in ln)
    assert "-17.18" in line  # theta = -0.3 rad, in degrees
    rows, _ = read_branch_table(out)
    angle = np.array([float(row["angle"]) for row in rows])
    R = np.array([float(row["R_top"]) for row in rows])
    assert np.all(angle <= TOP + 1e-12) and np.all(R >= -1e-9)
