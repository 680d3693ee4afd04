"""The batched downlock kernel against the single-point path and the closed form."""

import numpy as np
import pytest

from mechcont.analysis import downlock_condition, downlock_point
from mechcont.analysis.study import Distribution, GridAxis, StudySpec, run_chunk
from mechcont.continuation import choose_unknowns
from mechcont.continuation._batch import newton_batch
from mechcont.errors import ConvergenceError, InputError
from mechcont.models import load_model
from mechcont.models.nose_gear_geometry import aligned_downlock_force


@pytest.fixture(scope="module")
def nose():
    return load_model("nose_gear")


@pytest.fixture(scope="module")
def lockstay():
    return load_model("lockstay.toml")


def _batch(system, rows: list[dict]):
    h, f = downlock_condition(system)
    X = np.tile(system.vector(h, base=system.downlock.pose), (len(rows), 1))
    for i, r in enumerate(rows):
        X[i] = system.vector(r, base=X[i])
    return newton_batch(system, X, choose_unknowns(system, hold=list(h), free=[f])), f


def test_batched_downlock_equals_single_point_nose_gear(nose):
    """Every variable of every row equals the single-point solve to 1e-10 (in units of its scale),
    also where a geometric parameter moves the whole pose (L4, Ax, L32)."""
    rng = np.random.default_rng(7)
    rows = [{"LU": 1.3 + 0.02 * rng.standard_normal(), "l_sp1": 0.1 + 0.01 * rng.standard_normal(),
             "k": 20000 * (1 + 0.05 * rng.standard_normal()), "L4": 0.35 + 0.002 * rng.standard_normal(),
             "Ax": -1.40 + 0.003 * rng.standard_normal(), "L32": 1.2 + 0.002 * rng.standard_normal()}
            for _ in range(40)]
    sol, f = _batch(nose, rows)
    assert sol.converged.all()
    sc = nose.scales()
    for i, r in enumerate(rows):
        x = downlock_point(nose, r)
        assert np.max(np.abs(sol.x[i] - x) / sc) < 1e-10
        assert abs(sol.x[i, nose.index(f)] - x[nose.index(f)]) < 1e-10 * max(1.0, abs(x[nose.index(f)]))


def test_batched_downlock_force_matches_closed_form(nose):
    """At the dead centre the downlock force has a closed form (virtual work): F = (m4 + m5) g / 2
    - k (s - LU) u_y (1/2 - l_sp1 / L4); the batched solves meet it to 1e-9 relative."""
    from mechcont.models.nose_gear_geometry import PARAMETERS

    rng = np.random.default_rng(3)
    rows = [{"LU": rng.uniform(1.2, 1.4), "l_sp1": rng.uniform(-0.15, 0.15), "k": rng.uniform(5e3, 4e4)}
            for _ in range(50)]
    sol, f = _batch(nose, rows)
    assert sol.converged.all()
    base = {n: nose.variable(n).value for n in PARAMETERS}
    for i, r in enumerate(rows):
        exact = aligned_downlock_force({**base, **r})
        assert sol.x[i, nose.index(f)] == pytest.approx(exact, rel=1e-9, abs=1e-9)


def test_batched_downlock_equals_single_point_description_file(lockstay):
    """A description file (its condition declared, no closed-form start): the same answers."""
    rng = np.random.default_rng(11)
    rows = [{"k": rng.uniform(1.5e4, 2.5e4), "LU": lockstay.variable("LU").value * (1 + 0.02 * rng.standard_normal())}
            for _ in range(20)]
    sol, f = _batch(lockstay, rows)
    assert sol.converged.all()
    sc = lockstay.scales()
    for i, r in enumerate(rows):
        x = downlock_point(lockstay, r)
        assert np.max(np.abs(sol.x[i] - x) / sc) < 1e-10


def test_chunk_stragglers_and_failures(nose):
    """A chunk never stops at a bad sample: a value outside the model's range fails with the model's
    reason, a far geometric change the batched start cannot reach goes to the single-point path
    (same answer as downlock_point), the rest are batched."""
    spec = StudySpec("nose_gear", "grid", (("L4", GridAxis(-0.1, 0.55, 14)),), analyses=("downlock",))
    cols = run_chunk(nose, spec, 0)
    L4 = cols["L4"]
    bad = L4 <= 0
    assert (cols["status"][bad] == "failed").all()
    assert all("L4" in r and "positive" in r for r in cols["reason"][bad])
    good = ~bad & (cols["status"] == "converged")
    for i in np.nonzero(good)[0]:
        x = downlock_point(nose, {"L4": L4[i]})
        assert cols["downlock_force"][i] == pytest.approx(x[nose.index("F")], rel=1e-10, abs=1e-10)
    assert {"batched", "single"} <= set(cols["path"][good])
    for i in np.nonzero(~bad & (cols["status"] == "failed"))[0]:  # the single-point path fails too
        with pytest.raises((ConvergenceError, InputError)):
            downlock_point(nose, {"L4": L4[i]})
        assert cols["reason"][i].startswith("downlock solve:")


