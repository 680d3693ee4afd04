"""A start exactly on a stop's limit keeps the labels of the switch it sits on (issue 32, item 3).

Truth (own statics, numpy; no mechcont): two fresh levers pivoted at O, angle theta from +x.

- tests/data/limit_spring_lever.toml: a spring k from S = (0, -h) to P at a on the lever,
  l^2 = a^2 + h^2 + 2 a h sin(theta), pulls it onto a min stop at theta_s = -0.3; a tip force F (+y,
  arm L cos(theta)) lifts it. On the stop R = k (l - l0) dl/dtheta - F L cos(theta_s), with
  dl/dtheta = a h cos(theta) / l, so it releases at F_R = k (l - l0) a h / (l L) onto the stable
  free branch F = k a h (1 - l0 / l) / L (increasing in theta): an ``SR``.
- tests/data/limit_toggle_lock.toml: a spring from S = (0, s) to P at a, l^2 = a^2 + s^2 - 2 a s sin(theta),
  compressed past dead centre (bistable), held on a max stop at theta_s = 1.4 by M0 and opened by F
  (moment -F): R = M0 - F - V'(theta_s), V' = k (l - l0) dl/dtheta, dl/dtheta = -a s cos(theta) / l. It
  releases at F = M0 - V'(theta_s) where V'' < 0 (the free equilibrium is unstable): a non-smooth fold
  (``NSF``); the lever snaps back to the free equilibrium V'(theta) = M0 - F below the maximum of V'.

A start on the limit (the condition held there, the load solved for) is the switch itself: R = 0.
"""

import math
import re
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from mechcont.analysis import continuation_with_stops, equilibrium_on_stops
from mechcont.continuation import ContinuationOptions, find_equilibrium
from mechcont.mechanism import load_description, parse_description
from tests.cli_helpers import make_runner

DATA = Path(__file__).parent / "data"
LEVER, TOGGLE = DATA / "limit_spring_lever.toml", DATA / "limit_toggle_lock.toml"

# the spring lever
K1, A1, H1, L01, L1, SEAT = 4000.0, 0.6, 0.5, 0.3, 1.0, -0.3
_l1 = math.sqrt(A1**2 + H1**2 + 2 * A1 * H1 * math.sin(SEAT))
F_R = K1 * (_l1 - L01) * A1 * H1 / (_l1 * L1)


def _lever_bounds(sign):
    """F from -500 N to 800 N (mirrored for -F): short of theta = pi/2, where the tip force has no arm."""
    return ContinuationOptions(bounds={"F": (-500.0, 800.0) if sign > 0 else (-800.0, 500.0)})


# the toggle
K2, A2, S2, L02, LATCH, M0 = 3000.0, 0.4, 0.5, 0.35, 1.4, 250.0


def _dV(theta):
    """The toggle spring's moment dV/dtheta (N m)."""
    l = np.sqrt(A2**2 + S2**2 - 2 * A2 * S2 * np.sin(theta))
    return K2 * (l - L02) * (-A2 * S2 * np.cos(theta) / l)


F_NSF = M0 - _dV(LATCH)
_peak = minimize_scalar(lambda t: -_dV(t), bounds=(0.9, 1.55), method="bounded").x   # V'' = 0: stability changes
THETA_LAND = brentq(lambda t: _dV(t) - _dV(LATCH), 0.81, _peak)                       # the stable free equilibrium
TOGGLE_BOUNDS = ContinuationOptions(bounds={"F": (-100.0, 150.0)})


def _mirrored(path, old, new, name):
    return parse_description(path.read_text().replace(old, new), name).build()


def _on_limit(m, condition, theta, load):
    """The equilibrium with the lever's angle held exactly on the stop's limit and ``load`` solved for (R = 0)."""
    return find_equilibrium(m, hold={"theta_lever": theta}, free=[load], guess={"theta_lever": theta, condition: theta})


def _only(branch, label):
    pts = branch.special(label)
    assert len(pts) == 1, [(p.label, p.index) for p in branch.special_points]
    return pts[0]


def test_truth_is_what_the_premises_say():
    # the toggle's stop lies past the peak of V' (free equilibrium unstable there), the landing before it
    assert THETA_LAND < _peak < LATCH and _dV(THETA_LAND) == pytest.approx(_dV(LATCH), rel=1e-12)
    assert 0 < F_NSF < M0 and 0 < F_R < 800


