"""Built models kept in the disk cache, so that a new process starts like a compiled tool.

Deriving a model's equations in SymPy and compiling them is what a cold start costs; a
built :class:`~mechcont.equations.Model` pickles with its compiled code, and its symbolic
parts are pickled apart (see :mod:`._deferred`), so a process that loads one imports
neither SymPy nor the code generation. :func:`stored` keeps such objects in the disk cache
of compiled code (:mod:`._cache`: :func:`~._cache.load` and :func:`~._cache.store`, the same
files, directory, switches and safety).

The key: everything the object is made from that can change. The caller gives the inputs
(a description file's full text, a built-in model's name and values); added here are the
size and modification time of every module of mechcont's source (the code that builds from
them: any edit there invalidates every entry, by the rule of Python's own bytecode cache), the
versions of SymPy, SymEngine, NumPy and Python, and the platform. SymPy's version is read from
its ``release.py`` without importing it: :func:`~._cache.cache_key` imports SymPy (0.5 s), so
it is not used for these keys.
"""

from __future__ import annotations

import hashlib
import os
import sys
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TypeVar

from . import _cache, _deferred
from ._cache_key import digest

__all__ = ["stored", "stored_key"]

T = TypeVar("T")
_ENVIRONMENT: list[bytes] = []


def _sympy_release() -> bytes:
    """SymPy's ``release.py`` (its version), found without importing SymPy."""
    from importlib.util import find_spec

    spec = find_spec("sympy")
    if spec is None or spec.origin is None:  # pragma: no cover - SymPy is a dependency
        return b"no sympy"
    try:
        return (Path(spec.origin).parent / "release.py").read_bytes()
    except OSError:  # pragma: no cover - an unusual installation: the installed version instead
        from importlib.metadata import version

        return version("sympy").encode()


def _sources(root: str, rel: str = "") -> list[tuple[str, int, int]]:
    """``(path relative to root, size in bytes, modification time in ns)`` of every ``.py`` file under
    ``root``, sorted. The signature Python's own bytecode cache trusts (a ``.pyc`` is reused while its
    source's size and modification time are unchanged): one ``stat`` per file, where reading and
    hashing the 160 files took 5-7 ms of every warm start."""
    out = []
    with os.scandir(os.path.join(root, rel)) as entries:
        for entry in entries:
            name = f"{rel}/{entry.name}" if rel else entry.name
            if entry.is_dir(follow_symlinks=False):
                if entry.name != "__pycache__":
                    out.extend(_sources(root, name))
            elif entry.name.endswith(".py"):
                st = entry.stat()
                out.append((name, st.st_size, st.st_mtime_ns))
    return sorted(out)


def _environment() -> bytes:
    """The digest of mechcont's source and of the versions and platform (once per process)."""
    if not _ENVIRONMENT:
        import platform

        import numpy
        import symengine

        from .._version import __version__

        h = hashlib.sha256()
        for rel, size, mtime in _sources(str(Path(__file__).resolve().parent.parent)):
            h.update(f"{len(rel)} {rel} {size} {mtime}\n".encode())
        h.update(_sympy_release())
        h.update("\n".join(["stored 1", __version__, f"symengine {symengine.__version__}", f"numpy {numpy.__version__}",
                            f"python {sys.version_info[:3]}", f"{sys.platform} {platform.machine()} {sys.byteorder}"]
                           ).encode())
        _ENVIRONMENT.append(h.digest())
    return _ENVIRONMENT[0]


def stored_key(parts: Iterable[str | bytes]) -> str:
    """SHA-256 (hex) of ``parts`` (separated unambiguously), mechcont's source and the environment."""
    return digest(b"mechcont stored object\n" + _environment(), parts)


def stored(parts: Callable[[], Iterable[str | bytes]], build: Callable[[], T], valid: Callable[[object], bool]) -> T:
    """``build()``, or the object an earlier process stored under the key of ``parts()``.

    ``valid(obj)`` must accept a loaded object (else it is built again and the entry
    rewritten). With caching off (``MECHCONT_NO_CACHE``), just ``build()``; with SymEngine's
    interpreted backend (whose code would be compiled again on loading) nothing is stored.
    The cache's ``STATS`` count the look-ups.
    """
    if not _cache.enabled():
        return build()
    with _deferred.later():  # parts a later use may never need are compiled then, and cached then
        return _cache.load_or_build(stored_key(parts()), build, valid)
