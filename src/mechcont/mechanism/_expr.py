"""Values in a mechanism description: numbers or expressions in named quantities.

Every geometric or physical value of a description (a length, a mass, a point coordinate,
a load magnitude) may be a number or a string such as ``"L1/2"`` or ``"k*cos(psi1)"``.

A description file is data: its strings are never evaluated as code. An expression is
parsed by Python's own parser into a syntax tree (``ast.parse(text, mode="eval")``, which
only builds the tree) and that tree is translated node by node into SymPy objects over a
whitelist: numbers (integers and decimals), the declared names, ``pi``, the operators
``+ - * / **`` (``^`` also means power), unary ``+``/``-``, parentheses and calls of the
functions of :data:`FUNCTIONS` with positional arguments. Anything else (attributes,
subscripts, strings, lambdas, comprehensions, comparisons, keyword arguments, ...) is
refused with a one-line :class:`~mechcont.errors.InputError`, as are non-ASCII text (Python
would silently NFKC-normalise look-alike letters such as ``ｋ`` into ``k``), texts longer
than :data:`MAX_LENGTH` characters, more than :data:`MAX_NODES` syntax nodes or nesting
deeper than :data:`MAX_DEPTH`, exponents larger than :data:`MAX_EXPONENT` in magnitude and
numbers beyond the floating-point range (so ``10**10**10`` is refused at once instead of
being computed).
"""

from __future__ import annotations

import ast
import math
import sys
from collections.abc import Callable, Mapping, Sequence

import mpmath
import sympy as sp

from ..errors import InputError
from ._numeric import numeric_value

__all__ = ["Value", "to_expr", "float_value", "evaluate", "symbol", "Gradient", "FUNCTIONS",
           "MAX_LENGTH", "MAX_NODES", "MAX_DEPTH", "MAX_EXPONENT"]

Value = float | int | str
#: ``gradient(expr, symbols)``: the derivatives of ``expr`` by each of ``symbols`` (SymPy's, or the equations' own).
Gradient = Callable[[sp.Expr, Sequence[sp.Symbol]], list[sp.Expr]]

#: Functions and constants allowed in expressions of a description file.
FUNCTIONS = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "asin": sp.asin, "acos": sp.acos, "atan": sp.atan,
    "atan2": sp.atan2, "sinh": sp.sinh, "cosh": sp.cosh, "tanh": sp.tanh, "sqrt": sp.sqrt, "exp": sp.exp,
    "log": sp.log, "abs": sp.Abs, "pi": sp.pi, "Min": sp.Min, "Max": sp.Max,
}
#: The names of FUNCTIONS that are constants, not functions.
_CONSTANTS = {"pi"}
#: Number of positional arguments of each function: (fewest, most); None means any number.
#: ``log(x, b)`` is the logarithm to base ``b``; ``Min`` and ``Max`` take one or more.
_ARITY: dict[str, tuple[int, int | None]] = {
    **{f: (1, 1) for f in FUNCTIONS if f not in _CONSTANTS}, "atan2": (2, 2), "log": (1, 2),
    "Min": (1, None), "Max": (1, None),
}

#: Longest expression text (characters).
MAX_LENGTH = 2000
#: Most syntax-tree nodes (numbers, names, operators, calls) in one expression.
MAX_NODES = 500
#: Deepest nesting of operators and calls (``-(-(-x))`` is 3 deep, ``a+b+c`` 2).
MAX_DEPTH = 250
#: Largest magnitude of a numeric exponent (``L1**64`` is fine, ``2**65`` is refused).
MAX_EXPONENT = 64
_FLOAT_MAX = sys.float_info.max
_LOG10_FLOAT_MAX = math.log10(_FLOAT_MAX)

_RANGE = f"numbers must lie within +-{_FLOAT_MAX:.4g}"
_OPERATORS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
_VALID = ("numbers, declared names, pi, + - * / ** ^, parentheses and the functions "
          + ", ".join(f for f in FUNCTIONS if f not in _CONSTANTS))
#: What the refused syntax is called in error messages (by AST node class name).
_REFUSED = {
    "Attribute": "attribute access ('.')", "Subscript": "subscripts ('[...]')", "Slice": "slices",
    "Lambda": "lambda", "Compare": "comparisons", "BoolOp": "'and'/'or'", "IfExp": "'if ... else'",
    "NamedExpr": "':=' assignments", "Starred": "'*' unpacking", "JoinedStr": "f-strings",
    "FormattedValue": "f-strings", "Tuple": "tuples (',')", "List": "lists ('[...]')", "Set": "sets ('{...}')",
    "Dict": "dicts ('{...}')", "ListComp": "comprehensions", "SetComp": "comprehensions",
    "DictComp": "comprehensions", "GeneratorExp": "generator expressions", "Await": "'await'",
    "Yield": "'yield'", "YieldFrom": "'yield'",
}


