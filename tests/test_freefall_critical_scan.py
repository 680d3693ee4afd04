"""``critical_scan`` (issue 34, item 4: the comparison ``mechcont freefall --critical --scan`` built in the CLI, now
the library's) on tests/data/freefall_pendulum.toml: quasi-static critical U_c = sqrt(2 m g / (rho C_D d L))
in closed form (tests/test_freefall.py)."""

import math

import pytest

from mechcont.dynamics.freefall import bisection_runs, critical_airspeed, critical_scan
from mechcont.models import load_model

PATH = "tests/data/freefall_pendulum.toml"
U_C = math.sqrt(2 * 10.0 * 9.81 / (1.225 * 1.2 * 0.2 * 1.0))
OPTIONS = {"end_at_lock": True}


@pytest.fixture(scope="module")
def model():
    return load_model(PATH)


@pytest.fixture(scope="module")
def scan(model):
    return critical_scan(model, {"angle": 1.0}, "U", 24.0, 30.0, lock="downlock", until=30.0, tol=0.5,
                         scan=("c", [20.0]), **OPTIONS)


def test_each_bracket_is_the_critical_airspeed_at_that_value(model, scan):
    (bracket,) = scan.brackets
    calls = []
    direct = critical_airspeed(model, {"angle": 1.0}, "U", 24.0, 30.0, tol=0.5, lock="downlock", until=30.0,
                               values={"c": 20.0}, progress=lambda: calls.append(1), **OPTIONS)
    assert (bracket.locked, bracket.failed) == pytest.approx((direct.locked, direct.failed), rel=1e-12)
    assert 0 < bracket.width <= 0.5 and bracket.locks_below
    # the progress callback counts the runs: both ends and one per halving of 6 m/s down to 0.5 (12 -> 1: 4 halvings)
    assert not direct.unsettled and len(calls) == len(direct.runs) == bisection_runs(24.0, 30.0, 0.5) == 6


def test_quasi_static_predictor_is_the_closed_form_and_the_comparison_follows(scan):
    assert scan.travel == "angle" and scan.unit == "m/s"
    (predictor,) = scan.quasi_static
    assert predictor is not None and predictor.fold
    assert scan.quasi_static_values == (pytest.approx(U_C, rel=1e-9),)
    (bracket,) = scan.brackets
    # heavily damped (c = 20): the gear creeps through the fold, the dynamic value is the quasi-static one
    assert bracket.locked < U_C < bracket.failed
    (line,) = [ln for ln in scan.describe() if "dynamic - quasi-static" in ln]
    assert line.startswith("c = 20: dynamic - quasi-static = ")
    printed = float(line.split("quasi-static = ")[1].split()[0])  # 4 significant digits
    assert printed == pytest.approx(bracket.locked - U_C, rel=1e-3)
    assert line.endswith("not significant (within the bracket's width)")


def test_table(scan):
    assert scan.header() == ["c", "locked_U [m/s]", "failed_U [m/s]", "quasi_static_U [m/s]"]
    ((c, locked, failed, qs),) = scan.rows()
    assert c == 20.0 and qs == pytest.approx(U_C, rel=1e-9)
    assert (locked, failed) == (scan.brackets[0].locked, scan.brackets[0].failed)
