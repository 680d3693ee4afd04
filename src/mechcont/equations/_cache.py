"""Disk cache of compiled code, so a second process starts without recompiling.

Compiling a model's equations (exact derivatives, then machine code through SymEngine's
LLVM backend) is what makes a cold start slow; the compiled functions are picklable
(:class:`~mechcont.equations._codegen.CompiledFunction`), so they are kept on disk, keyed
by a hash of everything they are made from:

* the symbolic content: the variables (names, assumptions) and the expressions, written
  losslessly (SymPy ``srepr``; SymEngine expressions with every float in hexadecimal), so
  two models that differ anywhere, even in a float's last bit, never share an entry;
* the code that turns them into functions: the source of the modules that compile (a change
  there invalidates every entry), the mechcont, SymPy, SymEngine and Python versions, the
  code-generation backend and the platform (:mod:`._cache_key` makes the key).

Where: ``$MECHCONT_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/mechcont`` or the platform's
user cache directory (``~/.cache/mechcont``, ``~/Library/Caches/mechcont``). The entry of
key ``k`` is ``<root>/k[:2]/k.pkl``. ``MECHCONT_NO_CACHE=1`` (any value other than empty,
``0``, ``false``, ``no``, ``off``) turns it off: nothing is read or written. It is also off
with SymEngine's interpreted ``lambda`` backend (a wheel without LLVM), whose functions
cannot be stored as code (loading them would compile them again), and on platforms without
POSIX file ownership, ``O_NOFOLLOW`` and directory descriptors (Windows), where the checks
below cannot be made.

Threat model. An entry is a pickle holding machine code: loading one runs code as the
user, so whoever can put an entry where this process reads it can run code as this user.
The cache trusts only files the current (effective) user made in folders nobody else can
write; other local users, files copied in from elsewhere and links planted to make the
process read someone else's file or a device are the threats. (The user themselves and
root can always run code as the user; they are not.) The checks, all made before anything
is unpickled:

1. Folders. The root is opened without following a final symbolic link (``O_NOFOLLOW |
   O_DIRECTORY``; links higher up the path are followed as usual), and the shard folder
   ``k[:2]`` likewise relative to the root's descriptor; every later file operation is
   relative to these descriptors, so renaming or swapping a folder mid-way redirects
   nothing. Each must be owned by ``os.geteuid()`` and not writable by group or others.
   If one is not (or is a link), the process prints ONE warning on stderr for that root,
   saying which folder, why and how to fix it, and runs without the cache (no reads, no
   writes). A root mechcont creates is created with mode 0700; an existing folder's mode
   is never changed.
2. Entries are opened with ``O_NOFOLLOW | O_NONBLOCK | O_NOCTTY`` (a link is refused, a
   FIFO never blocks) and must be a regular file owned by the user, not group- or other-writable, at
   most ``_MAX_ENTRY`` bytes (256 MiB: the largest entry, the nose gear's second
   derivatives, is about 4 MB; a bound only stops a huge or growing file from exhausting
   memory), read with a read of exactly its size.
3. An entry is ``magic line, key, newline, tag, payload``: the magic and the key are
   compared as plain bytes first.
4. ``tag`` is the HMAC-SHA256 of header and payload under a per-user secret: 32 random
   bytes in ``<root>/hmac-key``, made once (written to a temporary file, then hard-linked
   into place, so it is created exclusively and never seen half-written), mode 0600, and
   checked like an entry but also not readable by group or others (a bad key file is a
   warning, like a bad folder). An entry whose tag does not verify (forged, copied from
   another cache, truncated, corrupt) is a miss: compiled again and rewritten. Only then is
   the payload unpickled.

Anything else that goes wrong (a missing, unreadable, corrupt or foreign entry, a read-only
or full disk) only means no caching, never an error. An entry is written to a temporary file
in its folder (``.tmp-PID-XXXXXXXXXXXXXXXX.pkl``: one left by a killed writer is removed by the
next store into that folder) and renamed into place (atomic), so concurrent processes never see half an
entry; two that compile the same model write the same content and the last rename wins.
The cache is never pruned; deleting the folder is always safe (the key is made again).
"""

from __future__ import annotations

import contextlib
import hashlib
import hmac
import os
import pickle
import re
import stat
import sys
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any, TypeVar

# imported with the module, not on first use: a process that drops its privileges (or whose source tree
# becomes unreadable) after start-up still builds and cleans entries
from .._signals import process_state
from ._backend import backend
from ._cache_key import cache_key, digest, expr_text
from ._lock import build_lock