@pytest.mark.parametrize("sign", [1, -1], ids=["released-increasing", "released-decreasing"])
def test_a_start_on_the_seat_keeps_the_release(sign):
    # sign -1: the force written as -F, so the lever leaves the stop as F decreases (the other run)
    m = load_description(LEVER).build() if sign > 0 else _mirrored(LEVER, 'magnitude = "F"', 'magnitude = "-F"',
                                                                     "lever_minus.toml")
    x0 = _on_limit(m, "tilt", SEAT, "F")
    assert m.as_dict(x0)["F"] == pytest.approx(sign * F_R, rel=1e-12)
    at_rest, contact = equilibrium_on_stops(m, m.defaults())
    assert contact == ["seat"]
    for start in (x0, equilibrium_on_stops(m, x0)[0], at_rest):
        run = continuation_with_stops(m, start, "F", direction=0, options=_lever_bounds(sign))
        sr = _only(run.branch, "SR")
        assert sr["F"] == pytest.approx(sign * F_R, rel=1e-9) and sr.stop == "seat"
        assert abs(sr["R_seat"]) < 1e-9 and sr.unknowns is not None and "R_seat" in sr.unknowns
        assert not run.branch.special("SC") and not run.branch.special("NSF")
        assert [s[:2] for s in run.switches] == [("SR", "seat")]
    # each way alone from the limit: off the stop it is released at the start; onto it, it stays in contact
    away = continuation_with_stops(m, x0, "F", direction=sign, options=_lever_bounds(sign))
    assert away.contact[0] == () and _only(away.branch, "SR").index == 0
    onto = continuation_with_stops(m, x0, "F", direction=-sign, options=_lever_bounds(sign))
    assert onto.contact[0] == ("seat",) and not onto.branch.special("SR")
    b = onto.branch
    np.testing.assert_allclose(b["R_seat"], (F_R - sign * b["F"]) * L1 * math.cos(SEAT), rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("sign", [1, -1], ids=["opened-increasing", "opened-decreasing"])
def test_a_start_on_the_latch_keeps_the_non_smooth_fold_and_the_jump(sign):
    m = load_description(TOGGLE).build() if sign > 0 else _mirrored(TOGGLE, 'magnitude = "-F"', 'magnitude = "F"',
                                                                      "toggle_plus.toml")
    x0 = _on_limit(m, "swing", LATCH, "F")
    assert m.as_dict(x0)["F"] == pytest.approx(sign * F_NSF, rel=1e-12)
    run = continuation_with_stops(m, x0, "F", direction=0, options=TOGGLE_BOUNDS)
    nsf = _only(run.branch, "NSF")
    fold = nsf.nonsmooth
    assert nsf["F"] == pytest.approx(sign * F_NSF, rel=1e-9) and nsf.stop == "latch" and fold is not None
    assert fold.jump is True and fold.landing is not None and fold.landing.stable is True and fold.landing.contact == ()
    land = dict(zip(run.branch.names, fold.landing.x))
    assert land["theta_lever"] == pytest.approx(THETA_LAND, abs=1e-9) and land["F"] == pytest.approx(sign * F_NSF)
    # the same as from the lever at rest on its latch, away from the limit
    rest, contact = equilibrium_on_stops(m, m.defaults())
    assert contact == ["latch"] and m.as_dict(rest)["R_latch"] == pytest.approx(M0 - _dV(LATCH), rel=1e-10)
    away = _only(continuation_with_stops(m, rest, "F", direction=0, options=TOGGLE_BOUNDS).branch, "NSF")
    assert away["F"] == pytest.approx(nsf["F"], rel=1e-9)
    assert away.nonsmooth is not None and away.nonsmooth.landing is not None
    assert away.nonsmooth.landing.x == pytest.approx(fold.landing.x, abs=1e-8)


def _point(output, label, column=1):
    line = next(ln for ln in output.splitlines() if ln.startswith(label + " "))
    return float(line.split()[column])


def test_continue_from_the_limit_on_the_command_line(tmp_path):
    run = make_runner()
    r = run("continue", LEVER, "--stops", "--vary", "F", "--start", "tilt=-0.3", "--bounds", "F=-500:800")
    assert r.exit_code == 0, r.output
    assert _point(r.output, "SR1") == pytest.approx(F_R, rel=1e-9)   # printed to 10 digits
    r = run("continue", TOGGLE, "--stops", "--vary", "F", "--start", "swing=1.4", "--bounds", "F=-100:150")
    assert r.exit_code == 0, r.output
    assert _point(r.output, "NSF1") == pytest.approx(F_NSF, rel=1e-9)
    jump = next(ln for ln in r.output.splitlines() if ln.startswith("NSF1:"))
    got = re.search(r"the mechanism jumps and lands at swing \(deg\) = (\S+)", jump)
    assert got and float(got.group(1)) == pytest.approx(math.degrees(THETA_LAND), rel=1e-8)
    # and from the description's pose, on the latch with no free equilibrium near: the same fold
    r = run("continue", TOGGLE, "--stops", "--vary", "F", "--bounds", "F=-100:150")
    assert r.exit_code == 0, r.output
    assert _point(r.output, "NSF1") == pytest.approx(F_NSF, rel=1e-9)
