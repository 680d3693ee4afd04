"""A table of periodic orbits (``mechcont cycles --out``) given where a branch of equilibria is read: one line saying so.

A fresh user gave a cycles table to ``draw --point``: its rows hold each orbit's period and its states' min and max,
not a pose, and the answer was a raw ``lacks the column(s)`` listing fourteen of the model's variables. Every command
that reads a row (``--point``: draw, folds, sensitivity, cycles, optimize) or a branch of equilibria (``--branch``
of animate and sweep) now says it is a table of periodic orbits and how to see an orbit (explore with ``--orbits``,
docs/reference.md), exit status 2; explore, which draws such tables, still takes it.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.continuation.branch_rows import read_branch_row
from mechcont.errors import InputError
from mechcont.models import load_model

CASTER = Path(__file__).parent / "data" / "caster_tyre_saturating.toml"


@pytest.fixture(scope="module")
def run():
    return make_runner()


@pytest.fixture(scope="module")
def tables(tmp_path_factory, run):
    """A branch of equilibria of the caster with its Hopf point, and a few cycles born there (``cycles --out``)."""
    d = tmp_path_factory.mktemp("cyc")
    branch, cycles = d / "b.csv", d / "c.csv"
    r = run("continue", CASTER, "--vary", "V", "--bounds", "V=0.5:10", "--dynamic", "--out", branch, "--quiet")
    assert r.exit_code == 0, r.output
    r = run("cycles", CASTER, "--point", f"{branch}:HB1", "--vary", "V", "--bounds", "V=0.5:10", "--max-steps", 4,
            "--out", cycles, "--quiet")
    assert r.exit_code == 0, r.output
    return branch, cycles


WORDS = ("periodic orbits", "cycles --out", "explore", "--orbits")


@pytest.mark.parametrize("args", [
    ("draw", CASTER, "--point", "{c}:1", "--out", "{d}/x.png"),
    ("folds", CASTER, "--point", "{c}:1", "--along", "k"),
    ("sensitivity", CASTER, "--point", "{c}:1", "--params", "k"),
    ("cycles", CASTER, "--point", "{c}:HB1", "--vary", "V"),
    ("optimize", CASTER, "--minimize", "fold_load", "--design", "k=1:2", "--point", "{c}:1"),
    ("animate", CASTER, "--branch", "{c}", "--out", "{d}/x.gif"),
    ("sweep", CASTER, "--branch", "{c}", "--ramp", "V=1:2:1", "--watch", "theta_wheel"),
], ids=lambda a: a[0])
def test_a_cycles_table_is_named_as_such(run, tables, tmp_path, args):
    _, cycles = tables
    given = [str(a).format(c=cycles, d=tmp_path) for a in args]
    res = run(*given)
    one_line_error(res, *WORDS)  # before: "lacks the column(s) x_wheel, y_wheel, ... of model 'caster'"
    assert "lacks" not in res.stderr and list(tmp_path.iterdir()) == []


def test_read_branch_row_refuses_it_and_reads_the_branch(tables):
    branch, cycles = tables
    m = load_model(str(CASTER))
    with pytest.raises(InputError, match="periodic orbits"):
        read_branch_row(m, cycles, "1")
    row = read_branch_row(m, branch, "HB1")  # the branch of equilibria it came from is read as before
    assert row.point.label == "HB" and row.vary == "V"


def test_what_a_cycles_table_is():
    from mechcont.continuation.branch_rows import is_cycles_table

    assert is_cycles_table(["V", "period", "min_theta", "max_theta", "floquet_max", "label", "s"])
    assert not is_cycles_table(["V", "theta", "y", "label", "s"])  # a branch of equilibria
    assert not is_cycles_table(["period", "theta", "max_theta"])  # a model's own 'period' parameter, no min/max pair


def test_explore_still_draws_it(run, tables, tmp_path):
    _, cycles = tables
    res = run("explore", CASTER, "--branch", cycles, "--out", tmp_path / "e.html")
    assert res.exit_code == 0 and (tmp_path / "e.html").exists(), res.output