__all__ = ["cache_dir", "enabled", "cache_key", "cached", "load", "store", "load_or_build", "digest", "expr_text",
           "STATS"]

T = TypeVar("T")

_MAGIC = b"mechcont-compiled-cache 2\n"
_TAG_SIZE = 32
_SECRET_NAME = "hmac-key"
_SECRET_SIZE = 32
#: Largest entry read or written, bytes (see the module docstring).
_MAX_ENTRY = 256 * 2**20
_KEY = re.compile(r"[0-9a-f]{64}")
#: Counters of this process: ``hits`` (entries loaded), ``misses`` (looked up, not found or
#: unusable), ``writes`` (entries stored). For tests and benchmarks.
STATS = {"hits": 0, "misses": 0, "writes": 0}
_OFF = {"", "0", "false", "no", "off"}
_SUPPORTED = hasattr(os, "geteuid") and hasattr(os, "O_NOFOLLOW") and os.open in os.supports_dir_fd
_DIR_FLAGS = os.O_RDONLY | getattr(os, "O_DIRECTORY", 0) | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
_FILE_FLAGS = (os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
               | getattr(os, "O_CLOEXEC", 0))
_NEW_FLAGS = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
#: Roots refused in this process, with the reason (each warned about once).
_DISTRUSTED: dict[str, str] = {}


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


class _Untrusted(Exception):
    """A folder or key file of the cache that this user must not trust (message: what and how to fix)."""


def _problem(st: os.stat_result, kind: int, shared: int) -> str | None:
    """Why a file with status ``st`` is not trusted (not of ``kind``, not ours, ``shared`` mode bits set), or None."""
    if stat.S_IFMT(st.st_mode) != kind:
        return "is not a folder" if kind == stat.S_IFDIR else "is not a regular file"
    if st.st_uid != os.geteuid():
        return f"is owned by user id {st.st_uid}, not by this user (id {os.geteuid()})"
    if st.st_mode & shared:
        return f"is {'writable' if shared == 0o022 else 'readable or writable'} by group or others (mode {st.st_mode & 0o777:o})"
    return None


def _refuse(where: str, problem: str) -> _Untrusted:
    if where.endswith(_SECRET_NAME):
        fix = f"delete {where} (a new key is made)"
    elif problem.startswith("is writable"):
        fix = f"run `chmod 700 {where}`"
    else:
        fix = "make it a folder of your own, not a link"
    return _Untrusted(f"{where} {problem}; {fix}, or set MECHCONT_CACHE_DIR to a private folder of your own")


def _why_not_opened(name: str | Path, dir_fd: int | None, kind: int, shared: int) -> str | None:
    """Why ``name``, which could not be opened, is not to be trusted (a link, another user's), or None (absent, say)."""
    try:
        st = os.stat(name, dir_fd=dir_fd, follow_symlinks=False)
    except OSError:
        return None
    return "is a symbolic link" if stat.S_ISLNK(st.st_mode) else _problem(st, kind, shared)


def _open_folder(name: str | Path, dir_fd: int | None, where: str, create: bool) -> int | None:
    """Descriptor of the trusted folder ``name`` (made 0700 if absent and ``create``), or None if absent.

    Raises _Untrusted for a link or a folder that is not private to this user.
    """
    try:
        fd = os.open(name, _DIR_FLAGS, dir_fd=dir_fd)
    except FileNotFoundError:
        if not create:
            return None
        try:
            if dir_fd is None:
                Path(name).parent.mkdir(parents=True, exist_ok=True)
            os.mkdir(name, 0o700, dir_fd=dir_fd)
        except FileExistsError:
            pass
        except OSError:
            return None
        return _open_folder(name, dir_fd, where, False)
    except OSError:
        problem = _why_not_opened(name, dir_fd, stat.S_IFDIR, 0o022)
        if problem:
            raise _refuse(where, problem) from None
        return None
    try:
        problem = _problem(os.fstat(fd), stat.S_IFDIR, 0o022)
    except OSError:
        problem = "cannot be examined"
    if problem:
        os.close(fd)
        raise _refuse(where, problem)
    return fd


def _read_file(name: str, dir_fd: int, shared: int, limit: int) -> tuple[bytes | None, str | None]:
    """(content, None) of a regular file of ours, at most ``limit`` bytes; (None, why) otherwise.

    ``why`` is None when the file is absent or unreadable, else why it is not trusted.
    """
    try:
        fd = os.open(name, _FILE_FLAGS, dir_fd=dir_fd)
    except OSError:
        return None, _why_not_opened(name, dir_fd, stat.S_IFREG, shared)
    try:
        st = os.fstat(fd)
        problem = _problem(st, stat.S_IFREG, shared)
        if problem is None and st.st_size > limit:
            problem = f"is larger than {limit} bytes"
        if problem:
            return None, problem
        chunks, left = [], st.st_size
        while left > 0:
            chunk = os.read(fd, left)
            if not chunk:
                break
            chunks.append(chunk)
            left -= len(chunk)
        return b"".join(chunks), None
    except OSError:
        return None, None
    finally:
        os.close(fd)


