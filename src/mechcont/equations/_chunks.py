"""One list of values compiled as several functions (chunks), each writing its slice of the same output.

SymEngine's common sub-expression elimination grows faster than linearly with the number of expressions
it is given, and LLVM's compile time with the length of one function: a large model's second derivatives
(the dual-sidestay gear's 19,871 entries) compile in about half the time as four functions, which run
slower per call (sub-expressions shared between chunks are computed in each). :func:`compile_chunked` makes
them; :class:`ChunkedKernel` is what the one compiled function would have been (a :class:`Kernel`, also
callable from C through :meth:`ChunkedKernel.as_ctypes`), so every caller of the values is unchanged.
"""

from __future__ import annotations

import ctypes
from collections.abc import Sequence
from typing import Any

import numpy as np
import symengine as se

from ._backend import Kernel, backend
from ._codegen import CompiledFunction, _lambdify, compile_values

__all__ = ["ChunkedKernel", "compile_chunked"]

_DOUBLE = ctypes.sizeof(ctypes.c_double)
_CALLBACK = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)


class ChunkedKernel:
    """Kernels whose outputs, one after the other, are one output of ``sum(sizes)`` values."""

    def __init__(self, kernels: Sequence[Kernel], sizes: Sequence[int]) -> None:
        self.kernels, self.sizes = list(kernels), [int(s) for s in sizes]
        self.bounds = np.concatenate([[0], np.cumsum(self.sizes)]).astype(int).tolist()
        self._trampoline: Any = None

    def unsafe_real(self, x: np.ndarray, out: np.ndarray, /) -> None:
        """Each chunk's values into its slice of ``out`` (contiguous, ``sum(sizes)`` long) at ``x``."""
        b = self.bounds
        for k, fn in enumerate(self.kernels):
            fn.unsafe_real(x, out[b[k]:b[k + 1]])

    def unsafe_eval(self, X: np.ndarray, out: np.ndarray, m: int, /) -> None:
        """The values at each of the ``m`` rows of ``X`` into ``out`` (flat, row after row)."""
        rows, b = out.reshape(m, -1), self.bounds
        for k, fn in enumerate(self.kernels):
            part = np.empty(m * self.sizes[k])
            fn.unsafe_eval(X, part, m)
            rows[:, b[k]:b[k + 1]] = part.reshape(m, -1)

    def as_ctypes(self) -> tuple[Any, ctypes.c_void_p]:
        """``(callback, data)`` as SymEngine's LLVM functions give them, for the compiled corrector: a C
        callable ``callback(out, inp, data)`` that calls each chunk's machine code on its slice of ``out``."""
        if self._trampoline is None:
            parts = []
            for k, fn in enumerate(self.kernels):
                cb, data = fn.as_ctypes()  # type: ignore[attr-defined]
                parts.append((_CALLBACK(ctypes.cast(cb, ctypes.c_void_p).value or 0), data, self.bounds[k] * _DOUBLE))

            def call(out: int, inp: int, _data: int) -> None:  # the chunks' code lives as long as self.kernels
                for fn_k, data_k, offset in parts:
                    fn_k(out + offset, inp, data_k)

            self._trampoline = _CALLBACK(call)
        return self._trampoline, ctypes.c_void_p(None)

    def __reduce__(self) -> tuple[type[ChunkedKernel], tuple[list[Kernel], list[int]]]:
        return ChunkedKernel, (self.kernels, self.sizes)


def compile_chunked(args: Sequence[se.Symbol], exprs: Sequence[se.Basic], chunk: int,
                    opt_level: int = 3) -> CompiledFunction:
    """Compile ``exprs`` (SymEngine, in the positional ``args``) as :func:`compile_values` does, their
    values in order, but as functions of at most ``chunk`` expressions each when there are more.

    The values are those of one function to rounding: each chunk's sub-expressions are shared within
    it only, and SymEngine may then build a sum in another order. With SymEngine's interpreted backend
    (whose functions do not pickle) the expressions are kept and compiled again, as one, on unpickling.
    """
    exprs = list(exprs)
    if len(exprs) <= chunk:
        return compile_values(args, exprs, opt_level=opt_level)
    starts = range(0, len(exprs), chunk)
    kernels = [_lambdify(list(args), exprs[s:s + chunk], opt_level)[0] for s in starts]
    source = None if backend() == "llvm" else (list(args), exprs)
    return CompiledFunction(ChunkedKernel(kernels, [len(exprs[s:s + chunk]) for s in starts]), len(args), (len(exprs),),
                            None, source)
