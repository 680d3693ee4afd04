"""Answers do not depend on the units a description is written in (issue 32, item 4).

Shipped examples are rewritten with lengths x L and masses x M (seconds kept; forces then x L M, moments
x L^2 M, stiffnesses x M, ...; tests/corpus/scaling.py), their unit labels renamed as a user would write
them ("mm", "g mm/s^2"), and the same command must give the same answer in the new units: a contact
reaction from `check`, a release (non-smooth fold) from `continue --stops`, the folds of a continuation,
the time and speed of a freefall onto its lock. Closed forms are the truth where they exist (each file's
comment gives it); elsewhere the SI run is. Tolerances: the closed forms are met to 1e-9 relative (the
printed 10 digits); a simulation's event time and speed to 1e-6 relative (its error control is relative
to the states' scales, so the same steps are taken in any units, up to rounding).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner
from corpus.scaling import write_scaled
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

ROOT = Path(__file__).parents[1]
DATA = ROOT / "tests" / "data"
#: mm and g, mm and kg, km and kg, micrometres and kg: (length factor, mass factor) from SI
NAMED = [(1e3, 1e3), (1e3, 1.0), (1e-3, 1.0), (1e6, 1.0)]
SCALES = st.one_of(st.sampled_from(NAMED),
                   st.tuples(st.sampled_from([1e-3, 1e-2, 10.0, 1e2, 1e4]), st.sampled_from([1e-3, 1.0, 1e3])))
SETTINGS = settings(max_examples=2, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


def _number(pattern: str, text: str) -> float:
    m = re.search(pattern, text)
    assert m, f"{pattern!r} not in:\n{text}"
    return float(m.group(1))


@SETTINGS
@given(scale=SCALES)
@example(scale=(1e6, 1.0))
@example(scale=(1e3, 1e3))
def test_a_stop_release_in_any_units(tmp_path_factory, scale):
    """pendulum_lock: on its stop at 0.3 rad, released at F = M0 - m g L/2 cos(0.3) (N m): x L^2 M."""
    L, M = scale
    path = write_scaled(DATA / "pendulum_lock.toml", tmp_path_factory.mktemp("u") / "lock.toml", L, M, labels=True)
    moment = L * L * M
    r = make_runner()("continue", path, "--vary", "F", "--bounds", f"F={-5 * moment}:{30 * moment}",
                      "--bounds", "theta_bar=-3:3", "--stops", "--start", "angle=0.2")
    assert r.exit_code == 0, r.output
    truth = (15.0 - 2.0 * 9.81 * 1.0 / 2 * math.cos(0.3)) * moment
    released = _number(r"NSF1: non-smooth fold at F \([^)]*\) = (\S+)", r.output)
    assert released == pytest.approx(truth, rel=1e-9)


@SETTINGS
@given(scale=SCALES)
@example(scale=(1e6, 1.0))
@example(scale=(1e-3, 1.0))
def test_check_finds_the_same_contact_in_any_units(tmp_path_factory, scale):
    """check: pendulum_lock's stop reaction M0 - m g L/2 cos(0.3) (N m), and the spatial pendulum's
    m g d_min / (2 L) (N, tests/data/spatial/pendulum_stop_3d.toml), in the new units."""
    L, M = scale
    d = tmp_path_factory.mktemp("u")
    run = make_runner()
    r = run("check", write_scaled(DATA / "pendulum_lock.toml", d / "lock.toml", L, M, labels=True))
    assert r.exit_code == 0, r.output
    assert _number(r"reaction R_top = (\S+)", r.output) == pytest.approx(
        (15.0 - 9.81 * math.cos(0.3)) * L * L * M, rel=1e-5)  # check prints 6 digits
    r = run("check", write_scaled(DATA / "spatial" / "pendulum_stop_3d.toml", d / "p3.toml", L, M, labels=True))
    assert r.exit_code == 0, r.output
    assert _number(r"reaction R_floor = (\S+)", r.output) == pytest.approx(2.0 * 9.81 * 0.72 / 1.6 * L * M, rel=1e-5)


@pytest.mark.parametrize("scale", NAMED, ids=["mm-g", "mm-kg", "km-kg", "um-kg"])
def test_a_loop_closes_in_any_units(tmp_path, scale):
    """The toggle clamp with a stop assembles at its held angle in any units: its loop closes to the
    rounding of its lengths (in micrometres, 3e-11 "m" is 3e-17 of a metre: the loop is closed)."""
    L, M = scale
    r = make_runner()("check", write_scaled(DATA / "toggle_clamp_stop.toml", tmp_path / "clamp.toml", L, M, labels=True))
    assert r.exit_code == 0, r.output
    assert "is open by" not in r.output and "cannot close" not in r.output


@pytest.mark.parametrize("scale", NAMED, ids=["mm-g", "mm-kg", "km-kg", "um-kg"])
def test_a_clamp_on_its_stop_in_any_units(tmp_path, scale):
    """The toggle clamp's stop reaction from `check` is the SI file's x L^2 M."""
    L, M = scale
    run = make_runner()
    si = run("check", DATA / "toggle_clamp_stop.toml")
    r = run("check", write_scaled(DATA / "toggle_clamp_stop.toml", tmp_path / "clamp.toml", L, M, labels=True))
    assert r.exit_code == 0, r.output
    assert _number(r"reaction R_over = (\S+)", r.output) == pytest.approx(
        _number(r"reaction R_over = (\S+)", si.output) * L * L * M, rel=1e-5)


@SETTINGS
@given(scale=SCALES)
@example(scale=(1e3, 1e3))
@example(scale=(1e6, 1.0))
def test_folds_in_any_units(tmp_path_factory, scale):
    """The overcentre's two folds in F (N: x L M) and theta1 (rad) are the SI file's in the new units."""
    L, M = scale
    d = tmp_path_factory.mktemp("u")
    src = ROOT / "src" / "mechcont" / "data" / "overcentre.toml"
    run = make_runner()

    def folds(path, force):
        out = path.with_suffix(".csv")
        r = run("continue", path, "--start", "theta1=0.3", "--vary", "F", "--bounds", f"F={-100 * force}:{120 * force}",
                "--out", out)
        assert r.exit_code == 0, r.output
        rows = [ln.split(",") for ln in out.read_text().splitlines()]
        head = rows[0]
        i, f, t = head.index("label"), next(k for k, h in enumerate(head) if h.startswith("F [")), head.index("theta1 [rad]")
        return sorted((float(row[f]), float(row[t])) for row in rows[1:] if row[i].startswith("LP"))

    si = folds(write_scaled(src, d / "si.toml", 1.0, 1.0), 1.0)
    scaled = folds(write_scaled(src, d / "scaled.toml", L, M, labels=True), L * M)
    assert len(si) == len(scaled) == 2
    for (f1, t1), (f2, t2) in zip(si, scaled):
        assert f2 == pytest.approx(f1 * L * M, rel=1e-9)
        assert t2 == pytest.approx(t1, abs=1e-9)


@pytest.mark.parametrize("scale", [(1e3, 1e3), (1e-3, 1.0)], ids=["mm-g", "km-kg"])
def test_a_freefall_in_any_units(tmp_path, scale):
    """The freefall leg (examples/freefall_leg.toml, U = 40 m/s: x L) locks at the same time, at the
    same angular speed, with its lock's reaction x L^2 M, as in SI."""
    L, M = scale
    run = make_runner()

    def fall(path, u, force, energy):
        r = run("freefall", path, "--start", "angle=3.0", "--lock", "downlock", "--until", "3", "--set", f"U={u}")
        assert r.exit_code == 0, r.output
        assert "outcome: locked" in r.output
        # each printed value names the unit it is in: the file's (declared) units
        return (_number(r"time to lock: (\S+) s", r.output), _number(r"impact speed at the lock: (\S+) rad/s", r.output),
                _number(r"peak stop reaction downlock: (\S+)", r.output),
                _number(rf"peak damper tension actuator: (\S+) {re.escape(force)} at", r.output),
                _number(rf"# energy \[{re.escape(energy)}\]: start (\S+),", r.output))

    si = fall(write_scaled(ROOT / "examples" / "freefall_leg.toml", tmp_path / "si.toml", 1.0, 1.0), 40.0, "N", "J")
    named = {(1e3, 1e3): ("g mm/s^2", "g mm^2/s^2"), (1e-3, 1.0): ("kg km/s^2", "kg km^2/s^2")}[scale]
    new = fall(write_scaled(ROOT / "examples" / "freefall_leg.toml", tmp_path / "new.toml", L, M, labels=True), 40.0 * L,
               *named)
    assert np.allclose(new, np.array(si) * [1.0, 1.0, L * L * M, L * M, L * L * M], rtol=1e-5, atol=0)  # 6 digits


