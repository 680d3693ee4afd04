"""What the printed stability eigenvalues are, planar and spatial (documented in docs/reference.md).

``mechcont check`` prints the eigenvalues of the reduced tangent stiffness ``Z^T K Z``, ``Z`` an
orthonormal basis of the allowed motions in the model's own coordinates ``q``. Their unit is
that of ``K`` along a unit step of ``q``, which mixes metres with radians (planar) or with Euler
parameters (spatial, about half an angle each), so the same mechanism written planar and spatial
prints different values; only their signs (the number of unstable directions) are independent of
the coordinates. The coordinate-free number is omega^2 (1/s^2), the eigenvalues of
``(Z^T K Z, Z^T M Z)``: checked here on the toggle press of tests/data against its closed form
``V''(phi) / M(phi)`` (V = k (2 L cos(phi) - L0)^2 / 2 - F L sin(phi); two uniform bars of mass m,
the first pinned at O: M = m L^2 (1/3 + 1/12 + 9/4 sin^2(phi) + 1/4 cos^2(phi))).
"""

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from mechcont.continuation import find_equilibrium
from mechcont.models import load_model

DATA = Path(__file__).parent / "data"
FILES = {"planar": DATA / "press.toml", "spatial": DATA / "spatial" / "press_3d.toml"}
L, K, M = 0.5, 2000.0, 1.0


def _closed_form(phi, F, L0):
    Vpp = K * ((2 * L * np.sin(phi)) ** 2 - (2 * L * np.cos(phi) - L0) * 2 * L * np.cos(phi)) + F * L * np.sin(phi)
    mass = M * L**2 * (1 / 3 + 1 / 12 + 2.25 * np.sin(phi) ** 2 + 0.25 * np.cos(phi) ** 2)
    return Vpp, Vpp / mass


@pytest.mark.parametrize("phi", [0.3, 0.7, 1.2])
def test_omega_squared_is_the_same_planar_and_spatial_the_raw_eigenvalue_is_not(phi):
    raw = {}
    for kind, path in FILES.items():
        s = load_model(path)
        x = find_equilibrium(s, hold={"phi": phi}, free=["F"])
        mech = s.mechanics
        Z = mech.allowed_motions(x)
        Kr, Mr = Z.T @ mech.tangent_stiffness(x) @ Z, Z.T @ mech.mass(x) @ Z
        omega2 = scipy.linalg.eigvalsh(Kr, Mr)
        Vpp, expected = _closed_form(phi, x[s.index("F")], x[s.index("L0")])
        assert omega2 == pytest.approx([expected], rel=1e-9), kind
        st = mech.stability(x)
        assert st.conservative and st.n_unstable == int(Vpp < 0)
        raw[kind] = float(st.eigenvalues[0])
    # the printed eigenvalue depends on the coordinates: same sign, different value (here about 3x)
    assert np.sign(raw["planar"]) == np.sign(raw["spatial"])
    assert abs(raw["spatial"] / raw["planar"] - 1) > 0.5
