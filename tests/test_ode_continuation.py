"""Equilibria, folds and stability of ODE files against closed forms.

AUTO's demo ab: du1/dt = -u1 + D (1 - u1) e^u2, du2/dt = -u2 + D B (1 - u1) e^u2 - beta u2.
At an equilibrium the first equation gives D (1 - u1) e^u2 = u1; put in the second, u2 = c u1 with
c = B / (1 + beta); so the branch is D(u1) = u1 e^(-c u1) / (1 - u1), 0 <= u1 < 1. Its folds in D are
where d ln D / d u1 = 1/u1 - c + 1/(1 - u1) = 0, i.e. u1^2 - u1 + 1/c = 0: u1 = (1 -+ sqrt(1 - 4/c)) / 2,
two folds when c > 4 and a cusp at c = 4 (u1 = 1/2, D = e^-2). There df/du is
[[-1/(1 - u1), u1], [-B u1/(1 - u1), B u1 - 1 - beta]].
"""

from pathlib import Path

import numpy as np
import pytest

from mechcont.continuation import continuation, continue_folds, find_equilibrium, run_options
from mechcont.equations import dynamics_of
from mechcont.models import load_model, model_at

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _ab_branch(B: float, beta: float = 3.0):
    model = model_at(EXAMPLES / "ab.toml", {"B": B, "beta": beta})
    x0 = find_equilibrium(model, guess=model.vector({}))
    return model, continuation(model, x0, "D", options=run_options({"D": (0.0, 0.25)}, dsmax=0.05))


def _ab_jacobian(u1, B, beta):
    return np.array([[-1 / (1 - u1), u1], [-B * u1 / (1 - u1), B * u1 - 1 - beta]])


@pytest.mark.parametrize("B", [14.0, 17.0])
def test_ab_branch_points_satisfy_the_closed_form(B):
    model, branch = _ab_branch(B)
    assert len(branch) > 20
    u1, u2, D = branch.column("u1"), branch.column("u2"), branch.column("D")
    c = B / 4.0
    assert np.max(np.abs(u2 - c * u1)) < 1e-10 * max(1.0, float(np.max(np.abs(u2))))
    D_closed = u1 * np.exp(-c * u1) / (1 - u1)
    assert np.max(np.abs(D - D_closed)) < 1e-10
    assert u1.max() > 0.6  # the branch went past the folds (B = 17) and the Hopf point (B = 14)


def test_ab_folds_against_the_closed_form():
    model, branch = _ab_branch(17.0)
    c = 17.0 / 4.0
    root = np.sqrt(1 - 4 / c)
    want = sorted((1 - s * root) / 2 for s in (1, -1))
    lp = sorted((p for p in branch.special_points if p.label == "LP"), key=lambda p: p.x[model.index("u1")])
    assert len(lp) == 2
    for p, u1 in zip(lp, want):
        assert p.x[model.index("u1")] == pytest.approx(u1, abs=1e-10)
        assert p.x[model.index("D")] == pytest.approx(u1 * np.exp(-c * u1) / (1 - u1), abs=1e-12)
    # no fold where c < 4 (B = 14: c = 3.5): D rises monotonically along the branch
    _, branch14 = _ab_branch(14.0)
    assert not [p for p in branch14.special_points if p.label == "LP"]
    assert np.all(np.diff(branch14.column("D")) > 0)


def test_ab_fold_curve_meets_the_cusp_at_c_equal_4():
    model, branch = _ab_branch(17.0)
    lp = next(p for p in branch.special_points if p.label == "LP")
    curve = continue_folds(model, lp, "D", "B", options=run_options({"B": (15.0, 20.0)}, dsmax=0.2))
    B, D, u1 = curve.column("B"), curve.column("D"), curve.column("u1")
    c = B / 4.0
    # every point of the fold curve is a fold of the closed form: u1^2 - u1 + 1/c = 0, D = D(u1)
    assert np.max(np.abs(u1**2 - u1 + 1 / c)) < 1e-10
    assert np.max(np.abs(D - u1 * np.exp(-c * u1) / (1 - u1))) < 1e-10
    cusps = [p for p in curve.special_points if p.label == "CP"]
    assert len(cusps) == 1
    assert cusps[0].x[model.index("B")] == pytest.approx(16.0, abs=1e-6)
    assert cusps[0].x[model.index("D")] == pytest.approx(np.exp(-2.0), abs=1e-6)


@pytest.mark.parametrize("B", [14.0, 17.0])
def test_ab_stability_counts_the_eigenvalues_with_positive_real_part(B):
    model, branch = _ab_branch(B)
    u1 = branch.column("u1")
    labels = branch.labels
    counted = 0
    for i, v in enumerate(u1):
        lam = np.linalg.eigvals(_ab_jacobian(v, B, 3.0))
        if labels[i] in ("LP",) or np.min(np.abs(lam.real)) < 1e-6:
            continue  # on a fold or a Hopf point the count is decided by rounding
        assert branch.n_unstable[i] == int(np.sum(lam.real > 0)), (i, v, lam)
        counted += 1
    assert counted > 20
    # the branch's own eigenvalues are the closed form's (dynamics_of at a branch point)
    i = len(u1) // 2
    got = np.sort_complex(dynamics_of(model).linearise(branch.values[i]).eigenvalues())
    np.testing.assert_allclose(got, np.sort_complex(np.linalg.eigvals(_ab_jacobian(u1[i], B, 3.0))), atol=1e-9)


