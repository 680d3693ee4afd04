"""The freefall section of ``mechcont paper`` (issue 23, item 6): the nose gear, the damping study and the
dual-sidestay gear from gear up. The section runs once per session (tests/test_figure_review.py's section_run,
shared with its figure review); its summary is checked here."""

import math
import re

import numpy as np
import pytest

from mechcont.analysis import equilibrium_on_stops
from mechcont.dynamics.freefall import freefall
from mechcont.models import model_from_text
from mechcont.paper.freefall import THETA_UP, description_text


def test_nose_gear_locks_from_the_uplock_and_rests_with_the_static_reaction():
    system = model_from_text(description_text(), "nose_gear_freefall.toml")
    run = freefall(system, {"fitting": THETA_UP}, lock="downlock", until=3.0, values={"U": 50.0})
    assert run.outcome == "locked" and 0.5 < run.time_to_lock < 3.0
    h = run.history
    assert h["overcentre"][0] < -1.0 and h["overcentre"][-1] == pytest.approx(0.035, abs=1e-9)  # from folded to the stop
    x = h.values[-1].copy()
    x[system.index("R_downlock")] = 0.0
    xe, contact = equilibrium_on_stops(system, x, values={"U": 50.0}, contact=["downlock"])
    assert contact == ["downlock"]
    assert h["R_downlock"][-1] == pytest.approx(xe[system.index("R_downlock")], rel=1e-8)


@pytest.fixture(scope="module")
def section(shared):
    """The freefall section's run and its summary text: the run tests/test_figure_review.py reviews, made once per
    session (``mechcont paper --only`` itself, which writes the same lines to summary.md after a header, is
    tests/test_paper.py's)."""
    from test_figure_review import section_run

    run = section_run("freefall", shared)
    return run, "\n".join(run.lines)


@pytest.mark.slow
def test_paper_section_reports_the_critical_airspeed(section):
    run, text = section
    assert "## Freefall extension of the nose gear" in text and "| 125 | still moving |" in text
    sr = float(text.split("releases (SR) at U = ")[1].split()[0])
    low = float(text.split("largest airspeed run that locked, ")[1].split()[0])
    high = float(text.split("the smallest that did not, ")[1].split()[0])
    assert low <= sr <= high  # a run locks exactly when its contact reaction is positive: below SR
    assert run.sizes["freefall_nose_gear.png"] > 0
    assert run.sizes["freefall_critical_vs_damping.png"] > 0


def _sidestay_rows(text):
    table = text.split("### Dual-sidestay main gear: freefall from gear up")[1].split("| k_att (N/m)")[1]
    rows = [r for r in table.splitlines()[2:] if r.startswith("| ")]
    return [[c.strip() for c in r.strip("|").split("|")] for r in rows]


@pytest.mark.slow
def test_paper_section_dual_sidestay_gear_locks_both_sidestays(section):
    """Every row of the table is consistent: locked after the pair's first strike, the gap is aft minus fwd,
    the nominal gear (first row) locks both pairs; the pose paragraph reports a physical retracted pose."""
    _, text = section
    rows = _sidestay_rows(text)
    assert len(rows) >= 3 and rows[0][:3] == ["5e+07", "0.7", "locked"]
    for _k, _stretch, outcome, fwd_hit, fwd_lock, aft_hit, aft_lock, gap, load in rows:
        if outcome != "locked":
            continue
        hits = [float(fwd_hit.split()[0]), float(aft_hit.split()[0])]
        locks = [float(fwd_lock.split()[0]), float(aft_lock.split()[0])]
        assert all(h <= t + 1e-9 for h, t in zip(hits, locks))
        assert float(gap) == pytest.approx(locks[1] - locks[0], abs=0.11)  # cells rounded to 0.1 ms
        assert 1.0 < locks[0] / 1e3 < 3.0 and 10.0 < float(load) < 200.0
    um = float(re.search(r"the attachment deflects (\d+) um", text).group(1))
    mm = float(re.search(r"the aft upper arm ends (\d+) mm off", text).group(1))
    assert 0 < um < 1000 and mm > 50  # physical: tens of microns; kinematic: the attachment dragged away


@pytest.mark.slow
def test_dual_sidestay_retracted_pose_is_the_quasi_static_one(section):
    """The released pose: theta at gear up, the joints closed, every stop on its allowed side, both pairs
    folded, and the attachment deflected by its force over its stiffness (the compliant joint's law, from the
    pose's reaction and the attachment point's position, to 1e-6)."""
    from mechcont.dynamics.freefall import condition_value
    from mechcont.paper import freefall_sidestay as fs

    model = fs.freefall_gear()
    x = fs.retracted(model)
    assert condition_value(model, x, "theta") == pytest.approx(fs.SIDESTAY_UP, abs=1e-9)
    assert np.max(np.abs(model.mechanics.phi(x))) < 1e-9
    for st in model.stops:
        assert st.side * (condition_value(model, x, st.condition) - st.limit) > 0.1
    force = np.linalg.norm([x[model.index(f"R_aft_A_{c}")] for c in "xyz"])
    assert fs.attachment_offset(model, x) == pytest.approx(force / x[model.index("k_att")], rel=1e-6)
    assert math.degrees(abs(math.asin(condition_value(model, x, "aft_lock")))) > 5.0


def test_held_pose_is_the_equilibrium_whatever_the_path_and_not_the_kinematic_assembly():
    """held_pose (freefall --held-by) against an independent path: the equilibria with theta held and F_act
    solved followed from theta = 0.05 rad in 12 steps (find_equilibrium directly) land on the same pose to
    1e-8; the kinematic assembly at the same theta drags the compliant attachment a hundred millimetres."""
    from mechcont.continuation import find_equilibrium
    from mechcont.dynamics.freefall import held_pose
    from mechcont.paper import freefall_sidestay as fs

    model = fs.freefall_gear()
    x = held_pose(model, {"theta": fs.SIDESTAY_UP}, "F_act")
    y = None
    for t in np.linspace(0.05, fs.SIDESTAY_UP, 13):
        y = find_equilibrium(model, hold={"theta": float(t)}, free=["F_act"], guess=y)
    assert y is not None and y[model.index("F_act")] < -1e4  # the actuator holds the gear up
    i = model.index("F_act")
    assert x[i] == 0.0  # released
    states = [k for k, v in enumerate(model.variables) if v.kind == "state" and k != i]
    assert np.max(np.abs(x[states] - y[states])) < 1e-8
    assert fs.attachment_offset(model, x) < 1e-3 < 0.1 < fs.kinematic_offset(model)[0]


def test_the_paper_pendulum_is_the_tested_one():
    """The damping study of the paper uses the pendulum whose closed forms tests/test_freefall.py checks."""
    from mechcont.paper.freefall import PENDULUM

    with open("tests/data/freefall_pendulum.toml") as fh:
        assert PENDULUM == fh.read()
