"""``mechcont check`` and ``mechcont.mechanism.check_report``: degrees of freedom against the truth,
redundancy, loop closure, equilibrium and stability, the labelled drawing, and one-line errors."""

from __future__ import annotations

import functools
import math
import tomllib

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from PIL import Image
from test_mechanism_redundant import TRIPLE

from mechcont.mechanism import (
    Prismatic,
    Revolute,
    Slider,
    Weld,
    check_report,
    find_description,
    load_description,
    parse_description,
)

run = make_runner()

SHIPPED = ("overcentre", "fourbar", "fivebar", "slidercrank", "nose_gear")
#: Degrees of freedom of the shipped mechanisms, by counting (each has no redundant constraint).
TRUE_DOF = {"overcentre": 1, "fourbar": 1, "fivebar": 2, "slidercrank": 1, "nose_gear": 1}
FOURBAR = find_description("fourbar").read_text()


def gruebler(mech) -> int:
    """Planar mobility by counting: 3 per body minus what each joint removes."""
    removed = {Revolute: 2, Slider: 1, Prismatic: 2, Weld: 3}
    return 3 * len(mech.bodies) - sum(removed[type(j)] for j in mech.joints)


@functools.cache
def report(name: str, reduced: bool = False):
    return check_report(name, reduced=reduced)


@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_descriptions_check_clean(name):
    r = report(name)
    mech = load_description(name)
    declared = tomllib.loads(find_description(name).read_text())["mechanism"]["dof"]
    assert r.dof == TRUE_DOF[name] == declared == r.intended_dof == gruebler(mech)
    assert r.ok and r.findings == () and r.redundant == () and r.dropped_residual is None
    assert r.n_coordinates == 3 * len(mech.bodies) and r.n_coordinates - r.rank == r.dof
    n_conditions = sum(e.startswith("cond_") for e in r.system.equation_names)
    assert r.n_equations == r.n_unknowns == r.n_coordinates + r.n_constraints + n_conditions
    assert {q.name for q in r.closure} == {j.name for j in mech.joints}
    assert max(q.value for q in r.closure) < 1e-12
    np.testing.assert_allclose(r.system.mechanics.phi(r.x), 0, atol=1e-12)
    # the equilibrium really is one, and its stability is the model's
    assert r.x_equilibrium is not None
    res = r.system.residual(r.x_equilibrium)
    assert np.max(np.abs(res)) < 1e-8
    assert r.stability.n_unstable == r.system.mechanics.stability(r.x_equilibrium).n_unstable
    # every variable listed once with the scale the continuation uses
    assert [q.name for q in r.scales] == list(r.system.names)
    np.testing.assert_array_equal([q.value for q in r.scales], r.system.scales())
    assert [p.name for p in r.parameters] == [p.name for p in mech.parameters]
    text = r.to_text()
    assert f"degrees of freedom: {TRUE_DOF[name]} (as intended)" in text and "findings: none" in text


def test_text_shows_angles_in_degrees_and_units():
    text = report("fourbar").to_text()
    # theta_crank is held at 1.2 rad by [assembly]: shown in degrees, kept in radians
    assert f"{math.degrees(1.2):.4f} deg" in text
    assert "held: theta_crank = 68.7549 deg" in text
    assert report("fourbar").states[2].assembled == pytest.approx(1.2)
    assert "  k          200 N/m     spring stiffness" in text
    assert "R_A_x" in text and " N " in text
    assert "stability at the equilibrium: stable" in text


def test_reduced_form_names_the_joints_it_closes_exactly():
    r = report("fourbar", reduced=True)
    assert r.reduced and r.dof == 1 and r.ok
    assert r.n_coordinates == 3 and r.n_constraints == 2   # the three angles; the loop-closing pin D
    assert set(r.eliminated_joints) | {q.name for q in r.closure} == {"A", "B", "C", "D"}
    assert "closed exactly by the reduced form" in r.to_text()
    full = report("fourbar")
    # same equilibrium configuration from both forms
    for name in ("theta_crank", "theta_coupler", "theta_rocker"):
        i, j = full.system.index(name), r.system.index(name)
        assert r.x_equilibrium[j] == pytest.approx(full.x_equilibrium[i], abs=1e-8)


