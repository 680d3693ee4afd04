"""Freefall outcomes told as they are (issue 31, item 6): locked, at rest short of locking, or still moving
(having struck the lock and left it).

tests/data/freefall_swing.toml: a uniform bar (m, L, I_O = m L^2 / 3) released at rest at theta = beta swings
through the bottom onto a plastic lock stop past it, at theta_s = -pi/2 - gamma, arriving at
sqrt(3 g (sin(beta) + cos(gamma)) / L) (energy). The impact stops it there for an instant, but gravity pulls it
off the stop again: it is still moving, not "stalled" (which the run used to say at the impact's instant)."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from mechcont.dynamics.freefall import freefall
from mechcont.models import load_model

SWING = "tests/data/freefall_swing.toml"
G, L, BETA, THETA_S = 9.81, 1.0, 0.5, -1.9707963267948966


def _swing(y0, t_span, damping=0.0, events=()):
    """The independent engine: I_O theta'' = -m g (L/2) cos(theta) - d I_O theta' (the mass-proportional damping)."""
    return solve_ivp(lambda t, y: [y[1], -1.5 * G / L * math.cos(y[0]) - damping * y[1]], t_span, y0,
                     events=events, rtol=1e-11, atol=1e-12, dense_output=True)


def test_a_lock_that_cannot_hold_is_left_and_the_leg_still_moving():
    run = freefall(load_model(SWING), {"angle": BETA}, lock="lock", until=1.5, end_at_lock=True)
    assert run.outcome == "still moving" and not run.locked and run.time_to_lock is None

    def strike(t, y):
        return y[0] - THETA_S
    strike.terminal = True
    fall = _swing([BETA, 0.0], (0.0, 5.0), events=[strike])
    t_hit = float(fall.t_events[0][0])
    speed = math.sqrt(3 * G * (math.sin(BETA) + math.cos(THETA_S + math.pi / 2)) / L)
    assert abs(fall.y_events[0][0][1]) == pytest.approx(speed, rel=1e-9)  # the engine against energy
    lock = run.stops["lock"]
    assert lock.impact_speed == pytest.approx(speed, rel=1e-7)
    assert lock.left == pytest.approx(t_hit, rel=1e-7) and lock.time is None
    # after the plastic impact it swings back from rest on the stop, as the independent engine has it
    back = _swing([THETA_S, 0.0], (t_hit, 1.5))
    h = run.history
    assert h.t[-1] == pytest.approx(1.5)
    assert h["angle"][-1] == pytest.approx(back.y[0, -1], abs=1e-6)
    assert run.final_speed == pytest.approx(abs(back.y[1, -1]), rel=1e-5) and run.final_speed > 0.1
    lines = run.describe()
    assert lines[0] == "outcome: still moving at t = 1.5 s (lock: stop lock)"
    assert f"left the lock stop at {t_hit:.6g} s (it did not hold)" in lines


def test_a_leg_that_settles_short_of_its_lock_is_at_rest():
    """Damped, the leg strikes the lock, leaves it and settles at the bottom (theta = -pi/2): at rest short of
    locking, with the time it left the stop."""
    run = freefall(load_model(SWING), {"angle": BETA}, lock="lock", until=40.0, damping=1.0, end_at_lock=True)
    assert run.outcome == "at rest" and run.final_speed <= 1e-4
    assert run.history["angle"][-1] == pytest.approx(-math.pi / 2, abs=1e-4)
    assert run.stops["lock"].impact_speed is not None and run.stops["lock"].left is not None
    assert run.describe()[0] == "outcome: at rest short of locking (lock: stop lock)"


def test_nose_gear_at_125_leaves_its_downlock_and_is_still_moving(tmp_path):
    """The case of the issue: at U = 125 m/s the nose gear's lock links strike the downlock, the airload pulls
    them off (no contact follows the impact) and at 2.5 s the gear still moves (it was "stalled" at the impact)."""
    from cli_helpers import make_runner

    from mechcont.paper.freefall import THETA_UP, description_text

    path = tmp_path / "nose_gear_freefall.toml"
    path.write_text(description_text())
    res = make_runner()("freefall", path, "--from", f"fitting={THETA_UP}", "--lock", "downlock", "--until", 2.5,
                        "--set", "U=125")
    assert res.exit_code == 0, res.output
    lines = res.output.splitlines()
    assert "outcome: still moving at t = 2.5 s (lock: stop downlock)" in lines
    (left,) = [ln for ln in lines if ln.startswith("left the lock stop at ")]
    (last,) = [ln for ln in lines if ln.startswith("at t = 2.5 s: max speed ")]
    assert float(last.split()[7].rstrip(",")) > 1e-2  # moving, not at rest
    assert 0.5 < float(left.split()[5]) < 1.5
    assert not any("stalled" in ln for ln in lines)


def test_the_at_rest_event_needs_the_lock_stop_in_contact():
    """The run ended at the lock stops only when they are in contact: with the stop holding (a plain fall onto
    it, the pendulum file) it ends in contact at rest; the at-rest instant of a plastic impact that does not
    hold (the swing) does not end it."""
    locked = freefall(load_model("tests/data/freefall_pendulum.toml", c=5.0), {"angle": 1.0}, lock="downlock",
                      until=20.0, values={"U": 10.0}, end_at_lock=True)
    assert locked.locked and locked.history.stop_events[-1].kind == "contact"
    swing = freefall(load_model(SWING), {"angle": BETA}, lock="lock", until=1.0, end_at_lock=True)
    assert swing.history.t[-1] == pytest.approx(1.0) and np.max(np.abs(swing.history.qdot[-1])) > 0.1
