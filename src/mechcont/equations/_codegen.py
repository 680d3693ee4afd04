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


def _diff(e, a):
    """d e / d a, with |u|' = sign(u) u' and sign' = 0 (SymEngine leaves both unevaluated).

    Absolute values appear where a length is computed from parameters (sqrt(L^2) of a
    real L); away from zero these are the exact derivatives. ``Max(u1, u2, ...)`` (and
    ``Min``) of a description's expressions differentiates to the derivative of the argument
    that is largest (smallest) there, as a ``Piecewise``; at a tie, of the first such argument
    (a one-sided derivative: the kink itself has none).
    """
    d = e.diff(a)
    derivs = d.atoms(se.Derivative)
    if derivs:
        subs = {}
        for D in derivs:
            f, var = D.args[0], D.args[1]
            if isinstance(f, se.Abs):
                subs[D] = se.sign(f.args[0]) * _diff(f.args[0], var)
            elif isinstance(f, type(se.sign(se.Symbol("u")))):
                subs[D] = se.Integer(0)
            elif isinstance(f, (se.Max, se.Min)):
                subs[D] = _extremum_derivative(f, var)
            else:
                raise ValueError(f"cannot differentiate {f} exactly")
        d = d.xreplace(subs)
    return d


def _extremum_derivative(f, var):
    """d Max(u_i)/d var (or Min): u_k' where u_k is the first argument attaining the extremum."""
    better = se.Ge if isinstance(f, se.Max) else se.Le
    args = list(f.args)
    pieces = [(_diff(u, var), se.And(*(better(u, w) for j, w in enumerate(args) if j != i)))
              for i, u in enumerate(args[:-1])]
    return se.Piecewise(*pieces, (_diff(args[-1], var), True))


def derivative_entries(exprs: Sequence, args: Sequence) -> list[tuple[tuple[int, int], object]]:
    """Non-zero entries ``((i, j), d expr_i / d arg_j)`` of the Jacobian of ``exprs``."""
    out = []
    for i, e in enumerate(exprs):
        fs = e.free_symbols
        for j, a in enumerate(args):
            if a in fs:
                d = _diff(e, a)
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


def _evaluator(args, exprs, shape):
    fn = _lambdify(args, exprs)
    n_args, n_out = len(args), len(exprs)
    if hasattr(fn, "unsafe_real"):
        # unsafe_real skips SymEngine's argument checks (4x cheaper per call); the length
        # check here is what makes it safe.
        def evaluate(x) -> np.ndarray:
            x = np.ascontiguousarray(x, dtype=float)
            if x.shape != (n_args,):
                raise ValueError(f"expected {n_args} values, got shape {x.shape}")
            out = np.empty(n_out)
            fn.unsafe_real(x, out)
            return out.reshape(shape)
    else:  # pragma: no cover - older SymEngine
        def evaluate(x) -> np.ndarray:
            return np.asarray(fn(np.asarray(x, dtype=float)), dtype=float).reshape(shape)
    return evaluate


def compile_dense(args: Sequence, exprs: Sequence):
    """Compile expressions into ``f(x) -> ndarray`` with one entry per expression.

    ``args`` are SymPy or SymEngine symbols; ``x`` is a 1-D float array ordered like them.
    """
    args = to_engine(list(args))
    exprs = to_engine(list(exprs))
    if not exprs:
        return lambda x: np.zeros(0)
    return _evaluator(args, exprs, (len(exprs),))


def compile_sparse(args: Sequence, entries: Sequence[tuple[tuple[int, ...], object]], shape: tuple[int, ...]):
    """Compile the non-zero entries of an array into ``f(x) -> ndarray`` of ``shape``.

    ``entries`` is a list of ``(index_tuple, expression)``; other entries are zero.
    Returns a callable producing a fresh dense array per call.
    """
    args = to_engine(list(args))
    size = int(np.prod(shape))
    if size == 0:
        return lambda x: np.zeros(shape)
    dense = [se.Integer(0)] * size
    for idx, e in entries:
        dense[int(np.ravel_multi_index(idx, shape))] = se.sympify(e)
    return _evaluator(args, dense, shape)


def sympy_symbols(names: Sequence[str]) -> list[sp.Symbol]:
    """Real SymPy symbols for ``names``."""
    return [sp.Symbol(n, real=True) for n in names]
