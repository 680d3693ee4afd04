"""The frames of an animation: a branch (a :class:`~mechcont.continuation.Branch`, its CSV table or plain rows
of full variable vectors) read into :class:`BranchFrames`, each row's values, label and stability.

Apart from :mod:`.animation`, which draws the frames (Matplotlib): this reads and checks data (a table's
columns, units and cells) and draws nothing; the drawing command and the tables use it without a figure.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .._io import read_csv_header
from ..errors import InputError

if TYPE_CHECKING:
    from ..continuation import Branch
    from ..equations import Model

__all__ = ["BranchFrames", "branch_frames"]


@dataclass(frozen=True)
class BranchFrames:
    """Points of a branch ready to _d.draw.

    Attributes
    ----------
    values:
        Array (N, n_names), rows are full variable vectors ordered like ``system.names``.
    stable:
        Per row ``True`` (stable), ``False`` (unstable) or ``None`` (not known).
    labels:
        Special-point label per row (``"LP"``, ``"BP"``, ... or ``""``).
    vary:
        The continuation parameter, printed first on every frame: the ``Branch``'s
        ``vary``, or for a table without it the one parameter that changes along the rows
        (``None`` when that is not unique).
    """

    values: np.ndarray
    stable: tuple[bool | None, ...]
    labels: tuple[str, ...]
    vary: str | None = None

    @property
    def numbered_labels(self) -> list[str]:
        """Labels numbered per kind in branch order (``LP1``, ``LP2``), as ``row`` accepts them."""
        return _numbered(self.labels)

    def row(self, spec: str | int) -> int:
        """Row index from an integer (0-based, negative from the end) or a label like ``"LP2"``.

        ``"LP2"`` is the second row labelled ``LP`` (``"LP"`` alone: the first); an
        :class:`InputError` names what is valid.
        """
        n = len(self.values)
        text = str(spec).strip()
        if len(text) > 32:  # no branch has rows or labels numbered beyond 32 digits
            raise InputError("point", f"no row '{text[:20]}...'; give a row number 0..{n - 1} or a label with its "
                                      "number (e.g. LP1)")
        try:
            i = int(text)
        except ValueError:
            text = text.rstrip("?")  # LP1? (an approximate fold) is LP1
            kind = text.rstrip("0123456789")
            count = int(text[len(kind):] or 1)
            hits = [j for j, lab in enumerate(self.labels) if lab.rstrip("?") == kind]
            if not kind or count < 1 or count > len(hits):
                have = sorted({lab.rstrip("?") for lab in self.labels if lab})
                raise InputError("point", f"no row '{text}'; give a row number 0..{n - 1} or a label "
                                          f"({', '.join(have) or 'this branch has none'}) with its number") from None
            return hits[count - 1]
        if not -n <= i < n:
            raise InputError("point", f"row {i} out of range; the branch has {n} rows (0..{n - 1})")
        return i % n


def _numbered(labels: Sequence[str]) -> list[str]:
    """``["LP", "", "LP?"]`` -> ``["LP1", "", "LP2?"]``: the names ``branch["LP2"]`` and ``--point`` use.

    A ``?`` (a special point only approximately located) keeps its place in the numbering.
    """
    seen: dict[str, int] = {}
    out = []
    for lab in labels:
        if lab:
            kind, mark = lab.rstrip("?"), "?" if lab.endswith("?") else ""
            seen[kind] = seen.get(kind, 0) + 1
            lab = f"{kind}{seen[kind]}{mark}"
        out.append(lab)
    return out


#: Words of the ``stability`` column: a fold (``LP`` row) is neutral, neither stable nor unstable.
_STABILITY_WORDS = {"stable": True, "unstable": False, "fold": None, "": None}


def _columns(path: Path, header: list[str], system: Model) -> dict[str, tuple[str, float]]:
    """``{name: (header, factor to SI)}`` from headers ``name [unit]`` (or bare names, as
    tables were written before units). A unit must be the model's; an angle may be in ``deg``."""
    out: dict[str, tuple[str, float]] = {}
    for h in header:
        name, unit = read_csv_header(h or "")
        factor = 1.0
        if unit and name in system.names:
            want = system.variable(name).unit
            if unit == "deg" and want == "rad":
                factor = math.pi / 180.0
            elif unit != want:
                raise InputError("branch", f"'{path}' column '{h}': the unit of {name} in model '{system.name}' is "
                                           f"'{want or 'none'}', not '{unit}'")
        out.setdefault(name, (h, factor))
    return out


