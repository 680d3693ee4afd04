"""The build lock of the compiled-code cache: one process builds an entry, the others wait for it,
but none can wait forever.

The lock is an exclusive ``flock`` on ``KEY.lock`` beside the entry; its holder writes its process
id into the file. A process that finds the lock taken polls it, and stops waiting (and builds the
entry itself: the cache's atomic writes make two builds harmless, only slower) when

* the holder is stopped (Ctrl-Z, SIGSTOP: state ``T`` in ``/proc/PID/stat``) or gone (a lock
  inherited by a child of a dead process): seen on two polls :data:`STALE_GRACE` seconds apart,
  so a holder that has just taken the lock and not yet written its id is not mistaken for one;
* it has waited :data:`TIMEOUT` seconds (``MECHCONT_LOCK_TIMEOUT``, seconds, overrides it).

Either way it says so in one line on stderr. While it waits, a line on a terminal says what it
waits for, every :data:`NOTICE` seconds (``MECHCONT_LOCK_NOTICE``); nothing otherwise. The lock
file must be a regular file: anything else there (a FIFO, a device) is an :class:`InputError`
naming it, and it is opened without blocking and without following a link.
"""

from __future__ import annotations

import contextlib
import os
import stat
import sys
import time
from collections.abc import Iterator
from types import ModuleType

from .._signals import process_state as holder_state
from ..errors import InputError

__all__ = ["build_lock", "holder_state", "TIMEOUT", "NOTICE", "STALE_GRACE"]

#: Seconds a process waits for another's build before it builds the entry itself.
TIMEOUT = 600.0
#: Seconds between the waiting lines on a terminal (the first after this long).
NOTICE = 5.0
#: Seconds a holder must stay stopped or gone before the lock is called stale.
STALE_GRACE = 0.5
_POLL = 0.05
_FLAGS = (os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
          | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0))


def _seconds(env: str, default: float) -> float:
    """A positive finite number of seconds from the environment variable ``env``, else ``default``."""
    try:
        value = float(os.environ.get(env, ""))
    except ValueError:
        return default
    return value if 0 < value < 1e9 else default


def _holder(fd: int) -> int | None:
    """The process id written in the lock file, or None."""
    try:
        text = os.pread(fd, 32, 0).decode("ascii").strip()
    except (OSError, UnicodeDecodeError):
        return None
    return int(text) if text.isdigit() and 0 < int(text) < 2**31 else None


def _open(path: str, dir_fd: int | None) -> int:
    """The lock file, opened without blocking; InputError if it is not a regular file."""
    try:
        fd = os.open(path, _FLAGS, 0o600, dir_fd=dir_fd)
    except OSError as exc:
        try:
            st = os.stat(path, dir_fd=dir_fd, follow_symlinks=False)
        except OSError:
            raise exc from None
        if not stat.S_ISREG(st.st_mode):
            raise InputError(path, _not_regular(st.st_mode)) from None
        raise
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        os.close(fd)
        raise InputError(path, _not_regular(st.st_mode))
    return fd


def _not_regular(mode: int) -> str:
    kind = "a FIFO" if stat.S_ISFIFO(mode) else "a link" if stat.S_ISLNK(mode) else "not a regular file"
    return (f"the build lock of the compiled-code cache is {kind}; delete it (a regular file is made again), "
            "or set MECHCONT_CACHE_DIR to a private folder of your own")


@contextlib.contextmanager
def build_lock(name: str, dir_fd: int | None = None, what: str = "this model's compiled equations") -> Iterator[bool]:
    """Hold the build lock ``name`` (in the folder ``dir_fd``) for the ``with`` block; yields True when
    held, False when this process stopped waiting (a stopped or gone holder, the timeout) and builds
    without it. Raises InputError if the lock file is not a regular file; any other failure to lock
    (a file system without ``flock``) yields False at once."""
    import fcntl

    try:
        fd = _open(name, dir_fd)
    except OSError:
        yield False
        return
    where = name if dir_fd is None else f"{_folder(dir_fd)}/{name}"
    try:
        held = _wait(fd, where, what, fcntl)
        if held:
            with contextlib.suppress(OSError):
                os.ftruncate(fd, 0)
                os.pwrite(fd, f"{os.getpid()}\n".encode("ascii"), 0)
        try:
            yield held
        finally:
            if held:
                with contextlib.suppress(OSError):
                    os.ftruncate(fd, 0)  # no id left behind for the next waiter to misread
    finally:
        os.close(fd)  # releases the lock


def _folder(dir_fd: int) -> str:
    try:
        return os.readlink(f"/proc/self/fd/{dir_fd}")
    except OSError:
        return "the cache folder"


def _wait(fd: int, where: str, what: str, fcntl: ModuleType) -> bool:
    """Take the lock (True), or give up on a stale holder or the timeout with one line on stderr (False)."""
    timeout, notice = _seconds("MECHCONT_LOCK_TIMEOUT", TIMEOUT), _seconds("MECHCONT_LOCK_NOTICE", NOTICE)
    grace = min(STALE_GRACE, timeout / 4)
    tty = bool(getattr(sys.stderr, "isatty", None) and sys.stderr.isatty())
    t0 = time.monotonic()
    next_notice = t0 + notice
    suspect: tuple[int, str, float] | None = None  # (pid, state, since)
    while True:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except BlockingIOError:
            pass
        except OSError:
            return False
        now = time.monotonic()
        pid = _holder(fd)
        state = holder_state(pid) if pid is not None and pid != os.getpid() else None
        if state is None or pid is None:
            suspect = None
        elif suspect is None or suspect[:2] != (pid, state):
            suspect = (pid, state, now)
        elif now - suspect[2] >= grace:
            how = "is stopped (Ctrl-Z or SIGSTOP; `fg` or `kill -CONT` resumes it)" if state == "stopped" else \
                "has ended without releasing it"
            _say(f"process {pid}, which holds the build lock {where}, {how}: building {what} here instead")
            return False
        if now - t0 >= timeout:
            holder = f"process {pid}" if pid is not None else "another process"
            _say(f"waited {timeout:g} s for {holder} to build {what} (lock {where}): building it here instead "
                 "(MECHCONT_LOCK_TIMEOUT sets the wait, s)")
            return False
        if tty and now >= next_notice:
            holder = f"process {pid}" if pid is not None else "another process"
            _say(f"waiting for {holder} to build {what} (lock {where}), {now - t0:.0f} s so far")
            next_notice = now + notice
        time.sleep(_POLL)


def _say(line: str) -> None:
    with contextlib.suppress(OSError, ValueError):
        sys.stderr.write(f"mechcont: {line}\n")
        sys.stderr.flush()
