"""Which SymEngine backend compiles: LLVM machine code when the installed wheel has it, else its
interpreted ``lambda`` form.

Apart from :mod:`._codegen`: the disk cache (:mod:`._cache`, :mod:`._cache_key`) asks it too (it stores
only LLVM code, and the backend is part of every key), and the code generation uses the cache. What either
backend makes is a :class:`Kernel`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    import numpy as np

__all__ = ["backend", "Kernel"]

_BACKEND: str | None = None


def backend() -> str:
    """The SymEngine Lambdify backend in use: ``"llvm"`` if the wheel has it, else ``"lambda"``."""
    global _BACKEND
    if _BACKEND is None:
        import symengine as se

        try:
            x = se.Symbol("x")
            se.Lambdify([x], [x], backend="llvm")
            _BACKEND = "llvm"
        except (RuntimeError, ValueError, TypeError):  # wheel built without LLVM
            _BACKEND = "lambda"
    return _BACKEND


class Kernel(Protocol):
    """What SymEngine's ``Lambdify`` makes (LLVM machine code or its interpreted form): the values of its
    expressions written into ``out``, at one argument vector or at each of ``m`` rows."""

    def unsafe_real(self, x: np.ndarray, out: np.ndarray, /) -> None: ...

    def unsafe_eval(self, X: np.ndarray, out: np.ndarray, m: int, /) -> None: ...
