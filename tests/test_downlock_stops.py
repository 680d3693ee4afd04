"""``downlock`` on descriptions with stops: the locked state rests on the stop (issue 23, item 3).

Truth (statics of a pendulum, m = 2 kg, L = 1 m, a = m g L / 2 the largest gravity moment):
- tests/data/pendulum_lock.toml: held up against a max stop at 0.3 rad by a lock moment M0, opened by F.
  On the stop R = M0 - F - a cos(0.3); it releases at F = M0 - a cos(0.3) onto the unstable free branch
  (sin(0.3) > 0), so that release is the unlock load, a non-smooth fold (NSF).
- tests/data/pendulum_stop.toml: resting on a min stop at -1.2 rad, lifted by T. On the stop
  R = (m g L / 2) cos(1.2) - T; it releases there onto a stable branch and gives way at the fold T = m g L / 2.
"""

import math
import re
from pathlib import Path

import numpy as np
import pytest

from mechcont.analysis.stop_lock import downlock_on_stops
from mechcont.errors import InputError
from mechcont.mechanism import load_description, parse_description

DATA = Path(__file__).parent / "data"
G = 9.81
A = 2.0 * G * 1.0 / 2


def test_lock_on_a_stop_with_a_snap_release():
    m = load_description(DATA / "pendulum_lock.toml").build()
    res = downlock_on_stops(m, "M0", {"M0": (12.0, 20.0)}, force="F")
    b = res.branch
    assert res.lock_stops == ("top",) and res.condition == {"angle": 0.3}
    assert b["M0"].min() == pytest.approx(12.0) and b["M0"].max() == pytest.approx(20.0)
    np.testing.assert_allclose(b["R_top"], b["M0"] - A * math.cos(0.3), rtol=1e-10)
    assert np.all(b.n_unstable == 0)
    u = res.unlock
    assert u.stable is True and u.downlock_force == 0.0
    assert u.above.label == "NSF" and u.unlock_force == pytest.approx(15.0 - A * math.cos(0.3), rel=1e-9)
    assert any("non-smooth fold" in n for n in u.notes)
    (land,) = [n for n in u.notes if "lands on" in n]
    # released at F = M0 - a cos(0.3) the bar swings down to theta = -0.3, where a cos(theta) balances again
    got = re.search(r"lands on no stop \(stable; theta_bar from (\S+) deg to (\S+) deg\)", land)
    assert got and float(got.group(1)) == pytest.approx(math.degrees(0.3), rel=1e-5)
    assert float(got.group(2)) == pytest.approx(-math.degrees(0.3), rel=1e-5)


def test_lock_on_a_stop_with_a_smooth_release_then_a_fold():
    m = load_description(DATA / "pendulum_stop.toml").build()
    res = downlock_on_stops(m, "m", {"m": (1.0, 3.0)}, force="T")
    b = res.branch
    np.testing.assert_allclose(b["R_rest"], b["m"] * G / 2 * math.cos(1.2), rtol=1e-10)
    u = res.unlock
    assert u.above.label == "LP" and u.unlock_force == pytest.approx(A, rel=1e-9)
    (note,) = [n for n in u.notes if n.startswith("increasing")]
    release = float(re.search(r"releases at T = (\S+)", note).group(1))
    assert release == pytest.approx(A * math.cos(1.2), rel=1e-5)   # printed to 6 digits


def test_not_resting_on_a_stop_is_said():
    text = (DATA / "pendulum_stop.toml").read_text().replace('T = { value = 0.0', 'T = { value = 8.0')
    m = parse_description(text, "lifted.toml").build()
    with pytest.raises(InputError, match="rests on none of its stops"):
        downlock_on_stops(m, "m", {"m": (1.0, 3.0)}, force="T")


def test_downlock_cli_takes_the_lock_on_the_stop(tmp_path):
    from mechcont.continuation import read_branch_table
    from tests.cli_helpers import make_runner, one_line_error

    run = make_runner()
    out = tmp_path / "d.csv"
    r = run("downlock", DATA / "pendulum_lock.toml", "--force", "F", "--vary", "M0", "--bounds", "M0=12:20", "--out", out)
    assert r.exit_code == 0, r.output
    assert "lock resting on stop top" in r.output and "UNSTABLE" not in r.output
    summary = next(ln for ln in r.output.splitlines() if ln.startswith("at M0 = 15"))
    assert "stable" in summary
    assert float(re.search(r"F = (\S+) N m increasing", summary).group(1)) == pytest.approx(15.0 - A * math.cos(0.3),
                                                                                          rel=1e-5)
    assert "non-smooth fold (NSF)" in r.output
    rows, units = read_branch_table(out)
    M0 = np.array([float(row["M0"]) for row in rows])
    np.testing.assert_allclose([float(row["unlock_F"]) for row in rows], M0 - A * math.cos(0.3), rtol=1e-9)
    np.testing.assert_allclose([float(row["R_top"]) for row in rows], M0 - A * math.cos(0.3), rtol=1e-10)
    # a condition given on a description with stops: held as asked, and said in one line that the stops are ignored
    r = run("downlock", DATA / "pendulum_lock.toml", "--force", "F", "--vary", "M0", "--bounds", "M0=12:20",
            "--hold", "theta_bar=0.3")
    assert r.exit_code == 0, r.output
    assert sum("stops of pendulum_lock (top) are ignored" in ln for ln in r.output.splitlines()) == 1
    one_line_error(run("downlock", DATA / "pendulum_lock.toml", "--force", "F", "--vary", "F", "--bounds", "F=0:1"),
                   "vary", "unlock force")


def test_the_clamp_resting_on_its_stop_is_a_lock():
    # the toggle clamp of test_toggle_clamp.py with a stop past the straight toggle (a collinear condition, a
    # sine): the lock rests on it; pushed open it releases where the hand force holds the handle there alone,
    # force_to_hold(theta) of the closed-form potential; off the stop (towards the straight toggle) the free
    # branch holds less than that, so nothing carries a larger force nearby: the release is the snap
    from mechcont.models import load_model
    from tests.cli_helpers import make_runner
    from tests.test_toggle_clamp import force_to_hold

    m = load_model(DATA / "toggle_clamp_stop.toml")
    res = downlock_on_stops(m, "l0", {"l0": (0.58, 0.62)}, force="F")
    b, u = res.branch, res.unlock
    assert res.lock_stops == ("over",) and u.stable is True and np.all(b["R_over"] > 0)
    theta = float(b.values[np.argmin(np.abs(b["l0"] - 0.6)), m.index("theta_handle")])
    assert u.above.label == "NSF"
    assert u.unlock_force == pytest.approx(force_to_hold(theta, 0.6), rel=1e-9)
    assert force_to_hold(theta * (1 - 1e-4), 0.6) < force_to_hold(theta, 0.6)
    r = make_runner()("check", DATA / "toggle_clamp_stop.toml")
    assert "over  min of toggle = -0.05: in contact, reaction R_over = " in r.output
    assert "stability there (a stop in contact holds its condition): stable" in r.output
