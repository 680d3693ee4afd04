"""Jumps of a sweep whose watched coordinate rests (on a stop) for most of a segment.

A fresh user's strut (tests/data/fresh_user/strut.toml) ramped F = 400 -> 5000 N at 1000 N/s with its downlock stop
rests on the stop until the release (87 % of the segment), then follows its branch slowly, ringing. The jump threshold
was 10 x span / segment duration: the span is covered in 13 % of the segment, so the quasi-static rate was
underestimated 8 times and the ringing (0.004 deg a swing) printed as 9 jumps. The quasi-static rate is now taken over
the time the coordinate moves (dynamics._jumps.moving_time).

Truths: the release load is the drag that holds the leg on its stop with no reaction, F = V'(phi) / x_axle'(phi) of
the independent one-angle model of tests/test_fresh_review_units.py at the angle where the brace's alignment (the sine
of the docs' collinear condition) is the stop's -0.05; synthetic records whose jumps are known.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner
from scipy.optimize import brentq
from test_fresh_review_units import U, _force, _pose

from mechcont.dynamics._jumps import find_jump_windows, find_runaway

STRUT = Path(__file__).parent / "data" / "fresh_user" / "strut.toml"


def _brace_sine(phi: float) -> float:
    """The strut's condition brace_line (collinear up.a, up.b, lo.b): the sine of the angle U-knee to U-lug."""
    _, _, knee, _, c_lo = _pose(phi)
    a, b = knee - U, 2 * c_lo - knee - U
    return float((a[0] * b[1] - a[1] * b[0]) / (np.hypot(*a) * np.hypot(*b)))


def test_strut_reports_its_release_and_no_jump():
    phi_stop = brentq(lambda p: _brace_sine(p) + 0.05, -1.55, -1.531, xtol=1e-14)
    release = _force(phi_stop)  # 4386.10 N
    res = make_runner()("sweep", STRUT, "--start", "theta_leg=-1.8", "--ramp", "F=400:5000:1000", "--watch",
                        "theta_leg", "--stops", "--no-progress")
    assert res.exit_code == 0, res.output
    said = float(re.search(r"release loads: ([\d.]+) N", res.stdout).group(1))
    assert abs(said - release) < 0.05 + 1e-6 * release, (said, release)  # printed to 6 digits
    assert "jump 1" not in res.stdout and "runaway" not in res.stdout, res.stdout  # before: 9 jumps of 0.004 deg
    assert "no jump of theta_leg detected" in res.stdout


def _at_rest_then_ringing(jump: bool, rest: float = 8.7):
    """0..10 s: w rests (to 1e-13) until ``rest`` s, then rises at 1 unit/s while ringing at 8 Hz with a rate
    amplitude of 1.5 units/s (the strut's proportions); with ``jump``, a step of 1 unit over ~5 ms at 9.5 s."""
    t = np.linspace(0.0, 10.0, 20001)
    rng = np.random.default_rng(1)
    on = t > rest
    om = 2 * math.pi * 8
    w = np.where(on, (t - rest) + 1.5 / om * (1 - np.cos(om * (t - rest))), 0.0)
    w = w + 1e-13 * rng.standard_normal(len(t))
    wdot = np.where(on, 1.0 + 1.5 * np.sin(om * (t - rest)), 0.0) + 1e-12 * rng.standard_normal(len(t))
    if jump:
        tau, x = 0.005, np.clip((t - 9.5) / 0.005, -50, 50)
        w = w + 0.5 * (1 + np.tanh(x))
        wdot = wdot + 0.5 / tau / np.cosh(x) ** 2
    return t, w, wdot


