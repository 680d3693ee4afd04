"""The continuation engine on small systems with known answers."""

import numpy as np
import pytest
import sympy as sp

from mechcont import Model, Variable
from mechcont.continuation import ContinuationOptions, ValueEvent, continuation, continue_folds, find_equilibrium
from mechcont.errors import ConvergenceError, InputError


def make(name, exprs, states, params):
    vs = [Variable(n, "state", v) for n, v in states.items()] + [Variable(n, "parameter", v) for n, v in params.items()]
    sym = {v.name: v.symbol for v in vs}
    return Model(name, vs, [e(sym) for e in exprs]).compile()


def test_circle_has_two_folds_located_exactly():
    # x^2 + p^2 = 1: folds in p at p = +-1, x = 0
    s = make("circle", [lambda v: v["x"] ** 2 + v["p"] ** 2 - 1], {"x": 1.0}, {"p": 0.0})
    b = continuation(s, s.vector({"x": 1.0, "p": 0.0}), "p", options=ContinuationOptions(max_steps=200, stability=False,
                                                                                          bounds={"x": (-0.5, 2)}))
    lps = b.special("LP")
    assert len(lps) == 2
    ps = sorted(lp["p"] for lp in lps)
    assert ps == pytest.approx([-1.0, 1.0], abs=1e-12)
    for lp in lps:
        assert abs(lp["x"]) < 1e-7  # fold at x = 0; p error is quadratic in x error
    # both ends at the x = -0.5 bound, located exactly
    eps = b.special("EP")
    assert [round(e["x"], 15) for e in eps] == [-0.5, -0.5]


@pytest.mark.parametrize("direction", [1, -1])
def test_passes_a_fold_in_either_direction(direction):
    s = make("circle", [lambda v: v["x"] ** 2 + v["p"] ** 2 - 1], {"x": 1.0}, {"p": 0.0})
    b = continuation(s, s.vector({"x": 1.0, "p": 0.0}), "p", direction=direction,
                     options=ContinuationOptions(max_steps=200, stability=False, bounds={"x": (-0.9, 2)}))
    lp = b["LP1"]
    assert lp["p"] == pytest.approx(direction * 1.0, abs=1e-12)
    # after the fold the branch continues on the lower half (x < 0) to the bound
    assert b["x"].min() == pytest.approx(-0.9, abs=1e-14)
    assert np.all(np.abs(b["x"] ** 2 + b["p"] ** 2 - 1) < 1e-10)


def test_does_not_skip_between_close_branches():
    # two parallel branches x = sin(p) and x = sin(p) + eps; a large dsmax must not jump
    eps = 1e-3
    s = make("parallel", [lambda v: (v["x"] - sp.sin(v["p"])) * (v["x"] - sp.sin(v["p"]) - eps)],
             {"x": 0.0}, {"p": 0.0})
    b = continuation(s, s.vector({"x": 0.0, "p": 0.0}), "p", direction=1,
                     options=ContinuationOptions(ds=0.5, dsmax=2.0, max_steps=5000, stability=False, bounds={"p": (-1, 10)}))
    assert b["p"][-1] == pytest.approx(10.0)
    # residual_tol 1e-10 with |dG/dx| = eps bounds the error by 1e-7; a jump would give eps
    assert np.max(np.abs(b["x"] - np.sin(b["p"]))) < 1e-6
    assert not b.special("BP")  # the sign flip of det between the branches is not reported as a BP


def test_branch_point_detected_on_pitchfork():
    # G = x (x^2 - p): trivial branch x = 0 crosses x^2 = p at p = 0
    s = make("pitchfork", [lambda v: v["x"] * (v["x"] ** 2 - v["p"])], {"x": 0.0}, {"p": -1.0})
    b = continuation(s, s.vector({"x": 0.0, "p": -1.0}), "p", direction=1,
                     options=ContinuationOptions(max_steps=100, stability=False, bounds={"p": (-2, 1)}))
    bps = b.special("BP")
    assert len(bps) == 1 and bps[0]["p"] == pytest.approx(0.0, abs=1e-10)
    assert not b.special("LP")


def test_user_event_located():
    s = make("circle", [lambda v: v["x"] ** 2 + v["p"] ** 2 - 1], {"x": 1.0}, {"p": 0.0})
    b = continuation(s, s.vector({"x": 1.0, "p": 0.0}), "p", direction=1, events=[ValueEvent("x", 0.5, label="HALF")],
                     options=ContinuationOptions(stability=False, bounds={"x": (0.2, 2)}))
    (pt,) = b.special("HALF")
    assert pt["x"] == pytest.approx(0.5, abs=1e-12)
    assert pt["p"] == pytest.approx(np.sqrt(0.75), abs=1e-10)


def test_cusp_of_normal_form():
    # G = x^3 - mu x - p: fold curve p = -2 (mu/3)^(3/2) ..., cusp at mu = p = 0
    s = make("cusp", [lambda v: v["x"] ** 3 - v["mu"] * v["x"] - v["p"]], {"x": 1.0}, {"p": 0.0, "mu": 1.0})
    b = continuation(s, s.vector({"x": 1.0, "p": 0.0, "mu": 1.0}), "p",
                     options=ContinuationOptions(stability=False, bounds={"x": (-2, 2)}))
    lp = b["LP1"]
    assert abs(lp["x"]) == pytest.approx(np.sqrt(1 / 3), abs=1e-12)
    fc = continue_folds(s, lp, vary="p", free="mu", options=ContinuationOptions(bounds={"mu": (-0.5, 1.5)}))
    (cp,) = fc.special("CP")
    assert cp["mu"] == pytest.approx(0.0, abs=1e-10) and cp["p"] == pytest.approx(0.0, abs=1e-10)
    # along the fold curve: mu = 3 x^2, p = -2 x^3
    assert np.max(np.abs(fc["mu"] - 3 * fc["x"] ** 2)) < 1e-10
    assert np.max(np.abs(fc["p"] + 2 * fc["x"] ** 3)) < 1e-10