def test_ab_stability_changes_at_the_hopf_point_of_the_closed_form():
    """B = 14: trace(df/du) = -1/(1 - u1) + 14 u1 - 4 vanishes (with det > 0) at the Hopf points; the
    count goes 0 -> 2 between the two rows that bracket the first."""
    _, branch = _ab_branch(14.0)
    u1, n = branch.column("u1"), branch.n_unstable
    change = int(np.flatnonzero(np.diff(n) != 0)[0])
    assert (n[change], n[change + 1]) == (0, 2)

    def trace(v):
        return -1 / (1 - v) + 14 * v - 4

    assert trace(u1[change]) < 0 < trace(u1[change + 1])


LINEAR = """
[system]
name = "linear"
[parameters]
p = 1.0
k = -1.0
[states]
x = 0.0
y = 0.0
z = 0.0
[rates]
x = "-2*x + y + p"
y = "x - 3*y"
z = "k*z"
"""


def test_a_linear_ode_has_its_exact_equilibrium_and_eigenvalues(tmp_path):
    """dx/dt = -2x + y + p, dy/dt = x - 3y, dz/dt = k z: equilibrium (3p/5, p/5, 0), eigenvalues
    (-5 +- sqrt 5)/2 and k, exactly, along a branch in p; with k > 0 every point of it is unstable in
    one direction."""
    path = tmp_path / "linear.toml"
    path.write_text(LINEAR)
    model = load_model(path)
    x0 = find_equilibrium(model, guess=model.vector({}))
    np.testing.assert_allclose(x0[[model.index(n) for n in "xyz"]], [0.6, 0.2, 0.0], atol=1e-14)
    branch = continuation(model, x0, "p", options=run_options({"p": (-2.0, 2.0)}, dsmax=0.5))
    p = branch.column("p")
    np.testing.assert_allclose(branch.column("x"), 3 * p / 5, atol=1e-13)
    np.testing.assert_allclose(branch.column("y"), p / 5, atol=1e-13)
    assert np.all(branch.n_unstable == 0)
    lam = dynamics_of(model).linearise(x0).eigenvalues()
    np.testing.assert_allclose(np.sort(lam.real), np.sort([(-5 - 5**0.5) / 2, (-5 + 5**0.5) / 2, -1.0]), atol=1e-14)
    assert np.all(lam.imag == 0)
    unstable = model_at(path, {"k": 0.5})
    assert dynamics_of(unstable).linearise(unstable.vector({"x": 0.6, "y": 0.2})).eigenvalues()[0] == \
        pytest.approx(0.5, abs=1e-14)
    b2 = continuation(unstable, unstable.vector({"x": 0.6, "y": 0.2}), "p",
                      options=run_options({"p": (0.0, 2.0)}, dsmax=0.5))
    assert np.all(b2.n_unstable == 1)


def test_an_algebraic_system_folds_at_mu_zero_exactly_and_has_no_stability(tmp_path):
    """[equations] x = "x^2 - mu": the branch x = +-sqrt(mu) folds at mu = 0, x = 0."""
    path = tmp_path / "square.toml"
    path.write_text('[system]\nname = "square"\n[parameters]\nmu = 1.0\n[states]\nx = 1.0\n'
                    '[equations]\nx = "x^2 - mu"\n')
    model = load_model(path)
    branch = continuation(model, model.vector({}), "mu", options=run_options({"x": (-1.5, 1.5)}, dsmax=0.2))
    x, mu = branch.column("x"), branch.column("mu")
    np.testing.assert_allclose(mu, x**2, atol=1e-12)
    lp = [p for p in branch.special_points if p.label == "LP"]
    assert len(lp) == 1
    assert abs(lp[0].x[model.index("mu")]) < 1e-12 and abs(lp[0].x[model.index("x")]) < 1e-6
    assert np.all(branch.n_unstable == -1)  # AUTO's IPS = 0: no dynamics, so no stability


def test_ode_full_vectors_are_full_vector_row_by_row():
    # the Dynamics protocol's batch: every row the point-by-point full vector, the parameters kept
    from mechcont.equations import OdeDynamics
    from mechcont.errors import InputError
    m = load_model(str(EXAMPLES / "ab.toml"))
    dyn = OdeDynamics(m)
    x = m.defaults()
    x[m.index("D")] = 0.17
    Z = np.random.default_rng(5).normal(size=(7, len(dyn.state_names)))
    rows = dyn.full_vectors(Z, x)
    assert rows.shape == (7, len(m.names))
    for z, row in zip(Z, rows):
        np.testing.assert_array_equal(row, dyn.full_vector(z, x))
    with pytest.raises(InputError, match="Z"):
        dyn.full_vectors(np.zeros((2, len(dyn.state_names) + 1)), x)