def _secret(root_fd: int, where: str, create: bool) -> bytes | None:
    """The cache's HMAC key (made if absent and ``create``), or None. Raises _Untrusted for a bad key file."""
    data, problem = _read_file(_SECRET_NAME, root_fd, 0o077, _SECRET_SIZE)
    if problem is None and data is not None and len(data) != _SECRET_SIZE:
        problem = f"is not a {_SECRET_SIZE}-byte key"
    if problem:
        raise _refuse(f"{where}/{_SECRET_NAME}", problem)
    if data is not None or not create:
        return data
    import secrets  # only when writing (with random, 1-2 ms of every start-up otherwise)

    key = secrets.token_bytes(_SECRET_SIZE)
    tmp = f".tmp-key-{secrets.token_hex(8)}"
    try:
        fd = os.open(tmp, _NEW_FLAGS, 0o600, dir_fd=root_fd)
    except OSError:
        return None
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(key)
        # a hard link never replaces an existing key: of concurrent processes, one wins
        os.link(tmp, _SECRET_NAME, src_dir_fd=root_fd, dst_dir_fd=root_fd, follow_symlinks=False)
        return key
    except FileExistsError:
        return _secret(root_fd, where, False)
    except OSError:
        return None
    finally:
        with contextlib.suppress(OSError):
            os.unlink(tmp, dir_fd=root_fd)


@contextlib.contextmanager
def _shard(key: str, create: bool) -> Iterator[tuple[int, bytes] | None]:
    """(descriptor of the trusted folder of ``key``'s entry, HMAC key), or None: no caching now.

    The walk from the root goes by descriptors; a folder or key file not to be trusted turns
    the cache off for this root in this process, with one warning.
    """
    root = cache_dir() if _SUPPORTED and _KEY.fullmatch(key) else None
    where = str(root)
    if root is None or where in _DISTRUSTED:
        yield None
        return
    fds: list[int] = []
    found: tuple[int, bytes] | None = None
    try:
        root_fd = _open_folder(root, None, where, create)
        if root_fd is not None:
            fds.append(root_fd)
            secret = _secret(root_fd, where, create)
            shard_fd = _open_folder(key[:2], root_fd, f"{where}/{key[:2]}", create) if secret else None
            if shard_fd is not None and secret is not None:  # a shard is opened only with a secret
                fds.append(shard_fd)
                found = (shard_fd, secret)
    except _Untrusted as e:
        _DISTRUSTED[where] = str(e)
        sys.stderr.write(f"mechcont: not using the compiled-code cache: {e}\n")
    except OSError:
        pass
    try:
        yield found
    finally:
        for fd in fds:
            os.close(fd)


def _header(key: str) -> bytes:
    return _MAGIC + key.encode("ascii") + b"\n"


def _tag(secret: bytes, header: bytes, payload: bytes | memoryview) -> bytes:
    mac = hmac.new(secret, header, hashlib.sha256)
    mac.update(payload)
    return mac.digest()


def _encode(key: str, payload: bytes, secret: bytes) -> bytes:
    """An entry's bytes: header (magic, key), HMAC tag, payload."""
    header = _header(key)
    return header + _tag(secret, header, payload) + payload


def _decode(data: bytes, key: str, secret: bytes) -> memoryview | None:
    """The payload (a view, not a copy) of an entry for ``key`` whose tag verifies, else None. Nothing is unpickled here."""
    header = _header(key)
    if not data.startswith(header) or len(data) < len(header) + _TAG_SIZE:
        return None
    view = memoryview(data)
    tag, payload = view[len(header):len(header) + _TAG_SIZE], view[len(header) + _TAG_SIZE:]
    return payload if hmac.compare_digest(tag, _tag(secret, header, payload)) else None


def load(key: str) -> Any:  # whatever was stored: the callers' `valid` checks it
    """The object stored under ``key``, or None (absent, untrusted, unverified, corrupt, caching off)."""
    with _shard(key, create=False) as found:
        if found is None:
            return None
        data, _ = _read_file(f"{key}.pkl", found[0], 0o022, _MAX_ENTRY)
        payload = None if data is None else _decode(data, key, found[1])
    if payload is None:
        return None
    try:
        return pickle.loads(payload)
    except Exception:  # noqa: BLE001 - a bad entry is only a cache miss
        return None


