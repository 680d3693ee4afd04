"""Unlocking the generated dual-sidestay gear from its overcentre stops (issue 11).

Truth: the release loads (SR) against an independent solve (the force that holds a pair on its stop
with zero contact force); the unlock loads (LP) are maxima of the force along the run and singular
points of the piece's equations; the cusp of the unlock fold curve separates spring preloads whose
unlock snaps (a fold) from those that do not (checked by continuation on both sides of it).
"""

import math

import numpy as np
import pytest

from mechcont.analysis import continuation_with_stops, equilibrium_on_stops
from mechcont.continuation import ContinuationOptions, find_equilibrium
from mechcont.models.dual_sidestay_description import STOP_SINE
from mechcont.paper.dual_sidestay import generated_gear, unlock_study


@pytest.fixture(scope="module")
def gear():
    return generated_gear()


@pytest.fixture(scope="module")
def study(gear):
    return unlock_study(gear)


def test_downlocked_on_both_stops(gear, study):
    d = gear.as_dict(study.locked)
    assert d["fwd_lock"] == pytest.approx(STOP_SINE, rel=1e-11) and d["aft_lock"] == pytest.approx(STOP_SINE, rel=1e-11)
    assert study.contact["R_fwd_stop"] > 0 and study.contact["R_aft_stop"] > 0
    assert np.max(np.abs(gear.residual(study.locked))) < 1e-8
    # the stops are 2 deg past aligned, on the side an unlock force moves away from
    assert math.degrees(math.asin(STOP_SINE)) == pytest.approx(2.0)


@pytest.mark.parametrize("force, stop, other", [("F_fwd", "fwd_stop", "aft_stop"), ("F_aft", "aft_stop", "fwd_stop")])
def test_release_load_equals_the_force_that_empties_the_stop(gear, study, force, stop, other):
    release = study.release(force)[stop]
    # independent: both pairs held on their stops, this stop's contact force zero, the force solved for
    x = find_equilibrium(gear, values={f"R_{stop}": 0.0}, hold={"fwd_lock": STOP_SINE, "aft_lock": STOP_SINE},
                         free=[force, f"R_{other}"], guess=study.locked)
    assert x[gear.index(force)] == pytest.approx(release, rel=1e-8)
    assert x[gear.index(f"R_{other}")] > 0


@pytest.mark.parametrize("force", ["F_aft", "F_lock"])
def test_unlock_load_is_a_located_maximum_of_the_force(gear, study, force):
    run = study.runs[force]
    lp = run.first_fold()
    assert lp is not None and lp.located
    F = run.branch.values[:, gear.index(force)]
    assert np.all(F <= lp[force] * (1 + 1e-12))
    # past its releases no stop is left in contact on the piece that unlocks (both together)
    if force == "F_lock":
        assert run.contact[-1] == ()
        assert [s[:2] for s in run.switches] == [("SR", "fwd_stop"), ("SR", "aft_stop")]


def test_forward_pair_alone_cannot_unlock(gear, study):
    run = study.runs["F_fwd"]
    assert run.first_fold() is None
    end = run.branch.values[-1]
    assert end[gear.index("F_fwd")] == pytest.approx(1000.0)
    assert end[gear.index("R_aft_stop")] > study.contact["R_aft_stop"]   # the aft stop carries more


def test_cusp_separates_snapping_from_gradual_unlock(gear, study):
    cusps = [p for p in study.fold_curve.special_points if p.label == "CP"]
    assert len(cusps) == 1
    c = cusps[0]["stretch"]
    assert 0.9 < c < 1.0

    def unlock_fold(stretch):
        x, _ = equilibrium_on_stops(gear, study.locked, values={"stretch": stretch})
        run = continuation_with_stops(gear, x, "F_lock", stop_at_fold=True,
                                      options=ContinuationOptions(bounds={"F_lock": (-1.0, 400.0)}, max_steps=200))
        return run.first_fold()

    below, above = unlock_fold(c - 0.01), unlock_fold(c + 0.01)
    assert below is not None and above is None
