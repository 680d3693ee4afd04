"""Values in a mechanism description: numbers or expressions in named quantities.

Every geometric or physical value of a description (a length, a mass, a point coordinate,
a load magnitude) may be a number or a string such as ``"L1/2"`` or ``"k*cos(psi1)"``.
Strings are parsed by SymPy over an explicit whitelist of functions, so a misspelt name is
reported as an unknown reference instead of silently becoming a new symbol.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.parsing.sympy_parser import convert_xor, parse_expr, standard_transformations

from ..errors import InputError

__all__ = ["Value", "to_expr", "symbol", "FUNCTIONS"]

Value = float | int | str

#: Functions and constants allowed in expressions of a description file.
FUNCTIONS = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "asin": sp.asin, "acos": sp.acos, "atan": sp.atan,
    "atan2": sp.atan2, "sinh": sp.sinh, "cosh": sp.cosh, "tanh": sp.tanh, "sqrt": sp.sqrt, "exp": sp.exp,
    "log": sp.log, "pi": sp.pi, "Min": sp.Min, "Max": sp.Max,
}
_PARSER_GLOBALS = {"Integer": sp.Integer, "Float": sp.Float, "Rational": sp.Rational, "Symbol": sp.Symbol,
                   "Function": sp.Function, **FUNCTIONS}
_TRANSFORMS = standard_transformations + (convert_xor,)


def symbol(name: str) -> sp.Symbol:
    """The real SymPy symbol of a named quantity (the same as ``Variable(name).symbol``)."""
    return sp.Symbol(name, real=True)


def to_expr(value: Value, field: str, known: Mapping[str, sp.Symbol]) -> sp.Expr:
    """Parse a number or expression string into a SymPy expression over ``known`` symbols.

    Parameters
    ----------
    value:
        A finite number, or a string in the names of ``known`` and the functions of
        :data:`FUNCTIONS` (``^`` means power).
    field:
        Where the value comes from (e.g. ``"bodies.crank.length"``), used in errors.
    known:
        The names that may appear, mapped to their symbols.

    Returns
    -------
    sympy.Expr

    Raises
    ------
    InputError
        Not a number or string, unparsable, non-finite, or using an unknown name.
    """
    if isinstance(value, bool):
        raise InputError(field, f"expected a number or an expression string, got {value!r}")
    if isinstance(value, (int, float)):
        if not math.isfinite(value):
            raise InputError(field, f"must be finite, got {value!r}")
        return sp.Integer(value) if isinstance(value, int) else sp.Float(value)
    if not isinstance(value, str):
        raise InputError(field, f"expected a number or an expression string, got {type(value).__name__}")
    text = value.strip()
    if not text or "__" in text or "lambda" in text or ";" in text:
        raise InputError(field, f"not a valid expression: {value!r}")
    local = dict(known)
    try:
        expr = parse_expr(text, local_dict=local, global_dict=dict(_PARSER_GLOBALS), transformations=_TRANSFORMS)
    except Exception as exc:  # SyntaxError, TokenError, TypeError from SymPy's parser
        raise InputError(field, f"cannot parse expression {value!r} ({type(exc).__name__})") from None
    if not isinstance(expr, sp.Expr):
        raise InputError(field, f"not a scalar expression: {value!r}")
    undefined = expr.atoms(AppliedUndef)
    if undefined:
        fn = sorted(str(f.func) for f in undefined)[0]
        raise InputError(field, f"unknown function '{fn}' in {value!r}; allowed: {', '.join(sorted(FUNCTIONS))}")
    allowed = set(known.values())
    unknown = sorted(str(s) for s in expr.free_symbols if s not in allowed)
    if unknown:
        raise InputError(field, f"unknown name '{unknown[0]}' in {value!r}; declare it under [parameters]")
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan, sp.I):
        raise InputError(field, f"expression is not a finite real value: {value!r}")
    return expr
