"""``mechcont downlock`` / ``design`` on a description that declares its downlock condition; runs that
stop short are named on stderr; ``design --levels 2``; the signed lock margin."""

from __future__ import annotations

import json

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from scipy.optimize import brentq

from mechcont.analysis import downlock
from mechcont.continuation import read_branch_table
from mechcont.models import load_model
from mechcont.models.nose_gear_geometry import aligned_downlock_force, defaults


@pytest.fixture(scope="module")
def run():
    return make_runner()


def test_downlock_on_a_description_needs_no_flags_and_reports_the_unlock_force(tmp_path, run):
    out = tmp_path / "k.csv"
    r = run("downlock", "lockstay.toml", "--vary", "k", "--bounds", "k=10000:30000", "--out", out)
    assert r.exit_code == 0, r.output
    assert "aligned=0 held" in r.output and "(the unlock force)" in r.output
    assert r.stderr == ""
    rows = read_branch_table(out)[0]
    system = load_model("lockstay.toml")
    api = downlock(system, "k", {"k": (10000.0, 30000.0)})
    assert [float(x["k"]) for x in rows] == pytest.approx(list(api.branch["k"]), rel=1e-12)
    assert [float(x["F"]) for x in rows] == pytest.approx(list(api.branch["F"]), rel=1e-12)
    at = next(x for x in rows if float(x["k"]) == 20000.0)
    assert float(at["unlock_F"]) == pytest.approx(api.unlock.unlock_force, rel=1e-12)
    assert f"{api.unlock.unlock_force:.6g}" in r.output
    assert all(float(x["unlock_F"]) > float(x["F"]) for x in rows)  # a lock: the fold lies beyond the downlock force


def test_downlock_json_carries_the_unlock_column(tmp_path, run):
    out = tmp_path / "k.json"
    r = run("downlock", "lockstay.toml", "--condition", "aligned", "--vary", "k", "--bounds", "k=15000:25000",
            "--out", out)
    assert r.exit_code == 0, r.output
    doc = json.loads(out.read_text())
    assert len(doc["columns"]["unlock_F"]) == len(doc["columns"]["F"]) > 3


def test_a_run_that_stops_early_is_a_warning_on_stderr(run):
    r = run("downlock", "lockstay.toml", "--vary", "k", "--bounds", "k=5000:40000", "--max-steps", "2")
    assert r.exit_code == 0, r.output
    warnings = [ln for ln in r.stderr.splitlines() if ln.startswith("warning: ")]
    assert len(warnings) == 2
    for w in warnings:
        assert "downlock branch in k (aligned = 0) stopped early at k = " in w and "max_steps" in w


@pytest.mark.parametrize("args, words", [
    (("--condition", "nope"), ("--condition", "unknown condition 'nope'", "aligned, leg_angle")),
    (("--condition", "aligned", "--hold", "theta_leg=-1.35"), ("--condition", "either")),
    (("--max-steps", "0"), ("--max-steps", "positive")),
])
def test_downlock_bad_condition_flags(tmp_path, run, args, words):
    out = tmp_path / "never.csv"
    one_line_error(run("downlock", "lockstay.toml", "--vary", "k", "--bounds", "k=5000:40000", *args, "--out", out),
                   *words)
    assert not out.exists()


def test_design_with_two_levels_and_a_signed_lock_margin(tmp_path, run):
    """Two levels used to fail (the F = 0 boundary started outside the LU range). LU = 1.35 m does
    not lock unaided at l_sp1 = 0.1 m: its margin is negative, the distance to the F = 0 crossing."""
    out = tmp_path / "t.csv"
    r = run("design", "nose_gear", "--bounds", "l_sp1=-0.175:0.175", "--bounds", "LU=1.25:1.35", "--levels", "2",
            "--out", out)
    assert r.exit_code == 0, r.output
    assert r.stderr == ""
    rows = read_branch_table(out)[0]
    assert [float(x["LU (m)"]) for x in rows] == [1.25, 1.35]
    margin = "lock margin to F=0 (+ locks, - does not) (m)"
    unaided = "locks unaided at l_sp1=0.1 m"
    p = defaults()
    for row in rows:
        F0 = aligned_downlock_force({**p, "LU": float(row["LU (m)"]), "l_sp1": 0.1})
        assert row[unaided] == ("yes" if F0 > 0 else "no")
        if row[margin] != "none":
            m = float(row[margin])
            assert (m > 0) == (F0 > 0)
    low = rows[1]
    assert low[unaided] == "no"
    zero = brentq(lambda x: aligned_downlock_force({**p, "LU": 1.35, "l_sp1": x}), 0.1, 0.175, xtol=1e-14)
    assert float(low[margin]) == pytest.approx(-(zero - 0.1), rel=1e-6)


def test_design_on_a_description_and_its_warnings(run):
    r = run("design", "lockstay.toml", "--x", "k", "--y", "Sy", "--bounds", "k=5000:40000", "--bounds", "Sy=-0.1:0.1",
            "--levels", "2")
    assert r.exit_code == 0, r.output
    assert r.stderr == "" and "| Sy (m) |" in r.output
    r = run("design", "lockstay.toml", "--x", "k", "--y", "Sy", "--bounds", "k=5000:40000", "--bounds", "Sy=-0.1:0.1",
            "--levels", "2", "--max-steps", "2")
    assert r.exit_code == 0, r.output
    warnings = [ln for ln in r.stderr.splitlines() if ln.startswith("warning: ")]
    assert warnings and all("stopped early at" in w for w in warnings)
    assert any(w.startswith("warning: Sy = -0.1: downlock branch in k") for w in warnings)


def test_design_parameters_default_to_the_bounds_names_in_order(run):
    named = run("design", "lockstay.toml", "--x", "k", "--y", "Sy", "--bounds", "k=5000:40000", "--bounds", "Sy=-0.1:0.1",
                "--levels", "2")
    inferred = run("design", "lockstay.toml", "--bounds", "k=5000:40000", "--bounds", "Sy=-0.1:0.1", "--levels", "2")
    assert named.exit_code == 0 and inferred.exit_code == 0, inferred.output
    assert inferred.output == named.output
    one_line_error(run("design", "lockstay.toml", "--bounds", "k=5000:40000"), "--bounds", "two design parameters")


def test_a_signed_margin_is_never_positive_for_a_design_that_does_not_lock():
    from mechcont.analysis.design import DesignRow

    row = DesignRow(1.35, -139.97, ((0.16, 0.175),), (), float("nan"), 0.06)
    assert not row.locks_unaided and row.lock_margin == -0.06
    assert np.isnan(DesignRow(1.0, -1.0, (), (), float("nan")).lock_margin)
