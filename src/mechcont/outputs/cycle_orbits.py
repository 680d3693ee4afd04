"""The orbits of a family of cycles as a table: one period of each orbit as the model's full vectors.

``mechcont cycles --orbits FILE.csv`` writes it beside the family's table (which holds per orbit only
its parameter, period, extremes and stability): columns ``row`` (the orbit's row in the cycles table),
``t [s]`` (time from the orbit's phase origin, 0 .. period) and every variable of the model with its
unit, ``samples + 1`` rows per orbit (the first instant again at the end). The explorer reads it to
play one period of the mechanism's motion, or to draw an ODE's phase portrait.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .._io import atomic_write
from ..errors import InputError

if TYPE_CHECKING:
    from ..continuation import Branch, CycleBranch
    from ..equations import Model

__all__ = ["write_orbits", "read_orbits", "ORBIT_SAMPLES"]

#: Instants per period written (the first again at the end makes one more).
ORBIT_SAMPLES = 48


def write_orbits(cycles: CycleBranch, system: Model, path: str | os.PathLike, samples: int = ORBIT_SAMPLES) -> Path:
    """Write one period of every orbit of ``cycles`` (a :class:`~mechcont.continuation.CycleBranch` of
    ``system``) at ``samples`` + 1 equally spaced instants as full vectors (SI, radians); returns the path."""
    import csv

    from ..continuation import unit_header
    from ..equations import dynamics_of

    dyn = dynamics_of(system)
    units = {v.name: v.unit for v in system.variables}
    header = ["row", "t [s]"] + [unit_header(n, units[n]) for n in system.names]
    blocks = [(i, *cycles.full_vectors(dyn, i, samples)) for i in range(len(cycles))]

    def write(tmp: str) -> None:
        with open(tmp, "w", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(header)
            for i, t, X in blocks:
                for tk, x in zip(t, X):
                    w.writerow([i, repr(float(tk))] + [repr(float(v)) for v in x])

    return atomic_write(path, write)


def read_orbits(path: str | os.PathLike) -> tuple[Branch, dict[int, np.ndarray]]:
    """The orbit table at ``path`` as a :class:`~mechcont.continuation.Branch` (columns ``row``, ``t`` and the
    model's variables) and ``{cycles row: table rows}``; one-line :class:`InputError` (field ``orbits``) when it
    is not an orbit table."""
    from ..continuation import Branch

    table = Branch.read_csv(path)
    if "row" not in table.names or "t" not in table.names:
        raise InputError("orbits", f"'{path}' is not an orbit table (mechcont cycles --orbits): it has no row "
                                   "and t [s] columns")
    rows = table.column("row")
    if not np.all(rows == np.round(rows)) or np.any(rows < 0):
        raise InputError("orbits", f"'{path}': the row column must hold the cycles table's row numbers (0, 1, ...)")
    groups: dict[int, np.ndarray] = {}
    for r in np.unique(rows).astype(int):
        groups[int(r)] = np.flatnonzero(rows == r)
    return table, groups
