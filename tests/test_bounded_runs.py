"""Freefall runs and bisections bounded before they hang (issue 33, item 2; issue 32, item 5).

The bisection is checked on a stand-in for the runs whose outcome is known exactly (locked below a chosen
critical value, undecided in a band around it), so its stopping rules are tested against that truth without
the cost of simulations; the command-line cases run tests/data/freefall_pendulum.toml."""

import math

import pytest
from cli_helpers import make_runner, one_line_error

import mechcont.dynamics._critical as critical
from mechcont.dynamics.freefall import CriticalAirspeed, critical_airspeed
from mechcont.models import load_model

PATH = "tests/data/freefall_pendulum.toml"
TRUTH = 47.123456789


class _Run:
    def __init__(self, locked: bool, decided: bool = True):
        self.locked, self.decided = locked, decided
        self.outcome = "locked" if locked else ("at rest" if decided else "still moving")


@pytest.fixture(scope="module")
def pendulum():
    return load_model(PATH)


def _stand_in(monkeypatch, undecided_band=0.0, calls=None):
    """Runs that lock below TRUTH, hang above, and stay undecided within ``undecided_band`` of it."""
    def fake(model, start, *, lock, until, values, **options):
        v = values["U"]
        if calls is not None:
            calls.append((v, until))
            assert len(calls) < 500, "the bisection does not stop"
        return _Run(v < TRUTH, abs(v - TRUTH) >= undecided_band)
    monkeypatch.setattr(critical, "freefall", fake)  # the runs the bisection makes


def test_a_tolerance_below_the_floats_resolution_stops_there_and_says_so(pendulum, monkeypatch):
    calls = []
    _stand_in(monkeypatch, calls=calls)
    crit = critical_airspeed(pendulum, {"angle": 1.0}, "U", 0.0, 100.0, tol=1e-300, lock="downlock", until=1.0)
    assert crit.locked < TRUTH <= crit.failed
    assert crit.failed == math.nextafter(crit.locked, math.inf)  # adjacent floats: nothing between them
    assert "floating-point" in crit.stopped and len(calls) < 80
    assert any("bisection stopped" in line for line in crit.describe("m/s"))


def test_an_undecided_run_stops_the_bisection_with_a_bracket_that_holds_the_truth(pendulum, monkeypatch):
    calls = []
    _stand_in(monkeypatch, undecided_band=1e-3, calls=calls)
    crit = critical_airspeed(pendulum, {"angle": 1.0}, "U", 0.0, 100.0, tol=1e-6, lock="downlock", until=2.0)
    assert crit.locked < TRUTH < crit.failed  # the truth is inside, though the bracket is wider than tol
    assert crit.width > 1e-6 and crit.unsettled and abs(crit.unsettled[0] - TRUTH) <= 1e-3
    assert "undecided" in crit.stopped and crit.undecided
    assert (crit.unsettled[0], 8.0) in calls  # run again, four times as long, before giving up


def test_a_bracket_on_the_wrong_side_of_the_statics_contradicts_them():
    below = CriticalAirspeed("U", locked=77.6772, failed=77.6777, runs=[(77.6772, "locked"), (77.6777, "at rest")])
    assert below.contradicts(77.67804)  # a run that did not lock where no equilibrium can hold it
    assert not below.contradicts(77.6770)
    above = CriticalAirspeed("U", locked=80.0, failed=79.0, runs=[(80.0, "locked"), (79.0, "at rest")])
    assert above.contradicts(78.0) and not above.contradicts(79.5)  # locking above: failing above it is impossible


@pytest.fixture(scope="module")
def run():
    return make_runner()


@pytest.mark.parametrize("args, words", [
    (["--rest-speed", "inf"], ["--rest-speed", "finite"]),
    (["--rest-speed", "nan"], ["--rest-speed"]),
    (["--critical", "U=0:1e308"], ["--critical", "U = 1e+308", "not finite"]),
])
def test_hostile_freefall_options_are_one_line(run, args, words):
    result = run("freefall", PATH, "--start", "angle=1.0", "--lock", "downlock", "--until", "2", *args)
    one_line_error(result, *words)


@pytest.mark.parametrize("args, words", [
    (["--set", "c=1e12"], ["c = 1e+12 N s/m", "Radau", "--step-budget"]),  # a damper's rate c / I ~ 1e11 1/s
    (["--set", "m=1e-300"], ["m = 1e-300 kg", "Radau"]),
    (["--damping", "1e308"], ["damping option", "Radau"]),
    (["--step-budget", "0"], ["--step-budget", "positive"]),
])
def test_stiff_runs_end_with_one_line_naming_the_stiff_element(run, args, words, tmp_path):
    """Each of these ran for hours (an explicit method at the fastest time scale, 1e-11 s to 1e-300 s per step)."""
    out = tmp_path / "h.csv"
    result = run("freefall", PATH, "--start", "angle=1.0", "--lock", "downlock", "--until", "5", "--out", out, *args)
    one_line_error(result, *words)
    if args[0] != "--step-budget":
        assert out.exists() and "history up to there" in result.stderr  # the history up to the stop is kept


def test_a_simulation_over_its_budget_keeps_its_history(pendulum):
    from mechcont.dynamics import simulate
    from mechcont.dynamics.freefall import freefall as one_run

    r = one_run(pendulum, {"angle": 1.0}, lock="downlock", until=5.0, values={"c": 1e12}, max_steps=2000, audit=False)
    assert r.outcome == "failed" and "c = 1e+12 N s/m" in r.history.detail and len(r.history) >= 200
    assert simulate  # the same budget is simulate's (max_steps), freefall passes it on
