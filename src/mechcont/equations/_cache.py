"""Disk cache of compiled code, so a second process starts without recompiling.

Compiling a model's equations (exact derivatives, then machine code through SymEngine's
LLVM backend) is what makes a cold start slow; the compiled functions are picklable
(:class:`~mechcont.equations._codegen.CompiledFunction`), so they are kept on disk, keyed
by a hash of everything they are made from:

* the symbolic content: the variables (names, assumptions) and the expressions, written
  losslessly (SymPy ``srepr``; SymEngine expressions with every float in hexadecimal), so
  two models that differ anywhere, even in a float's last bit, never share an entry;
* the code that turns them into functions: the source of ``_codegen.py``, ``_system.py``,
  ``_mechanics.py`` and this module (a change there invalidates every entry), the mechcont,
  SymPy, SymEngine and Python versions, the code-generation backend and the platform.

Where: ``$MECHCONT_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/mechcont`` or the platform's
user cache directory (``~/.cache/mechcont``, ``~/Library/Caches/mechcont``,
``%LOCALAPPDATA%\\mechcont\\cache``). ``MECHCONT_NO_CACHE=1`` (any value other than empty,
``0``, ``false``, ``no``, ``off``) turns it off: nothing is read or written. It is also off
with SymEngine's interpreted ``lambda`` backend (a wheel without LLVM), whose functions
cannot be stored as code: loading them would compile them again.

Safety: an entry is written to a temporary file in the same directory and renamed into
place (``os.replace``, atomic), so concurrent processes never see half an entry; two that
compile the same model both write the same content and the last rename wins. An entry
starts with a magic line and the SHA-256 of its payload; one that is truncated, corrupt,
from another format or unreadable is ignored (the code is compiled again and the entry
rewritten), never an error, and any failure to write (read-only or full disk) only means
no caching. Entries contain machine code that is loaded and run: the directory is created
private to the user (mode 0700), and it should not be shared with untrusted users. The
cache is never pruned; deleting the directory is always safe.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import platform
import sys
import tempfile
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TypeVar

__all__ = ["cache_dir", "enabled", "cache_key", "cached", "load", "store", "expr_text", "STATS"]

T = TypeVar("T")

_MAGIC = b"mechcont-compiled-cache 1\n"
_FORMAT = "1"
#: Counters of this process: ``hits`` (entries loaded), ``misses`` (looked up, not found or
#: unusable), ``writes`` (entries stored). For tests and benchmarks.
STATS = {"hits": 0, "misses": 0, "writes": 0}
_OFF = {"", "0", "false", "no", "off"}
_environment: str | None = None


def enabled() -> bool:
    """False when ``MECHCONT_NO_CACHE`` is set to a true value."""
    return os.environ.get("MECHCONT_NO_CACHE", "").strip().lower() in _OFF


def cache_dir() -> Path | None:
    """The cache directory (not created here), or None when caching is off."""
    if not enabled():
        return None
    explicit = os.environ.get("MECHCONT_CACHE_DIR")
    if explicit:
        return Path(explicit).expanduser()
    xdg = os.environ.get("XDG_CACHE_HOME")
    if xdg:
        return Path(xdg).expanduser() / "mechcont"
    if sys.platform == "win32":
        base = os.environ.get("LOCALAPPDATA")
        return (Path(base) if base else Path.home() / "AppData" / "Local") / "mechcont" / "cache"
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "mechcont"
    return Path.home() / ".cache" / "mechcont"


def _environment_text() -> str:
    """Everything besides the symbolic content that decides what compiled code is."""
    global _environment
    if _environment is None:
        import numpy
        import symengine
        import sympy

        from .. import __version__
        from ._codegen import backend

        here = Path(__file__).parent
        h = hashlib.sha256()
        for name in ("_codegen.py", "_system.py", "_mechanics.py", "_cache.py"):
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


def _engine_text(e) -> str:
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


def expr_text(e) -> str:
    """Lossless, deterministic text of a SymPy or SymEngine expression (for cache keys)."""
    import sympy as sp

    if isinstance(e, sp.Basic):
        return sp.srepr(e)
    if isinstance(e, (int, float, str)):
        return repr(e)
    return _engine_text(e)


def cache_key(parts: Iterable[str | bytes]) -> str:
    """SHA-256 (hex) of ``parts`` (separated unambiguously) and the environment."""
    h = hashlib.sha256(_environment_text().encode())
    for p in parts:
        b = p if isinstance(p, bytes) else p.encode("utf-8", "surrogatepass")
        h.update(len(b).to_bytes(8, "little"))
        h.update(b)
    return h.hexdigest()


def _path(key: str) -> Path | None:
    d = cache_dir()
    return None if d is None else d / key[:2] / f"{key}.pkl"


def load(key: str):
    """The object stored under ``key``, or None (absent, unreadable, corrupt, caching off)."""
    path = _path(key)
    if path is None:
        return None
    try:
        data = path.read_bytes()
    except OSError:
        return None
    try:
        if not data.startswith(_MAGIC):
            return None
        digest, payload = data[len(_MAGIC):len(_MAGIC) + 32], data[len(_MAGIC) + 32:]
        if hashlib.sha256(payload).digest() != digest:
            return None
        stored_key, obj = pickle.loads(payload)
        return obj if stored_key == key else None
    except Exception:  # noqa: BLE001 - a bad entry is only a cache miss
        return None


def store(key: str, obj) -> bool:
    """Write ``obj`` under ``key`` atomically; False (and no error) if it cannot be written."""
    path = _path(key)
    if path is None:
        return False
    try:
        payload = pickle.dumps((key, obj), protocol=pickle.HIGHEST_PROTOCOL)
    except Exception:  # noqa: BLE001 - e.g. a backend whose code cannot be pickled
        return False
    tmp = None
    try:
        path.parent.parent.mkdir(parents=True, exist_ok=True, mode=0o700)  # the cache root: private
        path.parent.mkdir(exist_ok=True, mode=0o700)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=".pkl")
        with os.fdopen(fd, "wb") as f:
            f.write(_MAGIC + hashlib.sha256(payload).digest() + payload)
        os.replace(tmp, path)
        tmp = None
        STATS["writes"] += 1
        return True
    except OSError:
        return False
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass


def cached(parts: Iterable[str | bytes] | Callable[[], Iterable[str | bytes]], build: Callable[[], T],
           valid: Callable[[object], bool] | None = None) -> T:
    """``build()``, or its result stored by an earlier process under the key of ``parts``.

    ``parts`` may be a callable returning them (called only when caching is on).
    ``valid(obj)`` may reject a loaded object (then it is rebuilt and the entry rewritten).
    With caching off, just ``build()``.
    """
    from ._codegen import backend

    if not enabled() or backend() != "llvm":  # the interpreted backend's code is rebuilt on loading anyway
        return build()
    key = cache_key(parts() if callable(parts) else parts)
    obj = load(key)
    if obj is not None and (valid is None or valid(obj)):
        STATS["hits"] += 1
        return obj
    STATS["misses"] += 1
    obj = build()
    store(key, obj)
    return obj
