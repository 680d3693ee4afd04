"""``mechcont cycles`` (issue 35, item 4): the table, the figure, --at, and one-line errors that keep what was computed.

The command is run in-process on ODE models built here (the file reader of ODE systems is another
module's); its model loader is replaced by one that returns them.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
import sympy as sp
from cli_helpers import make_runner, one_line_error

from mechcont.continuation import Branch, SpecialPoint
from mechcont.equations import ode_model

x, y, mu = sp.symbols("x y mu", real=True)
R2 = x**2 + y**2


def _sl():
    return ode_model("sl", {"x": 0.0, "y": 0.0}, {"mu": 0.0}, {"x": mu * x - y - x * R2, "y": x + mu * y - y * R2})


def _domain():
    """A Hopf point whose family cannot grow beyond r = 0.01 (its rates are not real there)."""
    g = mu - R2 + sp.sqrt(sp.Rational(1, 10000) - R2) - sp.Rational(1, 100)
    return ode_model("dom", {"x": 0.0, "y": 0.0}, {"mu": 0.0}, {"x": x * g - y, "y": y * g + x})


def _centre():
    """A linear centre at mu = 0: every orbit of its family has mu = 0 (l1 = 0, a degenerate Hopf point)."""
    return ode_model("centre", {"x": 0.0, "y": 0.0}, {"mu": 0.0}, {"x": mu * x - y, "y": x + mu * y})


@pytest.fixture
def run(monkeypatch):
    models = {"sl": _sl(), "dom": _domain(), "centre": _centre()}
    monkeypatch.setattr("mechcont.cli.cycles.load_at", lambda name, values: models[name].with_values(values))
    return make_runner()


def _table(path, model, labels=("", "HB", "")):
    """A branch table of ``model`` in mu with rows at mu = -0.1, 0 (labelled as given), 0.1 on the equilibrium 0."""
    rows = [model.vector({"mu": v}) for v in (-0.1, 0.0, 0.1)]
    sp_ = [SpecialPoint(lab, i, rows[i], model.names) for i, lab in enumerate(labels) if lab]
    Branch(model.names, rows, [0.0, 0.1, 0.2], [-1] * 3, list(labels), sp_, "mu", ("x", "y"), model=model.name,
           units={}).to_csv(path)
    return path


def _read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def test_cycles_writes_the_table_the_figure_and_rows_at_the_asked_values(run, tmp_path):
    table = _table(tmp_path / "b.csv", _sl())
    out, plot = tmp_path / "c.csv", tmp_path / "c.png"
    r = run("cycles", "sl", "--point", f"{table}:HB1", "--vary", "mu", "--bounds", "mu=-1:0.5", "--at", "mu=0.1,0.3",
            "--out", out, "--plot", plot)
    assert r.exit_code == 0, r.output
    header, rows = _read(out)
    assert header == ["mu", "period [s]", "min_x", "max_x", "min_y", "max_y", "floquet_max", "n_unstable", "stability",
                      "label", "s"]
    labels = [row[header.index("label")] for row in rows]
    assert labels[0] == "HB" and labels[-1] == "EP" and labels.count("UZ") == 2
    for row in rows:
        if row[header.index("label")] == "UZ":
            m = float(row[0])
            assert m in (pytest.approx(0.1, abs=1e-12), pytest.approx(0.3, abs=1e-12))
            assert float(row[header.index("max_x")]) == pytest.approx(math.sqrt(m), abs=1e-6)  # nodes/Gauss points
            assert float(row[header.index("period [s]")]) == pytest.approx(2 * np.pi, rel=1e-9)
            assert float(row[header.index("floquet_max")]) == pytest.approx(math.exp(-2 * m * 2 * np.pi), rel=1e-6)
            assert row[header.index("stability")] == "stable"
    assert plot.stat().st_size > 1000
    assert "UZ1" in r.stdout and f"wrote {out}" in r.stdout


def test_cycles_from_a_point_that_is_not_a_hopf_point_is_one_line(run, tmp_path):
    table = _table(tmp_path / "b.csv", _sl())
    one_line_error(run("cycles", "sl", "--point", f"{table}:0", "--vary", "mu"), "--point", "not a Hopf point")
    one_line_error(run("cycles", "sl", "--point", f"{table}:HB2", "--vary", "mu"), "--point", "HB2")
    one_line_error(run("cycles", "sl", "--point", "nofile.csv", "--vary", "mu"), "--point")
    one_line_error(run("cycles", "sl", "--point", f"{table}:HB1", "--vary", "mu", "--at", "x=1"), "--at")
    one_line_error(run("cycles", "sl", "--point", f"{table}:HB1", "--vary", "mu", "--ncol", "1"), "ncol")
    one_line_error(run("cycles", "sl", "--point", f"{table}:HB1", "--vary", "x"), "--vary", "not a parameter")
    one_line_error(run("cycles", "sl", "--point", f"{table}:HB1", "--vary", "nu"), "nu")
    one_line_error(run("cycles", "sl", "--point", f"{table}:HB1", "--vary", "mu", "--out", tmp_path / "c.json"), "--out")
    assert not (tmp_path / "c.json").exists()


def test_a_family_whose_collocation_fails_keeps_what_it_computed(run, tmp_path):
    table = _table(tmp_path / "b.csv", _domain())
    out = tmp_path / "c.csv"
    r = run("cycles", "dom", "--point", f"{table}:HB1", "--vary", "mu", "--bounds", "mu=-1:1", "--out", out,
            "--quiet")
    one_line_error(r, "collocation failed after mu", "not finite")
    header, rows = _read(out)
    assert len(rows) > 2 and rows[0][header.index("label")] == "HB"
    radius = [float(row[header.index("max_x")]) for row in rows]
    assert max(radius) < 0.0101  # the family stops where its rates end


def test_a_degenerate_hopf_point_whose_family_is_vertical_cannot_start(run, tmp_path):
    table = _table(tmp_path / "b.csv", _centre())
    out = tmp_path / "c.csv"
    r = run("cycles", "centre", "--point", f"{table}:HB1", "--vary", "mu", "--bounds", "mu=-1:1", "--out", out,
            "--quiet")
    one_line_error(r, "cannot start", "does not leave mu = 0", "degenerate Hopf point")
    header, rows = _read(out)
    assert rows[0][header.index("label")] == "HB"
    assert all(abs(float(row[header.index("mu")])) < 1e-12 for row in rows)
