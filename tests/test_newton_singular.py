"""The square Newton solve (find_equilibrium's): a singular or ill-conditioned start is refused with where and
why, a well-conditioned one converges to its closed form, and no SVD is taken to learn that it is well-conditioned."""

import numpy as np
import pytest

from mechcont import Model, Variable, _dense
from mechcont.continuation import find_equilibrium
from mechcont.continuation._newton import SINGULAR_CONDITION, newton_square
from mechcont.errors import ConvergenceError


def _model(name, exprs, states, params):
    vs = [Variable(n, "state", v) for n, v in states.items()] + [Variable(n, "parameter", v) for n, v in params.items()]
    sym = {v.name: v.symbol for v in vs}
    return Model(name, vs, [e(sym) for e in exprs]).compile()


def _linear(A, b):
    return (lambda u: A @ u - b), (lambda u: A.copy())


def test_exactly_singular_jacobian_is_reported_at_its_iteration_along_the_free_unknown():
    """x^2 = y, y = -1 from (1, -1): Newton's first step goes to x = (x0^2 + c) / (2 x0) = 0 exactly, where the
    Jacobian [[2x, -1], [0, 1]] loses its first column: refused at iteration 2, x named as not fixed, the partial
    iterate the point of the refusal."""
    s = _model("parabola", [lambda v: v["x"] ** 2 - v["y"], lambda v: v["y"] - v["c"]], {"x": 1.0, "y": -1.0},
               {"c": -1.0})
    with pytest.raises(ConvergenceError, match="singular Jacobian at iteration 2") as exc:
        find_equilibrium(s)
    text = str(exc.value)
    assert "null direction along x)" in text and "\n" not in text, text
    partial = s.as_dict(exc.value.partial)
    assert partial["x"] == 0.0 and partial["y"] == pytest.approx(-1.0, abs=1e-15)


def test_singular_at_the_first_iteration_names_the_dependent_pair():
    """x + y = 1, 2x + 2y = 2: one equation twice, null direction (1, -1)/sqrt2: both unknowns named
    (in either order: equal components)."""
    f, J = _linear(np.array([[1.0, 1.0], [2.0, 2.0]]), np.array([1.0, 2.0]))
    with pytest.raises(ConvergenceError, match="singular Jacobian at iteration 1") as exc:
        newton_square(f, J, np.zeros(2), names=["x", "y"])
    along = str(exc.value).split("null direction along ")[1].split(")")[0]
    assert sorted(along.split(", ")) == ["x", "y"], along


@pytest.mark.parametrize("gap, refused", [(2.0 ** -50, True), (1e-13, False), (1e-10, False)])
def test_refusal_follows_the_exact_condition_number(gap, refused):
    """A = [[1, 1], [1, 1 + gap]] (rows already of unit size): condition number ~4 / gap, by its closed-form
    singular values. Above SINGULAR_CONDITION refused at iteration 1 (rounding would make any answer noise);
    below it (4e13: where a cheap estimate is too close to the limit to decide; 4e10) solved, to the accuracy the
    condition allows: |u - u*| <= cond eps |u*| (times 4 for the residual's own rounding)."""
    A = np.array([[1.0, 1.0], [1.0, 1.0 + gap]])
    g = A[1, 1] - 1.0  # the gap as stored (exact: Sterbenz)
    # symmetric positive definite: singular values = eigenvalues, (2 + g +- sqrt(4 + g^2)) / 2, product g
    smax = (2.0 + g + np.sqrt(4.0 + g * g)) / 2.0
    cond = smax * smax / g
    assert (cond > SINGULAR_CONDITION) == refused
    u_true = np.array([1.0, 2.0])
    f, J = _linear(A, A @ u_true)
    if refused:
        with pytest.raises(ConvergenceError, match="singular Jacobian at iteration 1"):
            newton_square(f, J, np.zeros(2))
    else:
        u, _ = newton_square(f, J, np.zeros(2))
        assert np.max(np.abs(u - u_true)) <= 4 * cond * np.finfo(float).eps * np.max(np.abs(u_true))


def test_non_finite_jacobian_is_reported_as_such_with_its_equation():
    def jac(u):
        return np.array([[1.0, 0.0], [np.nan, 1.0]])

    with pytest.raises(ConvergenceError, match=r"non-finite Jacobian at iteration 1 .*equation\(s\) 1"):
        newton_square(lambda u: u - 1.0, jac, np.zeros(2))


def test_well_conditioned_system_converges_to_the_closed_form_without_an_svd(monkeypatch):
    """x^2 + y^2 = 4 with x = y, in metres and kilometres (scales 1 and 1e3): (sqrt2, sqrt2) to rounding, found
    with no singular value decomposition (the solver's condition estimate comes from its LU factors)."""
    def refuse(*args, **kwargs):
        raise AssertionError("an SVD was taken on a well-conditioned system")

    for where in (np.linalg, _dense):
        for name in ("svd", "cond", "singular_values"):
            if hasattr(where, name):
                monkeypatch.setattr(where, name, refuse)

    for k in (1.0, 1e3):
        def fun(u, k=k):
            x, y = u[0], u[1] / k
            return np.array([x ** 2 + y ** 2 - 4.0, x - y])

        def jac(u, k=k):
            x, y = u[0], u[1] / k
            return np.array([[2 * x, 2 * y / k], [1.0, -1.0 / k]])

        u, it = newton_square(fun, jac, np.array([1.0, 0.5 * k]), scale=np.array([1.0, k]))
        assert u == pytest.approx([np.sqrt(2.0), k * np.sqrt(2.0)], rel=1e-14)
        assert it <= 8
