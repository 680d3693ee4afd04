"""The `mechcont paper` dynamics section: figures written, jumps past the folds, gap law."""

import re

import pytest

from mechcont.paper import dynamics


@pytest.mark.slow
def test_paper_dynamics_section(tmp_path):
    lines = dynamics.run(tmp_path, quiet=True)
    text = "\n".join(lines)
    for name in ("dynamics_fig3_sweep_vs_continuation.png", "dynamics_fig4bc.png", "dynamics_gap_vs_rate.png"):
        assert (tmp_path / name).stat().st_size > 1000
        assert f"({name})" in text
    rows = [ln for ln in lines if ln.startswith("| 1 (") or ln.startswith("| 2 (")]
    assert len(rows) == 2 and all(r.rstrip().endswith("| yes |") for r in rows)
    assert "LU = 2 m: 0 jumps" in text
    slope = float(re.search(r"rate\^([0-9.]+) \(slow", text).group(1))
    assert slope == pytest.approx(2 / 3, abs=0.08)
