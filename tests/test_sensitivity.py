"""Exact sensitivities (implicit-function theorem) against central differences of re-solved quantities
and against the overcentre's closed-form fold load differentiated by hand."""

from pathlib import Path

import numpy as np
import pytest

from mechcont.analysis import downlock_point
from mechcont.analysis.sensitivity import (
    derivative_unit,
    downlock_sensitivity,
    equilibrium_sensitivity,
    fold_sensitivity,
)
from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.continuation._fold_point import polish_fold
from mechcont.errors import ConvergenceError, InputError

DATA = Path(__file__).parent / "data"
OVERCENTRE_STATES = ["x1", "y1", "theta1", "x2", "y2", "theta2"]


def step(system, x, name, rel=1e-4):
    """A central-difference step for ``name``: ``rel`` of its value (of its scale when it is zero)."""
    v = x[system.index(name)]
    return rel * (abs(v) if v != 0 else system.variable(name).scale)


def central(f, system, x, name, rel=1e-4):
    """Central difference of ``f`` along ``name``, Richardson-extrapolated from steps h and h/2.

    Truncation error O(h^4) (~1e-16 relative with h = 1e-4 of the value, where a plain
    central difference is off by 1e-5 near the overcentre's steep end); the re-solved
    quantity's own error (Newton to ~1e-12 relative) divided by h stays below 1e-7.
    """
    h = step(system, x, name, rel)
    i = system.index(name)

    def diff(d):
        lo, hi = x.copy(), x.copy()
        lo[i] -= d
        hi[i] += d
        return (f(hi) - f(lo)) / (2 * d)

    return (4 * diff(h / 2) - diff(h)) / 3


def relative_error(a, b):
    return np.max(np.abs(np.asarray(a) - np.asarray(b))) / max(np.max(np.abs(b)), 1e-300)


@pytest.fixture(scope="module")
def overcentre_branch(overcentre):
    x0 = find_equilibrium(overcentre, values={"LU": 0.4}, hold={"theta1": 0.3}, free=["F"])
    return continuation(overcentre, x0, "F", options=ContinuationOptions(bounds={"F": (-200.0, 200.0)}))


def test_overcentre_fold_load_matches_closed_form(overcentre, overcentre_branch):
    """F* = W + s k L u^{3/2}, u = 1 - (LU/L)^{2/3}, W = (m1 + m2) g / 2, differentiated by hand:
    dF*/dk = s L u^{3/2}, dF*/dLU = -s k u^{1/2} (LU/L)^{-1/3}, dF*/dL = s k u^{1/2} (both bars
    together: dL1 + dL2), dF*/dm1 = g/2, dF*/dg = (m1 + m2)/2."""
    L, k, LU, g, m1, m2 = 1.5, 127.0, 0.4, 9.81, 1.0, 1.0
    r = LU / L
    u = 1 - r ** (2 / 3)
    folds = overcentre_branch.special("LP")
    assert len(folds) == 2
    signs = set()
    for fold in folds:
        sens = fold.sensitivity(overcentre, ["k", "LU", "L1", "L2", "m1", "g"])
        s = 1.0 if sens.value > (m1 + m2) * g / 2 else -1.0
        signs.add(s)
        assert sens.value == pytest.approx((m1 + m2) * g / 2 + s * k * L * u ** 1.5, rel=1e-10)
        assert sens["k"] == pytest.approx(s * L * u ** 1.5, rel=1e-9)
        assert sens["LU"] == pytest.approx(-s * k * u ** 0.5 * r ** (-1 / 3), rel=1e-9)
        assert sens["L1"] + sens["L2"] == pytest.approx(s * k * u ** 0.5, rel=1e-9)
        assert sens["m1"] == pytest.approx(g / 2, rel=1e-9)
        assert sens["g"] == pytest.approx((m1 + m2) / 2, rel=1e-9)
        assert sens.units == {"k": "N/(N/m)", "LU": "N/m", "L1": "N/m", "L2": "N/m", "m1": "N/kg", "g": "N/(m/s^2)"}
    assert signs == {1.0, -1.0}  # both folds, upper and lower


@pytest.mark.parametrize("params", [["k", "LU", "L1", "L2", "m", "n", "m2"]])
def test_overcentre_fold_load_and_states_match_finite_differences(overcentre, overcentre_branch, params):
    """The fold load and the states at the fold, re-located by the fold polish at p +- h."""
    fold = overcentre_branch["LP1"]
    sens = fold.sensitivity(overcentre, params)
    x = sens.x
    names = [*OVERCENTRE_STATES, "F"]
    idx = [overcentre.index(n) for n in names]

    def relocated(y):
        return polish_fold(overcentre, y, OVERCENTRE_STATES, "F").x[idx]

    for p in params:
        fd = central(relocated, overcentre, x, p)
        assert relative_error(sens[p], fd[-1]) < 1e-6, (p, sens[p], fd[-1])
        exact = np.array([sens.states[p][n] for n in names])
        assert relative_error(exact, fd) < 1e-6, (p, exact, fd)
        # the augmented system's fold-load row is the left-null-vector formula
        assert sens.states[p]["F"] == pytest.approx(sens[p], rel=1e-9, abs=1e-12 * abs(sens.value))


