"""`continue --at` at the start's own value, on a fresh user's spatial door (frame at the global origin, centre of
gravity off the hinge line, a full inertia tensor, a torsion spring and damper about a tilted hinge).

Truth: a rigid body turning by ``phi`` about the unit axis ``n`` through ``P`` has the potential
``V = m g z_cg(phi) + k phi^2 / 2 - M phi`` and the moment of inertia ``n^T J_P n`` (``J_P`` the tensor about the
cg moved to ``P`` by the parallel-axis theorem, invariant under the turn about ``n``); its small motions about an
equilibrium have ``I s^2 + c s + V''(phi) = 0``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

from mechcont.analysis import with_dynamic_stability
from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.models import load_model

DOOR = Path(__file__).parent / "data" / "fresh_user" / "door_3d.toml"
MASS, BETA, K, C, G = 12.0, 0.5, 300.0, 5.0, 9.81
AXIS = np.array([0.0, math.cos(BETA), math.sin(BETA)])
PIVOT = np.array([0.5, -0.2, 1.0])
ARM = np.array([1.1, 0.1, 0.7]) - PIVOT
I_CG = np.array([[0.8, 0.1, -0.05], [0.1, 1.2, 0.2], [-0.05, 0.2, 1.5]])


def _z_cg(phi):
    return PIVOT[2] + Rotation.from_rotvec(phi * AXIS).apply(ARM)[2]


def _truth(moment):
    """(phi, the least stable eigenvalue) of the door at the hinge moment ``moment`` (closed form, derivatives of
    the potential taken analytically: z_cg(phi) = a + b cos(phi) + c sin(phi))."""
    # z of R(phi) r with Rodrigues' formula: r cos + (n x r) sin + n (n . r)(1 - cos)
    along = AXIS * (AXIS @ ARM)
    zc, zs = (ARM - along)[2], np.cross(AXIS, ARM)[2]
    phi = brentq(lambda f: MASS * G * (-zc * math.sin(f) + zs * math.cos(f)) + K * f - moment, -3.0, 3.0)
    assert _z_cg(phi) == pytest.approx(PIVOT[2] + along[2] + zc * math.cos(phi) + zs * math.sin(phi), abs=1e-12)
    stiffness = MASS * G * (-zc * math.cos(phi) - zs * math.sin(phi)) + K
    inertia = AXIS @ (I_CG + MASS * (ARM @ ARM * np.eye(3) - np.outer(ARM, ARM))) @ AXIS
    s = np.roots([inertia, C, stiffness])
    return phi, s[np.argmax(s.real)]


def test_at_value_of_the_start_is_a_row():
    # before: --at M=0 with the branch started at M = 0 gave no UZ row, and the command warned that the branch
    # does not reach M = 0
    m = load_model(str(DOOR))
    branch = continuation(m, find_equilibrium(m), "M", options=ContinuationOptions(bounds={"M": (-200.0, 200.0)}),
                          at=[0.0, 50.0])
    assert branch.point_names() == ["EP1", "UZ1", "UZ2", "EP2"]
    dyn = with_dynamic_stability(m, branch)
    for name, moment in (("UZ1", 0.0), ("UZ2", 50.0)):
        row = dyn[name].values
        assert row["M"] == moment
        phi, s = _truth(moment)
        # e0 = cos(phi/2) and (e1, e2, e3) = sin(phi/2) n: the turn about the hinge axis
        assert 2 * math.acos(row["e0_door"]) == pytest.approx(abs(phi), abs=1e-9)
        assert np.array([row["e1_door"], row["e2_door"], row["e3_door"]]) / math.sin(phi / 2) == pytest.approx(
            AXIS, abs=1e-9)
        i = dyn[name].index
        assert dyn.values[i, dyn.names.index("leading_real")] == pytest.approx(s.real, rel=1e-8)
        assert dyn.values[i, dyn.names.index("leading_frequency")] == pytest.approx(abs(s.imag), rel=1e-8)
