"""A toggle clamp written as a user would (tests/data/toggle_clamp.toml): its downlock and unlock
folds against the closed form of its potential energy, and the CLI's report where no fold bounds
the locked state.

With the handle at angle theta, the plunger's pin is at x_p = Lh cos(theta) + sqrt(Ll^2 - Lh^2 sin^2(theta)),
the spring's length is 0.8 m - x_p and the hand force F (down, at the tip 2 Lh from O) has the
potential 2 F Lh sin(theta); equilibrium gives F(theta) = k (0.8 - x_p - l0) x_p'(theta) / (2 Lh cos(theta)).
"""

import re
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner
from scipy.optimize import minimize_scalar

from mechcont.analysis.downlock import downlock_point
from mechcont.analysis.unlock import unlock_folds
from mechcont.models import load_model

CLAMP = Path(__file__).parent / "data" / "toggle_clamp.toml"
Lh, Ll, k = 0.25, 0.30, 50000.0


def force_to_hold(theta, l0):
    """The hand force (N) that holds the handle at theta (rad): closed form from the potential."""
    root = np.sqrt(Ll**2 - Lh**2 * np.sin(theta) ** 2)
    xp = Lh * np.cos(theta) + root
    dxp = -Lh * np.sin(theta) - Lh**2 * np.sin(theta) * np.cos(theta) / root
    return k * (0.8 - xp - l0) * dxp / (2 * Lh * np.cos(theta))


def test_unlock_fold_is_the_maximum_of_the_holding_force():
    s = load_model(CLAMP, l0=0.6)
    x = downlock_point(s, condition="toggle", force="F")
    assert x[s.index("F")] == pytest.approx(0.0, abs=1e-9)  # aligned: the plunger's thrust passes through O
    assert x[s.index("theta_handle")] == pytest.approx(0.0, abs=1e-12)
    u = unlock_folds(s, x, "F", released=("toggle",))
    best = minimize_scalar(lambda t: -force_to_hold(t, 0.6), bounds=(0.1, 1.4), method="bounded",
                           options={"xatol": 1e-12})
    assert u.above.located and u.unlock_force == pytest.approx(-best.fun, rel=1e-9)
    assert u.above["theta_handle"] == pytest.approx(best.x, abs=1e-6)
    assert u.locked_range[0] == pytest.approx(best.fun, rel=1e-9)  # the mirror fold
    assert u.stable is False  # the straight toggle is pushed by a compressed spring: no lock


def test_cli_says_where_no_fold_bounds_the_locked_state(tmp_path):
    run = make_runner()
    r = run("downlock", CLAMP, "--condition", "toggle", "--force", "F", "--vary", "l0", "--bounds", "l0=0.55:0.8")
    assert r.exit_code == 0, r.output
    rows = [ln for ln in r.output.splitlines() if ln.lstrip().startswith("l0 =")]
    first = float(re.search(r"unlock\s+(\S+)", rows[0]).group(1))  # l0 = 0.55: a fold (about 7.5 kN)
    assert first == pytest.approx(-minimize_scalar(lambda t: -force_to_hold(t, 0.55), bounds=(0.1, 1.4),
                                                   method="bounded", options={"xatol": 1e-12}).fun, rel=1e-5)
    assert re.search(r"unlock\s+none", rows[-1])  # l0 = 0.8: none
    assert "unlock none: the release run from that point met no fold increasing F" in r.output
    assert "nan" not in r.output


def test_sweep_warns_of_an_unstable_start_and_of_a_branch_at_other_values(tmp_path):
    run = make_runner()
    branch = tmp_path / "b.csv"
    r = run("continue", CLAMP, "--start", "theta_handle=0.6", "--vary", "F", "--bounds", "theta_handle=-0.5:1.5",
            "--out", branch, "--quiet")
    assert r.exit_code == 0, r.output
    # l0 = 0.5 m: from theta_handle = 0.3 Newton lands on the straight toggle, pushed by a compressed spring
    r = run("sweep", CLAMP, "--set", "l0=0.5", "--start", "theta_handle=0.3", "--ramp", "F=0:50:500",
            "--watch", "theta_handle", "--branch", branch, "--no-progress")
    assert r.exit_code == 0, r.output
    warnings = [ln for ln in r.stderr.splitlines() if ln.startswith("warning: ")]
    assert any("continued at other parameter values: l0 = 0.6 m (sweep 0.5 m)" in w for w in warnings), r.stderr
    assert any("starts at an unstable equilibrium (theta_handle = " in w for w in warnings), r.stderr
    # the same values: no warning about the branch
    r = run("sweep", CLAMP, "--start", "theta_handle=0.3", "--ramp", "F=0:50:500", "--watch", "theta_handle",
            "--branch", branch, "--no-progress")
    assert r.exit_code == 0 and "other parameter values" not in r.stderr
