"""The compiled corrector (``_ckernel``) against the Python one and against closed forms.

Both run the same algorithm (``PseudoArclength._correct`` / ``tangent``); they differ only in
the rounding of their LU factorisations, so branches agree to a few ulps of each value's
scale, and every answer each gives is checked against the closed form where there is one.
"""

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from mechcont import Model, Variable
from mechcont.continuation import ContinuationOptions, _kernel, continuation, find_equilibrium
from mechcont.continuation._api import _Equilibria
from mechcont.continuation._corrector import PseudoArclength
from mechcont.continuation._events import BranchPointEvent
from mechcont.continuation._newton import residual_met
from mechcont.models import build_overcentre, load_model
from mechcont.models.nose_gear import build_nose_gear

needs_kernel = pytest.mark.skipif(not _kernel.AVAILABLE, reason="the compiled corrector was not built (no C compiler)")


def make(name, exprs, states, params):
    vs = [Variable(n, "state", v) for n, v in states.items()] + [Variable(n, "parameter", v) for n, v in params.items()]
    sym = {v.name: v.symbol for v in vs}
    return Model(name, vs, [e(sym) for e in exprs]).compile()


def both(monkeypatch, run):
    """``run()`` with the compiled corrector, then with the Python one."""
    monkeypatch.delenv("MECHCONT_PURE_PYTHON", raising=False)
    compiled = run()
    monkeypatch.setenv("MECHCONT_PURE_PYTHON", "1")
    python = run()
    monkeypatch.delenv("MECHCONT_PURE_PYTHON")
    return compiled, python


def test_the_kernel_is_built_where_a_compiler_is():
    # a silently failed build would leave every branch on the slower corrector
    if shutil.which("cc") is None and shutil.which("gcc") is None:
        pytest.skip("no C compiler on this machine: the Python corrector runs")
    assert _kernel.AVAILABLE


def _stepper(s, x, vary, options=None):
    options = options or ContinuationOptions(stability=False)
    problem = _Equilibria(s, x, vary, [n for n in s.state_names], stability=False)
    return PseudoArclength(problem, options), problem


def test_a_problem_hands_its_compiled_model_by_name():
    from mechcont.continuation._problem import CompiledModel

    s = build_overcentre(LU=0.4)
    x = find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])
    _, problem = _stepper(s, x, "F")
    m = problem.compiled_model()
    assert isinstance(m, CompiledModel) and m.fold is None and m.base is problem.base
    assert np.array_equal(m.idx, problem.idx) and m.n_out >= len(problem.scale) - 1


@needs_kernel
def test_a_step_on_the_circle_lands_on_the_hyperplane_with_the_exact_tangent(monkeypatch):
    # x^2 + p^2 = 1 from (1, 0), tangent (0, 1), sigma = 0.1: the hyperplane p = 0.1 cuts it at x = sqrt(0.99)
    monkeypatch.delenv("MECHCONT_PURE_PYTHON", raising=False)
    s = make("circle", [lambda v: v["x"] ** 2 + v["p"] ** 2 - 1], {"x": 1.0}, {"p": 0.0})
    eng, _ = _stepper(s, s.vector({"x": 1.0, "p": 0.0}), "p")
    assert eng.kernel is not None
    z0 = np.array([1.0, 0.0]) / eng.D
    t0 = np.array([0.0, 1.0]) * eng.D
    t0 /= np.linalg.norm(t0)
    st, iters, why = eng.step(z0, t0, 0.1 / eng.D[1] / t0[1])  # to the hyperplane p = 0.1
    assert why == "" and 1 <= iters <= 5
    x, p = st.u
    assert x == pytest.approx(math.sqrt(1 - p * p), abs=1e-13)
    # the tangent of the circle at (x, p), in scaled coordinates, unit, oriented along t0
    t = np.array([-p, x]) / eng.D
    t /= np.linalg.norm(t)
    # the tangent and Jacobian are those of the last evaluated iterate, within newton_tol (1e-10) of
    # the returned point (the corrector does not evaluate its last correction: see PseudoArclength)
    assert st.tangent == pytest.approx(t, abs=1e-10)
    assert st.jac == pytest.approx(np.array([[2 * x, 2 * p]]) * eng.D, abs=3e-10)
    # the branch-point test from the kernel's factors equals the one from the determinant
    plain = BranchPointEvent().value(None, type(st)(st.z, st.u, st.tangent, st.jac, st.x))
    assert st.bp_test == pytest.approx(plain, rel=1e-13)


