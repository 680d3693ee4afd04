"""One list of values compiled as several functions (chunks), each writing its slice of the same output.

SymEngine's common sub-expression elimination grows faster than linearly with the number of expressions
it is given, and LLVM's compile time with the length of one function: a large model's second derivatives
(the dual-sidestay gear's 19,871 entries) compile in about half the time as several functions, which run
slower per call where sub-expressions shared between chunks are computed in each. Most of what chunks
shared were whole entries: a second derivative appears several times (``d2 G_i / dx_j dx_k`` at ``(j, k)``
and ``(k, j)``; a constraint's second derivative again in the equilibrium rows its multiplier enters), the
gear's 19,871 entries being 8,537 distinct expressions. So each distinct expression is compiled once and
the output gathered from them. :func:`compile_chunked` makes the chunks; :class:`ChunkedKernel` is what the
one compiled function would have been (a :class:`Kernel`, also callable from C through
:meth:`ChunkedKernel.as_ctypes`), so every caller of the values is unchanged.
"""

from __future__ import annotations

import ctypes
from collections.abc import Sequence
from typing import Any

import numpy as np
import symengine as se

from ._backend import Kernel, backend
from ._codegen import CompiledFunction, _lambdify, compile_values

__all__ = ["ChunkedKernel", "compile_chunked", "distinct"]

_DOUBLE = ctypes.sizeof(ctypes.c_double)
_CALLBACK = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)


class ChunkedKernel:
    """Kernels whose outputs, one after the other, are ``sum(sizes)`` values: the output itself, or with
    ``gather`` (indices into those values) the output ``values[gather]``."""

    def __init__(self, kernels: Sequence[Kernel], sizes: Sequence[int], gather: np.ndarray | None = None) -> None:
        self.kernels, self.sizes = list(kernels), [int(s) for s in sizes]
        self.bounds = np.concatenate([[0], np.cumsum(self.sizes)]).astype(int).tolist()
        self.gather = None if gather is None else np.ascontiguousarray(gather, dtype=np.intp)
        self._trampoline: Any = None

    def _values(self, x: np.ndarray, out: np.ndarray) -> None:
        """Each chunk's values into its slice of ``out`` (contiguous, ``sum(sizes)`` long) at ``x``."""
        b = self.bounds
        for k, fn in enumerate(self.kernels):
            fn.unsafe_real(x, out[b[k]:b[k + 1]])

    def unsafe_real(self, x: np.ndarray, out: np.ndarray, /) -> None:
        """The output at ``x`` into the first entries of ``out`` (contiguous, at least the output's length, as
        SymEngine's kernels write: :meth:`CompiledFunction.gather` passes one entry more)."""
        if self.gather is None:
            self._values(x, out)
            return
        values = np.empty(self.bounds[-1])
        self._values(x, values)
        np.take(values, self.gather, out=out[:len(self.gather)])

    def unsafe_eval(self, X: np.ndarray, out: np.ndarray, m: int, /) -> None:
        """The output at each of the ``m`` rows of ``X`` into ``out`` (flat, row after row)."""
        b = self.bounds
        rows = out.reshape(m, -1) if self.gather is None else np.empty((m, b[-1]))
        for k, fn in enumerate(self.kernels):
            part = np.empty(m * self.sizes[k])
            fn.unsafe_eval(X, part, m)
            rows[:, b[k]:b[k + 1]] = part.reshape(m, -1)
        if self.gather is not None:
            np.take(rows, self.gather, axis=1, out=out.reshape(m, -1))

    def as_ctypes(self) -> tuple[Any, ctypes.c_void_p]:
        """``(callback, data)`` as SymEngine's LLVM functions give them, for the compiled corrector: a C
        callable ``callback(out, inp, data)`` that calls each chunk's machine code on its slice of ``out``
        (or of the distinct values, then gathered into ``out``)."""
        if self._trampoline is None:
            parts = []
            for k, fn in enumerate(self.kernels):
                cb, data = fn.as_ctypes()  # type: ignore[attr-defined]
                parts.append((_CALLBACK(ctypes.cast(cb, ctypes.c_void_p).value or 0), data, self.bounds[k] * _DOUBLE))
            gather, n_out = self.gather, 0 if self.gather is None else len(self.gather)

            def call(out: int, inp: int, _data: int) -> None:  # the chunks' code lives as long as self.kernels
                if gather is None:
                    for fn_k, data_k, offset in parts:
                        fn_k(out + offset, inp, data_k)
                    return
                values = np.empty(self.bounds[-1])
                base = values.ctypes.data
                for fn_k, data_k, offset in parts:
                    fn_k(base + offset, inp, data_k)
                np.take(values, gather, out=np.ctypeslib.as_array((ctypes.c_double * n_out).from_address(out)))

            self._trampoline = _CALLBACK(call)
        return self._trampoline, ctypes.c_void_p(None)

    def __reduce__(self) -> tuple[type[ChunkedKernel], tuple[list[Kernel], list[int], np.ndarray | None]]:
        return ChunkedKernel, (self.kernels, self.sizes, self.gather)


def distinct(exprs: Sequence[se.Basic]) -> tuple[list[se.Basic], np.ndarray]:
    """``(unique, gather)``: the distinct expressions of ``exprs`` in order of first appearance, and for each
    expression its position among them (``exprs[i] == unique[gather[i]]``; SymEngine's structural equality)."""
    first: dict[se.Basic, int] = {}
    unique: list[se.Basic] = []
    gather = np.empty(len(exprs), dtype=np.intp)
    for i, e in enumerate(exprs):
        k = first.get(e)
        if k is None:
            k = first[e] = len(unique)
            unique.append(e)
        gather[i] = k
    return unique, gather


def compile_chunked(args: Sequence[se.Symbol], exprs: Sequence[se.Basic], chunk: int,
                    opt_level: int = 3) -> CompiledFunction:
    """Compile ``exprs`` (SymEngine, in the positional ``args``) as :func:`compile_values` does, their
    values in order, but when there are more than ``chunk``, each distinct expression once (:func:`distinct`),
    as functions of at most ``chunk`` expressions each, the output gathered from their values.

    The values are those of one function to rounding: each chunk's sub-expressions are shared within
    it only, and SymEngine may then build a sum in another order. With SymEngine's interpreted backend
    (whose functions do not pickle) the expressions are kept and compiled again, as one, on unpickling.
    """
    exprs = list(exprs)
    if len(exprs) <= chunk:
        return compile_values(args, exprs, opt_level=opt_level)
    unique, gather = distinct(exprs)
    starts = range(0, len(unique), chunk)
    kernels = [_lambdify(list(args), unique[s:s + chunk], opt_level)[0] for s in starts]
    source = None if backend() == "llvm" else (list(args), exprs)
    return CompiledFunction(ChunkedKernel(kernels, [len(unique[s:s + chunk]) for s in starts], gather), len(args),
                            (len(exprs),), None, source)
