"""Every bad description gives a one-line InputError naming the item (and file line); CLI exit 2."""

import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from mechcont.cli._app import _register, cli
from mechcont.errors import InputError
from mechcont.mechanism import Body, Mechanism, Parameter, Revolute, find_description, parse_description

OVERCENTRE = find_description("overcentre").read_text()
FOURBAR = find_description("fourbar").read_text()


def line_of(text: str, needle: str) -> int:
    """1-based line of the first line containing ``needle``."""
    return next(i for i, line in enumerate(text.splitlines(), 1) if needle in line)


def error(text: str, build=True, **overrides) -> str:
    with pytest.raises(InputError) as info:
        mech = parse_description(text, "m.toml")
        if build:
            mech.build(**overrides)
    msg = str(info.value)
    assert "\n" not in msg
    return msg


def test_unknown_body_reference():
    text = OVERCENTRE.replace('b = "2.b"', 'b = "bar9.b"')
    msg = error(text)
    assert f"m.toml:{line_of(text, 'bar9')}: joints.apex.b" in msg
    assert "unknown body 'bar9'" in msg


def test_unknown_point_reference():
    text = OVERCENTRE.replace('a = "1.spring"\nb = "2.spring"\nk', 'a = "1.sprung"\nb = "2.spring"\nk')
    msg = error(text)
    assert f"m.toml:{line_of(text, '1.sprung')}: springs.spring.a" in msg
    assert "unknown point 'sprung' of body '1'" in msg


def test_unknown_ground_point():
    msg = error(OVERCENTRE.replace('a = "ground.O"\nb = "1.a"', 'a = "ground.Q"\nb = "1.a"'))
    assert "joints.pin.a" in msg and "unknown ground point 'Q'" in msg


def test_unknown_parameter_in_expression():
    text = OVERCENTRE.replace('length = "L1"', 'length = "L9/2"')
    msg = error(text)
    assert f"m.toml:{line_of(text, 'L9')}: bodies.1.length" in msg
    assert "unknown name 'L9'" in msg


def test_unknown_function_in_expression():
    msg = error(OVERCENTRE.replace('length = "L1"', 'length = "foo(L1)"'))
    assert "bodies.1.length" in msg and "unknown function 'foo'" in msg


def test_body_attached_to_nothing():
    text = OVERCENTRE + '\n[bodies.3]\nlength = 1.0\nmass = 1.0\n'
    msg = error(text)
    assert f"m.toml:{line_of(text, '[bodies.3]')}: bodies.3" in msg
    assert "attached to nothing" in msg


def test_body_not_connected_to_ground():
    text = OVERCENTRE + ('\n[bodies.3]\nlength = 1.0\nmass = 1.0\n[bodies.4]\nlength = 1.0\nmass = 1.0\n'
                         '[joints.j34]\ntype = "revolute"\na = "3.b"\nb = "4.a"\n')
    msg = error(text)
    assert "bodies.3" in msg and "not connected to the ground" in msg


@pytest.mark.parametrize("old,new,key,what", [
    ('length = "L1"', 'length = 0', "bodies.1.length", "length (m) must be positive, got 0"),
    ('length = "L2"', 'length = "-L2"', "bodies.2.length", "length (m) must be positive, got -1.5"),
    ('mass = "m1"', 'mass = -2.0', "bodies.1.mass", "mass (kg) must be positive, got -2"),
    ('k = "k"', 'k = 0', "springs.spring.k", "stiffness (N/m) must be positive, got 0"),
    ('free_length = "LU"', 'free_length = -0.1', "springs.spring.free_length", "must be positive, got -0.1"),
    ('c = "c"', 'c = -1', "dampers.damper.c", "damping (N s/m) must be non-negative, got -1"),
])
def test_impossible_values(old, new, key, what):
    text = OVERCENTRE.replace(old, new, 1)
    msg = error(text)
    assert f"m.toml:{line_of(text, new)}: {key}" in msg
    assert what in msg


def test_impossible_value_through_override():
    msg = error(OVERCENTRE, k=-5.0)
    assert "springs.spring.k" in msg and "got -5" in msg
    msg = error(OVERCENTRE, Lq=1.0)
    assert "Lq: not a parameter" in msg


def test_loop_that_cannot_close_names_loop_and_gap():
    # a + b + c = 1.7 m < d = 2.0 m: the four-bar misses by 0.3 m however it is posed
    text = FOURBAR.replace('d = { value = 0.7', 'd = { value = 2.0').replace("[assembly]\nhold = { theta_crank = 1.2 }", "")
    msg = error(text)
    assert "the loop ground - " in msg and "cannot close" in msg
    for joint in ("A", "B", "C", "D"):
        assert re.search(rf"joints [^)]*\b{joint}\b", msg)
    gap = float(re.search(r"misses by ([0-9.eE+-]+) m", msg).group(1))
    assert gap == pytest.approx(0.3, abs=1e-6)


