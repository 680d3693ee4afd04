"""``mechcont sweep`` from the command line."""

import csv

import pytest
from click.testing import CliRunner

from mechcont.cli._app import _register, cli
from mechcont.models.overcentre import symmetric_folds


@pytest.fixture(scope="module")
def runner():
    _register()
    return CliRunner()


def test_sweep_reports_jumps_and_writes_outputs(runner, tmp_path):
    out, fig = tmp_path / "sweep.csv", tmp_path / "sweep.png"
    res = runner.invoke(cli, ["sweep", "overcentre", "--set", "LU=0.4", "--set", "c=50", "--start", "theta1=1.2",
                              "--ramp", "F=-65:-90:1", "--ramp", "F=-90:110:4", "--watch", "theta1",
                              "--out", str(out), "--plot", str(fig), "--no-progress"])
    assert res.exit_code == 0, res.output
    lines = [ln for ln in res.output.splitlines() if ln.startswith("jump")]
    assert len(lines) == 2
    (_, F_up), (_, F_low) = symmetric_folds(1.5, 1.0, 1.0, 9.81, 127.0, 0.4)
    f1 = float(lines[0].split("F = ")[1].split()[0])
    f2 = float(lines[1].split("F = ")[1].split()[0])
    assert F_low - 8 < f1 < F_low and F_up < f2 < F_up + 15
    with open(out) as fh:
        rows = list(csv.reader(fh))
    header = rows[0]
    assert header[:4] == ["t [s]", "x1 [m]", "y1 [m]", "theta1 [rad]"] and len(rows) > 100
    assert header[-1] == "label" and "theta1_dot [rad/s]" in header and "F [N]" in header
    # the JUMP rows are the last samples before each snap, at the reported loads
    jump_rows = [r for r in rows[1:] if r[-1] == "JUMP"]
    assert len(jump_rows) == 2
    for row, f in zip(jump_rows, (f1, f2)):
        assert float(row[header.index("F [N]")]) == pytest.approx(f, abs=0.05)
    assert fig.stat().st_size > 1000
    # the CSV reads back as a branch of the model: draw the mechanism as it lets go
    drawing = tmp_path / "jump.png"
    res = runner.invoke(cli, ["draw", "overcentre", "--point", f"{out}:JUMP1", "--out", str(drawing)])
    assert res.exit_code == 0, res.output
    assert drawing.stat().st_size > 1000


@pytest.mark.parametrize("args, message", [
    (["--ramp", "F=1:2", "--watch", "theta1"], "--ramp"),
    (["--ramp", "F=1:2:0", "--watch", "theta1"], "ramp"),
    (["--ramp", "F=1:2:1", "--watch", "F"], "watch"),
    (["--ramp", "F=1:2:1", "--watch", "theta1", "--set", "LU=x"], "--set LU"),
    (["--ramp", "F=1:2:1", "--watch", "theta1", "--out", "a.txt"], "--out"),
    (["--ramp", "L1=1:2:1", "--watch", "theta1"], "L1"),
    (["--ramp", "F=1:2:1", "--watch", "theta1", "--through", "nan"], "through"),
    (["--ramp", "F=1:2:1", "--watch", "theta1", "--start", "x1=5"], "--start"),
    (["--ramp", "F=1:2:1", "--watch", "theta1", "--start", "F=5"], "F"),
    (["--ramp", "F=1:2:1", "--watch", "theta1", "--damping", "-1"], "damping"),
])
def test_bad_input_is_one_line_and_exit_2(runner, tmp_path, args, message):
    res = runner.invoke(cli, ["sweep", "overcentre", *args, "--no-progress", "--out", str(tmp_path / "s.csv")]
                        if "--out" not in args else ["sweep", "overcentre", *args, "--no-progress"])
    assert res.exit_code == 2
    err = res.output.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {message}")
    assert list(tmp_path.iterdir()) == []


def test_sweep_over_a_continuation_branch(tmp_path):
    """--branch draws the branch under the sweep and prints each jump's gap to the fold it follows."""
    from cli_helpers import make_runner, one_line_error

    run = make_runner()
    b = tmp_path / "b.csv"
    r = run("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=1.2", "--vary", "F", "--bounds", "F=-90:110",
            "--bounds", "theta1=-1.5:1.5", "--out", b, "--quiet")
    assert r.exit_code == 0, r.output
    fig = tmp_path / "s.png"
    r = run("sweep", "overcentre", "--set", "LU=0.4", "--set", "c=50", "--start", "theta1=1.2", "--ramp", "F=-65:-90:1",
            "--watch", "theta1", "--branch", b, "--plot", fig, "--no-progress")
    assert r.exit_code == 0, r.output
    # the branch has c = 0, the sweep c = 50: damping is not in the equilibrium equations, so no warning
    assert "warning" not in r.stderr, r.stderr
    (line,) = [ln for ln in r.output.splitlines() if ln.startswith("jump")]
    (_, F_up), (_, F_low) = symmetric_folds(1.5, 1.0, 1.0, 9.81, 127.0, 0.4)
    jump = float(line.split("F = ")[1].split()[0])
    assert f"N past LP2 (F = {F_low:.6g} N)" in line and "deg" in line
    gap = float(line.split("; ")[-1].split()[0])
    assert gap == pytest.approx(F_low - jump, abs=1e-3) and gap > 0
    assert fig.stat().st_size > 1000
    curve = tmp_path / "f.csv"
    assert run("folds", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--along", "LU",
               "--bounds", "LU=0.3:0.5", "--out", curve, "--quiet").exit_code == 0
    one_line_error(run("sweep", "overcentre", "--start", "theta1=1.2", "--ramp", "F=-65:-90:1", "--watch", "theta1",
                       "--branch", curve), "branch in LU")