def symbol(name: str) -> sp.Symbol:
    """The real SymPy symbol of a named quantity (the same as ``Variable(name).symbol``)."""
    return sp.Symbol(name, real=True)


def _show(value: str, limit: int = 60) -> str:
    """``repr`` of an expression for a message, shortened to about ``limit`` characters."""
    return repr(value if len(value) <= limit else value[:limit] + "...")


class _Refused(Exception):
    """Raised inside the translator; ``to_expr`` turns it into an InputError:
    ``<what> in <expression>; <hint>``."""

    def __init__(self, what: str, hint: str = f"valid: {_VALID}"):
        super().__init__(what)
        self.what, self.hint = what, hint


def to_expr(value: Value, field: str, known: Mapping[str, sp.Symbol], declare: str = "[parameters]") -> sp.Expr:
    """Parse a number or expression string into a SymPy expression over ``known`` symbols.

    Parameters
    ----------
    value:
        A finite number, or a string in the names of ``known`` and the functions of
        :data:`FUNCTIONS` (``^`` means power). The string is parsed, never evaluated as code.
    field:
        Where the value comes from (e.g. ``"bodies.crank.length"``), used in errors.
    known:
        The names that may appear, mapped to their symbols.
    declare:
        Where the file declares such names, for the error on an unknown one (an ODE file's rates may
        use its ``[parameters]`` and its ``[states]``).

    Returns
    -------
    sympy.Expr
        Integers become ``Integer``, decimals ``Float`` (with the precision of their digits),
        ``1/2`` the ``Rational`` 1/2, as SymPy's own arithmetic makes them.

    Raises
    ------
    InputError
        Not a number or string, unparsable, refused syntax, too long or too deep,
        non-finite, or using an unknown name or function.
    """
    if isinstance(value, bool):
        raise InputError(field, f"expected a number or an expression string, got {value!r}")
    if isinstance(value, int):
        _check_int(value, field)
        return sp.Integer(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise InputError(field, f"must be finite, got {value!r}")
        return sp.Float(value)
    if not isinstance(value, str):
        raise InputError(field, f"expected a number or an expression string, got {type(value).__name__}")
    if len(value) > MAX_LENGTH:
        raise InputError(field, f"expression is {len(value)} characters long; at most {MAX_LENGTH} are allowed")
    if not value.isascii():
        ch = next(c for c in value if not c.isascii())
        raise InputError(field, f"non-ASCII character {ch!r} (U+{ord(ch):04X}) in expression {_show(value)}; "
                                "write names, numbers and operators in ASCII")
    text = value.strip()
    if not text:
        raise InputError(field, f"not a valid expression: {value!r}; write a number or an expression string")
    text = text.replace("^", "**")  # as SymPy's convert_xor: ^ is power, with its precedence
    try:
        tree = ast.parse(text, mode="eval")
    except SyntaxError as exc:
        why = " ".join(str(exc.msg).split())
        raise InputError(field, f"cannot parse expression {_show(value)} ({why}); valid: {_VALID}") from None
    except (RecursionError, MemoryError, ValueError):
        raise InputError(field, f"cannot parse expression {_show(value)} (nested too deeply)") from None
    _check_size(tree, value, field)
    try:
        expr = _Translator(text, known, FUNCTIONS).node(tree.body, 0)
    except _Refused as exc:
        raise InputError(field, f"{exc.what} in {_show(value)}; {exc.hint}") from None
    except _UnknownName as exc:
        raise InputError(field, f"unknown name '{exc}' in {_show(value)}; declare it under {declare}") from None
    except _UnknownFunction as exc:
        raise InputError(field, f"unknown function '{exc}' in {_show(value)}; "
                                f"allowed: {', '.join(sorted(FUNCTIONS))}") from None
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan, sp.I):
        raise InputError(field, f"expression is not a finite real value: {_show(value)}")
    return expr


def _check_int(value: int, field: str) -> None:
    if abs(value) > _FLOAT_MAX:
        raise InputError(field, f"the number {str(value)[:20]}... ({len(str(abs(value)))} digits) is beyond the "
                                f"floating-point range; numbers must lie within +-{_FLOAT_MAX:.4g}")


