"""Sweeps that run away past the last fold (a crank spinning away) are reported as runaways, not "no jump".

tests/data/driven_bar.toml: a uniform bar (m, L) hinged at one end, turned by a moment M against gravity; its
equilibria M = m g (L/2) cos(theta) end at the fold M = m g L/2 (theta = 0). Ramped past it, the bar turns over
and spins on for ever. The old jump threshold, 10 x span / duration, grew with the runaway's own span and was
never reached. A runaway is paired with the fold it follows as a jump is (the branch's LP1 at m g L/2 exactly, the
delay past it shrinking with the ramp rate) and drawn on the sweep plot.
"""

import csv
import math

import numpy as np
import pytest
from cli_helpers import make_runner

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.dynamics import branch_jump_gaps, branch_runaway_gap, parse_ramps, runaway_gap, sweep, sweep_start
from mechcont.dynamics._jumps import find_jump_windows, find_runaway
from mechcont.models import model_at

BAR = "tests/data/driven_bar.toml"
M_FOLD = 1.0 * 9.81 * 1.0 / 2  # N m: m g L/2, the largest gravity moment


@pytest.fixture(scope="module")
def bar():
    return model_at(BAR, {})


def _sweep(bar, rate):
    ramps = parse_ramps({"M": (3.0, 7.0, rate)})
    return sweep(bar, sweep_start(bar, {"theta_bar": -1.0}, ramps), ramps, watch="theta_bar")


@pytest.fixture(scope="module")
def runs(bar):
    """The bar ramped from M = 3 to 7 N m at 0.5 and 0.25 N m/s."""
    return {rate: _sweep(bar, rate) for rate in (0.5, 0.25)}


@pytest.fixture(scope="module")
def branch(bar):
    """The bar's equilibria continued in M from M = 3 N m (theta < 0) over the fold to theta > 0."""
    x = find_equilibrium(bar, values={"M": 3.0}, guess={"theta_bar": -1.0})
    return continuation(bar, x, "M", options=ContinuationOptions(bounds={"M": (0.0, 7.0)}))


def test_a_bar_turned_past_its_fold_runs_away_just_after_it(runs):
    for rate, r in runs.items():
        assert r.jumps == []
        run = r.runaway
        assert run is not None and run.parameter == "M" and run.direction == 1 and run.segment == 0
        assert run.value > M_FOLD  # after the fold
        assert run.before["theta_bar"] > 0.0  # past the fold angle (the bar horizontal)
        assert run.after["theta_bar"] > 2 * math.pi  # turned over at least once, still turning
        # before it the bar follows its equilibrium M = m g (L/2) cos(theta), theta < 0: started at rest on it, an
        # undamped oscillator whose equilibrium moves at speed v lags by at most v / omega; v = rate dtheta/dM and
        # 1/omega (omega^2 = m g (L/2) sin|theta| / (m L^2 / 3)) both grow towards the fold, so M = 4.5 N m bounds them
        quasi = (r["M"] < 4.5) & (r.t < run.t_start)
        truth = -np.arccos(r["M"][quasi] / M_FOLD)
        s_45 = math.sqrt(1.0 - (4.5 / M_FOLD) ** 2)
        bound = rate / (M_FOLD * s_45) / math.sqrt(M_FOLD * s_45 * 3.0)
        assert np.max(np.abs(r["theta_bar"][quasi] - truth)) < bound
    # the slower the ramp, the nearer the fold it starts (slow passage: the delay shrinks with the rate)
    gaps = [runs[rate].runaway.value - M_FOLD for rate in (0.5, 0.25)]
    assert gaps[1] < gaps[0] / 1.5


def test_synthetic_runaway_is_timed_where_it_starts_and_a_settling_jump_is_no_runaway():
    """A record creeping at 0.1 /s that accelerates from t = 6 s (rate 100 (t - 6) /s) runs away there; the old
    threshold (10 x span / duration = 800 /s) was above its fastest rate (400 /s). A tanh step that settles is a
    jump, not a runaway."""
    t = np.linspace(0.0, 10.0, 20001)
    w = 0.1 * t + 50.0 * np.clip(t - 6.0, 0.0, None) ** 2
    wdot = 0.1 + 100.0 * np.clip(t - 6.0, 0.0, None)
    n = len(t) - 1
    assert find_jump_windows(t, w, wdot, 0, n, span=float(np.ptp(w)))[0] == []  # the old detection: nothing
    run = find_runaway(t, w, wdot, 0, n, duration=10.0)
    # |wdot| passes 10 x the median rate (0.1 /s) where 100 (t - 6) = 0.9
    assert run is not None and run.t_start == pytest.approx(6.009, abs=1e-3) and run.t_end == 10.0
    step = 0.1 * t + np.tanh((t - 5.0) / 0.05)
    step_dot = 0.1 + (1.0 - np.tanh((t - 5.0) / 0.05) ** 2) / 0.05
    assert find_runaway(t, step, step_dot, 0, n, duration=10.0) is None
    (jump,), _ = find_jump_windows(t, step, step_dot, 0, n, span=float(np.ptp(step)))
    assert 4.8 < jump.t_start < 5.0 < jump.t_end < 5.2


