"""One strict branch-table reader (issue 33, item 1): a regular file, bounded before it is read, finite cells,
the model's columns and units, rows in order, and the row re-solved and checked to be the point it claims.

Every case is a one-line error (exit 2) naming the file and the row or column; the tables are those
`continue` writes for the brace-lock fixture (tests/data/brace_lock.toml), edited as a user or an
attacker would."""

import csv
import os

import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.continuation import _table as table_module

FILE = __file__.rsplit("/", 1)[0] + "/data/brace_lock.toml"


@pytest.fixture(scope="module")
def table(tmp_path_factory):
    from mechcont.models import load_model

    model = load_model(FILE)
    x0 = find_equilibrium(model, hold={"brace": -0.1}, free=["F"])
    br = continuation(model, x0, "F", options=ContinuationOptions(bounds={"brace": (-1, 1), "F": (-9000, 9000)}))
    path = tmp_path_factory.mktemp("reader") / "b.csv"
    br.to_csv(path)
    rows = list(csv.reader(open(path, newline="")))
    name = next(n for n, p in zip(br.point_names(), br.special_points) if p.label == "LP" and p["brace"] < 0)
    row = 1 + next(p.index for n, p in zip(br.point_names(), br.special_points) if n == name)
    return path, rows, name, row


def _edited(tmp_path, rows, edit):
    rows = [list(r) for r in rows]
    edit(rows)
    path = tmp_path / "edited.csv"
    with open(path, "w", newline="") as f:
        csv.writer(f).writerows(rows)
    return path


def _sens(path, name, *extra):
    return make_runner()("sensitivity", FILE, "--point", f"{path}:{name}", "--params", "k", *extra)


def _cell(rows, row, header, value):
    def edit(rs):
        rs[row][rs[0].index(header)] = value
    return edit


def test_the_table_as_written_is_read(table):
    path, _, name, _ = table
    res = _sens(path, name)
    assert res.exit_code == 0, res.output


@pytest.mark.parametrize("value, words", [
    ("5e-324", ["is not"]),                      # today: polished onto another singular point, called LP
    ("nan", ["column theta_arm", "finite"]),     # today: SVD did not converge (a traceback)
    ("1e308", ["is not"]),
    ("inf", ["column theta_arm", "finite"]),
])
def test_corrupted_cell_in_the_point_row(table, tmp_path, value, words):
    path, rows, name, row = table
    edited = _edited(tmp_path, rows, _cell(rows, row, "theta_arm [rad]", value))
    one_line_error(_sens(edited, name), *words)


def test_corrupted_fold_row_is_not_called_a_fold(table, tmp_path):
    # every equation still holds (the row moved along the branch to an ordinary point), but it is no fold
    path, rows, name, row = table
    def edit(rs):
        keep = {c: rs[row][rs[0].index(c)] for c in ("s", "label", "stability")}
        rs[row] = list(rs[row - 3])
        for c, v in keep.items():
            rs[row][rs[0].index(c)] = v
    one_line_error(_sens(_edited(tmp_path, rows, edit), name), "is not a fold")


def test_not_a_regular_file(table, tmp_path):
    _, _, name, _ = table
    one_line_error(_sens("/dev/zero", name), "not a regular file")  # today: MemoryError
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    one_line_error(_sens(fifo, name), "not a regular file")  # today: blocks forever
    one_line_error(_sens(tmp_path, name), "not a regular file")


def test_limits_decided_before_reading(table, tmp_path, monkeypatch):
    path, rows, name, _ = table
    wide = tmp_path / "wide.csv"
    wide.write_text(",".join(f"c{i}" for i in range(100_000)) + "\n")
    one_line_error(_sens(wide, name), "line 1", "columns")
    monkeypatch.setattr(table_module, "MAX_TABLE_BYTES", 1000)
    one_line_error(_sens(path, name), "bytes")
    monkeypatch.setattr(table_module, "MAX_TABLE_BYTES", 64 * 2**20)
    monkeypatch.setattr(table_module, "MAX_TABLE_ROWS", 5)
    one_line_error(_sens(path, name), "rows")


@pytest.mark.parametrize("edit, words", [
    (lambda rs: rs[0].__setitem__(rs[0].index("x_arm [m]"), "y_arm [m]"), ["y_arm", "more than once"]),
    (lambda rs: rs[0].__setitem__(rs[0].index("k [N/m]"), "k [N/mm]"), ["k [N/mm]", "N/m"]),
    (lambda rs: rs[0].__setitem__(rs[0].index("d [m]"), "dd [m]"), ["dd", "not variables"]),
    (lambda rs: [r.pop(rs[0].index("ux")) for r in rs[::-1]], ["lacks", "ux"]),
    (lambda rs: rs[3].pop(), ["line 4", "cells"]),
    (lambda rs: rs.__setitem__(slice(2, 4), [rs[3], rs[2]]), ["row 2", "arclength order"]),
])
def test_header_and_rows(table, tmp_path, edit, words):
    _, rows, name, _ = table
    one_line_error(_sens(_edited(tmp_path, rows, edit), name), *words)


def test_animate_reads_with_the_same_reader(table, tmp_path):
    _, _, name, _ = table
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    one_line_error(make_runner()("animate", FILE, "--branch", fifo, "--out", tmp_path / "a.gif"),
                   "not a regular file")
