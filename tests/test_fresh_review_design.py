"""A fresh user's overcentre lock (tests/data/fresh/toggle_lock.toml) mapped by `design` over (k, P) with
`--set L0=0.12`: its downlock moment (the links held in line, theta = 0) is F(0) = k (|B - S| - L0) a with
B = (a, 0) straight above S (|B - S| = -Sy = 0.25 m, the arm a = 0.4 m), linear in k and free of P, so
dF/dk = F(0)/k. The slope's header is the derivative's unit, N m/(N/m) (the old one wrote N m/N/m)."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import make_runner
from test_fresh_review_stops import _F, FILE


def test_design_map_values_and_slope_unit(tmp_path: Path) -> None:
    out = tmp_path / "d.md"
    res = make_runner()("design", FILE, "--set", "L0=0.12", "--bounds", "k=1000:4000", "--bounds", "P=200:400",
                        "--out", out)
    assert res.exit_code == 0, res.output
    head, _, *rows = [[c.strip() for c in ln.strip("|").split("|")] for ln in out.read_text().splitlines() if ln]
    assert head[1] == "F at k=4000 N/m (N m)" and head[2] == "dF/dk at k=4000 N/m (N m/(N/m))"
    f0 = 4000.0 * (0.25 - 0.12) * 0.4
    assert _F(0.0, 4000.0) == pytest.approx(4000.0 * (0.25 - 0.1) * 0.4, rel=1e-12)   # the same closed form
    assert len(rows) == 11
    for r in rows:
        assert float(r[1]) == pytest.approx(f0, rel=1e-3) and float(r[2]) == pytest.approx(f0 / 4000.0, rel=1e-3)
