"""The Hopf system's Newton stops without a confirming iteration (issue 35's speed criterion) and still lands on
the truth: x''' + a1 x'' + a2 x' + a3 x = 0 has its Hopf point at a1 = a3 / a2 with omega^2 = a2 (Routh-Hurwitz)."""

import math

import numpy as np
import pytest
from hopf_models import S

from mechcont.continuation._hopf_point import HopfTest, polish_hopf
from mechcont.continuation._problem import EquilibriumProblem
from mechcont.equations import dynamics_of, ode_model

A2, A3 = 2.5, 4.0


def _polish(a1: float) -> tuple[float, float, int]:
    """``(a1, omega, evaluations of the equilibrium system)`` of the Hopf point polished from ``a1``."""
    x, y, z = S["x"], S["y"], S["z"]
    m = ode_model("rh", {"x": 0.0, "y": 0.0, "z": 0.0}, {"a1": a1, "a2": A2, "a3": A3},
                  {"x": y, "y": z, "z": -S["a3"] * x - S["a2"] * y - S["a1"] * z})
    m.compile()
    problem = EquilibriumProblem(m, m.vector({}), "a1", ["x", "y", "z"], stability=False)
    calls = [0]
    evaluate = problem.evaluate

    def counted(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        calls[0] += 1
        return evaluate(u)

    problem.evaluate = counted  # type: ignore[method-assign]
    u, pair, residual = polish_hopf(HopfTest(dynamics_of(m), m), problem, problem.u_of(m.vector({})))
    assert residual < 1e-13
    return float(problem.full(u)[m.index("a1")]), pair.omega, calls[0]


def test_a_located_point_is_confirmed_by_one_evaluation():
    a1, omega, calls = _polish(A3 / A2)
    assert a1 == pytest.approx(A3 / A2, rel=1e-14) and omega == pytest.approx(math.sqrt(A2), rel=1e-14)
    assert calls == 1  # the converged start is returned as it is, not stepped once more and evaluated again


@pytest.mark.parametrize("start", [1.3, 2.2])
def test_stopping_on_the_predicted_step_keeps_the_point_exact(start):
    """Newton stops where quadratic convergence puts the next step below the tolerance (1e-14 of the unknowns)
    and returns the stepped point unconfirmed: it must be the truth to that tolerance."""
    a1, omega, _ = _polish(start)
    assert a1 == pytest.approx(A3 / A2, rel=1e-14) and omega == pytest.approx(math.sqrt(A2), rel=1e-14)