def test_start_not_a_solution_is_an_input_error():
    s = make("circle", [lambda v: v["x"] ** 2 + v["p"] ** 2 - 1], {"x": 1.0}, {"p": 0.0})
    with pytest.raises(InputError, match="start"):
        continuation(s, s.vector({"x": 0.3, "p": 0.0}), "p")


def test_newton_failure_reports_and_returns_partial():
    s = make("none", [lambda v: v["x"] ** 2 + v["p"] ** 2 + 1], {"x": 1.0}, {"p": 0.0})
    with pytest.raises(ConvergenceError, match="did not converge") as exc:
        find_equilibrium(s, guess={"x": 2.0})
    assert exc.value.partial is not None and exc.value.partial.shape == (2,)


def test_step_size_underflow_returns_what_was_computed():
    # sqrt(p) type end: x^2 = p has a fold; with a domain wall the branch must end cleanly
    s = make("wall", [lambda v: v["x"] - sp.sqrt(v["p"])], {"x": 1.0}, {"p": 1.0})
    b = continuation(s, s.vector({"x": 1.0, "p": 1.0}), "p", direction=-1,
                     options=ContinuationOptions(stability=False, max_steps=500, dsmin=1e-6))
    assert len(b) > 3
    assert b.status == "step size underflow"
    assert "dsmin" in b.message and b.labels[0] == "EP"  # one direction, ordered by arclength
    assert np.all(b["p"] > 0)


@pytest.mark.parametrize("kwargs, field", [
    ({"ds": -1}, "ds"), ({"dsmin": 1, "dsmax": 0.1}, "dsmin"), ({"max_steps": 0}, "max_steps"),
    ({"bounds": {"p": (1, 0)}}, "p"), ({"bounds": {"p": (1, 1)}}, "p"), ({"bounds": {"p": ("a", 2)}}, "p"),
    ({"ds": float("nan")}, "ds"),
])
def test_bad_options(kwargs, field):
    with pytest.raises(InputError) as exc:
        ContinuationOptions(**kwargs)
    assert exc.value.field == field
    assert "\n" not in str(exc.value)


def test_lens_errors_name_the_problem():
    s = make("circle", [lambda v: v["x"] ** 2 + v["p"] ** 2 - 1], {"x": 1.0}, {"p": 0.0})
    with pytest.raises(InputError, match="unknown variable"):
        continuation(s, s.vector({"x": 1.0}), "q")
    with pytest.raises(InputError, match="free 1 more"):
        find_equilibrium(s, hold={"x": 0.5})
    x = find_equilibrium(s, hold={"x": 0.5}, free=["p"], guess={"p": 0.5})
    assert x[1] ** 2 == pytest.approx(0.75)


@pytest.mark.parametrize("kind", ["pitchfork", "transcritical"])
def test_branch_switching_at_bp(kind):
    from mechcont.continuation import switch_branch

    if kind == "pitchfork":  # x (x^2 - p): new branch x^2 = p
        s = make(kind, [lambda v: v["x"] * (v["x"] ** 2 - v["p"])], {"x": 0.0}, {"p": -1.0})
        on_new = lambda x, p: x ** 2 - p  # noqa: E731
    else:  # x (x - p): new branch x = p
        s = make(kind, [lambda v: v["x"] * (v["x"] - v["p"])], {"x": 0.0}, {"p": -1.0})
        on_new = lambda x, p: x - p  # noqa: E731
    opts = ContinuationOptions(max_steps=200, stability=False, bounds={"p": (-1, 1), "x": (-1.5, 1.5)})
    b = continuation(s, s.vector({"x": 0.0, "p": -1.0}), "p", direction=1, options=opts)
    (bp,) = b.special("BP")
    nb = switch_branch(s, bp, options=opts)
    assert len(nb) > 10
    assert np.max(np.abs(on_new(nb["x"], nb["p"]))) < 1e-9
    assert (nb["x"] > 0.1).any() and (nb["x"] < -0.1).any()  # both directions followed
    assert nb.labels[int(np.argmin(np.abs(nb.s)))] == "BP"


def test_every_point_solves_the_equations(overcentre):
    # the corrector may return its last correction unevaluated (Newton's linear model makes
    # its residual of the order of the correction squared): check each point afresh
    from mechcont.continuation._newton import residual_met

    s = make("circle", [lambda v: v["x"] ** 2 + v["p"] ** 2 - 1], {"x": 1.0}, {"p": 0.0})
    b = continuation(s, s.vector({"x": 1.0, "p": 0.0}), "p", options=ContinuationOptions(max_steps=200, stability=False,
                                                                                          bounds={"x": (-0.5, 2)}))
    assert np.abs(b["x"] ** 2 + b["p"] ** 2 - 1).max() < 1e-12  # residual_tol is 1e-10
    x0 = find_equilibrium(overcentre, hold={"theta1": 0.3}, free=["F"])
    b = continuation(overcentre, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}))
    idx = [overcentre.index(n) for n in (*b.unknowns, "F")]
    for x in b.values:
        J = overcentre.jacobian(x)[:, idx]
        assert residual_met(overcentre.residual(x), J, x[idx], 1e-10)
