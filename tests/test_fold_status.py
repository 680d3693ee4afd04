"""Honest special points: a fold that could not be polished is never shown as located."""

import csv
import json

import pytest
from cli_helpers import make_runner

import mechcont.continuation._api as api
from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.errors import ConvergenceError
from mechcont.models import build_overcentre
from mechcont.models.overcentre import symmetric_folds

OPTS = ContinuationOptions(bounds={"theta1": (-1.2, 1.2)})


def _branch():
    s = build_overcentre(LU=0.4)
    return continuation(s, find_equilibrium(s, hold={"theta1": 0.3}, free=["F"]), "F", options=OPTS)


def _failing_polish(*args, **kwargs):
    raise ConvergenceError("fold polish did not converge (forced by the test)")


def test_located_folds_carry_their_precision():
    b = _branch()
    folds = b.special("LP")
    assert len(folds) == 2 and not b.approximate
    exact = sorted(F for _, F in symmetric_folds(1.5, 1.0, 1.0, 9.81, 127.0, 0.4))
    assert sorted(p["F"] for p in folds) == pytest.approx(exact, rel=1e-10)
    for p in folds:
        assert p.status == "located" and p.located and p.tag == "LP"
        assert p.info["residual"] < 1e-13 and p.info["singular_value"] < 1e-12


def test_a_failed_polish_is_marked_approximate_everywhere(monkeypatch, tmp_path):
    monkeypatch.setattr(api, "polish_fold", _failing_polish)
    b = _branch()
    folds = b.special("LP")
    assert len(folds) == 2
    for p in folds:
        assert p.status == "approximate" and not p.located and p.tag == "LP?"
        assert "forced by the test" in p.info["reason"]
    assert b.approximate == folds
    b.to_csv(tmp_path / "b.csv")
    with open(tmp_path / "b.csv") as fh:
        labels = [r["label"] for r in csv.DictReader(fh) if r["label"]]
    assert labels.count("LP?") == 2 and "LP" not in labels
    b.to_json(tmp_path / "b.json")
    doc = json.loads((tmp_path / "b.json").read_text())
    assert [p["status"] for p in doc["special_points"] if p["label"] == "LP"] == ["approximate"] * 2


def test_cli_warns_about_approximate_folds(monkeypatch, tmp_path):
    monkeypatch.setattr(api, "polish_fold", _failing_polish)
    out = tmp_path / "b.csv"
    r = make_runner()("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
                      "--bounds", "theta1=-1.2:1.2", "--out", out)
    assert r.exit_code == 0, r.output
    assert "LP1?" in r.stdout and "LP2?" in r.stdout
    warnings = [ln for ln in r.stderr.splitlines() if "approximate" in ln]
    assert len(warnings) == 2 and all(ln.startswith("warning: LP") for ln in warnings)
    # the approximate fold is still reachable by its number when drawing
    monkeypatch.undo()
    d = make_runner()("draw", "overcentre", "--point", f"{out}:LP2", "--out", tmp_path / "lp2.png")
    assert d.exit_code == 0, d.output