@needs_kernel
@pytest.mark.parametrize("case", ["outside the domain", "singular", "no solution on the hyperplane"])
def test_a_failed_step_says_what_the_python_corrector_says(monkeypatch, case):
    if case == "outside the domain":  # sqrt(x) = p: a step to x < 0 has no real residual
        s = make("root", [lambda v: sp.sqrt(v["x"]) - v["p"]], {"x": 0.01}, {"p": 0.1})
        x, t, sigma = {"x": 0.01, "p": 0.1}, np.array([-1.0, 0.0]), 0.5
    elif case == "singular":  # (x - p)^2 = 0: its Jacobian vanishes on the solution, bordered by (1, 1)/sqrt2
        s = make("double", [lambda v: (v["x"] - v["p"]) ** 2], {"x": 0.0}, {"p": 0.0})
        x, t, sigma = {"x": 0.0, "p": 0.0}, np.array([1.0, 1.0]) / math.sqrt(2), 0.0
    else:  # x^2 + p^2 = 1 and the hyperplane p = 2 far outside it
        s = make("circle", [lambda v: v["x"] ** 2 + v["p"] ** 2 - 1], {"x": 1.0}, {"p": 0.0})
        x, t, sigma = {"x": 1.0, "p": 0.0}, np.array([0.0, 1.0]), 2.0

    def run():
        eng, _ = _stepper(s, s.vector(x), "p")
        return eng.step(s.vector(x)[[0, 1]] / eng.D, t, sigma)

    (st_c, _, why_c), (st_p, _, why_p) = both(monkeypatch, run)
    assert st_c is None and st_p is None
    assert why_c == why_p and why_c


DATA = Path(__file__).parent / "data" / "spatial"


@needs_kernel
@pytest.mark.parametrize("model", ["overcentre", "circle", "nose gear", "stiff compliance"])
def test_branches_agree_with_the_python_corrector(monkeypatch, model):
    if model == "overcentre":
        s = build_overcentre(LU=0.4)
        x0 = find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])
        vary, hold, opts = "F", (), ContinuationOptions(bounds={"F": (-200.0, 200.0)})
    elif model == "circle":
        s = make("circle", [lambda v: v["x"] ** 2 + v["p"] ** 2 - 1], {"x": 1.0}, {"p": 0.0})
        x0, vary, hold = s.vector({"x": 1.0, "p": 0.0}), "p", ()
        opts = ContinuationOptions(max_steps=200, stability=False, bounds={"x": (-0.5, 2)})
    elif model == "nose gear":  # 25 equations, from the downlocked pose in the lock actuator's force F
        s = build_nose_gear()
        x0 = find_equilibrium(s, hold={"theta4": 0.0}, free=["F"], guess=s.downlock.pose)
        vary, hold, opts = "F", (), ContinuationOptions(bounds={"theta4": (-0.3, 0.3)})
    else:  # a joint compliance of 1e10 N/m: the corrections stall at the rounding floor (step_noise)
        s = load_model(DATA / "bennett_compliant.toml", k_D=1e10, c_D=1e10)
        x0 = find_equilibrium(s, hold={"crank": 0.0}, free=["M"])
        vary, hold, opts = "M", (), ContinuationOptions(bounds={"crank": (-1.05, 1.0)})
    # a reaction of a joint of stiffness k is known only to k times the rounding of the 1 m-sized
    # coordinates (2.2e-16 m x 1e10 N/m = 2.2e-6 N a unit in the last place): tens of those
    noise = 1e-4 if model == "stiff compliance" else 0.0

    def run():
        return continuation(s, x0, vary, hold=hold, options=opts)

    a, b = both(monkeypatch, run)
    assert a.status == b.status
    labels = [p.label for p in b.special_points]
    assert [p.label for p in a.special_points] == labels and ("LP" in labels or model == "nose gear")
    tol = 1e-9 * np.maximum(np.abs(b.values).max(axis=0), 1e-300) + noise
    for pa, pb in zip(a.special_points, b.special_points):  # located to machine precision by both
        assert (np.abs(pa.x - pb.x) <= tol).all()
    if model == "stiff compliance":
        # at the rounding floor the two roundings can stop a corrector an iteration apart and the
        # step control then takes other steps: every point must still solve the equations
        idx = [s.index(n) for n in (*a.unknowns, vary)]
        for x in a.values:
            assert residual_met(s.residual(x), s.jacobian(x)[:, idx], x[idx], 1e-10)
        assert abs(len(a.values) - len(b.values)) <= 0.02 * len(b.values)
        return
    # the same steps (step control sees the same iteration counts), so point by point alike too
    assert a.values.shape == b.values.shape
    assert (np.abs(a.values - b.values) <= tol).all()
    # at a fold the reduced stiffness is singular and rounding decides the count (count_unstable):
    # compare it everywhere else
    regular = np.array([label not in ("LP", "BP") for label in b.labels])
    assert (a.n_unstable == b.n_unstable)[regular].all()


@needs_kernel
def test_fold_curves_agree_with_the_python_corrector(monkeypatch):
    # the fold problem has no compiled model of its own (its last row is a determinant): the kernel
    # calls its evaluate back; the overcentre's fold at LU = 0.1 m followed to its cusp
    from mechcont.continuation import continue_folds

    s = build_overcentre(LU=0.1)
    x0 = find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])
    lp = min(continuation(s, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.4, 1.4)})).special("LP"),
             key=lambda p: p["F"])

    def run():
        return continue_folds(s, lp, "F", "LU", options=ContinuationOptions(bounds={"LU": (0.1, 2.0)}), direction=1,
                              stop_at_cusp=True)

    a, b = both(monkeypatch, run)
    assert a.labels[-1] == b.labels[-1] == "CP"
    assert a.values.shape == b.values.shape
    tol = 1e-9 * np.maximum(np.abs(b.values).max(axis=0), 1e-300)
    assert (np.abs(a.values - b.values) <= tol).all()
