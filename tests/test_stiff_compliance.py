"""Stiff joint compliance: converged to what double precision allows, folds located, and the
compliant results tend to the rigid ones as 1/k.

The Bennett linkage (tests/data/spatial/bennett.toml, three structurally redundant rows dropped)
and the same linkage with its ground joint D compliant instead (bennett_compliant.toml, k_D in
N/m and c_D in N m/rad) are two formulations of one mechanism: the compliant one deflects by
reaction / stiffness, so its fold loads differ from the rigid ones by O(1/k). At 1e10 the
equilibrated Jacobian's three smallest singular values are ~2e-11 (condition ~1e11): Newton's
steps stall at the noise that rounding of the residual causes, and the solver must call that
converged instead of failing with a residual of 1e-15.
"""

from pathlib import Path

import numpy as np
import pytest

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.models import load_model

DATA = Path(__file__).parent / "data" / "spatial"
STIFF = (1e6, 1e8, 1e10)


def _folds(system, lo, hi):
    x0 = find_equilibrium(system, hold={"crank": 0.0}, free=["M"])
    b = continuation(system, x0, "M", options=ContinuationOptions(bounds={"crank": (lo, hi)}))
    return b, [(b["crank"][i], b["M"][i]) for i, lab in enumerate(b.labels) if lab.startswith("LP")], \
        [lab for lab in b.row_labels() if lab]


@pytest.fixture(scope="module")
def rigid_folds():
    _, folds, labels = _folds(load_model(DATA / "bennett.toml"), -1.05, 1.0)
    assert labels.count("LP") == 3
    return np.array([m for _, m in folds])


@pytest.mark.parametrize("k", STIFF)
def test_start_converges_at_any_stiffness(k):
    """At 1e10 the start failed with 'Newton did not converge in 50 iterations: residual 3.59e-15'."""
    s = load_model(DATA / "bennett_compliant.toml", k_D=k, c_D=k)
    x = find_equilibrium(s, hold={"crank": 0.3}, free=["M"])
    r, J = s.residual(x), s.jacobian(x)
    assert np.all(np.abs(r) <= 1e-10 + 1e-13 * np.abs(J * x).sum(axis=1))


def test_compliant_folds_are_located_and_tend_to_the_rigid_ones_as_one_over_k(rigid_folds):
    """Every fold is a located LP (at 1e8 they were LP? before), and its load's distance to the
    rigid linkage's falls a hundredfold for each hundredfold stiffness."""
    errors = []
    for k in STIFF:
        _, folds, labels = _folds(load_model(DATA / "bennett_compliant.toml", k_D=k, c_D=k), -1.05, 1.0)
        assert labels.count("LP") == 3 and "LP?" not in labels, labels
        errors.append(np.abs(np.array([m for _, m in folds]) - rigid_folds))
    e6, e8, e10 = errors
    assert np.all(e6 > 1e-6)  # the compliance is visible at 1e6 N/m
    assert np.all((e6 / e8 > 50) & (e6 / e8 < 200)), e6 / e8
    assert np.all(e10 < 1e-7)
    assert np.all(e8 / e10 > 20), e8 / e10  # still 1/k down to where rounding (1e-10 N m) sets in


@pytest.mark.parametrize("k", STIFF)
def test_the_compliant_linkage_goes_round_a_full_revolution(rigid_folds, k):
    """Continued in the crank moment from crank = 0 both ways to +-6.2 rad (past a full turn; the
    crank condition, 2 atan2, wraps at +-2 pi): every fold on the way is a located LP, the three
    within the rigid run's range carry its loads, each fold recurs one turn on with the same load,
    and the reactions change smoothly (with redundant rows chosen once they ran away to -4241 N)."""
    s = load_model(DATA / "bennett_compliant.toml", k_D=k, c_D=k)
    b, folds, labels = _folds(s, -6.2, 6.2)
    assert b["crank"].min() == pytest.approx(-6.2) and b["crank"].max() == pytest.approx(6.2)
    assert labels[0] == labels[-1] == "EP" and set(labels[1:-1]) == {"LP"} and len(labels) == 9
    tol = 1e3 / k  # the compliant folds differ from the rigid ones by O(1/k) (measured ~170/k N m)
    inside = [m for theta, m in folds if -1.05 < theta < 1.0]
    np.testing.assert_allclose(inside, rigid_folds, atol=tol)
    for theta, m in folds:
        partners = [m2 for t2, m2 in folds if abs(abs(t2 - theta) - 2 * np.pi) < 1e-3]
        assert all(m2 == pytest.approx(m, rel=1e-7) for m2 in partners)
    assert sum(1 for theta, _ in folds if abs(theta) < np.pi) == 4  # four folds a turn
    reactions = [n for n in s.names if n.startswith(("R_", "T_"))]
    R = np.column_stack([b[n] for n in reactions])
    assert np.max(np.abs(R)) < 100  # weights of 35 N, moments of 14 N m on 0.5 m links
    assert np.max(np.abs(np.diff(R, axis=0)) / np.ptp(R, axis=0)) < 0.1  # no jump between points
