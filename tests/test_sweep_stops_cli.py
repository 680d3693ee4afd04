"""``mechcont sweep --stops`` (issue 23, item 1): the stops simulated, the loads at contact and release printed.

tests/data/pendulum_stop.toml: a bar (m, L) hinged at O resting on a stop at theta = -1.2 under gravity;
a moment T lifts it off when T exceeds the gravity moment, m g (L/2) cos(1.2). Raised slowly from rest
on the stop, the bar stays in contact (at rest) and so lets go exactly there.
"""

import math

import pytest
from cli_helpers import make_runner, one_line_error

STOP = "tests/data/pendulum_stop.toml"


@pytest.fixture(scope="module")
def run():
    return make_runner()


def test_sweep_with_stops_prints_the_release_load(run):
    res = run("sweep", STOP, "--start", "theta_bar=-1.2", "--no-equilibrium", "--ramp", "T=3:4:1", "--watch",
              "theta_bar", "--stops", "--rtol", 1e-9, "--no-progress")
    assert res.exit_code == 0, res.output
    lines = res.output.splitlines()
    events = [ln for ln in lines if ln.startswith("t = ")]
    assert [ln.split()[4] for ln in events] == ["contact", "release"]
    (release,) = [ln for ln in lines if ln.startswith("release loads: ")]
    value = float(release.split()[2])
    assert value == pytest.approx(2.0 * 9.81 * 0.5 * math.cos(1.2), abs=5e-6)  # printed to 6 significant digits


def test_sweep_without_stops_ignores_them(run):
    res = run("sweep", STOP, "--start", "theta_bar=-1.2", "--no-equilibrium", "--ramp", "T=3:4:1", "--watch",
              "theta_bar", "--no-progress")
    assert res.exit_code == 0, res.output
    assert "release" not in res.output


def test_sweep_stops_on_a_model_without_stops_is_one_line_and_writes_nothing(run, tmp_path):
    out = tmp_path / "s.csv"
    res = run("sweep", "tests/data/damped_pendulum.toml", "--start", "theta_bar=-1.2", "--ramp", "c=3:4:1",
              "--watch", "theta_bar", "--stops", "--no-progress", "--out", out)
    one_line_error(res, "--stops", "declares no stops")
    assert not out.exists()
