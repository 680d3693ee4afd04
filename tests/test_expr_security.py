"""Description files are data: expression strings are parsed, never evaluated as code.

Hostile expressions are refused at once with a one-line InputError and run nothing; names
are ASCII identifiers (no look-alikes, no NFKC collisions) and reserved names are refused;
the parser agrees with Python's own arithmetic on well-formed expressions.
"""

import ast
import builtins
import math
import sys
import time

import pytest
import sympy as sp
import sympy.parsing.sympy_parser as sympy_parser
from hypothesis import given, settings
from hypothesis import strategies as st

from mechcont.errors import InputError
from mechcont.mechanism import builtin_descriptions, find_description, load_description, parse_description
from mechcont.mechanism._expr import FUNCTIONS, MAX_EXPONENT, MAX_LENGTH, float_value, symbol, to_expr

KNOWN = {"k": symbol("k"), "L1": symbol("L1")}
OVERCENTRE = find_description("overcentre").read_text()


def refused(text, *words, known=KNOWN):
    """``text`` is refused by to_expr within a second with one line containing ``words``."""
    t0 = time.perf_counter()
    with pytest.raises(InputError) as info:
        to_expr(text, "bodies.1.mass", known)
    elapsed = time.perf_counter() - t0
    assert elapsed < 1.0, f"{text[:40]!r} took {elapsed:.2f} s"  # a hang guard, not a benchmark
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith("bodies.1.mass: ")
    for w in words:
        assert w in msg, msg
    return msg


@pytest.fixture()
def no_code_evaluation(monkeypatch):
    """eval, exec, SymPy's text parser and sympify of a string all fail loudly if reached."""
    load_description("fourbar").build()  # import what a build imports lazily (imports compile code)
    def forbidden(name):
        def fail(*args, **kwargs):
            raise AssertionError(f"{name} was called")
        return fail

    monkeypatch.setattr(builtins, "eval", forbidden("eval"))
    monkeypatch.setattr(builtins, "exec", forbidden("exec"))
    real_compile = builtins.compile

    def compile_tree_only(source, filename, mode, flags=0, *args, **kwargs):
        # ast.parse compiles to a syntax tree only (PyCF_ONLY_AST); anything else would be code
        if not flags & ast.PyCF_ONLY_AST:
            raise AssertionError("compile to code was called")
        return real_compile(source, filename, mode, flags, *args, **kwargs)

    monkeypatch.setattr(builtins, "compile", compile_tree_only)
    monkeypatch.setattr(sympy_parser, "parse_expr", forbidden("parse_expr"))
    monkeypatch.setattr(sympy_parser, "eval_expr", forbidden("eval_expr"))
    real = sp.sympify

    def sympify(a, *args, **kwargs):
        if isinstance(a, str):
            raise AssertionError(f"sympify({a!r}) was called")
        return real(a, *args, **kwargs)

    monkeypatch.setattr(sp, "sympify", sympify)
    monkeypatch.setattr(sys.modules["sympy.core.sympify"], "sympify", sympify)


def hostile(tmp_path):
    pwned = tmp_path / "pwned"
    return [
        "().__class__.__bases__[0].__subclasses__()",
        "pi.__class__",
        "k.__class__.__mro__",
        f"__import__('os').system('touch {pwned}')",
        f"exec(\"open('{pwned}', 'w')\")",
        "(x for x in ()).gi_frame",
        "(lambda: 1)()",
        "lambda: 1",
        "f'{k}'",
        "'abc'",
        "b'abc'",
        '-"-"*3',
        "(y := 3)",
        "[x for x in (1, 2)]",
        "{x for x in (1, 2)}",
        "{1: 2}",
        "(1, 2)",
        "k[0]",
        "k[0:1]",
        "sin(x=1)",
        "sin(*k)",
        "Function('f')(k)",
        "Symbol('z')",
        "eval('1')",
        "exec('1')",
        "open('/etc/passwd')",
        "getattr(k, 'x')",
        "globals()",
        "Integer(3)",
        "Rational(1, 2)",
        "Float('1')",
        "k if k else 1",
        "k < 1",
        "k and 1",
        "not k",
        "~k",
        "k % 2",
        "k // 2",
        "k @ k",
        "k | 1",
        "k & 1",
        "k << 2",
        "True",
        "None",
        "...",
        "1j",
        "k;1",
        "import os",
        "k\n+1",
        "1\x00",
        "",
        "   ",
    ]


