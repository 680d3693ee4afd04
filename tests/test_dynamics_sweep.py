"""Quasi-static sweeps: jumps just past the folds, stable branches followed, bad input."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.dynamics import Ramp, assemble, sweep
from mechcont.dynamics._sweep import parse_ramps
from mechcont.errors import InputError
from mechcont.models import build_overcentre
from mechcont.models.overcentre import symmetric_folds, symmetric_force

L, M1, M2, G, K = 1.5, 1.0, 1.0, 9.81, 127.0
C = 50.0  # N s/m along the spring: enough that a jump lands on the neighbouring branch


def on_upper_branch(system, F, LU):
    """Assembled equilibrium on the theta1 > 0 stable branch at load F (closed form)."""
    th_fold = symmetric_folds(L, M1, M2, G, K, LU)[1][0] if LU < L else 0.0
    th = brentq(lambda t: symmetric_force(t, L, M1, M2, G, K, LU) - F, th_fold, math.pi / 2 - 1e-9)
    return assemble(system, {"theta1": th, "theta2": math.pi - th, "F": F}, hold=["theta1"])


@pytest.fixture(scope="module")
def oc04():
    return build_overcentre(LU=0.4, c=C)


@pytest.fixture(scope="module")
def slow_sweeps(oc04):
    """Down-ramps of F past the lower fold at three rates, each 4 times slower."""
    x0 = on_upper_branch(oc04, -65.0, 0.4)
    return {rate: sweep(oc04, x0, {"F": (-65.0, -90.0, rate)}, watch="theta1") for rate in (2.0, 0.5, 0.125)}


def test_one_jump_per_sweep_just_past_the_lower_fold(slow_sweeps):
    th_fold, F_fold = symmetric_folds(L, M1, M2, G, K, 0.4)[1]
    for rate, r in slow_sweeps.items():
        assert len(r.jumps) == 1, rate
        j = r.jumps[0]
        assert j.parameter == "F" and j.direction == -1 and j.segment == 0
        assert j.value < F_fold  # after passing the fold (F decreasing)
        assert j.before["theta1"] < th_fold < r["theta1"][0]  # left the branch beyond the fold angle
        assert j.after["theta1"] < -1.0  # landed on the other side (stable branch theta1 < -acos(LU/L))
        assert r.runaway is None  # it settled there: a jump, not a runaway
    # the slowest sweep is within 2 % of the fold load
    assert abs(slow_sweeps[0.125].jumps[0].value - F_fold) < 0.02 * abs(F_fold)


def test_jump_gap_shrinks_like_rate_to_two_thirds(slow_sweeps):
    # slow passage through a saddle-node: the delay in the load scales as rate^(2/3)
    F_fold = symmetric_folds(L, M1, M2, G, K, 0.4)[1][1]
    rates = sorted(slow_sweeps, reverse=True)
    gaps = [F_fold - slow_sweeps[r].jumps[0].value for r in rates]
    assert all(g > 0 for g in gaps)
    assert gaps[0] > gaps[1] > gaps[2]
    exponents = [math.log(gaps[i] / gaps[i + 1]) / math.log(rates[i] / rates[i + 1]) for i in range(2)]
    for e in exponents:
        assert e == pytest.approx(2 / 3, abs=0.08)


def test_down_then_up_sweep_makes_the_hysteresis_loop(oc04):
    (th_u, F_upper), (th_l, F_lower) = symmetric_folds(L, M1, M2, G, K, 0.4)
    x0 = on_upper_branch(oc04, -65.0, 0.4)
    r = sweep(oc04, x0, {"F": [(-65.0, -90.0, 1.0), (-90.0, 110.0, 4.0)]}, watch="theta1")
    assert [j.segment for j in r.jumps] == [0, 1]
    assert r.runaway is None  # the up jump still ringing at the sweep's end lands on a branch visited before
    down, up = r.jumps
    assert down.direction == -1 and F_lower - 8 < down.value < F_lower
    assert up.direction == 1 and F_upper < up.value < F_upper + 15
    assert up.before["theta1"] > th_u  # left the lower branch past the upper fold angle
    assert up.after["theta1"] > 1.0  # back on the upper branch
    F, th = r.curve(1)
    assert F[0] == pytest.approx(-90.0) and F[-1] == pytest.approx(110.0)
    assert th.shape == F.shape


def test_slow_sweep_without_folds_follows_the_stable_branch():
    # LU = 2 m > L: one stable branch for every F, no jump; compare with continuation
    system = build_overcentre(LU=2.0, c=C)
    x0 = on_upper_branch(system, 40.0, 2.0)
    r = sweep(system, x0, {"F": (40.0, -40.0, 2.0)}, watch="theta1")
    assert r.jumps == []
    start = find_equilibrium(system, values={"F": 40.0, "LU": 2.0, "c": C},
                             guess={"theta1": r["theta1"][0], "theta2": math.pi - r["theta1"][0]})
    branch = continuation(system, start, "F", options=ContinuationOptions(bounds={"F": (-45.0, 45.0)}))
    assert branch.stable.all()
    order = np.argsort(branch["F"])
    th_cont = np.interp(r["F"], branch["F"][order], branch["theta1"][order])
    assert np.max(np.abs(r["theta1"] - th_cont)) < 0.01  # rad, lag of a 2 N/s sweep


def test_through_value_and_stop_on_jump(oc04):
    x0 = on_upper_branch(oc04, -65.0, 0.4)
    F_fold = symmetric_folds(L, M1, M2, G, K, 0.4)[1][1]
    r = sweep(oc04, x0, {"F": (-65.0, -90.0, 1.0)}, watch="theta1", through=0.0, stop_on_jump=True)
    assert r.simulation.message.startswith("A terminal event")
    assert r["theta1"][-1] == pytest.approx(0.0, abs=1e-9)
    assert len(r.jumps) == 1
    j = r.jumps[0]
    assert j.value == pytest.approx(r["F"][-1])  # timed at the crossing
    assert j.value < F_fold and j.t_start < j.time


def test_settle_phase_is_not_searched_and_lets_a_release_come_to_rest(oc04):
    x0 = assemble(oc04, {"theta1": 1.2, "theta2": math.pi - 1.2}, hold=["theta1"])  # not at equilibrium
    r = sweep(oc04, x0, {"F": (-65.0, -70.0, 1.0)}, watch="theta1", settle=10.0)
    assert r.jumps == []
    assert r.segment_times[0] == pytest.approx([10.0, 15.0])
    i = np.searchsorted(r.t, 10.0)
    th_eq = brentq(lambda t: symmetric_force(t, L, M1, M2, G, K, 0.4) + 65.0, 0.9, math.pi / 2 - 1e-9)
    assert r["theta1"][i] == pytest.approx(th_eq, abs=1e-3)
    assert np.all(r["F"][: i] == -65.0)


def test_parse_ramps_forms():
    a = parse_ramps({"F": (1.0, 2.0, 0.5)})
    b = parse_ramps([("F", 1.0, 2.0, 0.5)])
    c = parse_ramps({"F": [(1.0, 2.0, 0.5), (2.0, 0.0, 1.0)]})
    assert a == b == (Ramp("F", 1.0, 2.0, 0.5),)
    assert c[1] == Ramp("F", 2.0, 0.0, 1.0) and c[1].duration == 2.0 and c[1].direction == -1


@pytest.mark.parametrize("kwargs, field", [
    ({"ramp": {"F": (0.0, 1.0, 0.0)}}, "ramp"),
    ({"ramp": {"F": (0.0, 0.0, 1.0)}}, "ramp"),
    ({"ramp": {"F": (0.0, 1.0)}}, "ramp"),
    ({"ramp": {"nope": (0.0, 1.0, 1.0)}}, "nope"),
    ({"ramp": {"L1": (1.5, 1.6, 1.0)}}, "L1"),
    ({"watch": "F"}, "watch"),
    ({"settle": -1.0}, "settle"),
    ({"stop_on_jump": True}, "stop_on_jump"),
])
def test_bad_sweep_input_names_the_field(oc04, kwargs, field):
    args = {"ramp": {"F": (-65.0, -66.0, 1.0)}, "watch": "theta1", **kwargs}
    ramp = args.pop("ramp")
    with pytest.raises(InputError, match=f"^{field}"):
        sweep(oc04, on_upper_branch(oc04, -65.0, 0.4), ramp, **args)
