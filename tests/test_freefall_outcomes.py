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
    res = make_runner()("freefall", path, "--start", f"fitting={THETA_UP}", "--lock", "downlock", "--until", 2.5,
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


# -- issue 32 item 5: outcomes decided by physics, brackets that hold the truth ----------------------------------
# tests/data/freefall_fold_leg.toml, written again here as one equation of motion in the leg's angle th about the
# pivot O (I_O th'' = moment of gravity, lock spring, drag, damper), from the file's geometry and nothing of mechcont.
FOLD_LEG = "tests/data/freefall_fold_leg.toml"
LEG = dict(m=120.0, L=1.6, g=9.81, rho=1.225, d=0.3, CD=1.2, k=20000.0, l0=0.5, A=(-0.9, 0.25), S=(-0.5, -1.5))


def _leg_moment(th, U):
    """Static moment about O (N m, positive opening th): gravity, the lock spring S -> 0.7 L, the drag on the segment
    O -> L of the air moving aft (-x) at U (force 1/2 rho C_D d L u_n |u_n| at mid-segment along the normal, u_n = U sin(th))."""
    m, L, g = LEG["m"], LEG["L"], LEG["g"]
    e = np.array([math.cos(th), math.sin(th)])
    p = 0.7 * L * e
    ds = p - np.array(LEG["S"])
    ls = math.hypot(*ds)
    F = -LEG["k"] * (ls - LEG["l0"]) * ds / ls
    un = U * math.sin(th)
    drag = LEG["rho"] * LEG["CD"] * LEG["d"] * L / 2 * un * abs(un) * (L / 2)  # normal force times arm L/2
    return -m * g * 0.55 * L * math.cos(th) + (p[0] * F[1] - p[1] * F[0]) + drag


def _damper_moment(th, w, c, c2):
    L = LEG["L"]
    lug = 0.35 * L * np.array([math.cos(th), math.sin(th)])
    dl = lug - np.array(LEG["A"])
    rate = dl @ (0.35 * L * np.array([-math.sin(th), math.cos(th)])) / math.hypot(*dl)  # dl/dth
    v = rate * w
    return -(c * v + c2 * v * abs(v)) * rate


I_LEG = LEG["m"] * (LEG["L"] ** 2 / 10 + (0.55 * LEG["L"]) ** 2)


def _leg_fold():
    """The stall branch's fold: the smallest U at which some angle of the travel is an equilibrium (bounded Brent
    on U(th) = sqrt(-gravity-and-spring / drag-per-U^2) near its interior minimum)."""
    from scipy.optimize import minimize_scalar

    def u_eq(th):
        G = _leg_moment(th, 0.0)
        return math.sqrt(G / (G - _leg_moment(th, 1.0)))
    r = minimize_scalar(u_eq, bounds=(4.2, 4.44), method="bounded", options={"xatol": 1e-12})
    return float(r.fun), float(r.x)


def _leg_run(U, c, c2, until):
    """The independent engine from rest at the uplock (th = 3): the time it reaches the lock th = 4.45 (None if not)."""
    def lock(t, y):
        return y[0] - 4.45
    lock.terminal, lock.direction = True, 1
    sol = solve_ivp(lambda t, y: [y[1], (_leg_moment(y[0], U) + _damper_moment(y[0], y[1], c, c2)) / I_LEG],
                    (0, until), [3.0, 0.0], events=lock, rtol=1e-10, atol=1e-12, method="DOP853")
    return (float(sol.t_events[0][0]) if len(sol.t_events[0]) else None), sol


def _leg_hangs(U, c, c2, until):
    """True when the own engine's leg is trapped short of the lock for good at ``until``: below the unstable
    equilibrium th_u past the stable one, with less kinetic energy than the work the static moment takes to carry
    it up to th_u (the moment depends on th alone, so in one degree of freedom the energy only falls)."""
    from scipy.integrate import quad
    from scipy.optimize import brentq

    grid = np.linspace(4.0, 4.45, 4501)
    signs = np.sign([_leg_moment(th, U) for th in grid])
    changes = np.flatnonzero(np.diff(signs))
    if len(changes) < 2:
        return False
    th_u = brentq(lambda th: _leg_moment(th, U), grid[changes[1]], grid[changes[1] + 1], xtol=1e-14)
    t_lock, sol = _leg_run(U, c, c2, until)
    th, w = sol.y[:, -1]
    barrier = -quad(lambda q: _leg_moment(q, U), th, th_u, epsabs=1e-12)[0]
    return t_lock is None and th < th_u and 0.5 * I_LEG * w * w < barrier


@pytest.fixture(scope="module")
def fold_leg():
    return load_model(FOLD_LEG)


def test_the_independent_leg_is_the_file(fold_leg):
    """The two formulations agree on the statics (the locked reaction and a free moment) before they judge each
    other: R_downlock of the model held at the lock equals the own moment there, at two airspeeds."""
    from mechcont.continuation import find_equilibrium

    for U in (20.0, 35.0):
        x = find_equilibrium(fold_leg, values={"U": U}, hold={"angle": 4.45}, free=["R_downlock"])
        assert x[fold_leg.index("R_downlock")] == pytest.approx(_leg_moment(4.45, U), rel=1e-9)


def test_a_leg_creeping_through_the_folds_ghost_is_still_moving_not_at_rest(fold_leg):
    """Heavily damped (c = 20000 N s/m) just below the fold there is no equilibrium anywhere in the travel, so the
    leg must lock: the own engine reaches the lock. At 60 s it creeps (speed < 1e-4 rad/s) near the ghost; the old
    rule called that "at rest"."""
    U_fold, _ = _leg_fold()
    U = U_fold - 0.003
    assert min(_leg_moment(th, U) for th in np.linspace(3.0, 4.45, 2001)) > 0  # no equilibrium on the way
    t_lock, sol = _leg_run(U, 20000.0, 0.0, 2000.0)
    assert t_lock is not None and t_lock > 60.0  # locks, but long after the run below ends
    run = freefall(fold_leg, {"angle": 3.0}, lock="downlock", until=60.0, end_at_lock=True,
                   values={"U": U, "c_ret": 20000.0, "c2_ret": 0.0}, audit=False)
    assert run.final_speed < 1e-4  # slow enough that the old rule said "at rest"
    assert run.outcome == "still moving" and not run.decided
    assert any(line.startswith("creeping: max speed") for line in run.describe())


def test_a_leg_at_rest_at_a_stable_equilibrium_ends_early_and_where_the_statics_say():
    """examples/freefall_leg.toml at U = 106 (damped): the own statics of that file (the pendulum above, its spring
    anchor S = (0.3, -0.6), free length 0.6) give a stable equilibrium short of the lock and a pulling lock
    (R = M(4.45) < 0): at rest there is the truth. A run asked for 1e6 s (the documented maximum, 35 min before)
    ends once at rest within 1e-6 rad of it."""
    from scipy.optimize import brentq

    saved = dict(LEG)
    LEG.update(S=(0.3, -0.6), l0=0.6)
    try:
        assert _leg_moment(4.45, 106.0) < -500  # the lock would pull: no locked state at U = 106
        th_eq = brentq(lambda th: _leg_moment(th, 106.0), 4.3, 4.45, xtol=1e-14)
        slope = (_leg_moment(th_eq + 1e-6, 106.0) - _leg_moment(th_eq - 1e-6, 106.0)) / 2e-6
    finally:
        LEG.clear()
        LEG.update(saved)
    assert slope < 0  # stable
    run = freefall(load_model("examples/freefall_leg.toml"), {"angle": 3.0}, lock="downlock", until=1e6,
                   end_at_lock=True, values={"U": 106.0}, audit=False)
    assert run.outcome == "at rest" and run.decided
    assert run.history.t[-1] < 100.0
    assert run.history["angle"][-1] == pytest.approx(th_eq, abs=2e-6)


def test_rest_speed_must_be_finite():
    from mechcont.errors import InputError

    with pytest.raises(InputError, match="rest_speed"):
        freefall(load_model(SWING), {"angle": BETA}, lock="lock", until=1.0, rest_speed=math.inf)


@pytest.mark.slow
def test_the_damped_critical_bracket_holds_the_truth_or_says_it_cannot(fold_leg):
    """Heavily damped (c = 20000 N s/m) the dynamic critical U cannot lie below the fold (no equilibrium there: every
    run locks) and the own engine's leg is trapped for good at U_fold + 2e-3. The old bisection called creeping
    runs failures and bracketed 31.39 (below the fold, a "negative difference" with the statics)."""
    from mechcont.dynamics.freefall import critical_airspeed

    U_fold, _ = _leg_fold()  # below it every run locks (no equilibrium on the way): the truth is >= U_fold
    assert _leg_hangs(U_fold + 2e-3, 20000.0, 0.0, 400.0)  # and this one is trapped for good: the truth is below
    crit = critical_airspeed(fold_leg, {"angle": 3.0}, "U", 31.0, 32.0, tol=1e-3, lock="downlock", until=20.0,
                             values={"c_ret": 20000.0, "c2_ret": 0.0}, end_at_lock=True)
    assert crit.locks_below and not crit.contradicts(U_fold)
    # the bracket holds the truth, in [U_fold, U_fold + 2e-3]: it cannot end below it, nor begin above it
    assert crit.failed >= U_fold and crit.locked <= U_fold + 2e-3
    if crit.width > 1e-3:
        assert crit.stopped and crit.unsettled  # it says why it could not narrow
