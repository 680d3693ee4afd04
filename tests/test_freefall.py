"""Freefall (issue 23, item 5) against closed forms and an independent reduced equation of motion.

tests/data/freefall_pendulum.toml: a uniform bar (mass m, length L, I_O = m L^2 / 3) hinged at O,
released at rest from the uplock theta = beta, falls onto the downlock theta = -beta against the drag
of an upward airflow U and a damper (coefficient c) from G = (0, 2L) to the tip. The net moment is

    M(theta) = (L/2) cos(theta) (k U^2 cos(theta) - m g),   k = rho C_D d L / 2,

so the stall equilibria satisfy cos(theta) = m g / (k U^2): a branch whose fold is at theta = 0,
U_c = sqrt(m g / k) -- the quasi-static critical airspeed. The damper's length is
l = L sqrt(5 - 4 sin(theta)), dl/dtheta = -2 L cos(theta) / sqrt(5 - 4 sin(theta)).
"""

import math

import pytest
from scipy.integrate import solve_ivp

from mechcont.dynamics.freefall import critical_airspeed, freefall, quasi_static_critical
from mechcont.errors import InputError
from mechcont.models import load_model
from mechcont.outputs.critical_plots import critical_figure

PATH = "tests/data/freefall_pendulum.toml"
M, L, G, BETA, RHO, CD, D = 10.0, 1.0, 9.81, 1.0, 1.225, 1.2, 0.2
K = RHO * CD * D * L / 2
U_C = math.sqrt(M * G / K)
I_O = M * L * L / 3


def moment(theta, U):
    return L / 2 * math.cos(theta) * (K * U * U * math.cos(theta) - M * G)


def arm(theta):
    return -2 * L * math.cos(theta) / math.sqrt(5 - 4 * math.sin(theta))


def reduced_locks(U, c, until):
    """The independent engine: I theta'' = M(theta) - c (dl/dtheta)^2 theta', from rest at beta;
    locked when theta reaches -beta (before an uplock return or the end of time)."""
    def rhs(t, y):
        return [y[1], (moment(y[0], U) - c * arm(y[0]) ** 2 * y[1]) / I_O]

    def down(t, y):
        return y[0] + BETA
    down.terminal = True

    def up(t, y):
        return y[0] - BETA - 1e-9
    up.terminal, up.direction = True, 1
    sol = solve_ivp(rhs, (0, until), [BETA, 0.0], events=[down, up], rtol=1e-10, atol=1e-12)
    return bool(len(sol.t_events[0])), sol


def reduced_peak_tension(U, c, t_lock):
    """The independent engine's largest |c dl/dt| (N) before the lock and when (s): on its dense output, a scan of
    20001 points refined by bounded Brent."""
    from scipy.optimize import minimize_scalar

    sol = solve_ivp(lambda t, y: [y[1], (moment(y[0], U) - c * arm(y[0]) ** 2 * y[1]) / I_O], (0, t_lock),
                    [BETA, 0.0], rtol=1e-12, atol=1e-13, dense_output=True)

    def tension(t):
        theta, rate = sol.sol(t)
        return abs(c * arm(theta) * rate)
    ts = [t_lock * k / 20000 for k in range(20001)]
    k = max(range(len(ts)), key=lambda i: tension(ts[i]))
    found = minimize_scalar(lambda t: -tension(t), bounds=(ts[max(k - 1, 0)], ts[min(k + 1, 20000)]),
                            method="bounded", options={"xatol": 1e-13})
    return -found.fun, found.x


def reduced_critical(c, until, lo, hi, tol):
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if reduced_locks(mid, c, until)[0] else (lo, mid)
    return 0.5 * (lo + hi)


