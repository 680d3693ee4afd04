"""One status vocabulary (Status) and typed special points: the words of before still read and compare."""

import json
from dataclasses import FrozenInstanceError, replace

import numpy as np
import pytest

import mechcont
from mechcont._status import Status
from mechcont.continuation import (
    Branch,
    ContinuationOptions,
    Landing,
    NonSmoothFold,
    SpecialPoint,
    Termination,
    continuation,
    find_equilibrium,
)
from mechcont.dynamics import SimulationStatus
from mechcont.errors import InputError
from mechcont.models import build_overcentre

OLD_WORDS = ("completed", "step size underflow", "located", "approximate", "converged", "failed", "stopped early")


def test_status_is_the_word_it_replaces():
    for word in OLD_WORDS:
        status = Status.of(word)
        assert status == word and f"{status}" == word and {status} == {word} and json.dumps(status) == f'"{word}"'
        assert status.message.endswith(".") and len(status.message) > len(word)
    assert Status.of(Status.LOCATED) is Status.LOCATED and mechcont.Status is Status
    assert SimulationStatus.FINISHED is Status.FINISHED  # the old name of the simulation's vocabulary
    assert {t.status for t in Termination} == {Status.COMPLETED, Status.STEP_UNDERFLOW}
    with pytest.raises(InputError, match="status.*unknown status 'done'.*completed"):
        Status.of("done")


def test_the_first_failure_decides_a_joined_result():
    assert Status.first_failure(["completed", "completed"]) is Status.COMPLETED
    assert Status.first_failure(["completed", "step size underflow", "failed"]) is Status.STEP_UNDERFLOW
    assert Status.first_failure([]) is Status.COMPLETED


def _point(**kw):
    return SpecialPoint("LP", 3, np.array([1.0, 2.0]), ("a", "F"), **kw)


def test_an_info_dict_fills_the_typed_fields():
    v = np.array([0.6, 0.8])
    p = _point(info={"status": "approximate", "reason": "no polish", "vary": "F", "unknowns": ["a"],
                     "null_vector": v, "residual": 1e-15, "stop": "top"})
    assert p.status is Status.APPROXIMATE and not p.located and p.tag == "LP?" and p.reason == "no polish"
    assert p.vary == "F" and p.unknowns == ("a",) and p.null_vector is v and p.residual == 1e-15
    assert p.singular_value is None and p.stop == "top" and p.extra == {}
    info = p.info  # the compatibility view: typed fields when set, then what analyses added
    assert info["status"] == "approximate" and info["unknowns"] == ("a",) and info["stop"] == "top"
    assert "singular_value" not in info and info.get("singular_value") is None
    with pytest.raises(TypeError):
        info["status"] = "located"  # type: ignore[index]
    again = _point(info=info)
    assert again.info == info and again.status is p.status


def test_freefall_outcomes_and_the_correctors_reasons_are_statuses():
    from mechcont.dynamics import freefall as ff

    assert (ff.LOCKED, ff.AT_REST, ff.MOVING, ff.FAILED) == (Status.LOCKED, Status.AT_REST, Status.STILL_MOVING,
                                                            Status.FAILED)
    assert [Status.of(w) for w in ("locked", "at rest", "still moving")] == [ff.LOCKED, ff.AT_REST, ff.MOVING]
    assert ff.MOVING.success and not Status.FAILED.success
    # a step rejected for a non-finite residual says so in the words of before, as a Status
    why = Status.of("residual not finite (outside the model's domain)")
    assert why is Status.NOT_FINITE and not why.success and "not finite" in why.message
    assert f"{Status.SINGULAR}; more" == "singular bordered Jacobian; more"


def test_a_non_smooth_fold_is_typed_and_its_flat_keys_read_back_into_it():
    x_land = np.array([0.1, 2.0])
    fold = NonSmoothFold("top", "F", 2.0, -1, True, Landing(x_land, ("seat",), False))
    p = SpecialPoint("NSF", 3, np.array([1.0, 2.0]), ("a", "F"), nonsmooth=fold, extra={"note": 1})
    assert p.stop == "top" and p.nonsmooth is fold and p.extra == {"note": 1}
    # the view of before (the JSON writes its scalars): stop, the parameter's value, sign, jump, landing...
    assert dict(p.info) == {"status": "located", "note": 1, "stop": "top", "F": 2.0, "sign": -1, "jump": True,
                            "landing": x_land, "landing_contact": ("seat",), "landing_stable": False}
    # rebuilt from that view with its record, the flat keys are not kept twice in extra
    again = SpecialPoint("NSF", 3, p.x, p.names, info=p.info, nonsmooth=fold)
    assert again.extra == {"note": 1} and again.stop == "top"
    # a fold's stop wins over the stop of the switch point it was found at
    assert SpecialPoint("NSF", 3, p.x, p.names, info={"stop": "seat"}, nonsmooth=fold).stop == "top"
    no_jump = replace(fold, jump=False, landing=None)
    assert replace(p, nonsmooth=no_jump).info["landing"] is None and p.nonsmooth is fold
    with pytest.raises(FrozenInstanceError):
        p.label = "LP"  # type: ignore[misc]


def test_a_point_without_data_is_located_and_its_keywords_win():
    p = _point()
    assert p.status is Status.LOCATED and p.reason == "" and p.vary is None and p.unknowns is None
    assert dict(p.info) == {"status": "located"}
    q = _point(info={"vary": "a"}, vary="F", extra={"switched": True})
    assert q.vary == "F" and q.info["switched"] is True


def test_a_branch_reads_its_status_words():
    b = Branch(("a", "F"), np.zeros((2, 2)), [0.0, 1.0], [0, 0], ["", ""], [], "F", ("a",), status="step size underflow")
    assert b.status is Status.STEP_UNDERFLOW and b.status == "step size underflow" and not b.success
    with pytest.raises(InputError, match="status"):
        Branch(("a", "F"), np.zeros((1, 2)), [0.0], [0], [""], [], "F", ("a",), status="done")


def test_a_located_fold_carries_its_lens_and_null_vector(tmp_path):
    s = build_overcentre(LU=0.4)
    b = continuation(s, find_equilibrium(s, hold={"theta1": 0.3}, free=["F"]), "F",
                     options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}))
    assert b.status is Status.COMPLETED and b.success
    folds = b.special("LP")
    assert len(folds) == 2
    for p in folds:
        assert p.status is Status.LOCATED and p.vary == "F" and p.unknowns == b.unknowns
        assert p.residual < 1e-13 and p.singular_value < 1e-12
        # the null vector is the state Jacobian's: J_states v = 0 relative to the Jacobian's size
        J = s.jacobian(p.x)[:, [s.index(n) for n in p.unknowns if n != "F"]]
        v = np.asarray(p.null_vector)
        assert np.linalg.norm(J @ v) < 1e-9 * np.linalg.norm(J) * np.linalg.norm(v)
        assert p.info["null_vector"] is p.null_vector and p.info["vary"] == "F"
    doc = json.loads(b.to_json(tmp_path / "b.json").read_text())
    assert doc["status"] == "completed" and {q["status"] for q in doc["special_points"]} == {"located"}
