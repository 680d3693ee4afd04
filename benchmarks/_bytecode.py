"""Bytecode for the timed processes, as on any machine that writes it.

Python writes a module's compiled bytecode (``__pycache__/*.pyc``) the first time it imports
it, unless ``PYTHONDONTWRITEBYTECODE`` is set (as on some CI machines and sandboxes). There,
an editable install never gets any, and every process compiles mechcont's modules again
(about 65 ms of a 0.25 s ``mechcont continue``), while an installed package (NumPy, AUTO's
own files, when they were compiled once) has them. The whole-process benchmarks compile
both sides first, so that they time what a user's second run costs.
"""

from __future__ import annotations

import compileall
import importlib.util
from pathlib import Path


def compile_sources(*folders: str | Path) -> None:
    """Write up-to-date bytecode for mechcont's package and for each of ``folders`` (quietly)."""
    spec = importlib.util.find_spec("mechcont")
    assert spec is not None and spec.submodule_search_locations
    for folder in [*spec.submodule_search_locations, *folders]:
        compileall.compile_dir(str(folder), quiet=1)