@pytest.mark.parametrize("jump", [False, True])
def test_ringing_after_a_rest_is_no_jump_and_a_jump_still_is(jump):
    t, w, wdot = _at_rest_then_ringing(jump)
    windows, thr = find_jump_windows(t, w, wdot, 0, len(t) - 1, span=float(np.ptp(w)))
    assert len(windows) == int(jump), [(x.t_start, x.t_end) for x in windows]
    moving = 1.3  # the span is covered in the last 1.3 s
    assert thr == pytest.approx(10 * np.ptp(w) / moving, rel=2e-3)
    if jump:
        (win,) = windows
        assert 9.5 - 5 * 0.005 < win.time < 9.5 and 9.5 < win.t_end < 9.6


def test_rest_noise_is_no_runaway():
    t, w, wdot = _at_rest_then_ringing(False)
    assert find_runaway(t, w, wdot, 0, len(t) - 1, duration=10.0) is None
    # a real runaway after a rest (from 5 s) and a quasi-static rise, w spinning away at 200 units/s within 0.1 s
    # from 9.5 s, is still one, timed where it starts (it lasts less than half the time w moves: _jumps.find_runaway)
    t, w, _ = _at_rest_then_ringing(False, rest=5.0)
    a = t - 9.5
    w = w + np.where(a > 0, np.where(a < 0.1, 1000 * a**2, 10 + 200 * (a - 0.1)), 0.0)
    run = find_runaway(t, w, np.gradient(w, t), 0, len(t) - 1, duration=10.0)
    assert run is not None and 9.49 < run.time < 9.52, run


def test_jumps_on_a_branch_without_fold_name_their_cause(tmp_path):
    """The overcentre's branch continued over F = -75..-30 N only (its lower fold, closed form, lies below): the sweep
    down to -90 N jumps past that fold, and the note says the branch does not reach the jump, not 'check --set'."""
    from mechcont.models.overcentre import symmetric_folds

    (_, _), (_, f_low) = symmetric_folds(1.5, 1.0, 1.0, 9.81, 127.0, 0.4)
    assert f_low < -75  # the fold the branch misses
    run = make_runner()
    b = tmp_path / "b.csv"
    assert run("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=1.2", "--vary", "F", "--bounds",
               "F=-75:-30", "--bounds", "theta1=-1.5:1.5", "--out", b, "--quiet").exit_code == 0
    r = run("sweep", "overcentre", "--set", "LU=0.4", "--set", "c=50", "--start", "theta1=1.2", "--ramp", "F=-65:-90:1",
            "--watch", "theta1", "--branch", b, "--no-progress")
    assert r.exit_code == 0, r.output
    (jump,) = [ln for ln in r.stdout.splitlines() if ln.startswith("jump")]
    value = float(jump.split("F = ")[1].split()[0])
    assert value < f_low  # past the fold (by the sweep's delay), so beyond the branch's end
    note = r.stdout.splitlines()[-1]
    assert note.startswith("the branch has no fold in F: no jump is expected, yet 1 jump(s) were found")
    assert f"covers F = -75 to -30 N only and the sweep jumped at {value:.6g} N" in note and "--bounds" in note
    assert "check --set" not in note


def test_jumps_within_a_branch_without_fold_list_the_plausible_causes():
    from types import SimpleNamespace

    from mechcont.cli.sweep import _no_fold_note
    from mechcont.continuation import Branch
    from mechcont.models import load_model

    m = load_model("overcentre")
    rows = np.tile(m.defaults(), (3, 1))
    rows[:, m.index("F")] = [-80.0, -60.0, -40.0]
    branch = Branch(m.names, rows, s=[0.0, 1.0, 2.0], n_unstable=[0, 0, 0], labels=["", "", ""], special_points=[],
                    vary="F", unknowns=["theta1"])
    jump = SimpleNamespace(value=-50.0)
    result = SimpleNamespace(ramps=[SimpleNamespace(name="F")], jumps=[jump], runaway=None)
    note = _no_fold_note(m, result, branch)
    assert "yet 1 jump(s) were found: plausible causes:" in note
    assert all(w in note for w in ("another branch", "--start", "--stops", "too fast")), note
    result.jumps = []
    assert _no_fold_note(m, result, branch) == "the branch has no fold in F: no jump is expected"
