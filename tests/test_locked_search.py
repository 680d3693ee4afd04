"""The active-set search tries the stops in contact before it gives up (issue 32, item 3).

Truth (own statics, numpy): tests/data/limit_stowed_leg.toml, a leg pivoted at O (mass m, cg at c = 0.5 m
along it), a spring k (free length l0) from S to P at p = 0.8 m along it, an extension moment Q; two stops
on its angle theta: the uplock (min 2.9 rad, where it is assembled) and the downlock (max 4.5 rad). With
V(theta) = k (l - l0)^2 / 2 + m g c sin(theta) - Q theta, l = |P - S|, the reaction on a min stop is
R = V'(theta) and on a max stop R = -V'(theta). Between the stops V' < 0 everywhere: the leg is pushed onto
the downlock (R > 0) and would pull on the uplock (R < 0). Free of its stops it balances only past the
uplock, or (a weak spring, a strong moment) nowhere near: the free Newton runs off or diverges.
"""

import math
import re
from pathlib import Path

import numpy as np
import pytest

from mechcont.analysis import continuation_with_stops, equilibrium_on_stops
from mechcont.analysis.stop_lock import locked_on_stops
from mechcont.continuation import ContinuationOptions
from mechcont.errors import ConvergenceError, InputError
from mechcont.mechanism import load_description, parse_description
from tests.cli_helpers import make_runner

LEG = Path(__file__).parent / "data" / "limit_stowed_leg.toml"
M, G, C, P, L0, S = 80.0, 9.81, 0.5, 0.8, 0.5, np.array([0.25, -0.7])
UP, DOWN = 2.9, 4.5


def dV(theta, k=2000.0, Q=600.0):
    """dV/dtheta of the leg (N m), exact."""
    e = np.array([math.cos(theta), math.sin(theta)])
    d = P * e - S
    l = float(np.linalg.norm(d))
    dl = float(d @ (P * np.array([-math.sin(theta), math.cos(theta)]))) / l
    return k * (l - L0) * dl + M * G * C * math.cos(theta) - Q


def _leg(**replace):
    text = LEG.read_text()
    for old, new in replace.items():
        text = text.replace(old, new)
    return parse_description(text, "leg.toml").build()


def test_truth_is_what_the_premises_say():
    th = np.linspace(UP, DOWN, 401)
    assert max(dV(t) for t in th) < 0 and -dV(DOWN) > 0 and dV(UP) < 0


@pytest.mark.parametrize("k, Q", [(2000.0, 600.0), (1.0, 6000.0)], ids=["free-runs-past-the-uplock", "free-diverges"])
def test_the_leg_assembled_on_its_uplock_is_found_on_its_downlock(k, Q):
    m = _leg(**{"k = { value = 2000.0": f"k = {{ value = {k}", "Q = { value = 600.0": f"Q = {{ value = {Q}"})
    x0 = m.defaults()
    assert m.as_dict(x0)["swing"] == pytest.approx(UP)
    x, contact = equilibrium_on_stops(m, x0)
    d = m.as_dict(x)
    assert contact == ["downlock"] and d["swing"] == pytest.approx(DOWN, abs=1e-12)
    assert d["R_downlock"] == pytest.approx(-dV(DOWN, k, Q), rel=1e-10) and d["R_uplock"] == 0.0
    y, there = locked_on_stops(m)
    assert there == ["downlock"] and m.as_dict(y)["R_downlock"] == pytest.approx(-dV(DOWN, k, Q), rel=1e-10)


def test_the_locked_leg_releases_where_its_reaction_reaches_zero():
    m = load_description(LEG).build()
    x, _ = equilibrium_on_stops(m, m.defaults())
    run = continuation_with_stops(m, x, "Q", direction=0, options=ContinuationOptions(bounds={"Q": (0.0, 1000.0)}))
    (sr,) = run.branch.special("SR")
    assert sr.stop == "downlock" and sr["Q"] == pytest.approx(dV(DOWN, Q=0.0), rel=1e-9)


def test_nothing_consistent_says_what_was_tried():
    # without the downlock nothing holds the leg near: on the uplock it would pull, free it runs past it
    text = LEG.read_text()
    m = parse_description(text[:text.index("[stops.downlock]")], "leg_up_only.toml").build()
    with pytest.raises(ConvergenceError) as err:
        equilibrium_on_stops(m, m.defaults())
    msg = str(err.value)
    got = re.search(r"uplock in contact: R_uplock = (\S+) N m pulls", msg)
    assert got and float(got.group(1)) == pytest.approx(dV(UP), rel=1e-5)   # printed to 6 digits
    assert re.search(r"none in contact: swing = \S+ rad, \S+ past the min of uplock \(2\.9\)", msg), msg
    with pytest.raises(InputError, match="no locked state"):
        locked_on_stops(m)


def test_check_continue_and_downlock_find_the_lock_from_the_uplock_pose(tmp_path):
    run = make_runner()
    r = run("check", LEG)
    assert r.exit_code == 0, r.output
    got = re.search(r"downlock +max of swing = 4\.5 rad: in contact, reaction R_downlock = (\S+) N m", r.output)
    assert got and float(got.group(1)) == pytest.approx(-dV(DOWN), rel=1e-5)
    assert re.search(r"uplock +min of swing = 2\.9 rad: free", r.output)
    r = run("continue", LEG, "--stops", "--vary", "Q", "--bounds", "Q=0:1000")
    assert r.exit_code == 0, r.output
    sr = next(ln for ln in r.output.splitlines() if ln.startswith("SR1 "))
    assert float(sr.split()[1]) == pytest.approx(dV(DOWN, Q=0.0), rel=1e-9)
    out = tmp_path / "d.csv"
    r = run("downlock", LEG, "--force", "Q", "--vary", "k", "--bounds", "k=1500:2500", "--out", out)
    assert r.exit_code == 0, r.output
    assert "lock resting on stop downlock" in r.output
    from mechcont.continuation import read_branch_table

    rows, _ = read_branch_table(out)
    for row in rows:
        assert float(row["R_downlock"]) == pytest.approx(-dV(DOWN, k=float(row["k"])), rel=1e-9)
