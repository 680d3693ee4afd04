"""The CLI on spatial description files: check, continue, folds, draw, and their one-line errors."""

import csv
from pathlib import Path

import pytest
from PIL import Image

from tests.cli_helpers import make_runner, one_line_error

DATA = Path(__file__).parent / "data" / "spatial"
run = make_runner()
OVERCENTRE = DATA / "overcentre_3d.toml"


def test_check_reports_dof_and_redundancy_of_a_declared_drop():
    r = run("check", DATA / "bennett.toml")
    assert r.exit_code == 0, r.output
    assert "degrees of freedom: 1 (as intended)" in r.output
    assert "redundant constraints: 3 row(s) dropped" in r.output
    assert "findings: none" in r.output


def test_check_of_an_indeterminate_rigid_mechanism_is_a_finding():
    r = run("check", DATA / "door_3d.toml")
    assert r.exit_code == 1
    assert "over-constrained: 5 redundant constraint(s) among joints upper, lower" in r.output
    assert "stiffness" in r.output


def test_check_reports_the_compliances_that_make_it_determinate(tmp_path):
    text = (DATA / "door_3d.toml").read_text().replace('[joints.upper]\ntype = "revolute"',
                                                      '[joints.upper]\ntype = "spherical"\nstiffness = "k"')
    text = text.replace('b = "door.high"\naxis = [0, 0, 1]', 'b = "door.high"')
    text = text.replace('b = "door.low"\naxis = [0, 0, 1]', 'b = "door.low"\naxis = [0, 0, 1]\nrotational_stiffness = "kr"')
    f = tmp_path / "door.toml"
    f.write_text(text)
    r = run("check", f)
    assert "redundant constraints: none" in r.output
    assert "compliant joint rows" in r.output
    assert "upper_x" in r.output and "stiffness 2e+07 N/m" in r.output
    assert "lower_rot1" in r.output and "N m/rad" in r.output


def test_continue_prints_the_planar_folds_and_writes_the_branch(tmp_path):
    out = tmp_path / "b.csv"
    r = run("continue", OVERCENTRE, "--vary", "F", "--start", "theta1=0.3", "--bounds", "F=-150:150",
            "--bounds", "theta1=-1.45:1.45", "--out", out)
    assert r.exit_code == 0, r.output
    # the out-of-plane row dropped at build stays implied along the whole branch
    assert "dropped at build (reactions indeterminate): slider_n2; their largest residual" in r.output
    assert "from row 0 (EP1): 1 degree(s) of freedom" in r.output
    rows = list(csv.DictReader(out.open()))
    lps = sorted(float(row["F [N]"]) for row in rows if row["label"].startswith("LP"))
    assert lps == pytest.approx([-75.58066788290293, 95.20066788290295], abs=1e-8)


def test_folds_reach_the_cusp(tmp_path):
    out = tmp_path / "f.csv"
    r = run("folds", OVERCENTRE, "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--along", "LU",
            "--bounds", "LU=0.1:2", "--out", out, "--quiet")
    assert r.exit_code == 0, r.output
    cusp = [row for row in csv.DictReader(out.open()) if row["label"].startswith("CP")]
    assert len(cusp) == 1 and float(cusp[0]["LU [m]"]) == pytest.approx(1.5, abs=1e-7)


def test_draw_makes_a_three_view(tmp_path):
    out = tmp_path / "bennett.png"
    r = run("draw", DATA / "bennett.toml", "--start", "crank=0.5", "--free", "M", "--out", out)
    assert r.exit_code == 0, r.output
    w, h = Image.open(out).size
    assert w >= 800 and h >= 600


def test_bad_spatial_input_is_one_line(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text((DATA / "pendulum_3d.toml").read_text().replace('type = "revolute"', 'type = "hinge"'))
    one_line_error(run("check", f), "joints.hinge.type", "spherical", "revolute", "universal")
    f.write_text((DATA / "pendulum_3d.toml").read_text().replace('axis = [0, "cos(beta)", "sin(beta)"]\n\n[gravity]',
                                                                 'axis = [0, 1]\n\n[gravity]'))
    one_line_error(run("check", f), "joints.hinge.axis", "3-vector")
    f.write_text((DATA / "pendulum_3d.toml").read_text().replace("dimension = 3", "dimension = 4"))
    one_line_error(run("check", f), "mechanism.dimension", "2", "3")


def test_label_points_on_draw_and_check(tmp_path, monkeypatch):
    """Issue 25: a spatial drawing names its bodies; its points only with --label-points (draw and check --plot)."""
    import mechcont.outputs.drawing3d as d3

    seen = []
    real = d3.label_views
    monkeypatch.setattr(d3, "label_views", lambda axes, scene, **kw: (seen.append(kw), real(axes, scene, **kw))[1])
    for extra in ((), ("--label-points",)):
        r = run("draw", DATA / "bennett.toml", "--start", "crank=0.5", "--free", "M", *extra, "--out",
                tmp_path / "b.png")
        assert r.exit_code == 0, r.output
        r = run("check", DATA / "bennett.toml", "--quiet", "--plot", tmp_path / "c.png", *extra)
        assert r.exit_code in (0, 1), r.output
        assert (tmp_path / "c.png").is_file()
    assert seen == [{"bodies": True, "label_points": False}] * 2 + [{"bodies": True, "label_points": True}] * 2