def _check_size(tree: ast.Expression, value: str, field: str) -> None:
    """Refuse trees with more than MAX_NODES nodes or deeper than MAX_DEPTH (iteratively)."""
    if sum(isinstance(n, ast.expr) for n in ast.walk(tree)) > MAX_NODES:
        raise InputError(field, f"expression {_show(value)} is too large (more than {MAX_NODES} terms); "
                                "split it over parameters")
    stack = [(tree.body, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise InputError(field, f"expression {_show(value)} is nested more than {MAX_DEPTH} levels deep")
        stack.extend((child, depth + 1) for child in ast.iter_child_nodes(node) if isinstance(child, ast.expr))


class _UnknownName(Exception):
    pass


class _UnknownFunction(Exception):
    pass


class _Translator:
    """Turns a whitelisted expression tree into SymPy objects, refusing everything else."""

    def __init__(self, text: str, known: Mapping[str, sp.Symbol], functions: Mapping):
        self.text, self.known, self.functions = text, known, functions

    def node(self, node: ast.AST, depth: int) -> sp.Expr:
        kind = type(node).__name__
        method = getattr(self, f"_{kind}", None)
        if method is None:
            what = _REFUSED.get(kind, kind)
            raise _Refused(f"{what} not allowed")
        if depth > MAX_DEPTH:  # also checked beforehand; a guard for the recursion
            raise _Refused(f"nested more than {MAX_DEPTH} levels deep", "simplify it")
        return method(node, depth + 1)

    def _Constant(self, node: ast.Constant, depth: int) -> sp.Expr:
        v = node.value
        if isinstance(v, bool) or v is None or v is Ellipsis:
            raise _Refused(f"{v!r} not allowed")
        if isinstance(v, int):
            if abs(v) > _FLOAT_MAX:
                raise _Refused(f"the number {str(v)[:20]}... is beyond the floating-point range", _RANGE)
            return sp.Integer(v)
        if isinstance(v, float):
            digits = (ast.get_source_segment(self.text, node) or repr(v)).replace("_", "")
            if not math.isfinite(v):
                raise _Refused(f"the number {digits} is beyond the floating-point range", _RANGE)
            return sp.Float(digits)  # the decimal digits as written, as SymPy's parser made them
        if isinstance(v, complex):
            raise _Refused("complex numbers ('j') not allowed", "values are real")
        if isinstance(v, (str, bytes)):
            raise _Refused("strings (quotes) not allowed")
        raise _Refused(f"{type(v).__name__} not allowed")  # pragma: no cover

    def _Name(self, node: ast.Name, depth: int) -> sp.Expr:
        name = node.id
        if name in self.known:
            return self.known[name]
        if name in _CONSTANTS:
            return self.functions[name]
        if name in self.functions:
            raise _Refused(f"'{name}' is a function", f"call it as {name}(...)")
        raise _UnknownName(name)

    def _UnaryOp(self, node: ast.UnaryOp, depth: int) -> sp.Expr:
        operand = self.node(node.operand, depth)
        if isinstance(node.op, ast.USub):
            return -operand
        if isinstance(node.op, ast.UAdd):
            return +operand
        op = {ast.Not: "'not'", ast.Invert: "'~'"}.get(type(node.op), type(node.op).__name__)
        raise _Refused(f"the operator {op} not allowed")

    def _BinOp(self, node: ast.BinOp, depth: int) -> sp.Expr:
        sym = _OPERATORS.get(type(node.op))
        if sym is None:
            op = {ast.FloorDiv: "//", ast.Mod: "%", ast.MatMult: "@", ast.LShift: "<<", ast.RShift: ">>",
                  ast.BitOr: "|", ast.BitAnd: "&", ast.BitXor: "^"}.get(type(node.op), type(node.op).__name__)
            raise _Refused(f"the operator '{op}' not allowed")
        a = self.node(node.left, depth)
        b = self.node(node.right, depth)
        if sym == "**":
            _check_power(a, b)
            out = a ** b
        else:
            out = {"+": a.__add__, "-": a.__sub__, "*": a.__mul__, "/": a.__truediv__}[sym](b)
        return _in_range(out)

    def _Call(self, node: ast.Call, depth: int) -> sp.Expr:
        if not isinstance(node.func, ast.Name):
            what = _REFUSED.get(type(node.func).__name__, "this call")
            raise _Refused(f"{what} not allowed", f"only the functions {', '.join(_ARITY)} may be called")
        name = node.func.id
        if name not in self.functions or name in _CONSTANTS:
            raise _UnknownFunction(name)
        if node.keywords:
            raise _Refused(f"keyword arguments of {name}(...) not allowed", "pass positional arguments")
        if any(isinstance(a, ast.Starred) for a in node.args):
            raise _Refused(f"'*' unpacking in {name}(...) not allowed", "pass positional arguments")
        lo, hi = _ARITY[name]
        n = len(node.args)
        if n < lo or (hi is not None and n > hi):
            want = f"{lo}" if lo == hi else (f"{lo} or {hi}" if hi is not None else f"at least {lo}")
            raise _Refused(f"{name}(...) given {n} argument(s)", f"{name} takes {want}")
        args = [self.node(a, depth) for a in node.args]
        return _in_range(self.functions[name](*args))


def _check_power(base: sp.Expr, exponent: sp.Expr) -> None:
    """Refuse powers whose exponent is a large number or whose numeric value would overflow."""
    if not exponent.is_Number:
        return
    if abs(exponent) > MAX_EXPONENT:
        raise _Refused(f"the exponent {exponent} is too large", f"exponents are at most {MAX_EXPONENT} in magnitude")
    if base.is_Number and base != 0 and exponent != 0:
        if float(exponent) * _log10_abs(base) > _LOG10_FLOAT_MAX:
            raise _Refused(f"a power ({_short(base)})**{exponent} beyond the floating-point range", _RANGE)


def _short(x: sp.Expr) -> str:
    text = str(x)
    return text if len(text) <= 20 else f"{text[:12]}...({len(text)} characters)"


def _log10_abs(x: sp.Number) -> float:
    """log10 |x| of a non-zero SymPy number, without overflow or underflow."""
    if x.is_Rational:
        return math.log10(abs(x.p)) - math.log10(x.q)
    return float(mpmath.log10(abs(mpmath.mpf(x._mpf_))))


def _in_range(expr: sp.Expr) -> sp.Expr:
    """``expr``, unless it is a number beyond the floating-point range."""
    if expr.is_Number and expr.is_finite and abs(expr) > _FLOAT_MAX:
        raise _Refused("a number beyond the floating-point range", _RANGE)
    return expr


def float_value(expr: sp.Expr, values: Mapping[sp.Symbol, float]) -> float:
    """The value of ``expr`` in double-precision arithmetic, bottom-up, at the symbol ``values``
    (its :func:`~._numeric.numeric_value` program).

    Overflow gives ``inf`` and a domain error (``sqrt(-1)``, ``acos(2)``) ``nan``, at once:
    unlike SymPy's arbitrary-precision evaluation, which may take hours on
    ``exp(exp(exp(100)))``, this never computes a number beyond the floating-point range.
    Raises TypeError if a free symbol has no value.
    """
    try:
        return numeric_value(expr)({s.name: v for s, v in values.items()})
    except KeyError as exc:
        raise TypeError(f"no value for {exc.args[0]}") from None


def evaluate(expr: sp.Expr, values: Mapping[str, float], field: str) -> float:
    """Numeric value of a parameter-only expression; InputError if it is not finite and real.

    The value is first computed in floating point (:func:`float_value`: an overflow such as
    ``exp(exp(exp(L)))`` is refused at once instead of being computed to arbitrary
    precision), then, when finite, by SymPy as before (correctly rounded).
    """
    subs = {s: values[s.name] for s in expr.free_symbols if s.name in values}
    if len(subs) < len(expr.free_symbols):
        raise InputError(field, f"{expr} depends on more than the parameters")
    _finite(expr, float_value(expr, subs), field)
    try:
        out = float(expr.xreplace(subs))
    except TypeError:
        raise InputError(field, f"{expr} is not a real number with the given parameters") from None
    if not math.isfinite(out):
        raise InputError(field, f"evaluates to {out} with the given parameters")
    return out


def _finite(expr: sp.Expr, quick: float, field: str) -> None:
    """InputError unless the floating-point value ``quick`` of ``expr`` is finite."""
    if math.isnan(quick):
        raise InputError(field, f"{expr} is not a real number with the given parameters (a division by zero, the "
                                "square root or logarithm of a negative number, asin or acos beyond +-1?)")
    if not math.isfinite(quick):
        raise InputError(field, f"{expr} overflows the floating-point range with the given parameters")
