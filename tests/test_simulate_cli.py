"""``mechcont simulate`` from the command line (issue 23, item 2)."""

import csv
import math

import pytest
from cli_helpers import make_runner, one_line_error

BAR = "tests/data/bar_drop.toml"


@pytest.fixture(scope="module")
def run():
    return make_runner()


def test_simulate_writes_history_with_units_and_a_row_at_each_stop_event(run, tmp_path):
    out, fig = tmp_path / "h.csv", tmp_path / "h.png"
    res = run("simulate", BAR, "--start", "theta_bar=0", "--until", 2.5, "--stops", "--rtol", 1e-9,
              "--out", out, "--plot", fig, "--no-progress")
    assert res.exit_code == 0, res.output
    printed = [ln for ln in res.output.splitlines() if ln.startswith("t = ")]
    kinds = [ln.split()[4] for ln in printed]
    assert kinds.count("impact") >= 5 and kinds[-1] == "contact" and all(ln.split()[5] == "rest" for ln in printed)
    assert "speed 5.23736 rad/s" in printed[0]  # sqrt(3 g / L sin 1.2), the energy speed
    with open(out) as fh:
        rows = list(csv.reader(fh))
    header = rows[0]
    for col in ("t [s]", "theta_bar [rad]", "theta_bar_dot [rad/s]", "R_rest [N m]", "angle [rad]"):
        assert col in header
    assert header[-1] == "label"
    labelled = [r for r in rows[1:] if r[-1]]
    # every printed event is on a row, at its time
    assert len(labelled) == len({ln.split()[2] for ln in printed}) and len(printed) == sum(
        r[-1].count(";") + 1 for r in labelled)
    for r, ln in zip(labelled, [p for i, p in enumerate(printed) if i == 0 or p.split()[2] != printed[i - 1].split()[2]]):
        assert float(r[0]) == pytest.approx(float(ln.split()[2]), rel=1e-8)
    first = labelled[0]
    assert first[-1].startswith("impact rest 5.23736")
    assert float(first[header.index("theta_bar [rad]")]) == pytest.approx(-1.2, abs=1e-9)
    last = rows[-1]
    assert float(last[header.index("R_rest [N m]")]) == pytest.approx(2 * 9.81 * 0.5 * math.cos(1.2), rel=1e-6)
    assert fig.stat().st_size > 1000


def test_simulate_without_stops_warns_that_they_are_ignored(run, tmp_path):
    res = run("simulate", BAR, "--start", "theta_bar=0", "--until", 0.5, "--no-progress")
    assert res.exit_code == 0, res.output
    assert "ignored" in res.stderr and "--stops" in res.stderr


@pytest.mark.parametrize("args, words", [
    (["--start", "nosuch=1"], ["--start", "nosuch"]),
    (["--start", "theta_bar=abc"], ["--start theta_bar"]),
    (["--start", "theta_bar"], ["--start", "NAME=VALUE"]),
    (["--start", "m=3"], ["--start", "coordinates or conditions"]),
    (["--start", "theta_bar=-1.5", "--stops"], ["--start", "past the limit of stop rest"]),
    (["--start", "theta_bar=0", "--until", "-1"], ["--until"]),
    (["--start", "theta_bar=0", "--watch", "nope"], ["--watch"]),
    (["--start", "theta_bar=0", "--rtol", "0"], ["--rtol"]),
    (["--start", "theta_bar=0", "--damping", "-1"], ["--damping"]),
    (["--start", "theta_bar=0", "--set", "R_rest=1", "--stops"], ["--set", "R_rest", "computed"]),
    (["--start", "theta_bar=0", "--until", "nan"], ["--until"]),
])
def test_bad_input_is_one_line_exit_2_and_no_file(run, tmp_path, args, words):
    out = tmp_path / "h.csv"
    argv = ["simulate", BAR, *args, "--out", out, "--no-progress"]
    if "--until" not in args:
        argv += ["--until", 0.2]
    res = run(*argv)
    one_line_error(res, *words)
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_start_may_hold_a_condition(run, tmp_path):
    out = tmp_path / "h.csv"
    res = run("simulate", BAR, "--start", "angle=-0.3", "--until", 0.1, "--stops", "--out", out, "--no-progress")
    assert res.exit_code == 0, res.output
    with open(out) as fh:
        rows = list(csv.reader(fh))
    first = dict(zip(rows[0], rows[1]))
    assert float(first["theta_bar [rad]"]) == pytest.approx(-0.3, abs=1e-12)
    assert float(first["theta_bar_dot [rad/s]"]) == 0.0  # from rest


BLOWUP = """
[mechanism]
name = "blowup"
[ground]
O = [0, 0]
[bodies.arm]
mass = 1.0
length = 1.0
points = { p = [-0.5, 0] }
[joints.pin]
type = "revolute"
a = "ground.O"
b = "arm.p"
[loads.push]
type = "custom"
at = "arm.origin"
moment = "1/(1 - theta_arm)^2"
"""


def test_integrator_that_cannot_go_on_is_one_line_exit_2_and_keeps_the_history(run, tmp_path):
    """A moment 1/(1 - theta)^2 drives the arm into theta = 1 in finite time (its speed grows without bound):
    the integrator's step collapses before. The history up to there is written, the error names the options
    to change, says when and why, and where the history is."""
    desc, out = tmp_path / "blowup.toml", tmp_path / "h.csv"
    desc.write_text(BLOWUP)
    res = run("simulate", desc, "--start", "theta_arm=0", "--until", 5, "--out", out, "--no-progress")
    one_line_error(res, "--rtol/--atol", "could not go on at t = ", str(out))
    with open(out) as f:
        rows = list(csv.DictReader(f))
    theta = [float(r["theta_arm [rad]"]) for r in rows]
    t_end = float(rows[-1]["t [s]"])
    assert 0.0 < t_end < 5.0 and f"t = {t_end:.6g} s" in res.stderr
    assert 0.99 < theta[-1] < 1.0  # it stopped at the singularity, not before
    # a plain run of the same arm that ends before the singularity succeeds
    ok = run("simulate", desc, "--start", "theta_arm=0", "--until", 0.3, "--no-progress")
    assert ok.exit_code == 0, ok.output
