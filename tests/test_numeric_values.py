"""A description's values evaluated at other parameter values without SymPy (mechanism/_numeric.py).

Each parsed expression is compiled once into a numeric program; its value is checked against SymPy's
own correctly rounded evaluation (double precision, a few operations: agreement to a few ulps, 1e-13
relative), its failures (a domain error, an overflow) against float_value's rules, and a model's
compiled value fields (a condition's target, a stop's limit, their derivatives) against closed forms
and finite differences, loaded in a fresh interpreter that does not import SymPy.
"""

from __future__ import annotations

import json
import math
import pickle
import subprocess
import sys

import pytest
import sympy as sp

from mechcont.errors import InputError
from mechcont.mechanism._expr import FUNCTIONS as ALLOWED
from mechcont.mechanism._expr import symbol, to_expr
from mechcont.mechanism._numeric import numeric_value

L, a, b = symbol("L"), symbol("a"), symbol("b")
KNOWN = {"L": L, "a": a, "b": b}
AT = [{"L": 1.3, "a": 0.4, "b": -0.7}, {"L": 0.05, "a": -1.2, "b": 2.5}, {"L": 7.0, "a": 0.0, "b": 0.9}]

#: Texts a description may hold: every allowed function, and forms SymPy rewrites (sqrt -> Pow, log to a
#: base -> a quotient, tan(x + pi/2) -> -cot(x), exp(1) -> E, 1/2 -> Rational, Max of one -> itself).
TEXTS = [
    "sin(a) + cos(b) * tan(a/3)", "asin(a/2) - acos(b/3) + atan(L)", "atan2(b, a) + atan2(-1, a - 2)",
    "sinh(a) * cosh(b) / (1 + tanh(L))", "sqrt(L) + L^(3/2) - L**-2", "exp(b) + log(L) + log(L, 2) + log(8, L + 2)",
    "abs(b) + abs(a - b)", "Min(a, b, L) + Max(a, 0) + Max(b)", "pi * L^2 / 4 + exp(1) * 1/2",
    "tan(b + pi/2) + sin(a + pi/2)", "L/2 - 1.25e-1 * cos(a) + 3", "-(-(-L))", "(a + b)**3 - 2**10 * L",
]


@pytest.mark.parametrize("text", TEXTS)
def test_the_numeric_program_is_sympys_value(text):
    expr = to_expr(text, "test", KNOWN)
    program = numeric_value(expr)
    assert program.names == {s.name for s in expr.free_symbols}
    for at in AT:
        exact = float(expr.xreplace({KNOWN[n]: sp.Float(v, 30) for n, v in at.items()}).evalf(30))
        assert program(at) == pytest.approx(exact, rel=1e-13, abs=1e-13), at


def test_every_allowed_function_has_a_numeric_form():
    for name in ALLOWED:
        if name == "pi":
            continue
        args = {"atan2": "a, L", "log": "L, 3", "Min": "a, b", "Max": "a, b"}.get(name, "a/2")
        expr = to_expr(f"{name}({args})", "test", KNOWN)
        ops = {op for op, _, _ in numeric_value(expr).program}
        assert "sympy" not in ops, name  # evaluated by math, not SymPy


def test_domain_errors_and_overflow_are_refused_naming_the_field():
    program = numeric_value(to_expr("sqrt(L - 2)", "x", KNOWN))
    assert math.isnan(program({"L": 1.0}))
    with pytest.raises(InputError, match=r"^stops\.top\.max: .*not a real number"):
        program.at({"L": 1.0}, "stops.top.max")
    huge = numeric_value(to_expr("exp(exp(exp(L)))", "x", KNOWN))
    assert huge({"L": 100.0}) == math.inf  # at once: no arbitrary-precision evaluation
    with pytest.raises(InputError, match="overflows"):
        huge.at({"L": 100.0}, "conditions.c.target")
    assert math.isnan(numeric_value(to_expr("1/(L - 1)", "x", KNOWN))({"L": 1.0}))
    with pytest.raises(InputError, match="depends on more than the parameters"):
        numeric_value(to_expr("a + L", "x", KNOWN)).at({"L": 1.0}, "f")


def test_a_function_without_a_float_form_is_evaluated_by_sympy_at_floats():
    program = numeric_value(sp.acoth(L) + sp.cot(a))  # no description writes these; SymPy may make cot
    at = {"L": 2.0, "a": 0.3}
    assert program(at) == pytest.approx(math.atanh(0.5) + 1 / math.tan(0.3), rel=1e-13)


