"""Writing files so that a failure leaves nothing half-written behind.

:func:`check_output_path` (and :func:`check_output_folder`) check, before any work starts,
that an output can be written where the user asked; :func:`atomic_write` then writes it to a
temporary file beside the target and moves it into place, with the permissions of an
ordinary new file (``0o666`` less the umask), removing the temporary file on any failure,
including an interrupt or (through the CLI's SIGTERM and SIGHUP handlers) termination. A
temporary file is named ``.STEM.mechcont-PID-XXXXXXXX.SUFFIX`` after the process writing it; one
left by a process killed outright (SIGKILL: no handler runs) is removed by the next
:func:`atomic_write` into the same folder once that process is gone (:func:`remove_stale_temporaries`).
:func:`read_csv_header` reads a table's column header (``name [unit]``) back.
"""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import overload

from ._signals import process_state, raise_pending
from .errors import InputError

__all__ = ["atomic_write", "check_output_path", "check_output_folder", "current_umask", "read_csv_header",
           "remove_stale_temporaries", "TEMPORARY"]

#: The name of :func:`atomic_write`'s temporary files: ``.STEM.mechcont-PID-XXXXXXXX.SUFFIX`` (mkstemp's 8 characters).
TEMPORARY = re.compile(r"\..*\.mechcont-(?P<pid>[0-9]{1,10})-[a-z0-9_]{8}(\.[^/]*)?")
_CLEANED: set[str] = set()


def current_umask() -> int:
    """The process's file-creation mask (read without changing it where the OS allows)."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)  # elsewhere: read it by setting it, then restore it at once
    os.umask(mask)
    return mask


def _folder_problem(folder: Path) -> str | None:
    """Why files cannot be created in ``folder`` (None when they can)."""
    if not folder.exists():
        return f"folder '{folder}' does not exist"
    if not folder.is_dir():
        return f"'{folder}' is a file, not a folder"
    if not os.access(folder, os.W_OK | os.X_OK):
        return f"folder '{folder}' is not writable"
    return None


@overload
def check_output_path(path: str | os.PathLike, option: str, suffixes: Sequence[str] | None = None) -> Path: ...
@overload
def check_output_path(path: None, option: str, suffixes: Sequence[str] | None = None) -> None: ...
@overload
def check_output_path(path: str | os.PathLike | None, option: str,
                      suffixes: Sequence[str] | None = None) -> Path | None: ...
def check_output_path(path: str | os.PathLike | None, option: str,
                      suffixes: Sequence[str] | None = None) -> Path | None:
    """Check that the output file ``path`` (given by ``option``, e.g. ``"--out"``) can be written.

    Call it before any work starts: a run of minutes should not end in "cannot write".
    ``path`` must have one of ``suffixes`` (case-insensitive; any when None), must not be a
    folder, and its folder must exist, be a folder and be writable. Returns ``Path(path)``
    (None for None). Raises :class:`InputError` naming ``option``.
    """
    if path is None:
        return None
    p = Path(path)
    if suffixes is not None and p.suffix.lower() not in tuple(s.lower() for s in suffixes):
        raise InputError(option, f"unknown file type '{p.suffix or p.name}'; valid: {', '.join(suffixes)}")
    if p.is_dir():
        raise InputError(option, f"'{p}' is a folder; give a file name in it (e.g. {p / ('out' + (suffixes or [''])[0])})")
    problem = _folder_problem(p.parent)
    if problem is not None:
        raise InputError(option, problem)
    return p


def check_output_folder(path: str | os.PathLike, option: str) -> Path:
    """Check that the output folder ``path`` exists and is writable, or can be created
    (its nearest existing ancestor is a writable folder). Raises :class:`InputError`."""
    p = Path(path)
    if p.exists():
        if not p.is_dir():
            raise InputError(option, f"'{p}' exists and is not a folder")
        if not os.access(p, os.W_OK | os.X_OK):
            raise InputError(option, f"folder '{p}' is not writable")
        return p
    ancestor = p.absolute().parent
    while not ancestor.exists() and ancestor != ancestor.parent:
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise InputError(option, f"cannot create folder '{p}': '{ancestor}' is a file, not a folder")
    if not os.access(ancestor, os.W_OK | os.X_OK):
        raise InputError(option, f"cannot create folder '{p}': folder '{ancestor}' is not writable")
    return p


def atomic_write(path: str | os.PathLike, write: Callable[[str], object]) -> Path:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then move it into place.

    The file gets the permissions of a newly created file (``0o666`` less the umask), not
    the private ``0o600`` of a temporary file. Raises :class:`InputError` if the folder
    does not exist or cannot be written; on any failure (an exception, ``KeyboardInterrupt``,
    ``SystemExit``) the temporary file is removed and the exception propagates. Returns the
    final path.
    """
    path = Path(path)
    problem = _folder_problem(path.parent)
    if problem is not None:
        raise InputError(str(path), problem)
    if path.is_dir():
        raise InputError(str(path), "is a folder, not a file")
    import tempfile  # here: a command that writes nothing does not import it (with shutil, 2-3 ms)

    if str(path.parent) not in _CLEANED:
        _CLEANED.add(str(path.parent))
        remove_stale_temporaries(path.parent)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.mechcont-{os.getpid()}-", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    try:
        write(tmp)
        raise_pending()  # a signal a library swallowed while writing still stops the run here
        os.chmod(tmp, 0o666 & ~current_umask())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def remove_stale_temporaries(folder: str | os.PathLike) -> list[str]:
    """Remove the temporary files of :func:`atomic_write` in ``folder`` whose writer is gone (killed
    with SIGKILL, or the machine stopped): regular files of this user named :data:`TEMPORARY` whose
    process id is no running process. Returns the names removed; never raises."""
    removed: list[str] = []
    try:
        entries = list(os.scandir(os.fspath(folder)))
    except OSError:
        return removed
    for e in entries:
        m = TEMPORARY.fullmatch(e.name)
        if not m or int(m["pid"]) == os.getpid() or process_state(int(m["pid"])) != "gone":
            continue
        try:
            st = e.stat(follow_symlinks=False)
            if stat.S_ISREG(st.st_mode) and st.st_uid == os.geteuid():
                os.unlink(e.path)
                removed.append(e.name)
        except (OSError, AttributeError):
            continue
    return removed


def read_csv_header(header: str) -> tuple[str, str]:
    """``"F [N]"`` -> ``("F", "N")``; ``"F"`` (a table written before units) -> ``("F", "")``."""
    text = header.strip()
    if text.endswith("]") and " [" in text:
        name, _, unit = text[:-1].rpartition(" [")
        return name.strip(), unit.strip()
    return text, ""
