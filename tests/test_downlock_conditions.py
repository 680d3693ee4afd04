"""Downlock and unlock on a description that declares its own condition, against the closed form.

The shipped overcentre description is changed into a lock: the apex force P acts downwards and
the condition ``aligned`` (collinear ground pin, apex, slider end: -sin(theta1) in the symmetric
pose) is held at -sin(1), i.e. theta1 = 1 rad, on the stable side of the folds at LU = 0.4 m.
The symmetric closed form (mechcont.models.overcentre) gives the downlock force
P = -F(theta1 = 1) and the unlock fold, where cos^3(theta1) = LU/L: P = -F(theta1 = acos((LU/L)^(1/3))).
"""

import math
import pickle

import numpy as np
import pytest

from mechcont.analysis import DownlockResult, design_region, downlock, downlock_point, with_unlock_columns
from mechcont.continuation import Branch, ContinuationOptions, continuation, locate_fold
from mechcont.errors import InputError
from mechcont.mechanism import find_description, parse_description
from mechcont.models.overcentre import symmetric_folds, symmetric_force

OVERCENTRE = find_description("overcentre").read_text()
TARGET = -math.sin(1.0)
P = dict(L=1.5, m1=1.0, m2=1.0, g=9.81, k=127.0)


def lock_text(target=TARGET):
    text = OVERCENTRE.replace("dof = 1", 'dof = 1\ndownlock = {condition = "aligned", force = "P"}')
    text = text.replace('F = { value = 0.0, unit = "N", description = "vertical force at the apex, positive up" }',
                        'P = { value = 0.0, unit = "N", description = "vertical force at the apex, positive down" }')
    text = text.replace('[loads.F]\ntype = "force"\nat = "1.b"\ndirection = [0, 1]\nmagnitude = "F"',
                        '[loads.P]\ntype = "force"\nat = "1.b"\ndirection = [0, -1]\nmagnitude = "P"')
    assert 'magnitude = "P"' in text
    return text + f'''
[conditions]
aligned = {{type = "collinear", points = ["1.a", "1.b", "2.a"], target = {target!r}}}
rel = {{type = "angle", bodies = ["1", "2"], target = {math.pi - 2.0!r}}}
gap = {{type = "distance", points = ["ground.O", "2.a"]}}
'''


def unlock_closed_form(LU):
    """P (N) at the fold bounding the stable segment theta1 > acos((LU/L)^(1/3))."""
    (_, _), (th, F) = symmetric_folds(LU=LU, **P)
    assert th > 0
    return -F


@pytest.fixture(scope="module", params=[False, True], ids=["full", "reduced"])
def lock(request):
    mech = parse_description(lock_text(), "lock.toml")
    return mech.build_reduced() if request.param else mech.build()


@pytest.fixture(scope="module")
def result(lock):
    return downlock(lock, "LU", {"LU": (0.3, 0.8)})  # condition and force from [mechanism] downlock


def test_the_description_declares_the_downlock(lock):
    assert lock.downlock.hold == {"aligned": TARGET} and lock.downlock.force == "P"
    x = downlock_point(lock)
    assert x[lock.index("theta1")] == pytest.approx(1.0, abs=1e-12)
    assert x[lock.index("P")] == pytest.approx(-symmetric_force(1.0, LU=0.4, **P), rel=1e-12)


def test_downlock_force_along_the_branch_is_the_closed_form(result):
    branch = result.branch
    assert isinstance(result, DownlockResult) and isinstance(branch, Branch)
    assert branch.success and result.warnings == [] and len(branch) > 10
    assert result.condition == {"aligned": TARGET} and result.force == "P"
    assert np.allclose(branch["theta1"], 1.0, atol=1e-12, rtol=0)
    for LU, Pd in zip(branch["LU"], branch["P"]):
        assert Pd == pytest.approx(-symmetric_force(1.0, LU=LU, **P), rel=1e-10, abs=1e-10)
    assert pickle.loads(pickle.dumps(result)).unlock.unlock_force == result.unlock.unlock_force


def test_unlock_fold_is_the_closed_form_and_the_fold_found_by_hand(lock, result):
    u = result.unlock
    assert u.stable is True and u.below is None and u.above.located
    assert u.force == "P" and u.downlock_force == pytest.approx(-symmetric_force(1.0, LU=0.4, **P), rel=1e-12)
    assert u.unlock_force == pytest.approx(unlock_closed_form(0.4), rel=1e-10)
    assert u.above["theta1"] == pytest.approx(math.acos((0.4 / 1.5) ** (1 / 3)), abs=1e-9)
    assert u.locked_range == (-np.inf, u.unlock_force)
    assert "P = 75.58" in u.summary() and "unlock force" in u.summary()
    # by hand: release the condition (default lens), continue in P, polish the nearest fold above
    x0 = downlock_point(lock)
    b = continuation(lock, x0, "P", options=ContinuationOptions(bounds={"P": (0.0, 200.0), "theta1": (0.2, 1.5)}))
    above = [p for p in b.special("LP") if p["P"] > x0[lock.index("P")]]
    nearest = min(above, key=lambda p: p["P"])
    xf, _, _ = locate_fold(lock, nearest, "P")
    assert u.unlock_force == pytest.approx(xf[lock.index("P")], rel=1e-12, abs=1e-12)