def _read_csv(system: Model, path: Path) -> BranchFrames:
    """The rows of the branch table at ``path`` (units read from its headers, see :func:`_columns`)."""
    from ..continuation import read_table
    from ..continuation.branch_rows import refuse_cycles_table

    header, raw = read_table(path)  # strict: a regular file, bounded, each column once, full rows
    rows = [dict(zip(header, r)) for r in raw]
    if not rows:
        raise InputError("branch", f"'{path}' has no rows")
    refuse_cycles_table([read_csv_header(h or "")[0] for h in header], path)
    cols = _columns(path, header, system)
    missing = [n for n in system.names if n not in cols]
    if missing:
        raise InputError("branch", f"'{path}' lacks the column(s) {', '.join(missing)} of model '{system.name}'")
    values = np.empty((len(rows), len(system.names)))
    for r, row in enumerate(rows):
        for c, name in enumerate(system.names):
            key, factor = cols[name]
            try:
                values[r, c] = float(row[key]) * factor
            except (TypeError, ValueError):
                raise InputError("branch", f"'{path}' line {r + 2}, column {key}: not a number: {row[key]!r}") from None
            if not math.isfinite(values[r, c]):
                raise InputError("branch", f"'{path}' line {r + 2}, column {key}: {row[key]!r} is not a finite number")

    def cell(row: Mapping[str, str], name: str) -> str:
        key = cols.get(name, (name, 1.0))[0]
        return (row.get(key) or "").strip()

    stable = []
    for r, row in enumerate(rows):
        word = cell(row, "stability").lower()
        if word not in _STABILITY_WORDS:
            raise InputError("branch", f"'{path}' line {r + 2}, column stability: {word!r} is not stable, unstable "
                                       "or fold")
        stable.append(_STABILITY_WORDS[word])
    for r, row in enumerate(rows):
        _check_extra_cells(path, r, cell(row, "s"), cell(row, "n_unstable"))
    labels = tuple(cell(row, "label") for row in rows)
    vary = cell(rows[0], "vary") or None  # written by Branch.to_csv
    if vary is not None and vary not in system.names:
        raise InputError("branch", f"'{path}' column vary: '{vary}' is not a variable of '{system.name}'")
    return BranchFrames(values, tuple(stable), labels, vary)


def _check_extra_cells(path: Path, r: int, s: str, n_unstable: str) -> None:
    """A branch table's ``s`` (arclength: a finite number) and ``n_unstable`` (a count of unstable
    directions, -1 for not evaluated) when present; InputError naming the row otherwise (the
    branch reader's own cell checks)."""
    from ..continuation import cell_count as _count
    from ..continuation import cell_number as _number

    if s and math.isnan(_number(path, r, "s", s)):
        raise InputError("branch", f"'{path}' row {r} (line {r + 2}), column s: {s!r} is not a finite number")
    if n_unstable:
        _count(path, r, n_unstable)


def _changing_parameter(system: Model, values: np.ndarray) -> str | None:
    """The only parameter whose column is not constant along ``values``, else ``None``."""
    changing = []
    for i, v in enumerate(system.variables):
        col = values[:, i]
        if v.kind == "parameter" and np.ptp(col) > 1e-12 * max(1.0, float(np.max(np.abs(col)))):
            changing.append(v.name)
    return changing[0] if len(changing) == 1 else None


def branch_frames(system: Model, source: BranchFrames | Branch | str | os.PathLike | np.ndarray | Sequence[Sequence[float]]
                  ) -> BranchFrames:
    """The rows of a branch to _d.draw, from any of the forms a branch comes in.

    Parameters
    ----------
    system:
        The model the branch belongs to.
    source:
        A :class:`BranchFrames`, a continuation ``Branch`` (``.values``, ``.labels``, ``.n_unstable`` with -1 for
        not evaluated), a path to a branch CSV (one column per variable name, optional
        ``stability`` with ``stable``/``unstable``/empty and ``label``; other columns such
        as ``s`` are ignored), or an array of rows ordered like ``system.names``.

    Returns
    -------
    BranchFrames
        With ``vary`` from the ``Branch``, or else the one parameter that changes along the rows.

    Raises
    ------
    InputError
        Unreadable file, missing columns, wrong row length, non-finite values.
    """
    if isinstance(source, BranchFrames):
        frames = source
    elif isinstance(source, (str, os.PathLike)):
        frames = _read_csv(system, Path(source))
    elif hasattr(source, "values") and not isinstance(source, np.ndarray):
        names = getattr(source, "names", None)
        if names is not None and tuple(names) != tuple(system.names):
            raise InputError("branch", f"its variables are not those of model '{system.name}'")
        values = np.asarray(source.values, dtype=float)
        nu = getattr(source, "n_unstable", None)
        stable = (None,) * len(values) if nu is None else tuple(None if k < 0 else bool(k == 0) for k in nu)
        labels = getattr(source, "labels", None)
        vary = getattr(source, "vary", None)
        frames = BranchFrames(values, stable, tuple(labels) if labels is not None else ("",) * len(values),
                              vary if vary in system.names else None)
    else:
        values = np.asarray(source, dtype=float)
        n = len(values) if values.ndim else 0
        frames = BranchFrames(values, (None,) * n, ("",) * n)
    v = frames.values
    if v.ndim != 2 or v.shape[1] != len(system.names):
        raise InputError("branch", f"rows must hold the {len(system.names)} variables of '{system.name}', "
                                   f"got shape {v.shape}")
    if len(v) == 0:
        raise InputError("branch", "the branch has no points")
    if not np.all(np.isfinite(v)):
        raise InputError("branch", f"row {int(np.where(~np.isfinite(v).all(axis=1))[0][0])} has a non-finite value")
    if len(frames.stable) != len(v) or len(frames.labels) != len(v):
        raise InputError("branch", "stability and labels must have one entry per row")
    if frames.vary is not None and frames.vary not in system.names:
        raise InputError("vary", f"'{frames.vary}' is not a variable of '{system.name}'")
    if frames.vary is None:
        frames = replace(frames, vary=_changing_parameter(system, v))
    return frames
