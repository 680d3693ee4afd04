"""Branch and sweep tables read strictly (:func:`read_table`): only a regular file, bounded in bytes, columns
and rows, each column named once; and their cells as numbers (:func:`cell_number`, :func:`cell_count`).

Apart from :mod:`._branch` (the :class:`~._branch.Branch` result and its writers): the readers of the
tables every command takes back (``--point``, ``--branch``, ``animate``, ``draw``, ``explore``) and their limits.
"""

from __future__ import annotations

import os

import numpy as np

from .._io import read_csv_header
from ..errors import InputError

__all__ = ["MAX_TABLE_BYTES", "MAX_TABLE_COLUMNS", "MAX_TABLE_ROWS", "cell_count", "cell_number", "read_branch_table",
           "read_table", "unit_header"]


def cell_number(path: str | os.PathLike[str], row: int, column: str, text: str) -> float:
    """A cell as a float: finite, or ``nan`` (an analysis's column with no value at that row: a downlock
    table's unlock load where none was found; :func:`check_branch_table` refuses it in the model's
    variables); :class:`InputError` naming the file, row and column otherwise."""
    try:
        v = float(text)
    except (TypeError, ValueError):
        raise InputError("branch", f"'{path}' row {row} (line {row + 2}), column {column}: not a number: "
                                   f"{text!r}") from None
    if np.isinf(v):
        raise InputError("branch", f"'{path}' row {row} (line {row + 2}), column {column}: {text!r} is not a "
                                   "finite number")
    return v


def cell_count(path: str | os.PathLike[str], row: int, text: str) -> int:
    """The ``n_unstable`` cell: an integer from -1 up; :class:`InputError` naming the row otherwise."""
    try:
        n = int(text)
    except ValueError:
        n = -2
    if n < -1:
        raise InputError("branch", f"'{path}' row {row} (line {row + 2}), column n_unstable: {text!r} is not a "
                                   "count (an integer >= -1)")
    return n


def unit_header(name: str, unit: str) -> str:
    """A CSV column header: ``"F [N]"``, or ``"label"`` for a column without a unit."""
    return f"{name} [{unit}]" if unit else name


#: Limits of a branch table, decided before reading it (a table mechcont writes is far below them).
MAX_TABLE_BYTES = 64 * 2**20
MAX_TABLE_COLUMNS = 4096
MAX_TABLE_ROWS = 200_000


def read_table(path: str | os.PathLike[str]) -> tuple[list[str], list[list[str]]]:
    """The header and the rows (lists of cell texts) of a CSV branch or sweep table, read strictly.

    Only a regular file is opened (not a FIFO, a device such as ``/dev/zero`` or a folder); its
    size (at most :data:`MAX_TABLE_BYTES`), its header's columns (at most
    :data:`MAX_TABLE_COLUMNS`, each named once) and its rows (at most :data:`MAX_TABLE_ROWS`, each
    with as many cells as the header) are checked as it is read, so nothing unbounded is read.
    Raises :class:`InputError` (field ``branch``) in one line naming the file, the line and what
    would be valid.
    """
    import csv
    import stat

    try:
        st = os.stat(path)
    except OSError as exc:
        raise InputError("branch", f"cannot read '{path}': {exc.strerror or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        raise InputError("branch", f"'{path}' is not a regular file (a FIFO, device or folder); give a CSV table "
                                   "written by continue, folds, downlock or sweep")
    if st.st_size > MAX_TABLE_BYTES:
        raise InputError("branch", f"'{path}' has {st.st_size} bytes; a branch table may have at most "
                                   f"{MAX_TABLE_BYTES} bytes")
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):  # replaced between the stat and the open
                raise InputError("branch", f"'{path}' is not a regular file")
            text = fh.read(MAX_TABLE_BYTES + 1)
        if len(text) > MAX_TABLE_BYTES:
            raise InputError("branch", f"'{path}' has more than {MAX_TABLE_BYTES} bytes")
        first = text.split("\n", 1)[0]
        if first.count(",") >= MAX_TABLE_COLUMNS:
            raise InputError("branch", f"'{path}' line 1: more than {MAX_TABLE_COLUMNS} columns")
        reader = csv.reader(text.splitlines())
        header = next(reader, [])
        rows: list[list[str]] = []
        for line, row in enumerate(reader, start=2):
            if len(row) != len(header):
                raise InputError("branch", f"'{path}' line {line}: {len(row)} cells for the {len(header)} columns "
                                           "of the header")
            if len(rows) == MAX_TABLE_ROWS:
                raise InputError("branch", f"'{path}' has more than {MAX_TABLE_ROWS} rows")
            rows.append(row)
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InputError("branch", f"cannot read '{path}': {getattr(exc, 'strerror', None) or exc}") from None
    if not header:
        raise InputError("branch", f"'{path}' is empty; a branch table starts with a header line")
    names = [read_csv_header(h)[0] for h in header]
    repeated = list(dict.fromkeys(h for h, n in zip(header, names) if names.count(n) > 1))
    if repeated:
        raise InputError("branch", f"'{path}' line 1: the column(s) {', '.join(map(repr, repeated))} name a "
                                   "variable more than once; each column may appear once")
    return header, rows


def read_branch_table(path: str | os.PathLike[str]) -> tuple[list[dict[str, str]], dict[str, str]]:
    """Read a branch (or sweep) CSV strictly (:func:`read_table`): rows as ``{name: text}`` keyed by plain
    names, and ``{name: unit}``.

    Headers ``F [N]`` give name ``F`` and unit ``N``; tables written before units (bare
    names) read the same, with no units.
    """
    header, raw = read_table(path)
    pairs = [read_csv_header(h) for h in header]
    rows = [dict(zip((n for n, _ in pairs), row)) for row in raw]
    return rows, {n: u for n, u in pairs if u}
