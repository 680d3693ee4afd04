"""How the corrector reports a failed correction, with the default (raw LAPACK) and a custom solver.

The default dense solver runs without its per-call checks inside the corrector; a non-finite
residual, a singular bordered matrix and a non-finite Jacobian must still each be reported with
their own reason, exactly as through the checked solver.
"""

import numpy as np
import pytest

from mechcont._status import Status
from mechcont.continuation import ContinuationOptions, DenseLU
from mechcont.continuation._corrector import _NOT_FINITE, PseudoArclength
from mechcont.continuation._problem import ContinuationProblem


class Circle(ContinuationProblem):
    """x^2 + p^2 = 1 (u = (x, p)); the residual is NaN for x > 2 (outside the domain), and the
    Jacobian NaN for p > 5 while the residual stays finite."""

    names, param_index, scale = ("x", "p"), 1, np.ones(2)

    def residual(self, u):
        return np.array([u[0] ** 2 + u[1] ** 2 - 1.0 if u[0] <= 2 else np.nan])

    def jacobian(self, u):
        return np.array([[2 * u[0], 2 * u[1] if u[1] <= 5 else np.nan]])

    def full(self, u):
        return np.array(u, float)


class Checked(DenseLU):
    """The same LU through the checked solve (a subclass: not the raw fast path)."""


@pytest.mark.parametrize("solver", [DenseLU(), Checked()], ids=["raw", "checked"])
def test_corrector_converges_and_names_each_failure(solver):
    eng = PseudoArclength(Circle(), ContinuationOptions(linear_solver=solver))
    assert eng._dense == (type(solver) is DenseLU)
    # a converging step along the circle from (1, 0), tangent (0, 1): lands on x^2 + p^2 = 1 at p = 0.1
    z, jac, _ = eng.correct(np.array([1.0, 0.1]), np.array([0.0, 1.0]))
    assert z is not None and z[0] ** 2 + z[1] ** 2 == pytest.approx(1.0, abs=1e-12) and z[1] == pytest.approx(0.1)
    # predictor beyond x = 2: the residual is NaN
    assert eng.correct(np.array([3.0, 0.0]), np.array([1.0, 0.0]))[:2] == (None, _NOT_FINITE)
    assert eng.correct(np.array([3.0, 0.0]), np.array([1.0, 0.0]))[1] is Status.NOT_FINITE
    # at (0, 1) with the border along x: [[0, 2], [1, 0]] is regular, but a border along p makes
    # [[0, 2], [0, 1]] exactly singular
    assert eng.correct(np.array([0.0, 1.0]), np.array([0.0, 1.0]))[:2] == (None, "singular bordered Jacobian")
    # a finite residual with a NaN Jacobian entry
    assert eng.correct(np.array([0.5, 6.0]), np.array([1.0, 0.0]))[:2] == (None, _NOT_FINITE)


@pytest.mark.parametrize("solver", [DenseLU(), Checked()], ids=["raw", "checked"])
def test_tangent_is_the_unit_null_vector_or_singular(solver):
    eng = PseudoArclength(Circle(), ContinuationOptions(linear_solver=solver))
    z = np.array([0.6, 0.8])
    t = eng.tangent(z, np.array([-1.0, 1.0]))  # the circle's tangent (-0.8, 0.6), oriented along the border
    assert t == pytest.approx([-0.8, 0.6], abs=1e-15)
    with pytest.raises(np.linalg.LinAlgError, match="singular tangent system"):
        eng.tangent(np.array([0.0, 1.0]), np.array([0.0, 1.0]))  # [[0, 2], [0, 1]]


@pytest.mark.parametrize("compiled", [False, True], ids=["python", "compiled"])
def test_a_whole_step_names_each_failure_in_the_same_words(monkeypatch, compiled):
    # PseudoArclength.step: the compiled corrector (calling this Python problem's evaluate back) and the
    # Python one report the same reason for each failure above, and land on the circle alike
    from mechcont.continuation import _kernel

    if compiled and not _kernel.AVAILABLE:
        pytest.skip("the compiled corrector was not built (no C compiler)")
    monkeypatch.setenv("MECHCONT_PURE_PYTHON", "0" if compiled else "1")
    eng = PseudoArclength(Circle(), ContinuationOptions())
    assert (eng.kernel is not None) == compiled
    st, _, why = eng.step(np.array([1.0, 0.0]), np.array([0.0, 1.0]), 0.1)
    assert why == "" and st.u[0] == pytest.approx(np.sqrt(0.99), abs=1e-12) and st.u[1] == pytest.approx(0.1)
    assert eng.step(np.array([3.0, 0.0]), np.array([1.0, 0.0]), 0.0)[1:] == (1, _NOT_FINITE)
    assert eng.step(np.array([0.0, 1.0]), np.array([0.0, 1.0]), 0.0)[2] == "singular bordered Jacobian"
    assert eng.step(np.array([0.5, 6.0]), np.array([1.0, 0.0]), 0.0)[2] == _NOT_FINITE
