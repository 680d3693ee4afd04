"""A fresh user's Ziegler column (tests/data/fresh/ziegler_*.toml), written from the docs alone: two links,
torsion springs k, lumped masses 2m and m with a small inertia J, a follower force P written as a custom
load. Truth: the linearised equations M q'' + C q' + K q = 0 of the file's comment, their eigenvalues by numpy
(the damped flutter load where the leading real part crosses zero; it tends to 41/28 k/l as c, J -> 0, the
destabilisation paradox, below the undamped (7/2 - sqrt 2) k/l)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from cli_helpers import csv_rows, make_runner
from scipy.optimize import brentq

DATA = Path(__file__).parent / "data" / "fresh"


def _A(P: float, c: float, J: float = 0.01) -> np.ndarray:
    """State matrix of the linearised column (l = m = k = 1)."""
    M = np.array([[3 + J, 1.0], [1.0, 1 + J]])
    K = np.array([[2 - P, P - 1], [-1.0, 1.0]])
    C = c * np.array([[2.0, -1.0], [-1.0, 1.0]])
    Mi = np.linalg.inv(M)
    return np.block([[np.zeros((2, 2)), np.eye(2)], [-Mi @ K, -Mi @ C]])


def _flutter(c: float) -> tuple[float, float]:
    """The damped flutter load (N) and the frequency (rad/s) of the pair on the imaginary axis there."""
    P = brentq(lambda P: max(np.linalg.eigvals(_A(P, c)).real), 0.5, 2.5, xtol=1e-14)
    ev = np.linalg.eigvals(_A(P, c))
    return P, float(abs(ev[np.argmin(abs(ev.real))].imag))



@pytest.fixture(scope="module")
def run():
    return make_runner()


@pytest.mark.parametrize("frame", ["pivot", "cg"])
def test_damped_flutter_load_and_frequency(run, tmp_path, frame):
    """The Hopf point at c = 0.05 wherever the links' frames sit, and the branch reaches P = 3 N (the force scale
    of a file of general bodies and torsion springs was the 1e-3 N floor: 2000 steps ended at P = 0.115 N)."""
    out = tmp_path / "z.csv"
    r = run("continue", DATA / f"ziegler_{frame}.toml", "--vary", "P", "--bounds", "P=0:3", "--dynamic",
            "--set", "c=0.05", "--out", out)
    assert r.exit_code == 0, r.output
    rows = csv_rows(out)
    hb = [row for row in rows if row["label"] == "HB"]
    P, omega = _flutter(0.05)
    assert len(hb) == 1
    assert float(hb[0]["P [N]"]) == pytest.approx(P, abs=1e-9)
    assert float(hb[0]["leading_frequency [rad/s]"]) == pytest.approx(omega, abs=1e-9)
    assert float(rows[-1]["P [N]"]) == pytest.approx(3.0, abs=1e-12)
    assert 1.4 < P < 41 / 28 + 0.05**2 / 2 < 3.5 - np.sqrt(2)  # the paradox: damping lowers the threshold


def test_undamped_column_has_no_hopf_noise(run, tmp_path):
    """Undamped, every eigenvalue is +-i omega up to the flutter (a collision, no crossing of a pair): the
    bialternate product is rounding there, and its random sign made 17 HB rows below P = 2 N."""
    out = tmp_path / "z0.csv"
    r = run("continue", DATA / "ziegler_pivot.toml", "--vary", "P", "--bounds", "P=0:3", "--dynamic", "--out", out)
    assert r.exit_code == 0, r.output
    rows = csv_rows(out)
    assert not [row for row in rows if row["label"].startswith("HB")]
    # the onset of flutter is still in the counts: between the two points that bracket the collision
    def discriminant(P: float) -> float:  # of det(K - w^2 M) = 0 in w^2: the two frequencies collide at zero
        B = np.linalg.solve(np.array([[3.01, 1.0], [1.0, 1.01]]), np.array([[2 - P, P - 1], [-1.0, 1.0]]))
        return float(np.trace(B) ** 2 - 4 * np.linalg.det(B))

    P_flutter = brentq(discriminant, 1.5, 2.5, xtol=1e-14)
    assert P_flutter == pytest.approx(3.5 - np.sqrt(2), abs=0.02)  # J = 0.01 moves it from the closed form
    for row in rows:
        P = float(row["P [N]"])
        if abs(P - P_flutter) > 1e-3:
            assert (float(row["n_unstable_dynamic"]) == 2) == (P > P_flutter), row


def test_flutter_load_in_mm_and_g(run, tmp_path):
    """The same column written in mm and g (a force in g mm/s^2 = 1e-6 N) flutters at the same load."""
    out = tmp_path / "mm.csv"
    r = run("continue", DATA / "ziegler_mm_g.toml", "--vary", "P", "--bounds", "P=0:3e6", "--dynamic",
            "--set", "c=5e7", "--out", out)
    assert r.exit_code == 0, r.output
    (hb,) = [row for row in csv_rows(out) if row["label"] == "HB"]
    P, omega = _flutter(0.05)
    assert float(hb["P [g mm/s^2]"]) * 1e-6 == pytest.approx(P, abs=1e-9)
    assert float(hb["leading_frequency [rad/s]"]) == pytest.approx(omega, abs=1e-9)
