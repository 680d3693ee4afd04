"""The row of a non-smooth fold (NSF) says the same whichever piece the run walked first.

Truth (own statics, numpy; no mechcont): tests/data/limit_toggle_lock.toml, a lever pivoted at O held on a max
stop at theta_s = 1.4 rad by the lock moment M0 against the unlock moment F, with a toggle spring k from S = (0, s)
to P at a: V(theta) = k (l - l0)^2 / 2, l^2 = a^2 + s^2 - 2 a s sin(theta). The applied moment M0 - F does not
depend on theta, so the free lever's stiffness is V''(theta). On the stop the lever's one degree of freedom is
held: stable, no unstable direction. Free at the stop V''(theta_s) < 0 (past the peak of V'): one unstable
direction. The stop releases at F = M0 - V'(theta_s) onto that unstable free branch: a non-smooth fold joining a
stable piece (0) and an unstable one (1). A run from the lever at rest on the stop walks the stable piece first;
a run from the free unstable equilibrium at theta = 1.3 walks the unstable one first. Before, the row took the
stability of the piece walked first (``stable`` from the stop, ``unstable`` from the free branch).
"""

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from mechcont.analysis import continuation_with_stops, equilibrium_on_stops
from mechcont.continuation import ContinuationOptions, find_equilibrium
from mechcont.mechanism import load_description
from mechcont.outputs.tables import jump_lines, special_table
from tests.cli_helpers import make_runner

TOGGLE = Path(__file__).parent / "data" / "limit_toggle_lock.toml"
K, A, S, L0, LATCH, M0 = 3000.0, 0.4, 0.5, 0.35, 1.4, 250.0
BOUNDS = ContinuationOptions(bounds={"F": (-100.0, 150.0)})


def _dV(theta):
    """dV/dtheta (N m) of the toggle spring."""
    l = np.sqrt(A**2 + S**2 - 2 * A * S * np.sin(theta))
    return K * (l - L0) * (-A * S * np.cos(theta) / l)


def _ddV(theta, h=1e-5):
    """The free lever's stiffness V'' (N m/rad), central difference (error ~ h^2 V'''' ~ 1e-6 N m/rad)."""
    return (_dV(theta + h) - _dV(theta - h)) / (2 * h)


F_NSF = M0 - _dV(LATCH)
#: the unstable directions of the pieces meeting at the fold, fewest first: on the stop none, free V'' < 0
SIDES = tuple(sorted([0, int(_ddV(LATCH) < 0)]))


@pytest.fixture(scope="module")
def toggle():
    return load_description(TOGGLE).build()


@pytest.fixture(scope="module")
def runs(toggle):
    """Two runs through the fold: from the lever at rest on the stop, and from the free unstable equilibrium."""
    rest, contact = equilibrium_on_stops(toggle, toggle.defaults())
    assert contact == ["latch"]
    free = find_equilibrium(toggle, hold={"theta_lever": 1.3, "R_latch": 0.0}, free=["F"],
                            guess={"theta_lever": 1.3, "swing": 1.3})
    return {"stop first": continuation_with_stops(toggle, rest, "F", direction=0, options=BOUNDS).branch,
            "free first": continuation_with_stops(toggle, free, "F", direction=0, options=BOUNDS).branch}


def test_the_premises():
    assert SIDES == (0, 1) and _ddV(LATCH) < -1.0   # far from zero against the difference's error
    assert 0 < F_NSF < M0


def test_the_fold_row_is_the_same_whichever_piece_was_walked_first(runs, tmp_path):
    for how, b in runs.items():
        (nsf,) = b.special("NSF")
        i = nsf.index
        assert nsf["F"] == pytest.approx(F_NSF, rel=1e-9), how
        assert nsf.nonsmooth is not None and nsf.nonsmooth.sides == SIDES, how
        st = b.stability_labels()
        assert st[i] == "fold" and b.n_unstable[i] == SIDES[0], how
        # the rows either side: on the stop stable, free at theta < theta_s with V'' < 0 unstable
        for j in (i - 1, i + 1):
            theta = b["theta_lever"][j]
            on_stop = abs(theta - LATCH) < 1e-9
            assert on_stop or _ddV(theta) < 0, how
            assert st[j] == ("stable" if on_stop else "unstable"), (how, j)
        assert {st[i - 1], st[i + 1]} == {"stable", "unstable"}, how
        path = b.to_csv(tmp_path / f"{how}.csv")
        (row,) = [r for r in csv.DictReader(path.open()) if r["label"] == "NSF"]
        assert (row["stability"], row["n_unstable"]) == ("fold", str(SIDES[0])), how
        (line,) = jump_lines(b, "F", "swing")
        assert "stable on one side, unstable (1 direction) on the other" in line, how
        (nsf_row,) = [ln for ln in special_table(b).splitlines() if ln.startswith("NSF1")]
        assert nsf_row.split()[-1] == "fold", how


def test_continue_prints_both_sides(tmp_path):
    out = tmp_path / "b.csv"
    r = make_runner()("continue", TOGGLE, "--stops", "--vary", "F", "--start", "swing=1.4", "--bounds", "F=-100:150",
                      "--out", out)
    assert r.exit_code == 0, r.output
    (line,) = [ln for ln in r.output.splitlines() if ln.startswith("NSF1:")]
    assert "(stop latch; stable on one side, unstable (1 direction) on the other)" in line
    assert math.isclose(float(line.split(" = ")[1].split()[0]), F_NSF, rel_tol=1e-9)
    (row,) = [r for r in csv.DictReader(out.open()) if r["label"] == "NSF"]
    assert row["stability"] == "fold" and row["n_unstable"] == "0"
