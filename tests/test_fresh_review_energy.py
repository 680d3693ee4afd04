"""A fresh user's overcentre lock (tests/data/fresh/toggle_lock.toml) simulated resting on its lock stop: at
k = 2000 N/m and F = 70 N m it stays locked (below the closed-form release F(-delta) of
tests/test_fresh_review_stops.py), the stop's reaction (F(-delta) - F)/cos(delta). The energy audit must close:
at rest the net force M qddot is zero, and the stop's large reaction times the positions' tolerance is what the
integrator's steps explain (the old bound left that term out and warned at rest: residual 1.7e-9 J against a
bound of 1.6e-17 J)."""

from __future__ import annotations

import csv

import numpy as np
import pytest
from cli_helpers import make_runner
from test_fresh_review_stops import _F, DELTA, FILE


def test_lock_at_rest_on_its_stop_closes_its_energy_balance(tmp_path) -> None:  # noqa: ANN001
    out = tmp_path / "rest.csv"
    res = make_runner()("simulate", FILE, "--set", "k=2000", "--set", "F=70", "--set", "c=5", "--start",
                        f"theta_l1={-DELTA}", "--stops", "--until", "3", "--out", out, "--no-progress")
    assert res.exit_code == 0, res.output
    assert "energy balance does not close" not in res.output
    with open(out, newline="") as fh:
        last = list(csv.DictReader(fh))[-1]
    assert float(last["theta_l1 [rad]"]) == pytest.approx(-DELTA, abs=1e-9)
    r = (_F(-DELTA, 2000.0) - 70.0) / np.cos(DELTA)
    assert float(last["R_lock [N m]"]) == pytest.approx(r, rel=1e-7)
    assert abs(float(last["E_residual [J]"])) < 1e-6 * r * DELTA   # far below the energy a release would move