def test_hostile_expressions_are_refused_and_run_nothing(tmp_path, no_code_evaluation):
    for text in hostile(tmp_path):
        refused(text)
    assert not (tmp_path / "pwned").exists()


@pytest.mark.parametrize("text, words", [
    ("10**10**10", ("exponent", f"at most {MAX_EXPONENT}")),
    ("2**99999999", ("exponent",)),
    ("9**9**9**9", ("exponent",)),
    ("2^99999999", ("exponent",)),
    ("k**65", ("exponent",)),
    ("(10**64)**64", ("floating-point range",)),
    ("(1e-300)**-2", ("floating-point range",)),
    ("1e308*10", ("floating-point range",)),
    ("1e400", ("floating-point range",)),
    ("exp(1e300)", ("floating-point range",)),
    ("1" + "0" * 400, ("floating-point range",)),
    ("(" * 5000 + "1" + ")" * 5000, (f"at most {MAX_LENGTH}",)),
    ("(" * 300 + "1" + ")" * 300, ("nested",)),
    ("-" * 300 + "1", ("levels deep",)),
    ("+".join(["k"] * 600), ("too large",)),
    ("k" * (MAX_LENGTH + 1), (f"at most {MAX_LENGTH}",)),
    ("1/0", ("not a finite real value",)),
    ("sin", ("is a function", "sin(...)")),
    ("sin(k, k)", ("sin takes 1",)),
    ("atan2(k)", ("atan2 takes 2",)),
    ("sqrt(k, 2)", ("sqrt takes 1",)),
])
def test_blow_ups_and_misuse_are_refused_quickly(text, words, no_code_evaluation):
    refused(text, *words)


@pytest.mark.parametrize("text, char", [
    ("ｋ*2", "U+FF4B"),            # fullwidth k: NFKC would make it k
    ("𝐤", "U+1D424"),             # mathematical bold k
    ("kо", "U+043E"),              # Cyrillic o
    ("L1 − 2", "U+2212"),          # minus sign
    ("ﬁ", "U+FB01"),               # ligature fi
])
def test_non_ascii_is_refused(text, char):
    refused(text, "non-ASCII", char)


def test_unknown_names_and_functions_keep_their_messages():
    assert "unknown name 'L9' in 'L9/2'; declare it under [parameters]" in refused("L9/2")
    msg = refused("foo(L1)", "unknown function 'foo'")
    assert "allowed: " + ", ".join(sorted(FUNCTIONS)) in msg


@pytest.mark.parametrize("text, expected", [
    ("L1/2", sp.Rational(1, 2) * KNOWN["L1"]),
    ("1/2", sp.Rational(1, 2)),
    ("2^3^2", sp.Integer(512)),       # ^ is ** with its precedence (right-associative)
    ("2*L1^2", 2 * KNOWN["L1"] ** 2),
    ("-2**2", sp.Integer(-4)),
    ("10**-3", sp.Rational(1, 1000)),
    ("pi/2", sp.pi / 2),
    ("0.5", sp.Float("0.5")),
    ("1_000", sp.Integer(1000)),
    ("sqrt(L1^2 + k^2)", sp.sqrt(KNOWN["L1"] ** 2 + KNOWN["k"] ** 2)),
    ("atan2(k, L1)", sp.atan2(KNOWN["k"], KNOWN["L1"])),
    ("log(k, 10)", sp.log(KNOWN["k"], 10)),
    ("Max(L1, k, 1)", sp.Max(KNOWN["L1"], KNOWN["k"], 1)),
    ("  L1  ", KNOWN["L1"]),
])
def test_valid_expressions(text, expected):
    out = to_expr(text, "f", KNOWN)
    assert sp.srepr(out) == sp.srepr(expected)


