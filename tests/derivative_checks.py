"""Finite-difference checks of every generated derivative of a system (as in test_mechanism_jacobians)."""

import numpy as np


def fd(f, x, h):
    """Central-difference Jacobian of ``f`` at ``x`` (columns: the components of ``x``)."""
    cols = []
    for i in range(len(x)):
        e = np.zeros(len(x))
        e[i] = h
        cols.append((f(x + e) - f(x - e)) / (2 * h))
    return np.array(cols).T


def close(A, B, tol=1e-6):
    scale = max(1.0, np.abs(B).max(initial=0.0))
    assert np.abs(A - B).max(initial=0.0) <= tol * scale


def check_derivatives(system, seed=1, h=1e-6):
    """Jacobian, its directional derivative, Phi_q, gamma, stiffness and curvature term vs differences."""
    rng = np.random.default_rng(seed)
    x = system.defaults() + 0.01 * rng.standard_normal(len(system.names))
    close(system.jacobian(x), fd(system.residual, x, h))
    v = rng.standard_normal(len(x))
    close(system.jacobian_derivative(x, v), fd(lambda y: system.jacobian(y) @ v, x, h))
    mech = system.mechanics
    qi = mech.q_index

    def with_q(q):
        y = x.copy()
        y[qi] = q
        return y

    q0 = x[qi]
    qd = rng.standard_normal(len(qi))
    close(mech.phi_q(x), fd(lambda q: mech.phi(with_q(q)), q0, h))
    close(mech.gamma(x, qd), -fd(lambda q: mech.phi_q(with_q(q)) @ qd, q0, h) @ qd)
    close(mech.tangent_stiffness(x, np.zeros(len(mech.constraints))),
          -fd(lambda q: mech.applied_forces(with_q(q), qd * 0), q0, h))
    lam = rng.standard_normal(len(mech.constraints))
    curv = mech.tangent_stiffness(x, lam) - mech.tangent_stiffness(x, np.zeros_like(lam))
    close(curv, fd(lambda q: mech.phi_q(with_q(q)).T @ lam, q0, h))
