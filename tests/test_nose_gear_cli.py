"""``mechcont downlock`` and ``mechcont design``: results, files, and bad input (one line, exit 2, nothing written)."""

from __future__ import annotations

import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.continuation import read_branch_table
from mechcont.models.nose_gear_geometry import aligned_downlock_force, defaults


@pytest.fixture(scope="module")
def run():
    return make_runner()


def test_downlock_writes_branch_with_closed_form_forces(tmp_path, run):
    out, fig = tmp_path / "k.csv", tmp_path / "k.png"
    r = run("downlock", "nose_gear", "--vary", "k", "--bounds", "k=0:40000", "--set", "l_sp1=-0.05",
            "--out", out, "--plot", fig)
    assert r.exit_code == 0, r.output
    rows = read_branch_table(out)[0]
    assert len(rows) > 5 and fig.stat().st_size > 1000
    for row in rows[::4]:
        p = defaults(k=float(row["k"]), l_sp1=-0.05)
        assert float(row["F"]) == pytest.approx(aligned_downlock_force(p), abs=1e-8)
        assert float(row["theta4"]) == 0.0


def test_downlock_on_the_description_file_needs_and_takes_hold(tmp_path, run):
    r = run("downlock", "nose_gear.toml", "--vary", "U", "--bounds", "U=0:50", "--hold", "theta4=0")
    assert r.exit_code == 0, r.output
    assert "71.99" in r.output


def test_design_prints_table_and_writes_files(tmp_path, run):
    out, fig = tmp_path / "t.csv", tmp_path / "r.png"
    r = run("design", "nose_gear", "--bounds", "l_sp1=-0.175:0.175", "--bounds", "LU=1.28:1.32", "--levels", "3",
            "--out", out, "--plot", fig)
    assert r.exit_code == 0, r.output
    assert "cusp: LU = 1.288" in r.output
    rows = read_branch_table(out)[0]
    assert [float(x["LU (m)"]) for x in rows] == [1.28, 1.3, 1.32]
    assert fig.stat().st_size > 1000


@pytest.mark.parametrize("args, words", [
    (("--vary", "F", "--bounds", "F=0:1"), ("vary", "downlock force")),
    (("--vary", "U"), ("bounds", "U=LO:HI")),
    (("--vary", "nope", "--bounds", "nope=0:1"), ("nope", "unknown variable")),
    (("--vary", "theta4", "--bounds", "theta4=-1:1"), ("theta4", "held")),
    (("--vary", "U", "--bounds", "U=5:1"), ("--bounds U", "LO < HI")),
    (("--vary", "U", "--bounds", "U=10:20"), ("U", "outside its bounds")),
    (("--vary", "U", "--bounds", "U=0:100", "--set", "k=abc"), ("--set k", "not a number")),
    (("--vary", "U", "--bounds", "U=0:100", "--set", "zz=1"), ("zz", "unknown variable")),
    (("--vary", "U", "--bounds", "U=0:100", "--hold", "F=0"), ("F", "only states")),
    (("--vary", "U", "--bounds", "U=0:100", "--force", "theta1"), ("theta1", "must be a parameter")),
    (("--vary", "U", "--bounds", "U=0:100", "--set", "F=3"), ("F", "fixed by the downlock condition")),
    (("--vary", "U", "--bounds", "U=0:100", "--set", "L4=-0.3"), ("L4", "positive")),
    (("--vary", "U", "--bounds", "U=0:100", "--set", "m4=-1"), ("m4", "not be negative")),
    (("--vary", "U", "--bounds", "U=0:100", "--set", "L1=0.1"), ("L1", "cannot assemble")),
])
def test_downlock_bad_input(tmp_path, run, args, words):
    out = tmp_path / "never.csv"
    r = run("downlock", "nose_gear", *args, "--out", out)
    one_line_error(r, *words)
    assert not out.exists()


def test_downlock_bad_files_and_models(tmp_path, run):
    one_line_error(run("downlock", "nose_gear", "--vary", "U", "--bounds", "U=0:1", "--out", tmp_path / "x.txt"),
                   "--out", ".csv")
    one_line_error(run("downlock", "nose_gear", "--vary", "U", "--bounds", "U=0:1", "--plot", tmp_path / "no" / "x.png"),
                   "--plot", "does not exist")
    one_line_error(run("downlock", "no_such_gear", "--vary", "U", "--bounds", "U=0:1"), "model")
    one_line_error(run("downlock", "fourbar.toml", "--vary", "k", "--bounds", "k=0:1"), "hold", "downlock condition")


@pytest.mark.parametrize("args, words", [
    (("--bounds", "l_sp1=-0.1:0.1"), ("--bounds", "LU")),
    (("--bounds", "l_sp1=-0.1:0.1", "--bounds", "LU=1.2:"), ("--bounds", "finite")),
    (("--bounds", "l_sp1=-0.1:0.1", "--bounds", "LU=1.2:1.3", "--levels", "1"), ("--levels",)),
    (("--x", "LU", "--y", "LU", "--bounds", "LU=1.2:1.3"), ("--y", "differ")),
    (("--x", "qq", "--bounds", "qq=0:1", "--bounds", "LU=1.2:1.3"), ("qq", "unknown variable")),
    (("--bounds", "l_sp1=-0.1:0.1", "--bounds", "LU=1.2:1.3", "--out", "t.xlsx"), ("--out", ".md")),
])
def test_design_bad_input(tmp_path, run, args, words):
    fig = tmp_path / "never.png"
    one_line_error(run("design", "nose_gear", *args, "--plot", fig), *words)
    assert not fig.exists()