def test_wrong_dof_count():
    msg = error(FOURBAR.replace("dof = 1", "dof = 2"))
    assert "mechanism.dof" in msg and "has 1 degree(s) of freedom, intended 2" in msg


def test_structure_has_zero_dof():
    # pin the coupler's midpoint to the ground where it is at theta_crank = 1.2: a structure
    text = FOURBAR.replace("S = [", "P = [0.4792338013778868, 0.43031053566678595]\nS = [")
    text += '\n[joints.extra]\ntype = "revolute"\na = "ground.P"\nb = "coupler.origin"\n'
    msg = error(text)
    assert "has 0 degree(s) of freedom, intended 1" in msg


def test_redundant_joints_are_named():
    text = OVERCENTRE + '\n[joints.pin_again]\ntype = "revolute"\na = "ground.O"\nb = "1.a"\n'
    msg = error(text)
    assert "2 redundant constraint(s) among joints" in msg  # both rows of the pin
    assert "pin_again" in msg and re.search(r"\bpin\b", msg)
    assert "the intended 1 degree(s) of freedom" in msg


def test_structure_with_extra_pin_names_the_redundant_joints():
    """Fourbar plus a pin of the coupler to the ground: 10 constraints of rank 9 on 9 coordinates."""
    text = FOURBAR.replace("S = [", "P = [0.4792338013778868, 0.43031053566678595]\nS = [")
    text += '\n[joints.extra]\ntype = "revolute"\na = "ground.P"\nb = "coupler.origin"\n'
    msg = error(text)
    assert "has 0 degree(s) of freedom, intended 1 (rank 9 of 10 constraints on 9 coordinates)" in msg
    assert "1 redundant constraint(s) among joints extra," in msg


def test_malformed_toml_gives_line_and_key():
    text = OVERCENTRE.replace('mass = "m1"', 'mass = m1"')
    msg = error(text, build=False)
    assert f"m.toml:{line_of(text, 'mass = m1')}: bodies.1.mass" in msg
    assert "malformed TOML" in msg


def test_unknown_key_and_wrong_type():
    text = OVERCENTRE.replace('mass = "m1"', 'mass = "m1"\nmas = 3')
    msg = error(text, build=False)
    assert f"m.toml:{line_of(text, 'mas = 3')}: bodies.1.mas" in msg and "unknown key" in msg
    text = OVERCENTRE.replace('mass = "m1"', 'mass = [1, 2]')
    msg = error(text, build=False)
    assert f"m.toml:{line_of(text, 'mass = [1, 2]')}: bodies.1.mass" in msg
    text = OVERCENTRE.replace('type = "slider"', 'type = "slidr"')
    msg = error(text, build=False)
    assert "joints.slider.type" in msg and "revolute, slider, prismatic, weld" in msg


def test_api_errors_name_the_item():
    with pytest.raises(InputError, match=r"bodies.bar.mass: mass \(kg\) must be positive"):
        Mechanism("m", [], [Body("bar", mass=-1.0, length=1.0)], [Revolute("p", "ground.O", "bar.a")],
                  ground={"O": (0, 0)}).build()
    with pytest.raises(InputError, match="joints.p.b: unknown point 'c' of body 'bar'"):
        Mechanism("m", [Parameter("L", 1.0, "m")], [Body("bar", mass=1.0, length="L")],
                  [Revolute("p", "ground.O", "bar.c")], ground={"O": (0, 0)})


@pytest.fixture()
def runner():
    _register()
    return CliRunner()


def test_cli_bad_file_exits_2_with_one_line_and_writes_nothing(runner, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    bad = tmp_path / "bad.toml"
    bad.write_text(OVERCENTRE.replace('k = "k"', "k = -3"))
    before = set(Path(tmp_path).iterdir())
    result = runner.invoke(cli, ["equations", str(bad)])
    assert result.exit_code == 2
    lines = [ln for ln in result.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and "springs.spring.k" in lines[0] and "bad.toml:" in lines[0]
    assert "Traceback" not in result.output
    assert set(Path(tmp_path).iterdir()) == before
    result = runner.invoke(cli, ["equations", "no_such_model"])
    assert result.exit_code == 2 and "unknown model" in result.output


def test_cli_prints_equations(runner):
    result = runner.invoke(cli, ["equations", "overcentre.toml", "--reduced"])
    assert result.exit_code == 0, result.output
    assert "slider_n: -L1*sin(theta1) + L2*sin(theta2) = 0" in result.output
    result = runner.invoke(cli, ["equations", "fourbar", "--latex", "--set", "k=300"])
    assert result.exit_code == 0 and result.output.startswith("\\begin{align}")
