"""The nose-gear freefall of ``mechcont paper --only freefall`` (issue 23, item 6)."""

import pytest
from click.testing import CliRunner

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


@pytest.mark.slow
def test_paper_section_reports_the_critical_airspeed(tmp_path):
    from mechcont.cli._app import _register, cli

    _register()
    res = CliRunner().invoke(cli, ["paper", "--out", str(tmp_path), "--only", "freefall", "--quiet"])
    assert res.exit_code == 0, res.output
    text = (tmp_path / "summary.md").read_text()
    assert "## Freefall extension of the nose gear" in text and "| 125 | timed out |" in text
    sr = float(text.split("releases (SR) at U = ")[1].split()[0])
    dyn = text.split("largest airspeed that locks, ")[1]
    low, high = (float(v) for v in dyn.split("bracket [")[1].split("]")[0].split(", "))
    assert low <= sr <= high  # a run locks exactly when its contact reaction is positive: below SR
    assert (tmp_path / "freefall_nose_gear.png").stat().st_size > 0


def test_the_paper_pendulum_is_the_tested_one():
    """The damping study of the paper uses the pendulum whose closed forms tests/test_freefall.py checks."""
    from mechcont.paper.freefall import PENDULUM

    with open("tests/data/freefall_pendulum.toml") as fh:
        assert PENDULUM == fh.read()