def test_unlock_columns_follow_the_closed_form(lock, result):
    out = with_unlock_columns(lock, result, "P", released=["aligned"])
    assert isinstance(out, DownlockResult) and out.unlock is result.unlock
    table = out.branch
    assert "unlock_P" in table.names and "unlock_P_decreasing" not in table.names
    for LU, Pu in zip(table["LU"], table["unlock_P"]):
        assert Pu == pytest.approx(unlock_closed_form(LU), rel=1e-9)
    assert table.units["unlock_P"] == "N"


def test_unlock_columns_reuse_the_start_points_release_run(lock, result, monkeypatch):
    import dataclasses

    from mechcont.analysis import unlock as unlock_mod

    calls = []
    real = unlock_mod.unlock_folds
    monkeypatch.setattr(unlock_mod, "unlock_folds", lambda *a, **k: (calls.append(1), real(*a, **k))[1])
    table = with_unlock_columns(lock, result, "P", released=["aligned"]).branch
    assert len(calls) == len(result.branch) - 1  # the start's run is result.unlock
    bare = dataclasses.replace(result, unlock=None)  # nothing to reuse: every row runs
    calls.clear()
    again = with_unlock_columns(lock, bare, "P", released=["aligned"]).branch
    assert len(calls) == len(result.branch)
    assert np.array_equal(table["unlock_P"], again["unlock_P"])


def test_release_run_without_stability_finds_the_same_folds(lock, result):
    """unlock_force_along skips the release runs' stability: the folds, notes and warnings are the same."""
    from mechcont.analysis.unlock import unlock_folds

    x = result.branch.values[len(result.branch) // 2]
    full = unlock_folds(lock, x, "P", released=["aligned"])
    lean = unlock_folds(lock, x, "P", released=["aligned"], stability=False)
    assert lean.locked_range == full.locked_range and lean.stable == full.stable
    assert (lean.notes, lean.warnings) == (full.notes, full.warnings)
    assert np.array_equal(lean.branch.values, full.branch.values) and lean.branch.labels == full.branch.labels
    assert set(lean.branch.n_unstable) == {-1} and -1 not in full.branch.n_unstable


def test_an_unstable_downlocked_point_is_reported_with_both_folds(lock):
    """At LU = 0.2 m the folds sit at theta1 = +-acos((0.2/1.5)^(1/3)) = +-1.034: theta1 = 1 lies
    between them, on the unstable branch: not a lock, bounded by a fold on either side."""
    b = downlock(lock, "k", {"k": (120.0, 130.0)}, values={"LU": 0.2})
    u = b.unlock
    assert u.stable is False and "UNSTABLE" in u.summary()
    (th_lo, F_lo), (th_hi, F_hi) = symmetric_folds(LU=0.2, **P)
    assert u.above["P"] == pytest.approx(-F_hi, rel=1e-10) and u.above["theta1"] == pytest.approx(th_hi, abs=1e-9)
    assert u.below["P"] == pytest.approx(-F_lo, rel=1e-10) and u.below["theta1"] == pytest.approx(th_lo, abs=1e-9)


def test_another_declared_condition_by_name(lock):
    res = downlock(lock, "k", {"k": (100.0, 150.0)}, condition="rel", unlock=False)
    b = res.branch
    assert res.condition == {"rel": math.pi - 2.0} and res.unlock is None
    assert np.allclose(b["theta1"], 1.0, atol=1e-12, rtol=0)
    for k, Pd in zip(b["k"], b["P"]):
        assert Pd == pytest.approx(-symmetric_force(1.0, LU=0.4, **{**P, "k": k}), rel=1e-10)


@pytest.mark.parametrize("kwargs, words", [
    ({"condition": "nope"}, ("condition", "unknown condition 'nope'", "aligned, rel, gap")),
    ({"condition": "gap"}, ("condition", "no target")),
    ({"condition": "aligned", "hold": {"theta1": 1.0}}, ("condition", "either")),
])
def test_bad_conditions_are_one_line_input_errors(lock, kwargs, words):
    with pytest.raises(InputError) as info:
        downlock(lock, "LU", {"LU": (0.2, 0.8)}, **kwargs)
    msg = str(info.value)
    assert "\n" not in msg
    for w in words:
        assert w in msg, msg


def test_a_run_that_stops_early_is_named(lock):
    b = downlock(lock, "LU", {"LU": (0.2, 0.8)}, max_steps=3)
    assert b.branch.success  # the engine's status: max_steps is a normal end ...
    assert len(b.warnings) == 2  # ... but neither direction reached its bound
    for w in b.warnings:
        assert "downlock branch in LU" in w and "stopped early at LU = " in w and "P = " in w and "max_steps" in w


def test_design_region_on_the_description(lock):
    region = design_region(lock, "LU", "k", x_bounds=(0.2, 0.8), y_levels=[110.0, 140.0], values={"LU": 0.4})
    assert region.warnings == []
    for row in region.rows:
        F = -symmetric_force(1.0, LU=0.4, **{**P, "k": row.level})
        assert row.force_at_design == pytest.approx(F, rel=1e-9)
        assert row.locks_unaided == (F > 0)
        # P(LU) is linear: -(m1+m2)g/2 + k (L cos 1 - LU) tan 1, zero at LU = L cos 1 - (m1+m2) g/(2 k tan 1)
        zero = 1.5 * math.cos(1.0) - 9.81 / (row.level * math.tan(1.0))
        assert row.margin_to_zero == pytest.approx(abs(zero - 0.4), rel=1e-8)
        assert row.lock_margin == pytest.approx(zero - 0.4, rel=1e-8)  # > 0: locks with that margin in LU