def test_redundant_parallelogram_with_drop():
    mech = parse_description(TRIPLE.format(extra='redundant = "drop"'), "triple.toml")
    r = check_report(mech)
    # 4 bodies, 6 pins: counting says 0, the rank says 1 because one constraint is redundant
    assert gruebler(mech) == 0 and r.dof == 1 == r.intended_dof
    assert r.redundant == (("C2_y", ("C2", "A", "B", "C", "A2", "B2")),)
    assert r.dropped_residual is not None and r.dropped_residual < 1e-12
    assert r.ok and r.n_constraints == 11
    text = r.to_text()
    assert "redundant constraints: 1 row(s) dropped" in text and "C2_y: implied by joints A, B, C, A2, B2" in text


def test_redundant_parallelogram_refused_is_a_finding(tmp_path):
    f = tmp_path / "triple.toml"
    f.write_text(TRIPLE.format(extra=""))
    result = run("check", f)
    assert result.exit_code == 1, result.output
    assert "Traceback" not in result.output
    assert "redundant constraints: 1 row(s) dropped" in result.stdout      # the rest is still reported
    assert "findings: 1" in result.stdout and "over-constrained" in result.stdout
    assert "C2" in result.stdout
    quiet = run("check", f, "--quiet")
    assert quiet.exit_code == 1 and quiet.stdout == ""
    lines = quiet.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("finding: ") and "over-constrained" in lines[0]


def test_wrong_declared_dof_is_a_finding(tmp_path):
    f = tmp_path / "fourbar2.toml"
    f.write_text(FOURBAR.replace("dof = 1", "dof = 2"))
    result = run("check", f)
    assert result.exit_code == 1, result.output
    assert "degrees of freedom: 1 (INTENDED 2)" in result.stdout
    assert "has 1 degree(s) of freedom, intended 2" in result.stdout


def test_loop_that_cannot_close_is_one_line_error(tmp_path):
    f = tmp_path / "open.toml"
    f.write_text(FOURBAR.replace('d = { value = 0.7', 'd = { value = 2.0'))
    one_line_error(run("check", f), "cannot close", "joints.")
    one_line_error(run("check", "fourbar", "--set", "d=2"), "cannot close")


@pytest.mark.parametrize("name", ["fourbar", "fivebar"])
def test_cli_prints_report_and_true_dof(name):
    result = run("check", name)
    assert result.exit_code == 0, result.output
    assert f"degrees of freedom: {TRUE_DOF[name]} (as intended)" in result.stdout
    for heading in ("size:", "redundant constraints: none", "loop closure", "equilibrium:", "parameters:",
                    "states:", "continuation scales", "findings: none"):
        assert heading in result.stdout
    assert result.stderr == ""


def test_cli_quiet_prints_nothing_when_all_is_well():
    result = run("check", "slidercrank", "--quiet")
    assert result.exit_code == 0 and result.stdout == "" and result.stderr == ""


def test_cli_plot_writes_a_labelled_png(tmp_path):
    out = tmp_path / "fourbar.png"
    result = run("check", "fourbar", "--quiet", "--plot", out)
    assert result.exit_code == 0, result.output
    with Image.open(out) as im:
        assert im.format == "PNG" and im.size[0] > 100 and im.size[1] > 100
        im.verify()


def test_cli_set_overrides_a_parameter():
    result = run("check", "fourbar", "--set", "k=300")
    assert result.exit_code == 0, result.output
    assert "k          300 N/m" in result.stdout


@pytest.mark.parametrize("args, words", [
    (["nosuch"], ["no such description"]),
    (["fourbar", "--set", "k"], ["--set", "NAME=VALUE"]),
    (["fourbar", "--set", "zz=1"], ["zz", "not a parameter"]),
    (["fourbar", "--set", "k=-5"], ["stiffness"]),
    (["fourbar", "--plot", "out.jpg"], ["--plot", ".png"]),
    (["fourbar", "--plot", "/no/such/folder/out.png"], ["--plot", "does not exist"]),
])
def test_cli_bad_input_is_one_line(args, words):
    one_line_error(run("check", *args), *words)


def test_cli_plot_checked_before_work(tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("")
    one_line_error(run("check", "nosuch", "--plot", afile / "x.png"), "--plot", "not a folder")
    one_line_error(run("check", "fourbar", "--plot", tmp_path), "--plot")


@pytest.mark.parametrize("path", ["pendulum_stop.toml", "spatial/door_3d.toml"])
def test_the_parameter_count_is_the_parameters_listed(path):
    """The size line's count and the parameters table agree (a stop's reaction R_NAME included)."""
    from pathlib import Path

    result = run("check", Path(__file__).parent / "data" / path)
    text = result.stdout
    count = int(text.split(" parameters\n")[0].rsplit(", ", 1)[1])
    block = text.split("\nparameters:\n", 1)[1].split("\n\n", 1)[0]
    assert count == len(block.splitlines()) > 0, text
