"""What one acceleration of the time simulation evaluates: the mechanics' terms from one argument vector, the
applied forces' Jacobian a stop's curvature is taken from, and the solve through a constant M^-1 with its
multipliers kept (checked against the separate evaluations, finite differences and the augmented system)."""

import math

import numpy as np
import pytest

from mechcont.dynamics import assemble
from mechcont.dynamics._udwadia_kalaba import ConstrainedDynamics, fundamental_equation, inverse_sqrt
from mechcont.models import build_overcentre, model_from_text

#: A bar pinned off its centre of gravity: its mass matrix depends on its angle (velocity-product forces).
OFFSET_BAR = """
[mechanism]
name = "offset_bar"
[parameters]
g = { value = 9.81, unit = "m/s^2" }
c = { value = 3.0, unit = "N s/m" }
[ground]
O = [0, 0]
G = [0.5, 1.0]
[bodies.bar]
mass = 2.0
length = 1.0
inertia = 0.1
cg = [0.2, 0.15]
points = { p = [-0.3, 0], tip = [0.4, 0] }
initial = { theta = 0.3 }
[joints.pivot]
type = "revolute"
a = "ground.O"
b = "bar.p"
[dampers.d]
a = "ground.G"
b = "bar.tip"
c = "c"
[gravity]
g = "g"
"""


@pytest.fixture(scope="module")
def models():
    overcentre = build_overcentre(LU=0.4, c=40.0)  # constant, diagonal mass matrix; a damper (forces in qdot)
    x_oc = assemble(overcentre, {"theta1": 1.0, "theta2": math.pi - 1.0}, hold=["theta1"])
    bar = model_from_text(OFFSET_BAR, "offset_bar.toml")
    return [(overcentre, x_oc, False), (bar, assemble(bar, {}), True)]  # (model, assembled x, M depends on q)


def _velocities(system, seed):
    return np.random.default_rng(seed).normal(size=len(system.mechanics.coordinates))


def test_acceleration_terms_are_the_separate_evaluations(models):
    for system, x, varying in models:
        mech, qd = system.mechanics, _velocities(system, 1)
        M = mech.mass(x)
        A, gamma, phi, Q, Mt = mech.acceleration_terms(x, qd, drift=True, varying_mass=varying)
        np.testing.assert_allclose(A, mech.phi_q(x), rtol=1e-15, atol=0)
        np.testing.assert_allclose(gamma, mech.gamma(x, qd), rtol=1e-15, atol=1e-300)
        np.testing.assert_allclose(phi, mech.phi(x), rtol=1e-15, atol=1e-300)
        want = mech.applied_forces(x, qd) + (mech.inertial_forces(x, qd) if varying else 0.0)
        np.testing.assert_allclose(Q, want, rtol=1e-15, atol=1e-300)
        if varying:
            np.testing.assert_allclose(Mt, M, rtol=1e-15, atol=0)
        else:
            assert Mt is None
        assert mech.acceleration_terms(x, qd, drift=False, varying_mass=varying)[2] is None


def test_force_jacobian_is_the_derivative_of_the_applied_forces(models):
    for system, x, _ in models:
        mech = system.mechanics
        q = np.array([system.index(c) for c in mech.coordinates])
        D = mech.force_jacobian(x)
        h = 1e-6
        fd = np.zeros_like(D)
        for j, i in enumerate(q):
            xp, xm = x.copy(), x.copy()
            xp[i] += h
            xm[i] -= h
            fd[:, j] = (mech.applied_forces(xp) - mech.applied_forces(xm)) / (2 * h)
        scale = max(1.0, float(np.max(np.abs(D))))
        np.testing.assert_allclose(D, fd, rtol=0, atol=1e-6 * scale)  # central differences: O(h^2) and rounding
        np.testing.assert_allclose(D, -mech.tangent_stiffness(x, np.zeros(mech.n_constraints)), rtol=1e-15, atol=0)


def test_constant_mass_solve_keeps_its_multipliers_and_is_the_fundamental_equation(models):
    system, x, _ = models[0]
    dyn = ConstrainedDynamics(system, x)
    q, qd = x[dyn.q_index], _velocities(system, 2)
    qdd = dyn.acceleration(0.0, q, qd)
    xx = dyn.full(0.0, q)
    A, b = dyn.joint_rows(xx, qd)
    Q, M = dyn.forces(xx, qd), system.mechanics.mass(xx)
    np.testing.assert_allclose(qdd, fundamental_equation(inverse_sqrt(M), Q, A, b), rtol=1e-10, atol=1e-12)
    known = dyn.recall(0.0, q, qd)
    assert known is not None and known[1] is not None  # the solve's multipliers, for the history's reactions
    z = known[1]
    scale = float(np.max(np.abs(M @ qdd)) + np.max(np.abs(Q)))
    np.testing.assert_allclose(M @ qdd, Q + A.T @ z, rtol=0, atol=1e-12 * scale)  # M qddot = Q + A^T z
    np.testing.assert_allclose(A @ qdd, b, rtol=0, atol=1e-12 * float(np.max(np.abs(b)) + 1.0))
