"""The Hopf polish of an ODE model (issue 35's speed criterion: "Hopf location as fast as LP location"): the
linearisation is the equilibrium Jacobian's state columns and each Newton step one square solve with g's exact
gradient. Checked against AUTO's ab demo's Hopf point solved independently (scipy's fsolve on f = 0, trace J = 0
with the Jacobian differentiated by hand), and against the bordered step of the same system through dynamics that
are not recognised as an ODE model's (differenced linearisations)."""

import math

import numpy as np
import pytest
from hopf_models import ab_hopf_independent, ab_jacobian, ab_model

from mechcont.continuation._hopf_point import HopfTest, polish_hopf
from mechcont.continuation._problem import EquilibriumProblem
from mechcont.equations import OdeDynamics, dynamics_of

B, BETA = 14.0, 3.0
#: near ab's Hopf point at B = 14, beta = 3 (about 1e-3 off in each unknown): Newton has work to do
START = {"u1": 0.156, "u2": 0.546, "D": 0.1311}


class _CountedOde(OdeDynamics):
    """An ODE model's dynamics, counting its linearisations."""

    linearisations = 0

    def linearise(self, x):
        self.linearisations += 1
        return super().linearise(x)


class _Plain:
    """The same dynamics, not an OdeDynamics (the generic path), counting its linearisations."""

    def __init__(self, model):
        self.inner = dynamics_of(model)
        self.state_names = self.inner.state_names
        self.linearisations = 0

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def linearise(self, x):
        self.linearisations += 1
        return self.inner.linearise(x)


def _polish(model, dynamics):
    problem = EquilibriumProblem(model, model.vector(START), "D", ["u1", "u2"], stability=False)
    u, pair, residual = polish_hopf(HopfTest(dynamics, model), problem, problem.u_of(model.vector(START)))
    return problem.full(u), pair, residual


def test_an_ode_models_hopf_point_needs_no_linearisation_of_its_own_and_is_the_truth():
    m = ab_model(B, BETA)
    dyn = dynamics_of(m)
    x, pair, residual = _polish(m, dyn)
    u1, u2, D = (x[m.index(n)] for n in ("u1", "u2", "D"))
    truth = ab_hopf_independent([u1, u2, D], B, BETA)
    assert [u1, u2, D] == pytest.approx(truth, rel=1e-13)
    assert pair.omega == pytest.approx(math.sqrt(np.linalg.det(ab_jacobian(*truth, B, BETA))), rel=1e-13)
    assert residual < 1e-14
    # the pair is that of the Jacobian's state columns: the dynamics' own linearisation there is the same matrix
    assert pair.A == pytest.approx(np.asarray(dyn.linearise(x).A), rel=1e-15, abs=0)


def test_the_square_step_and_the_bordered_step_locate_the_same_point():
    m = ab_model(B, BETA)
    counted = _CountedOde(m)
    x, pair, _ = _polish(m, counted)
    assert counted.linearisations == 0  # A came with the residual's Jacobian
    plain = _Plain(m)
    x_b, pair_b, _ = _polish(m, plain)
    assert plain.linearisations > 0  # the generic path linearises (and differences) the dynamics
    assert x_b == pytest.approx(x, rel=1e-13, abs=1e-15)
    assert pair_b.omega == pytest.approx(pair.omega, rel=1e-13)
