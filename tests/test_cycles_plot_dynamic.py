"""The amplitude diagram of ``cycles --plot`` draws the equilibria beneath the cycles by their *dynamic*
stability: on the damped Ziegler column (tests/data/fresh/ziegler_pivot.toml, c = 0.05) the static judgement
(the follower load's tangent stiffness) calls the equilibria stable well past the Hopf point, where they
flutter and the cycles are born. Truth: the linearised column's eigenvalues by numpy (the state matrix of
test_fresh_dynamics_mechanism)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from cli_helpers import csv_rows, make_runner
from test_fresh_dynamics_mechanism import _A, _flutter

import mechcont.outputs.cycle_plots as cycle_plots

DATA = Path(__file__).parent / "data" / "fresh" / "ziegler_pivot.toml"
C = 0.05



def test_cycles_plot_draws_the_equilibria_by_their_dynamic_stability(tmp_path, monkeypatch):
    run = make_runner()
    table = tmp_path / "z.csv"
    r = run("continue", DATA, "--vary", "P", "--bounds", "P=0:3", "--set", f"c={C}", "--out", table, "--dynamic")
    assert r.exit_code == 0, r.output
    rows = csv_rows(table)
    assert {row["n_unstable_dynamic"] for row in rows} == {"0", "2"}  # a count, written as one (was 0.0 / 2.0)
    P_rows = np.array([float(row["P [N]"]) for row in rows])
    static = np.array([row["stability"] for row in rows])
    assert (static[P_rows > 1.6] == "stable").any()  # the static judgement misses the flutter
    seen = {}
    real = cycle_plots.amplitude_figure

    def spy(family, branch=None, **kw):
        seen.update(family=family, branch=branch)
        return real(family, branch=branch, **kw)

    monkeypatch.setattr(cycle_plots, "amplitude_figure", spy)
    r = run("cycles", DATA, "--set", f"c={C}", "--point", f"{table}:HB1", "--vary", "P", "--bounds", "P=1:1.6",
            "--max-steps", "6", "--plot", tmp_path / "c.png", "--quiet")
    assert r.exit_code == 0, r.output
    branch = seen["branch"]
    P_hb, _ = _flutter(C)
    P = branch.column("P")
    truth = np.array([int(np.sum(np.linalg.eigvals(_A(p, C)).real > 1e-9)) for p in P])
    away = np.abs(P - P_hb) > 1e-6
    assert np.array_equal(branch.column("n_unstable_dynamic")[away], truth[away])
    assert truth[P > P_hb + 1e-6].min() == 2 and truth[P < P_hb - 1e-6].max() == 0
    ax = cycle_plots.plot_amplitude(seen["family"], branch=branch)
    drawn = {ln.get_label(): np.asarray(ln.get_xdata(), float) for ln in ax.get_lines()
             if ln.get_label().startswith("equilibria")}
    assert set(drawn) == {"equilibria, stable", "equilibria, unstable"}
    # the solid part ends, and the dashed begins, at the row of the Hopf point
    assert drawn["equilibria, stable"].max() == pytest.approx(P_hb, abs=1e-6)
    assert drawn["equilibria, unstable"].min() == pytest.approx(P_hb, abs=1e-6)
