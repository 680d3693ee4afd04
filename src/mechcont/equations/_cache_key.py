"""The key of a disk-cache entry: a hash of everything compiled code is made from.

Apart from :mod:`._cache`, which keeps entries safe on disk (folders, files, their tags): this says what an
entry *is* (the symbolic content written losslessly, and the environment: the compiling modules' source,
the library versions, the backend, the platform), the other what may be read. :func:`expr_text` and
:func:`digest` are also the stored objects' keys (:mod:`._stored`).
"""

from __future__ import annotations

import hashlib
import platform
import sys
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

from ._backend import backend

if TYPE_CHECKING:
    import symengine as se
    import sympy as sp

__all__ = ["cache_key", "digest", "expr_text"]

#: The entries' format (a new one invalidates every entry).
_FORMAT = "2"
#: The modules whose source decides what compiled code is.
SOURCES = ("_codegen.py", "_system.py", "_compiled.py", "_chunks.py", "_variables.py", "_mechanics.py", "_cache.py",
           "_cache_key.py", "_backend.py")
_environment: str | None = None


def _environment_text() -> str:
    """Everything besides the symbolic content that decides what compiled code is."""
    global _environment
    if _environment is None:
        import numpy
        import symengine
        import sympy

        from .._version import __version__

        here = Path(__file__).parent
        h = hashlib.sha256()
        for name in SOURCES:
            try:
                h.update((here / name).read_bytes())
            except OSError:  # pragma: no cover - installed without sources
                h.update(name.encode())
        _environment = "\n".join([
            _FORMAT, __version__, h.hexdigest(), f"sympy {sympy.__version__}", f"symengine {symengine.__version__}",
            f"numpy {numpy.__version__.split('.')[0]}", f"python {sys.version_info[:2]}", f"backend {backend()}",
            f"{sys.platform} {platform.machine()} {sys.byteorder}",
        ])
    return _environment


def _engine_text(e: se.Basic) -> str:
    """Lossless text of a SymEngine expression.

    ``str`` is exact for integers, rationals and names but rounds floats, so every float is
    first replaced by a symbol named after its exact (hexadecimal) value; the walk that finds
    them visits each distinct sub-expression once.
    """
    import symengine as se

    floats = {}
    seen = set()
    todo = [e]
    while todo:
        node = todo.pop()
        if isinstance(node, se.RealDouble):
            floats[node] = se.Symbol(f"__float({float(node).hex()})")
            continue
        for a in node.args:
            if a not in seen:
                seen.add(a)
                todo.append(a)
    if floats:
        e = e.xreplace(floats)
    return f"{type(e).__name__}:{e}"


def expr_text(e: sp.Basic | se.Basic | float | str) -> str:
    """Lossless, deterministic text of a SymPy or SymEngine expression (for cache keys)."""
    import sympy as sp

    if isinstance(e, sp.Basic):
        return sp.srepr(e)
    if isinstance(e, (int, float, str)):
        return repr(e)
    return _engine_text(e)


def digest(head: bytes, parts: Iterable[str | bytes]) -> str:
    """SHA-256 (hex) of ``head`` and then ``parts``, each preceded by its length (unambiguous)."""
    h = hashlib.sha256(head)
    for p in parts:
        b = p if isinstance(p, bytes) else p.encode("utf-8", "surrogatepass")
        h.update(len(b).to_bytes(8, "little"))
        h.update(b)
    return h.hexdigest()


def cache_key(parts: Iterable[str | bytes]) -> str:
    """SHA-256 (hex) of ``parts`` (separated unambiguously) and the environment."""
    return digest(_environment_text().encode(), parts)