def test_sweep_command_reports_the_runaway(tmp_path, branch):
    out, table, plot = tmp_path / "sweep.csv", tmp_path / "branch.csv", tmp_path / "sweep.png"
    branch.to_csv(table)
    res = make_runner()("sweep", BAR, "--start", "theta_bar=-1", "--ramp", "M=3:7:0.5", "--watch", "theta_bar",
                        "--no-progress", "--out", str(out), "--branch", str(table), "--plot", str(plot))
    assert res.exit_code == 0, res.output
    assert "no jump" not in res.output and plot.stat().st_size > 0
    (line,) = [ln for ln in res.output.splitlines() if ln.startswith("runaway")]
    load = float(line.split("M = ")[1].split()[0])
    assert M_FOLD < load < M_FOLD + 1.0 and "had not settled" in line
    # paired with the branch's fold as a jump is: "; 0.1 N m past LP1 (M = 4.905 N m)"
    gap, fold = line.split("; ")[-1].split(" N m past LP1 (M = ")
    assert float(fold.split()[0]) == pytest.approx(M_FOLD, rel=1e-6) and fold.endswith(" N m)")
    assert float(gap) == pytest.approx(load - M_FOLD, abs=6e-5)  # printed to 4 digits (0.1-1: 5e-5) and 6 (5e-6)
    rows = list(csv.reader(out.open()))
    (marked,) = [r for r in rows[1:] if r[-1] == "RUNAWAY"]  # the last sample before it: at most one time step
    # (1/400 of the 8 s segment) earlier, 0.02 s x 0.5 N m/s = 0.01 N m
    assert float(marked[rows[0].index("M [N m]")]) == pytest.approx(load - 0.005, abs=0.0051)


def test_the_runaway_is_paired_with_the_fold_it_follows(runs, branch):
    for r in runs.values():
        run = r.runaway
        fold, g = branch_runaway_gap(r, branch)
        assert fold == "LP1" and g.fold_value == pytest.approx(M_FOLD, rel=1e-9)  # the closed form m g L/2
        assert g.jump_value == run.value and g.gap == pytest.approx(run.value - M_FOLD, rel=1e-6)
        assert g.past and g.direction == 1
        assert runaway_gap(r, [1.0, M_FOLD, 9.0]).fold_value == M_FOLD  # the fold behind it, not a nearer one ahead
        assert branch_jump_gaps(r, branch) == []
    # slow passage through a saddle-node: the delay ~ rate^(2/3), 2^(2/3) = 1.59 times shorter at half the rate
    delays = [branch_runaway_gap(runs[rate], branch)[1].gap for rate in (0.5, 0.25)]
    assert 0 < delays[1] < delays[0] / 1.5


def test_the_sweep_plot_draws_the_runaway(runs, branch):
    from matplotlib.lines import Line2D
    from matplotlib.text import Annotation

    from mechcont.outputs.sweep_plots import sweep_figure

    r = runs[0.5]
    run = r.runaway
    fig = sweep_figure(r, title="bar", branch=branch, degrees=True)
    ax = fig.axes[0]
    start = (run.value, math.degrees(run.before["theta_bar"]))
    (mark,) = [ln for ln in ax.get_lines() if isinstance(ln, Line2D) and ln.get_label() == "runaway"]
    assert np.allclose(np.column_stack(mark.get_data()), [start])
    (arrow,) = [t for t in ax.texts if isinstance(t, Annotation) and t.get_gid() == "runaway"]
    assert np.allclose(arrow.xyann, start) and np.allclose(arrow.xy, (run.value, math.degrees(run.after["theta_bar"])))
    assert "runaway" in [t.get_text() for leg in fig.legends for t in leg.get_texts()]
