"""One computation per test session, shared by the pytest-xdist workers (the ``shared`` fixture of conftest.py).

A long computation that several test files check (a paper section, an optimum) ran once in each worker process
that needed it. :meth:`SessionStore.get` computes it in the first process to ask, under a lock on a file in the
session's temporary folder (common to the workers), and pickles the result there; a process asking later reads
it, one asking meanwhile waits for it (no longer than computing it itself would take). A computation that raises
stores nothing: the next process to ask computes it again and fails in its own test.
"""

from __future__ import annotations

import contextlib
import os
import pickle
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

try:
    import fcntl
except ImportError:  # not POSIX: no lock, a process that finds no result computes it itself
    fcntl = None  # type: ignore[assignment]


class SessionStore:
    """Results computed once per test session in ``root`` (a folder every worker of the session sees)."""

    def __init__(self, root: Path):
        self.root = Path(root)
        self._here: dict[str, Any] = {}
        self._computed: set[str] = set()

    def computed_here(self, key: str) -> bool:
        """Whether this process computed the result under ``key`` (not read it from another's): a test may then
        compare it with what it computes itself exactly, as the same code on the same inputs in one process."""
        return key in self._computed

    def get(self, key: str, compute: Callable[[], Any]) -> Any:
        """``compute()`` (picklable) as first computed in this session under ``key`` (a file-name-safe word)."""
        if key in self._here:
            return self._here[key]
        path = self.root / f"shared-{key}.pickle"
        with self._locked(path.with_suffix(".lock")):
            if path.exists():
                value = pickle.loads(path.read_bytes())
            else:
                value = compute()
                self._computed.add(key)
                partial = path.with_suffix(f".{os.getpid()}.part")
                partial.write_bytes(pickle.dumps(value))
                partial.replace(path)
        self._here[key] = value
        return value

    @staticmethod
    @contextlib.contextmanager
    def _locked(lock: Path) -> Iterator[None]:
        if fcntl is None:
            yield
            return
        with open(lock, "a") as fh:
            fcntl.flock(fh, fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(fh, fcntl.LOCK_UN)
