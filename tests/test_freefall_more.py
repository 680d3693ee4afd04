"""Freefall with several lock stops, and the freefall study (P(fails to lock) under tolerances).

tests/data/freefall_two_legs.toml: two uniform bars (mass m, lengths L1, L2, I_O = m L^2 / 3) released at
rest from theta = beta fall independently onto their downlocks at -beta. Each one's fall is the reduced
equation I theta'' = -m g (L/2) cos(theta) (the second leg also feels its drag and damper), so its lock time
comes from an independent integration and its impact speed from energy: sqrt(6 g sin(beta) / L).
"""

import math

import pytest
from scipy.integrate import solve_ivp

from mechcont.dynamics.freefall import freefall
from mechcont.errors import InputError
from mechcont.models import load_model

TWO = "tests/data/freefall_two_legs.toml"
M, G, BETA, L1, L2 = 10.0, 9.81, 1.0, 1.0, 1.5
K2 = 1.225 * 1.2 * 0.2 * L2 / 2  # drag factor of the second leg (as in test_freefall.py)


def fall_time(L, until=20.0):
    """The independent engine for a leg without airload or damper: when it reaches -beta from rest at beta."""
    I_O = M * L * L / 3

    def rhs(t, y):
        return [y[1], -M * G * L / 2 * math.cos(y[0]) / I_O]

    def down(t, y):
        return y[0] + BETA
    down.terminal = True
    sol = solve_ivp(rhs, (0, until), [BETA, 0.0], events=[down], rtol=1e-11, atol=1e-12)
    return float(sol.t_events[0][0]) if len(sol.t_events[0]) else None


def test_two_lock_stops_lock_at_their_own_times():
    run = freefall(load_model(TWO), {"angle1": BETA, "angle2": BETA}, lock=["lock1", "lock2"], until=3.0)
    assert run.outcome == "locked" and run.lock == "stops lock1, lock2"
    t1, t2 = fall_time(L1), fall_time(L2)
    assert run.stops["lock1"].time == pytest.approx(t1, rel=1e-6)
    assert run.stops["lock2"].time == pytest.approx(t2, rel=1e-6)
    for name, L in (("lock1", L1), ("lock2", L2)):
        assert run.stops[name].impact_speed == pytest.approx(math.sqrt(6 * G * math.sin(BETA) / L), rel=1e-6)
    assert run.time_to_lock == pytest.approx(max(t1, t2), rel=1e-6)
    assert run.lock_spread == pytest.approx(abs(t2 - t1), rel=1e-5)
    lines = run.describe()
    assert any(line.startswith("stop lock1: locked at ") for line in lines)
    assert any(line.startswith("locked ") and line.endswith(" s apart") for line in lines)


def test_one_leg_hangs_the_other_locks():
    """The second leg hangs in the airflow (cos(theta) = m g / (k U^2)); the first locks: not locked, the
    first's lock time reported, the second's None, no spread."""
    U = 1.2 * math.sqrt(M * G / K2)
    run = freefall(load_model(TWO, U=U, c=20.0), {"angle1": BETA, "angle2": BETA}, lock=["lock1", "lock2"],
                   until=60.0)
    assert run.outcome == "at rest" and run.time_to_lock is None and run.lock_spread is None
    assert run.stops["lock1"].time == pytest.approx(fall_time(L1), rel=1e-6)
    assert run.stops["lock2"].time is None and run.stops["lock2"].impact_speed is None
    assert run.history["angle2"][-1] == pytest.approx(math.acos(M * G / (K2 * U * U)), abs=1e-6)
    last = run.describe()[-1]  # where it hangs: every coordinate, or the columns asked for
    assert all(f"{c} = " in last for c in run.history.coordinates)
    shown = run.describe(show=["angle2"])[-1]
    assert shown.endswith(f"angle2 = {run.history['angle2'][-1]:.6g}") and "angle1" not in shown


def test_bad_lock_names():
    system = load_model(TWO)
    with pytest.raises(InputError, match="^lock: unknown stop 'nope'; stops of freefall_two_legs: uplock1"):
        freefall(system, {"angle1": BETA}, lock=["lock1", "nope"], until=1.0)
    with pytest.raises(InputError, match="^lock: stop 'lock1' is named twice"):
        freefall(system, {"angle1": BETA}, lock=["lock1", "lock1"], until=1.0)


