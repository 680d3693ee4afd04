"""Exact derivatives and fast numeric callables from symbolic expressions.

Models are written with SymPy (readable, printable); differentiation and code generation
use SymEngine, SymPy's C++ core, which differentiates two orders of magnitude faster and
compiles expressions with common sub-expression elimination to machine code (LLVM
backend, when the installed wheel has it) or to a fast interpreted form. A branch
evaluates these functions thousands of times, so per-call cost matters more than
vectorisation.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import symengine as se
import sympy as sp

__all__ = ["to_engine", "derivative_entries", "compile_dense", "compile_sparse"]

_BACKEND: str | None = None


def _backend() -> str:
    global _BACKEND
    if _BACKEND is None:
        try:
            x = se.Symbol("x")
            se.Lambdify([x], [x], backend="llvm")
            _BACKEND = "llvm"
        except (RuntimeError, ValueError, TypeError):  # wheel built without LLVM
            _BACKEND = "lambda"
    return _BACKEND


def to_engine(exprs):
    """Convert SymPy expressions (or a single one) to SymEngine."""
    if isinstance(exprs, (list, tuple)):
        return [se.sympify(e) for e in exprs]
    return se.sympify(exprs)


def derivative_entries(exprs: Sequence, args: Sequence) -> list[tuple[tuple[int, int], object]]:
    """Non-zero entries ``((i, j), d expr_i / d arg_j)`` of the Jacobian of ``exprs``."""
    out = []
    for i, e in enumerate(exprs):
        fs = e.free_symbols
        for j, a in enumerate(args):
            if a in fs:
                d = e.diff(a)
                if d != 0:
                    out.append(((i, j), d))
    return out


def _lambdify(args, exprs):
    # SymEngine's CSE names its temporaries x0, x1, ...: rename the arguments first so a
    # model variable called "x1" cannot collide with them.
    safe = [se.Symbol(f"mcarg_{i}") for i in range(len(args))]
    mapping = dict(zip(args, safe))
    exprs = [se.sympify(e).xreplace(mapping) for e in exprs]
    return se.Lambdify(safe, exprs, backend=_backend(), cse=True)


def compile_dense(args: Sequence, exprs: Sequence):
    """Compile expressions into ``f(x) -> ndarray`` with one entry per expression.

    ``args`` are SymPy or SymEngine symbols; ``x`` is a 1-D float array ordered like them.
    """
    args = to_engine(list(args))
    exprs = to_engine(list(exprs))
    if not exprs:
        return lambda x: np.zeros(0)
    fn = _lambdify(args, exprs)

    def evaluate(x) -> np.ndarray:
        return fn(np.asarray(x, dtype=float))

    return evaluate


def compile_sparse(args: Sequence, entries: Sequence[tuple[tuple[int, ...], object]], shape: tuple[int, ...]):
    """Compile the non-zero entries of a sparse array into ``f(x) -> ndarray`` of ``shape``.

    ``entries`` is a list of ``(index_tuple, expression)``; entries that are constant are
    filled once. Returns a callable producing a fresh dense array per call.
    """
    args = to_engine(list(args))
    const = np.zeros(shape)
    var_idx: list[tuple[int, ...]] = []
    var_expr = []
    for idx, e in entries:
        e = se.sympify(e)
        if e.free_symbols:
            var_idx.append(idx)
            var_expr.append(e)
        else:
            const[idx] = float(e)
    if not var_expr:
        return lambda x: const.copy()
    flat = np.ravel_multi_index(tuple(np.array(var_idx).T), shape)
    fn = _lambdify(args, var_expr)

    def evaluate(x) -> np.ndarray:
        out = const.copy()
        out.flat[flat] = fn(np.asarray(x, dtype=float))
        return out

    return evaluate


def sympy_symbols(names: Sequence[str]) -> list[sp.Symbol]:
    """Real SymPy symbols for ``names``."""
    return [sp.Symbol(n, real=True) for n in names]