def test_numbers_keep_their_types_and_digits():
    assert isinstance(to_expr(3, "f", {}), sp.Integer)
    assert isinstance(to_expr(0.25, "f", {}), sp.Float)
    # the decimal digits as written (as SymPy's parser made them), not a rounded float
    assert to_expr("0.4792338013778868", "f", {}) == sp.Float("0.4792338013778868")
    with pytest.raises(InputError, match="floating-point range"):
        to_expr(10 ** 400, "f", {})
    for bad in (math.inf, math.nan, True, None, [1]):
        with pytest.raises(InputError):
            to_expr(bad, "f", {})


def test_shipped_descriptions_load_and_build_without_evaluating_text(no_code_evaluation):
    for name in builtin_descriptions():
        mech = load_description(name)
        assert mech._exprs
        mech.build()


def test_float_value_never_blows_up():
    L = symbol("L")
    t0 = time.perf_counter()
    assert float_value(sp.exp(sp.exp(sp.exp(L))), {L: 100.0}) == math.inf
    assert math.isnan(float_value(sp.sqrt(L - 2), {L: 1.0}))
    assert math.isnan(float_value(sp.asin(L), {L: 2.0}))
    assert float_value(sp.atan2(L, 1) + sp.Max(L, 2) * sp.pi, {L: 1.0}) == pytest.approx(math.pi / 4 + 2 * math.pi)
    assert time.perf_counter() - t0 < 1.0


@pytest.mark.parametrize("old, new, words", [
    ('mass = "m1"', 'mass = "exp(exp(exp(100 + m1)))"', ("bodies.1.mass", "overflows")),
    ('points = { spring = ["m", 0] }', 'points = { spring = ["sqrt(m - 2)", 0] }',
     ("bodies.1.points.spring.x", "not a real number")),
    ("O = [0, 0]", 'O = ["exp(exp(exp(100)))", 0]', ("ground.O.x", "overflows")),
])
def test_values_that_overflow_at_the_parameters_are_refused_at_build(old, new, words):
    text = OVERCENTRE.replace(old, new, 1)
    assert text != OVERCENTRE
    t0 = time.perf_counter()
    with pytest.raises(InputError) as info:
        parse_description(text, "m.toml").build()
    assert time.perf_counter() - t0 < 5.0
    for w in words:
        assert w in str(info.value)


# -- names ----------------------------------------------------------------------------------
def _with_parameters(extra: str) -> str:
    return OVERCENTRE.replace("[parameters]\n", "[parameters]\n" + extra + "\n", 1)


@pytest.mark.parametrize("extra, words", [
    ('"ｋ" = 1.0', ("parameters.ｋ", "identifier", "ASCII")),        # NFKC-equal to the declared k
    ('"kо" = 1.0', ("identifier", "ASCII")),                          # Cyrillic o
    ('"k\\nx" = 1.0', ("parameters.k\\nx", "identifier")),            # one line even so
    ("s = 1.0", ("parameters.s", "reserved", "branch table")),
    ("label = 1.0", ("parameters.label", "reserved")),
    ("stability = 1.0", ("parameters.stability", "reserved")),
    ("vary = 1.0", ("parameters.vary", "reserved")),
    ("n_unstable = 1.0", ("parameters.n_unstable", "reserved")),
    ("theta1_dot = 1.0", ("parameters.theta1_dot", "_dot")),
    ("sin = 1.0", ("parameters.sin", "expression function")),
    ("pi = 3.0", ("parameters.pi", "expression constant")),
    ('"1k" = 1.0', ("parameters.1k", "identifier")),
])
def test_bad_parameter_names(extra, words):
    with pytest.raises(InputError) as info:
        parse_description(_with_parameters(extra), "m.toml")
    msg = str(info.value)
    assert "\n" not in msg
    for w in words:
        assert w in msg, msg