def test_regular_point_kept_state_matches_finite_differences(overcentre, overcentre_branch):
    """Away from a fold: F where theta1 keeps its value, theta1 held and F solved at p +- h."""
    i = next(j for j, lab in enumerate(overcentre_branch.labels) if not lab and j > 5)
    x = overcentre_branch.values[i]
    theta1 = x[overcentre.index("theta1")]
    sens = overcentre_branch.sensitivity(overcentre, i, ["k", "LU", "L2"], keep="theta1")
    assert sens.quantity == "F" and sens.kind == "equilibrium"

    def force(y):
        values = {p: y[overcentre.index(p)] for p in ("k", "LU", "L2")}
        z = find_equilibrium(overcentre, values=values, hold={"theta1": theta1}, free=["F"], guess=x)
        return z[overcentre.index("F")]

    for p in ("k", "LU", "L2"):
        assert relative_error(sens[p], central(force, overcentre, x, p)) < 1e-6, p


def test_point_that_is_not_a_fold_needs_keep_and_singular_lens_is_refused(overcentre, overcentre_branch):
    with pytest.raises(InputError, match="keep"):
        overcentre_branch.sensitivity(overcentre, 3, ["k"])
    with pytest.raises(InputError, match="valid: .*LU"):
        overcentre_branch.sensitivity(overcentre, "LP1", ["kk"])
    with pytest.raises(InputError, match="solved for"):
        overcentre_branch.sensitivity(overcentre, "LP1", ["theta1"])
    fold = overcentre_branch["LP1"]
    # at the fold theta1 is not a smooth function of the held F: G_u is singular there
    with pytest.raises(ConvergenceError, match="singular"):
        equilibrium_sensitivity(overcentre, fold.x, OVERCENTRE_STATES, ["k"], "theta1")


def test_description_fold_load_matches_finite_differences():
    """A description written for the test (a snap-through arm): its fold load in F against k, l0, L."""
    from mechcont.models import load_model

    model = load_model(str(DATA / "snap_arm.toml"))
    x0 = find_equilibrium(model, hold={"theta_arm": 0.5}, free=["F"])
    branch = continuation(model, x0, "F", options=ContinuationOptions(bounds={"F": (-2000.0, 2000.0),
                                                                              "theta_arm": (-1.0, 1.0)}))
    folds = branch.special("LP")
    assert folds
    states = [n for n in model.state_names]
    for fold in folds:
        sens = fold_sensitivity(model, fold.x, states, "F", ["k", "l0", "L"])

        def load(y):
            return polish_fold(model, y, states, "F").x[model.index("F")]

        for p in ("k", "l0", "L"):
            fd = central(load, model, sens.x, p)
            assert relative_error(sens[p], fd) < 1e-6, (p, sens[p], fd)


def test_nose_gear_downlock_force_matches_finite_differences():
    """The downlock force (theta4 = 0 held, F solved) against the spring and geometry parameters."""
    from mechcont.models import load_model

    model = load_model("nose_gear")
    params = ["LU", "k", "l_sp1", "L4", "U"]
    sens = downlock_sensitivity(model, params)
    x = sens.x
    assert sens.kind == "downlock" and sens.unit == "N"

    def force(y):
        values = {p: y[model.index(p)] for p in params}
        return downlock_point(model, values)[model.index("F")]

    for p in params:
        fd = central(force, model, x, p)
        if p == "U":  # no airspeed term in the downlocked force balance at the defaults: exactly zero
            assert sens[p] == 0.0 and abs(fd) < 1e-6
            continue
        assert relative_error(sens[p], fd) < 1e-6, (p, sens[p], fd)


def test_derivative_units():
    assert derivative_unit("N", "m") == "N/m"
    assert derivative_unit("N", "N/m") == "N/(N/m)"
    assert derivative_unit("N", "") == "N"
    assert derivative_unit("", "m") == "1/m"
    assert derivative_unit("m", "m") == "1"


def test_downlock_branch_rows_give_the_downlock_force_sensitivity():
    """A downlock branch in k: every row's default quantity is the downlock force (k held there), the same
    derivatives as the downlock point solved at that row's k, and central differences of it."""
    from mechcont.analysis import downlock
    from mechcont.models import load_model

    model = load_model("nose_gear")
    k0 = model.variable("k").value
    result = downlock(model, "k", {"k": (0.9 * k0, 1.1 * k0)}, unlock=False)
    x = result.branch.values[0]
    sens = result.sensitivity(model, 0, ["LU", "L4"])
    assert sens.quantity == "F"
    direct = downlock_sensitivity(model, ["LU", "L4"], {"k": x[model.index("k")]})
    for p in ("LU", "L4"):
        assert sens[p] == pytest.approx(direct[p], rel=1e-9)

    def force(y):
        return downlock_point(model, {p: y[model.index(p)] for p in ("k", "L4")})[model.index("F")]

    assert relative_error(sens["L4"], central(force, model, x, "L4")) < 1e-6
