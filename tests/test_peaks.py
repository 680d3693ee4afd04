"""Peaks located on the integrator's dense output (issue 31, item 3), against closed forms, with the saved rows
deliberately coarse.

tests/data/bar_drop.toml: a uniform bar (m, L) hinged at its end, released at rest from the horizontal. Without
its stop it swings through the bottom at its fastest, sqrt(3 g / L) (energy), at the quarter period
sqrt(2 L / (3 g)) K(1/2) (elliptic); with its stop at -phi_s it is fastest just before the first impact,
sqrt((3 g / L) sin(phi_s)), at the fall time of tests/test_sim_stops.py, and rests on the stop (restitution 0)
with the reaction (m g L / 2) cos(phi_s)."""

import math
import pickle

import numpy as np
import pytest
from scipy.special import ellipk
from test_sim_stops import PHI_S, K, bar, fall_time

from mechcont.dynamics import assemble, simulate
from mechcont.errors import InputError
from mechcont.models import load_model

ROWS = np.linspace(0.0, 1.0, 11)  # every 0.1 s: far coarser than the integrator's steps


def _swing():
    system = load_model("tests/data/bar_drop.toml")
    x0 = assemble(system, {"theta_bar": 0.0}, hold=["theta_bar"])
    return simulate(system, x0, (0.0, 1.0), rtol=1e-10, atol=1e-12, t_eval=ROWS)


def test_peak_speed_of_a_swinging_bar_is_located_at_the_bottom():
    result = _swing()
    assert len(result) == len(ROWS) and len(result.dense) > 3 * len(ROWS)
    peak = result.peak("theta_bar_dot", absolute=True)
    speed, when = math.sqrt(K), math.sqrt(2 / K) * ellipk(0.5)
    assert peak.value == pytest.approx(speed, rel=1e-8)
    assert peak.time == pytest.approx(when, rel=1e-6)
    sampled = np.max(np.abs(result["theta_bar_dot"]))
    assert abs(sampled / speed - 1) > 1e-3  # the rows missed it by a thousand times more
    # the dense output between the rows is the motion: the angle at the peak is the bottom
    x, qd = result.dense.row(peak.time)
    assert x[result.names.index("theta_bar")] == pytest.approx(-math.pi / 2, abs=1e-6)


def test_a_peak_at_an_impact_is_the_speed_just_before_it_and_a_reaction_peak_is_located_on_the_stop():
    """Plastic drop onto the stop: fastest at the impact (the end of a step, the velocity jumps to zero there);
    the stop's reaction, from the contact's multiplier on the dense output, at most the static one."""
    system = bar(0.0)
    x0 = assemble(system, {"theta_bar": 0.0}, hold=["theta_bar"])
    result = simulate(system, x0, (0.0, 1.0), stops=True, rtol=1e-10, atol=1e-12, t_eval=ROWS)
    peak = result.peak("theta_bar_dot", absolute=True)
    assert peak.value == pytest.approx(math.sqrt(K * math.sin(PHI_S)), rel=1e-8)
    assert peak.time == pytest.approx(fall_time(), rel=1e-9)
    reaction = result.peak("R_rest")
    static = 2.0 * 9.81 * 1.0 / 2 * math.cos(PHI_S)
    assert reaction.value == pytest.approx(static, rel=1e-8) and reaction.time >= fall_time() - 1e-12


def test_a_callable_quantity_and_the_fallbacks():
    result = _swing()
    i = result.names.index("theta_bar")
    far = result.peak(lambda x, qd: -x[i])  # the largest of -theta: the far horizontal, at half the period
    assert far.value == pytest.approx(math.pi, rel=1e-9)
    assert far.time == pytest.approx(2 * math.sqrt(2 / K) * ellipk(0.5), rel=1e-6)
    with pytest.raises(InputError, match="^nope: not a column"):
        result.peak("nope")
    again = pickle.loads(pickle.dumps(result))  # pickled without the dense output: the rows' largest
    assert again.dense is None
    assert again.peak("theta_bar_dot", absolute=True).value == pytest.approx(np.max(np.abs(result["theta_bar_dot"])))


def test_a_sweeps_phases_are_joined_into_one_dense_output():
    """A sweep of the swinging bar ramping a parameter that acts on nothing, in two phases: the peaks of either
    phase located as in one simulation (the far horizontal is reached in the second)."""
    from mechcont.dynamics import parse_ramps, sweep
    from mechcont.models import model_from_text

    text = open("tests/data/bar_drop.toml").read().replace("[ground]", 'idle = { value = 0.0, unit = "N" }\n\n[ground]')
    system = model_from_text(text, "bar_drop_idle.toml")
    x0 = assemble(system, {"theta_bar": 0.0}, hold=["theta_bar"])
    result = sweep(system, x0, parse_ramps([("idle", 0.0, 1.0, 2.0), ("idle", 1.0, 0.0, 2.0)]), watch="theta_bar",
                   rtol=1e-10, atol=1e-12).simulation
    assert result.t[-1] == pytest.approx(1.0) and result.dense is not None
    half = math.sqrt(2 / K) * ellipk(0.5)
    speed = result.peak("theta_bar_dot", absolute=True)
    assert speed.value == pytest.approx(math.sqrt(K), rel=1e-8) and speed.time == pytest.approx(half, rel=1e-6)
    i = result.names.index("theta_bar")
    far = result.peak(lambda x, qd: -x[i])
    assert far.value == pytest.approx(math.pi, rel=1e-9) and far.time == pytest.approx(2 * half, rel=1e-6)