@pytest.mark.parametrize("src", [ROOT / "examples" / "main_gear.toml", ROOT / "examples" / "freefall_leg.toml",
                                 DATA / "toggle_clamp_stop.toml", DATA / "fresh_user" / "strut.toml",
                                 DATA / "spatial" / "overcentre_3d.toml"],
                         ids=["main_gear", "freefall_leg", "clamp", "strut", "overcentre_3d"])
def test_the_first_assembly_in_any_units(tmp_path, src):
    """A description rewritten in mm and g (declared) assembles to the pose its SI file assembles to (its
    coordinates and conditions): the first assembly's minimum-norm steps are taken in SI coordinates
    (a length in mm weighs 1/1000 of its number). Truth: the SI build, every state to 1e-9 of its scale
    (the closure's tolerance is 1e-12 relative). The planar strut (unweighted steps in mm chose another
    pose, -89.8 deg for -88.1 deg) and the redundant spatial overcentre (bodies 1, 2: positions x1, y1 taken
    for angles) assembled elsewhere before."""
    from corpus.scaling import unit_factor

    from mechcont.models import load_model

    si = load_model(str(write_scaled(src, tmp_path / "si.toml", 1.0, 1.0)))
    mm = load_model(str(write_scaled(src, tmp_path / "mm.toml", 1e3, 1e3, labels=True)))
    a, b = si.defaults(), mm.defaults()
    states = [v for v in si.variables if v.kind == "state" and v.unit in ("m", "rad", "")]
    assert any(v.unit == "m" for v in states) and any(v.unit == "rad" for v in states)
    for v in states:
        got = b[mm.index(v.name)] / unit_factor(v.unit, 1e3, 1e3)
        assert got == pytest.approx(a[si.index(v.name)], rel=1e-9, abs=1e-9 * abs(v.scale)), v.name
