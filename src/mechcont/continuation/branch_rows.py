"""A row of a branch table written by a run (``continue``/``folds``/``downlock`` ``--out``) read back as the point an
analysis starts from: the table checked against the model, the row found, the unknowns solved for there."""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ..equations import Model
from ..errors import InputError
from ._branch import Branch, check_branch_table
from ._move import check_point
from ._problem import choose_unknowns
from ._special_point import SpecialPoint

__all__ = ["BranchRow", "read_branch_row", "HOPF_ROW_TOL", "is_cycles_table", "refuse_cycles_table"]

#: Largest change of any variable (relative to its scale or value) from a table's ``HB`` row to the Hopf point
#: polished from it for the row to be that point (:meth:`BranchRow.hopf`): a row written to 10 digits moves ~1e-10.
HOPF_ROW_TOL = 1e-6


@dataclass(frozen=True)
class BranchRow:
    """A row of a branch table of a model (:func:`read_branch_row`).

    ``branch`` is the table, ``point`` its row ``row`` (a label such as ``"LP1"`` or a 0-based number) with the full
    vector ``point.x`` (SI, rad) and its label, ``vary`` the branch's continuation parameter and ``unknowns`` the
    states (and freed parameters) solved for on the branch besides ``vary``; ``name`` is ``"PATH:ROW"``."""

    branch: Branch
    point: SpecialPoint
    vary: str
    unknowns: tuple[str, ...]
    name: str

    def check(self, system: Model, label: str | None = None) -> None:
        """Check that the row is the point it claims to be (``label``, default its own: a fold, a Hopf point, a
        branch point, or any solution), at its own values (:func:`~mechcont.continuation.check_point`);
        :class:`InputError` otherwise."""
        check_point(system, self.point.x, label=self.point.label if label is None else label, vary=self.vary,
                    states=self.unknowns, name=self.name)

    def hopf(self, system: Model, *, hold: Iterable[str] = (), free: Iterable[str] = ()) -> SpecialPoint:
        """The Hopf point this ``HB`` row is, polished to machine precision (:func:`~mechcont.continuation.locate_hopf`,
        ``hold`` and ``free`` as on the branch); :class:`InputError` (field ``point``) when the polished point lies
        further than :data:`HOPF_ROW_TOL` from the row (relative to each variable's scale or value): the row is not
        a Hopf point, and the error says where the nearest one is."""
        from ._hopf_api import locate_hopf

        x = np.asarray(self.point.x, dtype=float)
        hb = locate_hopf(system, x, self.vary, hold=hold, free=free)
        moved = np.max(np.abs(hb.x - x) / np.maximum(system.scales(), np.abs(x)))
        if moved > HOPF_ROW_TOL:
            raise InputError("point", f"{self.name} is not a Hopf point: the nearest one lies at {self.vary} = "
                                      f"{hb[self.vary]:.10g}")
        return hb


def is_cycles_table(names: Iterable[str]) -> bool:
    """True when the column names (without their units) are a table of periodic orbits (``mechcont cycles --out``,
    :meth:`CycleBranch.columns`): a ``period`` column and a ``min_X``/``max_X`` pair."""
    given = set(names)
    return "period" in given and any(n.startswith("max_") and "min_" + n[4:] in given for n in given)


def refuse_cycles_table(names: Iterable[str], path: str | os.PathLike[str], field: str = "branch") -> None:
    """:class:`InputError` (``field``) in one line when the table at ``path``, of columns ``names`` (without units),
    is a table of periodic orbits where a branch of equilibria is wanted: its rows hold each orbit's period and
    amplitudes, not a pose; the error says so and how to see an orbit (docs/reference.md, explore)."""
    if is_cycles_table(names):
        raise InputError(field, f"'{path}' is a table of periodic orbits (mechcont cycles --out), not a branch of "
                                "equilibria: its rows are no poses; to see an orbit, give it to mechcont explore "
                                f"MODEL --branch {path} --orbits ORBITS.csv (the orbits written by cycles --orbits)")


def read_branch_row(system: Model, path: str | os.PathLike[str], row: str, *, hold: Iterable[str] = (),
                    free: Iterable[str] = ()) -> BranchRow:
    """The row ``row`` of the branch table at ``path``: the table checked against ``system``
    (:func:`~mechcont.continuation.check_branch_table`: its columns, units and values), its ``vary`` column naming a
    variable of ``system``, the unknowns chosen as the run chose them (``hold`` states held, ``free`` parameters
    solved for). Raises :class:`InputError` (field ``point`` for the vary column, ``branch`` for the table, a table
    of periodic orbits among them (:func:`refuse_cycles_table`); the row's own errors from :meth:`Branch.point`)."""
    branch = Branch.read_csv(path, model=system.name)
    refuse_cycles_table(branch.names, path)
    check_branch_table(branch, system, path)
    if not branch.vary:
        raise InputError("point", f"'{path}' has no vary column naming its continuation parameter")
    if branch.vary not in system.names:
        raise InputError("point", f"'{path}': its vary column names '{branch.vary}', not a variable of model "
                                  f"'{system.name}'")
    point = branch.point(row)
    unknowns = choose_unknowns(system, hold=hold, free=free, exclude=[branch.vary])
    return BranchRow(branch, point, branch.vary, tuple(unknowns), f"{path}:{row}")
