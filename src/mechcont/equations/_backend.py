"""Which SymEngine backend compiles: LLVM machine code when the installed wheel has it, else its
interpreted ``lambda`` form.

Apart from :mod:`._codegen`: the disk cache (:mod:`._cache`, :mod:`._cache_key`) asks it too (it stores
only LLVM code, and the backend is part of every key), and the code generation uses the cache.
"""

from __future__ import annotations

__all__ = ["backend"]

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