def test_mc_chunk_matches_single_point_and_is_batched(nose):
    spec = StudySpec("nose_gear", "mc", (("LU", Distribution("normal", (1.3, 0.01))),
                                         ("l_sp1", Distribution("truncnormal", (0.1, 0.005, 0.09, 0.11)))), n=30, seed=5)
    cols = run_chunk(nose, spec, 0)
    assert (cols["path"] == "batched").all() and (cols["status"] == "converged").all()
    for i in range(0, 30, 7):
        x = downlock_point(nose, {"LU": cols["LU"][i], "l_sp1": cols["l_sp1"][i]})
        assert cols["downlock_force"][i] == pytest.approx(x[nose.index("F")], rel=1e-10)
    assert (cols["locks_unaided"] == (cols["downlock_force"] > 0)).all()


def test_batched_unlock_folds_equal_release_runs(lockstay):
    """The unlock folds of a chunk, polished all at once from its first sample's folds
    (continuation._batch.fold_batch), equal each sample's own release run (unlock_folds) to 1e-9,
    with the same stability; the fold margin is the unlock force less the downlock force."""
    from mechcont.analysis import unlock_folds

    spec = StudySpec("lockstay.toml", "mc", (("k", Distribution("normal", (20000.0, 1500.0))),
                                             ("LU", Distribution("normal", (0.6, 0.005)))), n=25, seed=3,
                     analyses=("unlock",), chunk=25)
    cols = run_chunk(lockstay, spec, 0)
    assert (cols["status"] == "converged").all()
    assert (cols["unlock_path"][1:] == "batched").all() and cols["unlock_path"][0] == "single"
    h, f = downlock_condition(lockstay)
    for i in range(25):
        x = downlock_point(lockstay, {"k": cols["k"][i], "LU": cols["LU"][i]})
        u = unlock_folds(lockstay, x, f, released=list(h))
        assert cols["unlock_force"][i] == pytest.approx(u.unlock_force, rel=1e-9)
        lo = u.locked_range[0]
        assert (np.isnan(cols["unlock_force_decreasing"][i]) and not np.isfinite(lo)) or \
            cols["unlock_force_decreasing"][i] == pytest.approx(lo, rel=1e-9)
        assert cols["stable"][i] == u.stable
        assert cols["unlock_margin"][i] == cols["unlock_force"][i] - cols["downlock_force"][i]


def test_branch_summary_of_each_release_run(lockstay):
    """`branch`: every sample's own release run, summarised. Each direction stops at its first fold,
    so the largest force of the run is the unlock fold; the unlock columns from these runs equal the
    batched ones."""
    params = (("k", Distribution("normal", (20000.0, 1500.0))), ("LU", Distribution("normal", (0.6, 0.005))))
    both = run_chunk(lockstay, StudySpec("lockstay.toml", "mc", params, n=6, seed=8, analyses=("unlock", "branch")), 0)
    batched = run_chunk(lockstay, StudySpec("lockstay.toml", "mc", params, n=6, seed=8, analyses=("unlock",)), 0)
    assert (both["unlock_path"] == "single").all() and (batched["unlock_path"][1:] == "batched").all()
    assert (both["branch_folds"] == 1).all() and (both["branch_points"] > 10).all()
    assert set(both["branch_status"]) == {"completed"}
    assert np.array_equal(both["branch_force_high"], both["unlock_force"])
    # decreasing, the lockstay has no fold: the run ends at its own bound, which is no force of the mechanism
    assert np.isnan(both["branch_force_low"]).all()
    assert all(n.startswith("decreasing: the release run ended at its bound") for n in both["branch_note"])
    # the locked segment up to its fold is stable; the fold point itself (a zero eigenvalue) is not "unstable"
    assert (both["stable"] == True).all() and (both["branch_unstable_points"] == 0).all()  # noqa: E712
    np.testing.assert_allclose(both["unlock_force"], batched["unlock_force"], rtol=1e-9)
    only = run_chunk(lockstay, StudySpec("lockstay.toml", "mc", params, n=2, seed=8, analyses=("branch",)), 0)
    assert "unlock_force" not in only and "branch_folds" in only