LEVER = """
[mechanism]
name = "lever"
downlock = {{ condition = "angle", force = "F" }}
[parameters]
m = {{ value = 2.0, unit = "kg" }}
L = {{ value = 1.0, unit = "m" }}
g = {{ value = 9.81, unit = "m/s^2" }}
h = {{ value = 0.4, unit = "m" }}
w = {{ value = 1.5, unit = "m" }}
M0 = {{ value = 15.0, unit = "N m" }}
F = {{ value = 0.0, unit = "N m" }}
c = {{ value = 3.0, unit = "N s/m" }}
[ground]
O = [0, 0]
A = [0, "h + w"]
[bodies.bar]
mass = "m"
length = "L"
initial = {{ theta = 0.3 }}
[joints.pin]
type = "revolute"
a = "ground.O"
b = "bar.a"
[dampers.d]
a = "ground.A"
b = "bar.b"
c = "c * w"
c2 = "c / h"
[loads.lock]
type = "moment"
body = "bar"
magnitude = "M0 - F"
[gravity]
g = "g"
[conditions]
angle = {{ type = "angle", bodies = ["ground", "bar"], target = "{target}" }}
[stops.top]
condition = "angle"
max = "{target}"
"""
TARGET = "atan(h / w)"


def target(h: float, w: float) -> float:
    """The closed form of the condition's target and the stop's limit (rad)."""
    return math.atan(h / w)


@pytest.fixture(scope="module")
def lever(tmp_path_factory):
    path = tmp_path_factory.mktemp("numeric") / "lever.toml"
    path.write_text(LEVER.format(target=TARGET))
    return path


def test_a_models_value_fields_and_their_derivatives_follow_the_values(lever):
    """model_at: the target, the stop's limit, the damper's coefficients at the values; the target's and the
    limit's derivatives (exact, compiled) against the closed form's central differences."""
    from mechcont.models import model_at

    h, w = 0.55, 1.2
    system = model_at(str(lever), {"h": h, "w": w, "c": 4.0})
    t = target(h, w)
    assert system.conditions["angle"] == pytest.approx(t, rel=1e-14)
    assert system.downlock.hold == {"angle": pytest.approx(t, rel=1e-14)}
    assert system.stops[0].limit == pytest.approx(t, rel=1e-14)
    assert (system.dampers[0].c, system.dampers[0].c2) == (pytest.approx(4.0 * w), pytest.approx(4.0 / h))
    eps = 1e-6
    fd = {"h": (target(h + eps, w) - target(h - eps, w)) / (2 * eps),
          "w": (target(h, w + eps) - target(h, w - eps)) / (2 * eps), "m": 0.0}
    for got in (system.target_derivatives("angle", fd), system.limit_derivatives("top", fd)):
        assert got == {p: pytest.approx(v, rel=1e-8, abs=1e-12) for p, v in fd.items()}
    assert system.written_in("stops.top.max") == {"h", "w"}
    assert system.written_in("dampers.d.c2") == {"c", "h"}
    with pytest.raises(InputError, match=r"^conditions\.angle\.target: .*not a real number"):
        system.with_values({"h": 0.0, "w": 0.0})  # atan(0/0)


LOADED = r"""
import json, pickle, sys
model = pickle.loads(open(sys.argv[1], "rb").read())
fields = model.fields_at({**{v.name: v.value for v in model.variables if v.kind == "parameter"}, "h": 0.3, "w": 2.0})
print(json.dumps([fields["stops"][0].limit, model.target_derivatives("angle", ["h"])["h"], "sympy" in sys.modules]))
"""


def test_a_loaded_models_value_fields_need_no_sympy(lever, tmp_path):
    """The model pickled (as the disk cache keeps it) and loaded in a fresh interpreter: its value fields at new
    values and their derivatives, without importing SymPy."""
    from mechcont.models import load_model

    path = tmp_path / "model.pickle"
    path.write_bytes(pickle.dumps(load_model(str(lever))))
    out = subprocess.run([sys.executable, "-c", LOADED, str(path)], capture_output=True, text=True, check=True,
                         timeout=120).stdout
    limit, slope, imported = json.loads(out.strip().splitlines()[-1])
    assert limit == pytest.approx(target(0.3, 2.0), rel=1e-14)
    assert slope == pytest.approx(1.5 / (1.5**2 + 0.4**2), rel=1e-14)  # d atan(h/w)/dh = w/(w^2 + h^2) at the file's
    assert imported is False