def test_lock_time_impact_speed_and_reaction_match_the_reduced_equation():
    system = load_model(PATH, c=5.0)
    run = freefall(system, {"angle": BETA}, lock="downlock", until=10.0, values={"U": 15.0})
    locks, sol = reduced_locks(15.0, 5.0, 10.0)
    assert locks and run.outcome == "locked"
    assert run.time_to_lock == pytest.approx(sol.t_events[0][0], rel=1e-6)
    assert run.impact_speed == pytest.approx(abs(sol.y_events[0][0][1]), rel=1e-6)
    # at rest on the downlock the stop carries the net moment there (restitution 0: no bounce)
    assert run.peak_reaction["downlock"] == pytest.approx(-moment(-BETA, 15.0), rel=1e-6)
    assert run.peak_reaction["uplock"] == 0.0
    # the damper's tension is c dl/dt = c (dl/dtheta) theta': its peak, located on the dense output, against the
    # independent engine's, located on its own dense output (a fine scan, then bounded Brent)
    h = run.history
    tension = [5.0 * arm(a) * b for a, b in zip(h["angle"], h["theta_leg_dot"])]
    rows = max(abs(v) for v in tension)
    value, when = reduced_peak_tension(15.0, 5.0, sol.t_events[0][0])
    peak = run.damper_peaks["retraction"]
    assert peak.value == pytest.approx(value, rel=1e-8) and peak.time == pytest.approx(when, rel=1e-4)
    assert abs(rows / value - 1) > 1e-5  # what the rows' largest value missed it by
    assert f"peak damper tension retraction: {peak.value:.6g} N at t = {peak.time:.6g} s" in run.describe()


def test_stall_rests_in_the_closed_form_equilibrium():
    """Short of the lock, at rest in the equilibrium cos(theta) = m g / (k U^2): "at rest", not locked."""
    system = load_model(PATH, c=20.0)
    U = 1.02 * U_C
    run = freefall(system, {"angle": BETA}, lock="downlock", until=60.0, values={"U": U}, end_at_lock=True)
    assert run.outcome == "at rest" and run.time_to_lock is None and run.impact_speed is None
    assert run.describe()[0] == "outcome: at rest short of locking (lock: stop downlock)"
    assert run.stops["downlock"].left is None
    theta = run.history["angle"][-1]
    assert theta == pytest.approx(math.acos(M * G / (K * U * U)), abs=1e-6)


def test_lock_condition_reached():
    system = load_model(PATH, c=5.0)
    run = freefall(system, {"angle": BETA}, lock=("angle", -0.5), until=10.0, values={"U": 15.0})
    def hit(t, y):
        return y[0] + 0.5
    hit.terminal = True
    sol = solve_ivp(lambda t, y: [y[1], (moment(y[0], 15.0) - 5.0 * arm(y[0]) ** 2 * y[1]) / I_O], (0, 10),
                    [BETA, 0.0], events=[hit], rtol=1e-10, atol=1e-12)
    assert run.outcome == "locked"
    assert run.time_to_lock == pytest.approx(sol.t_events[0][0], rel=1e-6)
    assert run.impact_speed == pytest.approx(abs(sol.y_events[0][0][1]), rel=1e-6)


def test_quasi_static_critical_is_the_closed_form_fold():
    q = quasi_static_critical(load_model(PATH), "angle", BETA, -BETA, "U")
    assert q.fold
    assert q.value == pytest.approx(U_C, rel=1e-9)
    assert q.pose == pytest.approx(0.0, abs=1e-6)


def test_overdamped_critical_airspeed_converges_to_the_quasi_static_fold():
    """The runs end once locked or at rest short of the lock (``end_at_lock``, as the freefall command's): the
    outcome of the run to ``until`` (test_a_run_ended_at_the_lock_has_the_lock_of_the_full_run; the light
    damping test below runs its bracket's ends again to the end)."""
    system = load_model(PATH, c=20.0)
    crit = critical_airspeed(system, {"angle": BETA}, "U", 25.0, 27.0, tol=2e-3, lock="downlock", until=200.0,
                             end_at_lock=True)
    assert crit.locks_below and 0 < crit.width <= 2e-3 and (crit.low, crit.high) == (crit.locked, crit.failed)
    assert crit.locked == pytest.approx(U_C, rel=1e-3)
    assert not crit.compare(U_C)[1]  # within the bracket's width of the fold: not a significant difference


