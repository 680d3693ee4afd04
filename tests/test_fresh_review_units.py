"""A fresh user's retracting strut written in SI and in millimetres and grams (tests/data/fresh_user/strut*.toml).

Truth: an independent one-angle model of the strut (the knee by the intersection of two circles, the potential of
gravity at the offset cg and of the preloaded spring, the drag's virtual work): on the equilibrium branch
``F = V'(phi) / x_b'(phi)``. The mm/g file is the SI one with every length times 1000 and every mass times 1000, so
its answers are the SI ones in those units.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

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


@pytest.mark.xfail(strict=True, reason="the generators' first assembly takes unweighted minimum-norm steps in the "
                                       "file's units (mechanism/_generate.py, weighted=False): in mm the lengths "
                                       "outweigh the angles and the assembled pose differs (reported, not fixed)")
def test_assembled_pose_does_not_depend_on_the_units():
    si, mm = load_model(str(DATA / "strut.toml")), load_model(str(DATA / "strut_mm_g.toml"))
    a, b = si.defaults(), mm.defaults()
    for n in ("theta_leg", "theta_up", "theta_lo"):
        assert b[mm.index(n)] == pytest.approx(a[si.index(n)], abs=1e-9), n
    assert b[mm.index("x_leg")] == pytest.approx(1000 * a[si.index("x_leg")], abs=1e-6)
