"""Families of periodic orbits in the explorer (:mod:`.explore`): the table's amplitude and one period of each orbit.

A cycles table (``mechcont cycles --out``, or a :class:`~mechcont.continuation.CycleBranch`) holds per orbit
its parameter, period, the smallest and largest value of each state (``min_X``, ``max_X``), stability
and labels; the orbit itself comes from the :class:`CycleBranch` or from the orbit table written by
``mechcont cycles --orbits`` (:mod:`.cycle_orbits`). The page draws the family as its amplitude (max
and min of a state against the parameter) and, at a row, plays one period: the mechanism's poses,
or an ODE's phase portrait.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from ..continuation import Branch, CycleBranch
    from ..equations import EquationSystem

    #: explore's reader of a table's full vectors: ``(model, table, its name, values) -> rows`` (SI)
    FullRows = Callable[[EquationSystem, Branch, str, Mapping[str, float]], np.ndarray]

__all__ = ["CycleTable", "cycle_table", "is_cycles", "has_orbits", "PAGE_FRAMES", "ORBIT_POINTS"]

#: Instants of one period embedded per orbit in the page: poses of a mechanism ...
PAGE_FRAMES = 24
#: ... and points of an ODE's phase portrait (a few numbers each).
ORBIT_POINTS = 96


@dataclass
class CycleTable:
    """A family of cycles for the page: ``branch`` its table as a :class:`Branch` (``vary`` its parameter),
    ``states`` the states with ``min_X``/``max_X`` columns, ``orbit(row, n)`` the full vectors of one period of
    the orbit of a table row at ``n`` instants equally spaced in time (fewer when the orbit table has fewer; SI;
    None without orbits)."""

    branch: Branch
    name: str
    states: list[str]
    orbit: Callable[[int, int], np.ndarray] | None


def is_cycles(branch: Branch) -> bool:
    """True when ``branch`` (a :class:`Branch` read from a CSV) is a cycles table: a ``period`` column and a
    ``min_X``/``max_X`` pair."""
    from ..continuation.branch_rows import is_cycles_table

    return is_cycles_table(branch.names)


def has_orbits(source: object) -> bool:
    """True for a family of cycles that carries its orbits (a :class:`~mechcont.continuation.CycleBranch`)."""
    return hasattr(source, "orbits") and hasattr(source, "full_vectors")


def _frames(n: int, k: int) -> np.ndarray:
    """Indices of ``k`` instants equally spaced in time among ``n`` closed samples (the last = the first; fewer
    when ``n`` is short)."""
    return np.unique(np.round(np.linspace(0, n - 1, min(k, n - 1) + 1)).astype(int))[:-1]


def _from_family(family: CycleBranch, system: EquationSystem | None, index: int) -> CycleTable:
    """The page's table of a computed family of cycles (its orbits from the family itself, given the model)."""
    from .._status import Status
    from ..continuation import Branch, SpecialPoint

    cols, units = family.columns(), family.units()
    names = [n for n in cols if n != "floquet_max" or np.all(np.isfinite(cols[n]))]
    values = np.column_stack([cols[n] for n in names])
    special = [SpecialPoint(lab, i, values[i].copy(), tuple(names),
                            status=Status.APPROXIMATE if i in family.approximate else Status.LOCATED)
               for i, lab in enumerate(family.labels) if lab]
    branch = Branch(names, values, family.s, family.n_unstable, list(family.labels), special, family.vary, (),
                    model=family.model, units={n: units[n] for n in names})
    orbit = None
    if system is not None:
        from ..equations import Model, dynamics_of

        if not isinstance(system, Model):   # an equation system alone: no rates, no mechanics
            raise InputError(system.name, "has neither rates (an ODE file) nor mechanics (a mechanism): no dynamics")
        dyn = dynamics_of(system)
        if tuple(family.names) != tuple(system.names):
            raise InputError("branch", f"the cycles of '{family.model}' are not of model '{system.name}'")

        def orbit(row: int, n: int) -> np.ndarray:
            return family.full_vectors(dyn, row, n)[1][:-1]

    return CycleTable(branch, f"cycles {index + 1}", list(family.state_names), orbit)


def _from_csv(branch: Branch, name: str, orbits: str | os.PathLike | None, system: EquationSystem | None,
              values: Mapping[str, float], full_rows: FullRows) -> CycleTable:
    """A cycles table read as ``branch``; ``orbits`` its orbit table (or None); ``full_rows`` explore's
    reader of a table's full vectors."""
    from .cycle_orbits import read_orbits

    # floquet_max has no value at a Hopf row (no non-trivial multiplier at zero amplitude): the page leaves it out
    keep = [n for n in branch.names if n != "floquet_max" or np.all(np.isfinite(branch.column(n)))]
    branch = branch.replace(names=keep, values=branch.values[:, [branch.names.index(n) for n in keep]],
                            vary=branch.vary or branch.names[0])
    states = [n[4:] for n in branch.names if n.startswith("max_") and "min_" + n[4:] in branch.names]
    orbit = None
    if orbits is not None and system is not None:
        table, groups = read_orbits(orbits)
        missing = [r for r in range(len(branch)) if r not in groups]
        if missing:
            raise InputError("orbits", f"'{orbits}' has no orbit for row {missing[0]} of '{name}' (the orbit "
                                       "table of another cycles table?)")
        X = full_rows(system, table, Path(orbits).name, values)

        def orbit(row: int, n: int) -> np.ndarray:
            at = groups[row]
            return X[at[_frames(len(at), n)]]

    return CycleTable(branch, name, states, orbit)


def cycle_table(source: CycleBranch | Branch | str | os.PathLike, index: int, orbits: str | os.PathLike | None,
                system: EquationSystem | None, values: Mapping[str, float], full_rows: FullRows) -> CycleTable | None:
    """``source`` (a :class:`CycleBranch`, or a CSV path or :class:`Branch` that is a cycles table) for the page,
    with ``orbits`` (an orbit table path, or None); None when ``source`` is not a family of cycles."""
    from ..continuation import Branch, CycleBranch

    if isinstance(source, CycleBranch):
        return _from_family(source, system, index)
    if isinstance(source, (str, os.PathLike)):
        branch, name = Branch.read_csv(source), Path(source).name
    elif isinstance(source, Branch):
        branch, name = source, source.model or f"branch {index + 1}"
    else:
        return None
    if not is_cycles(branch):
        if orbits is not None:
            raise InputError("orbits", f"'{orbits}' is given for '{name}', which is not a cycles table")
        return None
    return _from_csv(branch, name, orbits, system, values, full_rows)
