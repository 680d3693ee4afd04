"""A fresh user's Lorenz system (tests/data/fresh/lorenz.toml): `folds --point HB1 --along beta` with a `--set` of
another parameter than the table was run at. Truth: the Hopf point of C+ at r = sigma (sigma + beta + 3) /
(sigma - beta - 1) with omega^2 = beta (sigma + r). The old code continued the table's Hopf point and ignored
--set sigma=12 (its curve was sigma = 10's); cycles and sensitivity already took a row to their --set values."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner

FILE = Path(__file__).parent / "data" / "fresh" / "lorenz.toml"


def _rows(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.mark.parametrize("sigma", [10.0, 12.0])
def test_hopf_curve_at_the_set_values(tmp_path: Path, sigma: float) -> None:
    run = make_runner()
    branch, curve = tmp_path / "lz.csv", tmp_path / "hopf.csv"
    res = run("continue", FILE, "--vary", "r", "--bounds", "r=2:40", "--out", branch, "--quiet")
    assert res.exit_code == 0, res.output
    res = run("folds", FILE, "--set", f"sigma={sigma}", "--point", f"{branch}:HB1", "--along", "beta",
              "--bounds", "beta=1:4", "--bounds", "r=0:100", "--out", curve, "--quiet")
    assert res.exit_code == 0, res.output
    rows = _rows(curve)
    beta = np.array([float(r["beta"]) for r in rows])
    r = np.array([float(r["r"]) for r in rows])
    omega = np.array([float(r["omega [rad/s]"]) for r in rows])
    assert beta.min() == pytest.approx(1.0) and beta.max() == pytest.approx(4.0)
    assert np.array([float(x["sigma"]) for x in rows]) == pytest.approx(sigma, rel=1e-15)
    np.testing.assert_allclose(r, sigma * (sigma + beta + 3) / (sigma - beta - 1), rtol=1e-10)
    np.testing.assert_allclose(omega, np.sqrt(beta * (sigma + r)), rtol=1e-10)
