"""``mechcont freefall`` from the command line (issue 23, item 5) on tests/data/freefall_pendulum.toml
(closed forms in tests/test_freefall.py: quasi-static critical U_c = sqrt(2 m g / (rho C_D d L)))."""

import csv
import math

import pytest
from cli_helpers import make_runner, one_line_error

PATH = "tests/data/freefall_pendulum.toml"
U_C = math.sqrt(2 * 10.0 * 9.81 / (1.225 * 1.2 * 0.2 * 1.0))


@pytest.fixture(scope="module")
def run():
    return make_runner()


def test_one_run_locks_and_reports(run, tmp_path):
    from mechcont.dynamics.freefall import freefall
    from mechcont.models import load_model

    out, fig = tmp_path / "h.csv", tmp_path / "h.png"
    res = run("freefall", PATH, "--start", "angle=1", "--lock", "downlock", "--until", 5, "--set", "U=15",
              "--set", "c=5", "--out", out, "--plot", fig)
    assert res.exit_code == 0, res.output
    lines = res.output.splitlines()
    assert "outcome: locked (lock: stop downlock)" in lines
    lib = freefall(load_model(PATH, c=5.0), {"angle": 1.0}, lock="downlock", until=5.0, values={"U": 15.0})
    (t,) = [ln for ln in lines if ln.startswith("time to lock: ")]
    assert float(t.split()[3]) == pytest.approx(lib.time_to_lock, rel=1e-5)  # 6 significant digits printed
    (v,) = [ln for ln in lines if ln.startswith("impact speed at the lock: ")]
    assert v.endswith("rad/s") and float(v.split()[5]) == pytest.approx(lib.impact_speed, rel=1e-5)
    (tension,) = [ln for ln in lines if ln.startswith("peak damper tension retraction: ")]
    peak = lib.damper_peaks["retraction"]
    assert tension == f"peak damper tension retraction: {peak.value:.6g} N at t = {peak.time:.6g} s"
    assert any(ln.startswith("peak stop reaction downlock: ") and " N m at t = " in ln for ln in lines)
    with open(out) as fh:
        header = next(csv.reader(fh))
    assert "R_downlock [N m]" in header and header[-1] == "label"
    assert fig.stat().st_size > 0


def test_stall_is_reported_with_where_it_hangs(run):
    res = run("freefall", PATH, "--start", "angle=1", "--lock", "downlock", "--until", 40, "--set", f"U={1.02 * U_C}",
              "--set", "c=20")
    assert res.exit_code == 0, res.output
    assert "outcome: at rest short of locking (lock: stop downlock)" in res.output


def test_critical_airspeed_with_scan_writes_table_and_figure(run, tmp_path):
    out, fig = tmp_path / "c.csv", tmp_path / "c.png"
    res = run("freefall", PATH, "--start", "angle=1", "--lock", "downlock", "--until", 30, "--critical", "U=24:30",
              "--tol", 0.05, "--scan", "c=2", "--out", out, "--plot", fig)
    assert res.exit_code == 0, res.output
    assert "fold of the stall branch" in res.output
    with open(out) as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["c", "locked_U [m/s]", "failed_U [m/s]", "quasi_static_U [m/s]"]
    c, locked, failed, qs = (float(x) for x in rows[1])
    assert float(qs) == pytest.approx(U_C, rel=1e-9)
    assert 0 < failed - locked <= 0.05
    assert locked > 1.02 * U_C  # light damping: the momentum margin (tests/test_freefall.py checks its value)
    # the bracket's ends are runs made, printed with their outcomes, and the margin exceeds the bracket's width
    (line,) = [ln for ln in res.output.splitlines() if ln.startswith("c = 2: critical U between ")]
    assert f"the largest run that locked U = {locked:.6g} m/s" in line
    assert f"the smallest that did not U = {failed:.6g} m/s (" in line
    (diff,) = [ln for ln in res.output.splitlines() if "dynamic - quasi-static" in ln]
    assert diff.endswith(": significant")
    assert fig.stat().st_size > 0


@pytest.mark.parametrize("args, words", [
    (["--start", "angle=1", "--until", 1], ["--lock", "exactly one"]),
    (["--start", "angle=1", "--until", 1, "--lock", "downlock", "--lock-condition", "angle=-0.5"], ["--lock"]),
    (["--start", "angle=1", "--until", 1, "--lock", "nope"], ["--lock", "unknown stop 'nope'"]),
    (["--start", "phi=1", "--until", 1, "--lock", "downlock"], ["--start", "phi is not"]),
    (["--until", 1, "--lock", "downlock"], ["--start"]),
    (["--start", "angle=1.2", "--until", 1, "--lock", "downlock"], ["--start", "past the limit of stop uplock"]),
    (["--start", "angle=1", "--until", -1, "--lock", "downlock"], ["--until"]),
    (["--start", "angle=1", "--until", 1, "--lock", "downlock", "--critical", "U=30"], ["--critical", "NAME=LO:HI"]),
    (["--start", "angle=1", "--until", 1, "--lock", "downlock", "--critical", "V=1:2"], ["--critical", "V is not"]),
    (["--start", "angle=1", "--until", 2, "--lock", "downlock", "--critical", "U=5:6"], ["--critical", "both ends"]),
    (["--start", "angle=1", "--until", 1, "--lock", "downlock", "--critical", "U=5:6", "--plot", "PLOT"],
     ["--plot", "--scan"]),
    (["--start", "angle=1", "--until", 1, "--lock", "downlock", "--scan", "c=1,2"], ["--scan", "--critical"]),
    (["--start", "angle=1", "--until", 1, "--lock", "downlock", "--held-by", "angle"], ["--held-by", "angle is not a parameter"]),
])
def test_bad_input_is_one_line_and_writes_nothing(run, tmp_path, args, words):
    out, fig = tmp_path / "o.csv", tmp_path / "o.png"
    args = [str(fig) if a == "PLOT" else a for a in args]
    res = run("freefall", PATH, *args, "--out", out)
    one_line_error(res, *words)
    assert not out.exists() and not fig.exists()