def store(key: str, obj: object) -> bool:
    """Write ``obj`` under ``key`` atomically; False (and no error) if it cannot or may not be written."""
    try:
        payload = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
    except Exception:  # noqa: BLE001 - e.g. a backend whose code cannot be pickled
        return False
    with _shard(key, create=True) as found:
        if found is None:
            return False
        shard_fd, secret = found
        data = _encode(key, payload, secret)
        if len(data) > _MAX_ENTRY:
            return False
        import secrets

        _remove_stale(shard_fd)
        name = f".tmp-{os.getpid()}-{secrets.token_hex(8)}.pkl"
        tmp: str | None = name  # None once renamed into place
        try:
            fd = os.open(name, _NEW_FLAGS, 0o600, dir_fd=shard_fd)
            with os.fdopen(fd, "wb") as f:
                f.write(data)
            os.replace(name, f"{key}.pkl", src_dir_fd=shard_fd, dst_dir_fd=shard_fd)
            tmp = None
            STATS["writes"] += 1
            return True
        except OSError:
            return False
        finally:
            if tmp is not None:
                with contextlib.suppress(OSError):
                    os.unlink(tmp, dir_fd=shard_fd)


_STALE = re.compile(r"\.tmp-([0-9]{1,10})-[0-9a-f]{16}\.pkl")


def _remove_stale(shard_fd: int) -> None:
    """Remove the temporary entries in the shard whose writer is gone (killed while writing: SIGKILL)."""
    try:
        names = os.listdir(shard_fd)
    except OSError:
        return
    for name in names:
        m = _STALE.fullmatch(name)
        if m and int(m[1]) != os.getpid() and process_state(int(m[1])) == "gone":
            with contextlib.suppress(OSError):
                os.unlink(name, dir_fd=shard_fd)


def cached(parts: Iterable[str | bytes] | Callable[[], Iterable[str | bytes]], build: Callable[[], T],
           valid: Callable[[object], bool] | None = None, *, key: str | None = None) -> T:
    """``build()``, or its result stored by an earlier process under the key of ``parts``.

    ``parts`` may be a callable returning them (called only when caching is on).
    ``valid(obj)`` may reject a loaded object (then it is rebuilt and the entry rewritten).
    ``key``: the entry's key, :func:`cache_key` of ``parts`` made by an earlier process and
    kept with a stored model (then ``parts`` is not called: making the key imports SymPy, and
    a loaded model's parts are SymPy expressions). With caching off, just ``build()``.
    """
    if not enabled() or backend() != "llvm":  # the interpreted backend's code is rebuilt on loading anyway
        return build()
    return load_or_build(key or cache_key(parts() if callable(parts) else parts), build, valid)


def load_or_build(key: str, build: Callable[[], T], valid: Callable[[object], bool] | None = None) -> T:
    """The object stored under ``key`` if ``valid`` accepts it (a hit), else ``build()``, stored
    under ``key`` unless SymEngine's interpreted backend made it (its code would be compiled
    again on loading). Counts hits and misses in :data:`STATS`."""
    obj = load(key)
    if obj is not None and (valid is None or valid(obj)):
        STATS["hits"] += 1
        return obj
    with _build_lock(key):
        obj = load(key)  # built by another process while this one waited for the lock
        if obj is not None and (valid is None or valid(obj)):
            STATS["hits"] += 1
            return obj
        STATS["misses"] += 1
        obj = build()
        if backend() == "llvm":
            store(key, obj)
    return obj


@contextlib.contextmanager
def _build_lock(key: str) -> Iterator[None]:
    """Held while this process builds the entry ``key``: another process that needs the same entry
    waits and then loads it, instead of building it too (two test workers, or two runs of a study,
    on a 2-core machine each took twice as long). An exclusive ``flock`` on ``KEY.lock`` beside the
    entry, holding its holder's process id (:func:`._lock.build_lock`: a stopped or dead holder and a
    wait beyond its timeout are told in one line and end the wait; a lock file that is not a regular
    file is an InputError). Without a trusted cache folder or ``fcntl``, no lock: each process builds."""
    try:
        import fcntl  # noqa: F401
    except ImportError:  # pragma: no cover - not on POSIX
        yield
        return

    with _shard(key, create=True) as found:
        shard_fd = None if found is None else os.dup(found[0])  # the shard's own descriptor closes here
    if shard_fd is None:
        yield
        return
    try:
        with build_lock(f"{key}.lock", shard_fd):
            yield
    finally:
        os.close(shard_fd)
