"""The `mechcont paper` dynamics section: figures written, jumps past the folds, gap law. The section's run is the
one tests/test_figure_review.py reviews (``section_run``: made once per session); its outputs are checked here."""

import re

import pytest


@pytest.mark.slow
def test_paper_dynamics_section(shared):
    from test_figure_review import section_run

    run = section_run("dynamics", shared)
    lines = run.lines
    assert run.checks == [], "\n".join(run.checks)  # units on every axis, legends only for what is drawn, labels inside
    text = "\n".join(lines)
    for name in ("dynamics_fig3_sweep_vs_continuation.png", "dynamics_gap_vs_rate.png"):
        assert run.sizes[name] > 1000
        assert f"({name})" in text
    # Fig. 4b,c (the sweeps on their branches) belong to the overcentre section; this one points there
    assert "fig4b_overcentre_LU2.png" in text and "dynamics_fig4bc.png" not in run.written
    rows = [ln for ln in lines if ln.startswith("| 1 (") or ln.startswith("| 2 (")]
    assert len(rows) == 2 and all(r.rstrip().endswith("| yes |") for r in rows)
    # each jump names its fold as the branch (and every figure) numbers it
    from mechcont.paper.overcentre import branch

    b = branch(0.4)
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert b[cells[2]]["F"] == pytest.approx(float(cells[3]), abs=1e-4)
    assert "LU = 2 m: 0 jumps" in text
    slope = float(re.search(r"rate\^([0-9.]+) \(slow", text).group(1))
    assert slope == pytest.approx(2 / 3, abs=0.08)
    # Fig. 3 from two dynamic models, as in the paper: the Exudyn loop snaps through at the same loads
    from mechcont.dynamics._exudyn import exudyn_available

    pairs = re.findall(r"(-?[0-9.]+) N \(Udwadia–Kalaba: (-?[0-9.]+) N\)", text)
    if exudyn_available():
        assert len(pairs) == 2 and "snap-throughs" not in text
        for exu, uk in pairs:
            assert float(exu) == pytest.approx(float(uk), abs=0.05)  # N, 10 ms trapezoidal steps
    else:
        assert pairs == [] and "Exudyn is not installed" in text