def test_shipped_example_checks_clean_and_locks(run):
    res = run("check", "examples/freefall_leg.toml")
    assert res.exit_code == 0, res.output
    assert "findings: none" in res.output and "downlock  max of angle = 4.45 rad: in contact" in res.output
    res = run("freefall", "examples/freefall_leg.toml", "--start", "angle=3.0", "--lock", "downlock", "--until", 5,
              "--set", "U=40")
    assert res.exit_code == 0, res.output
    assert "outcome: locked (lock: stop downlock)" in res.output
    assert "peak damper tension actuator: " in res.output


def test_held_by_on_a_rigid_leg_is_its_assembly_and_the_same_fall(run):
    """--held-by solves the pose as an equilibrium; a rigid one-degree-of-freedom leg has one pose at the held
    angle, so it equals the kinematic assembly, the parameter is released to its value, and the fall is the same.
    The airspeed that holds it there is the closed form U = sqrt(m g / (k cos(angle))), k = rho C_D d L / 2."""
    import numpy as np

    from mechcont.continuation import find_equilibrium
    from mechcont.dynamics import assemble
    from mechcont.dynamics.freefall import held_pose
    from mechcont.models import load_model

    model = load_model(PATH)
    x, y = held_pose(model, {"angle": 1.0}, "U"), assemble(model, {"angle": 1.0}, hold=["angle"])
    coordinates = [model.index(n) for n in model.mechanics.coordinates]  # the pose (reactions differ: held vs free)
    assert np.max(np.abs(x[coordinates] - y[coordinates])) < 1e-10 and x[model.index("U")] == 20.0
    held = find_equilibrium(model, hold={"angle": 1.0}, free=["U"], guess=x)
    assert held[model.index("U")] == pytest.approx(math.sqrt(10.0 * 9.81 / (1.225 * 1.2 * 0.2 / 2 * math.cos(1.0))),
                                                   rel=1e-9)
    args = ["freefall", PATH, "--start", "angle=1", "--lock", "downlock", "--until", 5, "--set", "U=15"]
    plain, with_held = run(*args), run(*args, "--held-by", "U")
    assert plain.exit_code == 0 and with_held.exit_code == 0, with_held.output

    def lock_time(res):
        (line,) = [ln for ln in res.output.splitlines() if ln.startswith("time to lock: ")]
        return float(line.split()[3])

    assert lock_time(with_held) == pytest.approx(lock_time(plain), rel=1e-9)


def test_compliant_hinge_released_held_by_the_angle_or_by_the_actuator(run):
    """A 60 mm spatial leg on a compliant hinge (tests/data/freefall_compliant_leg.toml): without --held-by the
    pose is held by a moment conjugate to the angle (the hinge deflects by the weight over its stiffness,
    tests/test_assembly_compliance.py), no warning; with --held-by F_act the pose is the static one held by
    the actuator, whose force balances gravity about the hinge (closed form, to the hinge's deflection
    over the 20 mm lever: 5e-3) and whose hinge deflects by its reaction over its stiffness."""
    import numpy as np

    from mechcont.continuation import find_equilibrium
    from mechcont.dynamics.freefall import held_pose
    from mechcont.models import load_model

    path = "tests/data/freefall_compliant_leg.toml"
    args = ("freefall", path, "--start", "angle=1.2", "--lock", "downlock", "--until", "0.002")
    plain, held = run(*args), run(*args, "--held-by", "F_act")
    assert plain.exit_code == 0 and held.exit_code == 0, plain.output + held.output
    assert "compliant joints" not in plain.output + held.output
    model = load_model(path)
    theta = 1.2
    x = find_equilibrium(model, hold={"angle": theta}, free=["F_act"], guess=held_pose(model, {"angle": theta}, "F_act"))
    act = np.array([0.0, 0.02 * math.sin(theta), -0.02 * math.cos(theta)])
    u = (np.array([0.0, 0.03, 0.02]) - act) / np.linalg.norm(np.array([0.0, 0.03, 0.02]) - act)
    lever = act[1] * u[2] - act[2] * u[1]  # the moment about x of a unit tension
    weight_moment = 0.05 * 9.81 * 0.03 * math.sin(theta)
    assert x[model.index("F_act")] * lever == pytest.approx(weight_moment, rel=5e-3)
    leg = dict(model.scene(x).bars)["leg"]  # hinge, actuator and tip points where they are, deflected
    along = np.array([0.0, 0.03, 0.02]) - leg[1]
    force = x[model.index("F_act")] * along / np.linalg.norm(along)  # the hinge carries this and the weight
    reaction = np.array([x[model.index(f"R_hinge_{a}")] for a in "xyz"])
    assert reaction == pytest.approx(-(force + np.array([0.0, 0.0, -0.05 * 9.81])), abs=1e-9)
    assert leg[0] == pytest.approx(-reaction / 2.0e4, abs=1e-12)  # the hinge point off the airframe's: R / k