def test_cli_lock_repeatable_and_one_line_errors():
    from cli_helpers import make_runner, one_line_error

    run = make_runner()
    r = run("freefall", TWO, "--start", "angle1=1", "--start", "angle2=1", "--lock", "lock1", "--lock", "lock2",
            "--until", 3)
    assert r.exit_code == 0, r.output
    lib = freefall(load_model(TWO), {"angle1": BETA, "angle2": BETA}, lock=["lock1", "lock2"], until=3.0)
    (line,) = [ln for ln in r.output.splitlines() if ln.endswith(" s apart")]
    assert float(line.split()[1]) == pytest.approx(lib.lock_spread, rel=1e-5)
    assert "stop lock2: locked at " in r.output and "impact speed" in r.output
    one_line_error(run("freefall", TWO, "--start", "angle1=1", "--lock", "lock1", "--lock", "lock9", "--until", 3),
                   "--lock", "'lock9'", "lock1, lock2")
    one_line_error(run("freefall", TWO, "--start", "angle1=1", "--lock", "lock1", "--lock-condition", "angle1=0",
                       "--until", 3), "--lock", "exactly one")


# -- the freefall study --------------------------------------------------------------------------------------
PENDULUM = "tests/data/freefall_pendulum.toml"
K = 1.225 * 1.2 * 0.2 * 1.0 / 2  # the pendulum's drag factor: U_c = sqrt(m g / k) (tests/test_freefall.py)


def test_study_probability_of_failing_to_lock_matches_the_closed_form(tmp_path):
    """The pendulum with heavy damping (c = 20 N s/m: dynamic = quasi-static critical airspeed to 1e-3) at
    U = 20 m/s with a normally distributed mass: it fails to lock where U_c(m) = sqrt(m g / k) <= U, i.e.
    m <= m_c = k U^2 / g, so P = Phi((m_c - mean) / sd). Every sample's outcome matches that rule outside a
    band of 2e-3 relative in m (1e-3 in U_c, the dynamic-quasi-static gap at the finite --until), and the
    closed-form P lies in the study's Clopper-Pearson interval."""
    import pandas as pd
    from cli_helpers import make_runner
    from scipy.stats import norm

    U, mean, sd, n = 20.0, 6.2, 0.4, 24
    m_c = K * U * U / G
    out = tmp_path / "study"
    r = make_runner()("study", PENDULUM, "--analysis", "freefall", "--dist", f"m=normal:{mean}:{sd}", "--n", n,
                      "--hold", "angle=1", "--lock", "downlock", "--until", 100, "--set", f"U={U}", "--set", "c=20",
                      "--scheduler", "serial", "--out", out, "--quiet")
    assert r.exit_code == 0, r.output
    df = pd.read_parquet(out / "results.parquet")
    assert len(df) == n and (df["status"] == "converged").all()
    near = (df["m"] / m_c - 1).abs() < 2e-3
    assert (df["locked"] == (df["m"] > m_c))[~near].all()
    assert set(df.loc[df["locked"], "outcome"]) == {"locked"} and df.loc[df["locked"], "time_to_lock"].gt(0).all()
    from mechcont.analysis.study import failure_probability

    fp = failure_probability(df)
    assert fp.what == "freefall fails to lock" and fp.samples == n
    assert fp.low <= norm.cdf((m_c - mean) / sd) <= fp.high
    assert 0 < fp.failures < n  # both outcomes sampled: the test can tell a wrong rule


def test_study_freefall_settings_one_line_errors(tmp_path):
    from cli_helpers import make_runner, one_line_error

    run = make_runner()
    base = ("study", PENDULUM, "--analysis", "freefall", "--dist", "m=normal:6:0.4", "--n", 2, "--scheduler", "serial",
            "--out", tmp_path / "s")
    one_line_error(run(*base, "--hold", "angle=1", "--lock", "nope", "--until", 5), "lock", "'nope'", "uplock, downlock")
    one_line_error(run(*base, "--hold", "angle=1", "--until", 5), "lock", "give the lock stop")
    one_line_error(run(*base, "--lock", "downlock", "--until", 5), "hold", "released")
    one_line_error(run(*base, "--hold", "angle=1", "--lock", "downlock"), "until")
    one_line_error(run("study", PENDULUM, "--analysis", "freefall", "--analysis", "downlock", "--dist", "m=normal:6:0.4",
                       "--n", 2, "--hold", "angle=1", "--lock", "downlock", "--until", 5, "--out", tmp_path / "t"),
                   "analysis", "alone")