def test_light_damping_critical_airspeed_matches_the_reduced_equation():
    """With little damping the momentum carries the gear over the fold: a margin above U_c that the
    independent integrator reproduces to the bisection tolerance. The bisection's runs end once locked or at
    rest (``end_at_lock``, as the freefall command's); the two ends are run again to ``until`` without it."""
    system = load_model(PATH, c=2.0)
    crit = critical_airspeed(system, {"angle": BETA}, "U", 24.0, 30.0, tol=2e-3, lock="downlock", until=30.0,
                             end_at_lock=True)
    ref = reduced_critical(2.0, 30.0, 24.0, 30.0, 1e-4)
    assert crit.low - 1e-4 <= ref <= crit.high + 1e-4 and crit.width <= 2e-3
    assert crit.locked > 1.02 * U_C  # the momentum margin shows
    difference, significant = crit.compare(U_C)
    assert significant and difference == pytest.approx(crit.locked - U_C)
    # both ends were run with the stated outcomes: run again, and by the independent engine
    assert (crit.locked, "locked") in crit.runs and (crit.failed, crit.outcome(crit.failed)) in crit.runs
    again = [freefall(system, {"angle": BETA}, lock="downlock", until=30.0, values={"U": v}).locked
             for v in (crit.locked, crit.failed)]
    assert again == [True, False]
    assert reduced_locks(crit.locked, 2.0, 30.0)[0] and not reduced_locks(crit.failed, 2.0, 30.0)[0]


def test_bad_inputs():
    system = load_model(PATH)
    with pytest.raises(InputError, match="^lock: unknown stop 'nope'"):
        freefall(system, {"angle": BETA}, lock="nope", until=1.0)
    with pytest.raises(InputError, match="^critical: both ends"):
        critical_airspeed(system, {"angle": BETA}, "U", 5.0, 6.0, tol=0.1, lock="downlock", until=5.0)
    with pytest.raises(InputError, match="^critical: m2 is not a parameter"):
        critical_airspeed(system, {"angle": BETA}, "m2", 5.0, 6.0, tol=0.1, lock="downlock", until=5.0)


def test_critical_figure(tmp_path):
    fig = critical_figure([1.0, 10.0, 100.0], [(27.0, 27.1), (26.0, 26.1), (25.9, 26.0)], U_C,
                          damping_label="c (N s/m)")
    ax = fig.axes[0]
    assert len(ax.lines) == 2 and ax.get_xscale() == "log"
    assert list(ax.lines[0].get_ydata()) == [27.0, 26.0, 25.9]  # the ends that locked
    assert ax.lines[1].get_ydata()[0] == pytest.approx(U_C)


def test_a_run_ended_at_the_lock_has_the_lock_of_the_full_run():
    """end_at_lock stops the run once the downlock is in contact and the leg at rest: the same lock time as the
    run to the end (the time is the contact event, located alike), well before ``until``, and at rest then."""
    system = load_model(PATH)
    full = freefall(system, {"angle": BETA}, lock="downlock", until=20.0, values={"U": 10.0, "c": 5.0})
    short = freefall(system, {"angle": BETA}, lock="downlock", until=20.0, values={"U": 10.0, "c": 5.0},
                     end_at_lock=True)
    assert full.locked and short.locked
    assert short.time_to_lock == pytest.approx(full.time_to_lock, abs=1e-9)
    assert short.history.t[-1] < 0.5 * full.history.t[-1]
    assert short.final_speed <= 1e-4 * (1 + 1e-6)
    assert short.history["angle"][-1] == pytest.approx(-BETA, abs=1e-9)
