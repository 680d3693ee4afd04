"""A fresh user's retracting strut written in SI and in millimetres and grams (tests/data/fresh_user/strut*.toml).

Truth: an independent one-angle model of the strut (the knee by the intersection of two circles, the potential of
gravity at the offset cg and of the preloaded spring, the drag's virtual work): on the equilibrium branch
``F = V'(phi) / x_b'(phi)``. The mm/g file is the SI one with every length times 1000 and every mass times 1000, so
its answers are the SI ones in those units.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.models import load_model

DATA = Path(__file__).parent / "data" / "fresh_user"
U, S = np.array([-1.0, 0.2]), np.array([-0.9, 0.6])
L_LEG, L_UP, L_LO, M_LEG, M_UP, M_LO, K, L0, P0, G = 2.0, 0.6, 0.7, 60.0, 4.0, 5.0, 8000.0, 0.35, 150.0, 9.81


def _rot(t):
    return np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])


def _pose(phi):
    """Leg cg, axle, knee and the two link centres at leg angle ``phi`` (the knee on the description's side)."""
    centre = L_LEG / 2 * np.array([math.cos(phi), math.sin(phi)])
    lug, cg, axle = (centre + _rot(phi) @ p for p in ([-0.4, 0.0], [0.25, 0.06], [1.0, 0.0]))
    d = lug - U
    dist = float(np.hypot(*d))
    along = (L_UP**2 - L_LO**2 + dist**2) / (2 * dist)
    knee = U + along * d / dist + math.sqrt(L_UP**2 - along**2) * np.array([-d[1], d[0]]) / dist
    return cg, axle, knee, (U + knee) / 2, (knee + lug) / 2


def _potential(phi):
    cg, _, knee, c_up, c_lo = _pose(phi)
    length = float(np.hypot(*(knee - S)))
    return G * (M_LEG * cg[1] + M_UP * c_up[1] + M_LO * c_lo[1]) + P0 * length + K / 2 * (length - L0) ** 2


def _force(phi, h=1e-5):
    """The drag at the axle (+x) that holds the leg at ``phi``: central differences, error ~h^2 relative."""
    dV = (_potential(phi + h) - _potential(phi - h)) / (2 * h)
    dx = (_pose(phi + h)[1][0] - _pose(phi - h)[1][0]) / (2 * h)
    return dV / dx


def test_branch_against_an_independent_model():
    m = load_model(str(DATA / "strut.toml"))
    b = continuation(m, find_equilibrium(m, hold={"theta_leg": -1.8}, free=["F"]), "F",
                     options=ContinuationOptions(bounds={"F": (-3000.0, 3000.0), "theta_leg": (-3.0, -1.6)}))
    phi, F = b.column("theta_leg"), b.column("F")
    assert len(phi) > 10 and phi.min() < -2.9
    truth = np.array([_force(p) for p in phi])
    assert np.max(np.abs(F - truth) / np.maximum(np.abs(truth), 1.0)) < 1e-7


def test_assembled_pose_does_not_depend_on_the_units():
    si, mm = load_model(str(DATA / "strut.toml")), load_model(str(DATA / "strut_mm_g.toml"))
    a, b = si.defaults(), mm.defaults()
    for n in ("theta_leg", "theta_up", "theta_lo"):
        assert b[mm.index(n)] == pytest.approx(a[si.index(n)], abs=1e-9), n
    assert b[mm.index("x_leg")] == pytest.approx(1000 * a[si.index("x_leg")], abs=1e-6)


def test_a_simulation_starts_from_the_same_pose_in_any_units():
    """``simulate --start theta_leg=-2.0`` starts from the pose assembled with the angle held: the same knee
    branch in mm and g as in SI, so the start energy is the SI one in g mm^2/s^2 (x 1e9; printed to 6 digits).
    Before, the mm/g file assembled to its other knee branch: 1112.7 J against -152.9 J. Truth also: the
    start pose (dynamics.assemble) of each to 1e-9 of the leg's length."""
    from mechcont.dynamics import assemble
    from mechcont.models import load_model

    run = make_runner()

    def start_energy(name, unit):
        r = run("simulate", DATA / name, "--start", "theta_leg=-2.0", "--until", "0.01")
        assert r.exit_code == 0, r.output
        m = re.search(rf"# energy \[{re.escape(unit)}\]: start (\S+),", r.output)
        assert m, r.output
        return float(m.group(1))

    si, mm = start_energy("strut.toml", "J"), start_energy("strut_mm_g.toml", "g mm^2/s^2")
    assert mm / 1e9 == pytest.approx(si, rel=1e-5)
    a = load_model(str(DATA / "strut.toml"))
    b = load_model(str(DATA / "strut_mm_g.toml"))
    xa = assemble(a, {"theta_leg": -2.0}, hold=["theta_leg"])
    xb = assemble(b, {"theta_leg": -2.0}, hold=["theta_leg"])
    for n in ("theta_up", "theta_lo"):
        assert xb[b.index(n)] == pytest.approx(xa[a.index(n)], abs=1e-9), n
    for n in ("x_up", "y_up", "x_lo", "y_lo"):
        assert xb[b.index(n)] / 1e3 == pytest.approx(xa[a.index(n)], abs=1e-9 * L_LEG), n


@pytest.mark.parametrize("command", ["simulate", "freefall"])
@pytest.mark.parametrize(("name", "unit", "per_metre"), [("strut.toml", "m", 1.0), ("strut_mm_g.toml", "mm", 1e3)])
def test_a_start_where_the_brace_cannot_reach_says_by_how_much(command, name, unit, per_metre):
    """At theta_leg = -1.5 the lug is further from the brace's top pin U than the two links reach: no pose
    exists. The one-line error names the loop and its miss in the file's length unit. Truth: the miss
    |lug - U| - (L_up + L_lo) = 0.013120 m (the least-squares closure lines the links up and spreads the gap
    over the joints, whose gaps add up to it), printed to 4 digits."""
    r = make_runner()(command, DATA / name, "--start", "theta_leg=-1.5", "--until", "0.01",
                      *(["--lock", "downlock"] if command == "freefall" else []))
    one_line_error(r, "--start", "the loop", "cannot close", "theta_leg = -1.5")
    m = re.search(rf"misses by (\S+) {unit} at best", r.stderr)
    assert m, r.stderr
    phi = -1.5
    lug = L_LEG / 2 * np.array([math.cos(phi), math.sin(phi)]) + _rot(phi) @ np.array([-0.4, 0.0])
    truth = float(np.hypot(*(lug - U))) - (L_UP + L_LO)
    assert float(m.group(1)) / per_metre == pytest.approx(truth, rel=5e-4)