@pytest.mark.parametrize("old, new, words", [
    ('points = { spring = ["m", 0] }', 'points = { spring = ["m", 0], cg = [0, 0] }',
     ("bodies.1.points.cg", "built-in point")),
    ('points = { spring = ["m", 0] }', 'points = { spring = ["m", 0], origin = [0, 0] }',
     ("bodies.1.points.origin", "built-in point")),
    ('points = { spring = ["m", 0] }', 'points = { spring = ["m", 0], a = [0, 0] }',
     ("bodies.1.points.a", "bar's end")),
    ('points = { spring = ["m", 0] }', 'points = { "sprіng" = ["m", 0] }', ("identifier", "ASCII")),
    ("[joints.apex]", '[joints."apеx"]', ("joints.apеx", "identifier")),
    ("[bodies.2]", '[bodies."２"]', ("identifier",)),
])
def test_bad_declared_names(old, new, words):
    text = OVERCENTRE.replace(old, new, 1)
    assert text != OVERCENTRE
    with pytest.raises(InputError) as info:
        parse_description(text, "m.toml").build()
    for w in words:
        assert w in str(info.value), str(info.value)


# -- the parser's arithmetic agrees with Python's ------------------------------------------
_OPS = {"+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b, "/": lambda a, b: a / b,
        "**": lambda a, b: a ** b, "^": lambda a, b: a ** b}


def _expressions():
    """(text, value(k)): an expression over small integers and k, and its value in Python floats."""
    leaf = st.one_of(st.integers(0, 9).map(lambda i: (str(i), lambda k, i=i: float(i))),
                     st.just(("k", lambda k: k)))

    def binary(t):
        (a, fa), op, (b, fb) = t
        return f"({a}{op}{b})", lambda k: _OPS[op](fa(k), fb(k))

    return st.recursive(
        leaf,
        lambda sub: st.one_of(
            st.tuples(sub, st.sampled_from(sorted(_OPS)), sub).map(binary),
            sub.map(lambda e: (f"(-{e[0]})", lambda k, f=e[1]: -f(k))),
            sub.map(lambda e: (f"(+{e[0]})", lambda k, f=e[1]: +f(k))),
        ),
        max_leaves=8,
    )


@settings(max_examples=300, deadline=None)
@given(_expressions(), st.floats(0.5, 2.0))
def test_parser_agrees_with_python_arithmetic(expression, k):
    text, value = expression
    try:
        want = value(k)  # Python's own arithmetic on the same tree
    except (ZeroDivisionError, OverflowError):
        return
    if isinstance(want, complex) or not math.isfinite(want) or abs(want) > 1e12:
        return
    try:
        expr = to_expr(text, "f", {"k": symbol("k")})
    except InputError as exc:
        # only the documented refusals: a large exponent, a division by zero or a non-real constant
        assert any(w in str(exc) for w in ("exponent", "finite real", "floating-point")), str(exc)
        return
    got = complex(expr.xreplace({symbol("k"): sp.Float(k, 30)}).evalf(30))
    assert got.imag == pytest.approx(0, abs=1e-9 * max(1.0, abs(want)))
    assert got.real == pytest.approx(want, rel=1e-9, abs=1e-9)


def test_min_and_max_have_one_sided_exact_derivatives():
    """Min/Max stay allowed: the Jacobian is the derivative of the active argument, never NaN."""
    import numpy as np

    from mechcont.continuation import find_equilibrium

    text = OVERCENTRE.replace('k = "k"', 'k = "Max(k, 100)"', 1)
    text += '\n[loads.push]\ntype = "custom"\nat = "2.b"\nfx = "Min(theta1, 0.4, 2*theta1)*10"\n'
    system = parse_description(text, "m.toml").build()
    for theta in (0.2, 0.3, 0.5):  # Min's active argument changes at 0.4
        x = find_equilibrium(system, hold={"theta1": theta}, free=["F"])
        J = system.jacobian(x)
        h = 1e-7
        fd = np.column_stack([(system.residual(x + h * e) - system.residual(x - h * e)) / (2 * h)
                              for e in np.eye(len(x))])
        assert not np.isnan(J).any()
        assert np.max(np.abs(J - fd)) < 1e-5
        assert not np.isnan(system.jacobian_derivative(x, np.ones(len(x)))).any()
