"""ODE systems from a file ([system] TOML): the reader, --set, units, and every bad file in one line."""

from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.equations import dynamics_of
from mechcont.errors import InputError
from mechcont.models import describe_model, load_model, model_at

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

#: The issue's example (#35), verbatim.
AB = """
[system]
name = "ab"
[parameters]
D = 0.0
B = 14.0
beta = 3.0
[states]
u1 = 0.0
u2 = 0.0
[rates]
u1 = "-u1 + D*(1 - u1)*exp(u2)"
u2 = "-u2 + D*B*(1 - u1)*exp(u2) - beta*u2"
"""


def _ab_rates(u1, u2, D, B, beta):
    e = np.exp(u2)
    return np.array([-u1 + D * (1 - u1) * e, -u2 + D * B * (1 - u1) * e - beta * u2])


def _write(tmp_path, text, name="sys.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_the_issue_example_reads_verbatim_and_its_rates_are_the_written_ones(tmp_path):
    model = load_model(_write(tmp_path, AB))
    assert model.ode is not None and model.ode.states == ("u1", "u2") and not model.ode.algebraic
    assert model.state_names == ("u1", "u2") and model.parameter_names == ("D", "B", "beta")
    rng = np.random.default_rng(1)
    for _ in range(5):
        u1, u2, D, B, beta = rng.uniform(-1, 1, 5)
        x = model.vector({"u1": u1, "u2": u2, "D": D, "B": B, "beta": beta})
        np.testing.assert_allclose(model.residual(x), _ab_rates(u1, u2, D, B, beta), rtol=1e-13, atol=1e-14)
        # the exact Jacobian against central differences of the closed form
        h = 1e-6
        fd = np.column_stack([(_ab_rates(*(np.array([u1, u2, D, B, beta]) + h * e)) -
                               _ab_rates(*(np.array([u1, u2, D, B, beta]) - h * e))) / (2 * h) for e in np.eye(5)])
        np.testing.assert_allclose(model.jacobian(x), fd, rtol=1e-7, atol=1e-8)


def test_the_shipped_ab_example_is_the_issue_example():
    shipped = load_model(EXAMPLES / "ab.toml")
    assert shipped.ode.states == ("u1", "u2")
    x = shipped.vector({"u1": 0.3, "u2": 0.7, "D": 0.11})
    np.testing.assert_allclose(shipped.residual(x), _ab_rates(0.3, 0.7, 0.11, 14.0, 3.0), rtol=1e-13)


def test_set_changes_a_parameter_as_for_mechanisms(tmp_path):
    path = _write(tmp_path, AB)
    model = model_at(path, {"B": 17.0, "D": 0.1})
    assert model.variable("B").value == 17.0 and model.variable("D").value == 0.1
    x = model.vector({"u1": 0.2, "u2": 0.4})
    np.testing.assert_allclose(model.residual(x), _ab_rates(0.2, 0.4, 0.1, 17.0, 3.0), rtol=1e-13)
    with pytest.raises(InputError, match="C: unknown variable of model .ab."):
        model_at(path, {"C": 1.0})
    with pytest.raises(InputError, match="not a parameter of ab"):
        load_model(path, C=1.0)


def test_units_descriptions_and_scales_reach_the_model(tmp_path):
    text = """
[system]
name = "decay"
description = "first-order decay"
[parameters]
k = { value = 0.5, unit = "1/s", description = "rate constant", scale = 2.0 }
[states]
x = { value = 2.0, unit = "m", description = "position" }
[rates]
x = "-k*x"
"""
    model = load_model(_write(tmp_path, text))
    assert model.description == "first-order decay"
    assert (model.variable("x").unit, model.variable("x").description, model.variable("x").value) == ("m", "position", 2.0)
    assert (model.variable("k").unit, model.variable("k").scale) == ("1/s", 2.0)
    summary = describe_model(str(_write(tmp_path, text)))
    assert summary.states == (("x", "m", "position"),) and summary.parameters == (("k", 0.5, "1/s", "rate constant"),)


def test_the_functions_of_the_format(tmp_path):
    """exp, log, sin, cos, tan, tanh, sinh, cosh, sqrt, abs and powers ** and ^, against numpy."""
    text = """
[system]
name = "fns"
[parameters]
p = 0.7
[states]
a = 0.3
b = -0.4
[rates]
a = "exp(a) + log(p) + sin(a)*cos(b) + tan(a) + tanh(b) + sinh(a) - cosh(b)"
b = "sqrt(p) + abs(b) + a**3 + b^2 - p^-1"
"""
    model = load_model(_write(tmp_path, text))
    a, b, p = 0.3, -0.4, 0.7
    want = [np.exp(a) + np.log(p) + np.sin(a) * np.cos(b) + np.tan(a) + np.tanh(b) + np.sinh(a) - np.cosh(b),
            np.sqrt(p) + abs(b) + a**3 + b**2 - 1 / p]
    # each sum has terms near 1 that cancel: its rounding is a few ulps of 1, not of the result
    np.testing.assert_allclose(model.residual(model.vector({})), want, rtol=1e-14, atol=8 * np.finfo(float).eps)
    # d|b|/db = sign(b) = -1 here
    assert model.jacobian(model.vector({}))[1, model.index("b")] == pytest.approx(-1 + 2 * b, rel=1e-14)


def test_an_equations_table_is_algebraic(tmp_path):
    text = '[system]\nname = "sq"\n[parameters]\nmu = 1.0\n[states]\nx = 1.0\n[equations]\nx = "x^2 - mu"\n'
    model = load_model(_write(tmp_path, text))
    assert model.ode.algebraic and model.equation_names == ("x",)
    with pytest.raises(InputError, match="algebraic"):
        dynamics_of(model)


def test_parse_file_gives_an_ode_system_or_a_mechanism():
    from mechcont.mechanism._ode_file import OdeSystem, parse_file

    assert isinstance(parse_file(AB, "ab.toml"), OdeSystem)
    assert not isinstance(parse_file((EXAMPLES.parent / "src/mechcont/data/fourbar.toml").read_text(), "f.toml"),
                          OdeSystem)


_HEAD = '[system]\nname = "s"\n[parameters]\nD = 1.0\n'

#: (name, file text, words the one-line error must hold)
BAD = [
    ("missing rate", _HEAD + '[states]\nu1 = 0.0\nu2 = 0.0\n[rates]\nu1 = "-u1"\n', ["rates.u2", "missing", "du2/dt"]),
    ("rate of an unknown state", _HEAD + '[states]\nu1 = 0.0\n[rates]\nu1 = "-u1"\nu3 = "1"\n',
     ["rates.u3", "not a state", "u1"]),
    ("rates and equations", _HEAD + '[states]\nu1 = 0.0\n[rates]\nu1 = "-u1"\n[equations]\nu1 = "u1"\n',
     ["equations", "not both"]),
    ("neither rates nor equations", _HEAD + '[states]\nu1 = 0.0\n', ["rates", "missing"]),
    ("unknown function", _HEAD + '[states]\nu1 = 0.0\n[rates]\nu1 = "foo(u1)"\n', ["rates.u1", "unknown function 'foo'"]),
    ("unknown symbol", _HEAD + '[states]\nu1 = 0.0\n[rates]\nu1 = "u1 + q"\n',
     ["rates.u1", "unknown name 'q'", "[parameters] or [states]"]),
    ("a state also a parameter", _HEAD + '[states]\nD = 0.0\n[rates]\nD = "-D"\n', ["states.D", "also a parameter"]),
    ("non-numeric state", _HEAD + '[states]\nu1 = "one"\n[rates]\nu1 = "-u1"\n', ["states.u1", "must be a number"]),
    ("non-numeric parameter", '[system]\nname = "s"\n[parameters]\nD = [1, 2]\n[states]\nu1 = 0.0\n[rates]\nu1 = "-u1"\n',
     ["parameters.D", "must be a number"]),
    ("infinite state", _HEAD + '[states]\nu1 = inf\n[rates]\nu1 = "-u1"\n', ["states.u1", "finite"]),
    ("no states", _HEAD + '[states]\n[rates]\n', ["states", "at least one state"]),
    ("no states table", _HEAD + '[rates]\nu1 = "1"\n', ["states", "at least one state"]),
    ("expression too long", _HEAD + '[states]\nu1 = 0.0\n[rates]\nu1 = "u1' + "+u1" * 700 + '"\n',
     ["rates.u1", "characters long"]),
    ("code in an expression", _HEAD + '[states]\nu1 = 0.0\n[rates]\nu1 = "__import__(\'os\')"\n', ["rates.u1"]),
    ("a rate that is not text", _HEAD + '[states]\nu1 = 0.0\n[rates]\nu1 = true\n', ["rates.u1", "expression string"]),
    ("unknown key in [system]", '[system]\nname = "s"\nipS = 1\n[states]\nu1 = 0.0\n[rates]\nu1 = "-u1"\n',
     ["system.ipS", "unknown key"]),
    ("a mechanism table", _HEAD + '[states]\nu1 = 0.0\n[rates]\nu1 = "-u1"\n[bodies.a]\nmass = 1\n',
     ["bodies: unknown key; valid keys: equations, parameters, rates, states, system"]),
    ("a name that is a function", _HEAD + '[states]\nexp = 0.0\n[rates]\nexp = "-1"\n', ["states.exp", "reserved"]),
    ("a name that is not an identifier", _HEAD + '[states]\n"u 1" = 0.0\n[rates]\n"u 1" = "-1"\n', ["states.u 1", "name"]),
    ("[system] not a table", 'system = "s"\n[states]\nu1 = 0.0\n[rates]\nu1 = "-u1"\n', ["system", "must be a table"]),
    ("unknown key of a state", _HEAD + '[states]\nu1 = { value = 0.0, units = "m" }\n[rates]\nu1 = "-u1"\n',
     ["states.u1.units", "unknown key"]),
    ("a name that is a keyword", _HEAD + '[states]\nlambda = 0.0\n[rates]\nlambda = "-1"\n',
     ["states.lambda", "reserved"]),
]


@pytest.mark.parametrize("name,text,words", BAD, ids=[b[0] for b in BAD])
def test_a_bad_file_is_one_line_naming_the_field(tmp_path, name, text, words):
    path = _write(tmp_path, text, "bad.toml")
    with pytest.raises(InputError) as info:
        load_model(path)
    message = str(info.value)
    assert "\n" not in message and message.startswith("bad.toml"), message
    for w in words:
        assert w in message, message


@pytest.mark.parametrize("command", [["check"], ["equations"], ["continue", "--vary", "D"],
                                     ["simulate", "--until", "1"]])
def test_a_bad_file_exits_2_with_one_line_from_each_command(tmp_path, command):
    path = _write(tmp_path, BAD[0][1], "bad.toml")
    run = make_runner()
    one_line_error(run(command[0], path, *command[1:]), "rates.u2", "missing")


def test_the_line_of_the_field_is_given(tmp_path):
    path = _write(tmp_path, _HEAD + '[states]\nu1 = 0.0\n[rates]\nu1 = "u1 + q"\n', "bad.toml")
    with pytest.raises(InputError, match=r"^bad\.toml:8: rates\.u1"):
        load_model(path)
