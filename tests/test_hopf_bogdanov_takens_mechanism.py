"""Bogdanov-Takens points of Hopf curves on a mechanism, against their closed form, through the explicit state
matrix (ordered Schur form) and through a generalised eigenproblem ``A v = lambda E v`` (ordered QZ form).

tests/data/caster_tyre_pushed.toml: the castering wheel of caster_tyre.toml pushed towards its pivot by a dead
load P at r ahead of it. Linearised (psi the swivel angle, y the tyre's deflection):

    I psi'' + c psi' + (k - P r) psi + (e + t) C y / sigma = 0,    y' = e psi' + V psi - V y / sigma,

characteristic polynomial I s^3 + a2 s^2 + a1 s + a0 with a2 = c + I V / sigma, a1 = k - P r + c V / sigma +
e (e + t) C / sigma, a0 = V (k - P r + (e + t) C) / sigma. Hopf points: a2 a1 = I a0 (Routh-Hurwitz), omega^2 =
a1 / I; the Hopf curve in (P, c) ends where a0 and a1 vanish together (a double zero eigenvalue): the
Bogdanov-Takens point P r = k + (e + t) C, c = (e + t) (sigma - e) C / V (8000 N, 240 N m s/rad here).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mechcont.continuation import ContinuationOptions, continuation, continue_hopf, find_equilibrium
from mechcont.continuation._hopf_point import HopfTest
from mechcont.equations import dynamics_of
from mechcont.equations._linear_dynamics import LinearDynamics
from mechcont.models import load_model

FILE = Path(__file__).resolve().parent / "data" / "caster_tyre_pushed.toml"
V, E, T, K, I_W, SIGMA, C_Y, R = 5.0, 0.1, 0.02, 2000.0, 0.5, 0.3, 5.0e4, 1.0
P_BT, C_BT = (K + (E + T) * C_Y) / R, (E + T) * (SIGMA - E) * C_Y / V
OPTIONS = ContinuationOptions(bounds={"c": (1.0, 300.0), "P": (0.0, 9000.0)}, scales={"P": 1000.0, "c": 10.0},
                              ds=0.5, dsmax=2.0)


def _hopf_load(c: float) -> float:
    """P at the Hopf point for the damper rate c: a2 a1 = I a0 is linear in P."""
    a2 = c + I_W * V / SIGMA
    rest = K + c * V / SIGMA + E * (E + T) * C_Y / SIGMA  # a1 without -P r
    # a2 (rest - P r) = I V (K + (E + T) C - P r) / sigma
    return (a2 * rest - I_W * V * (K + (E + T) * C_Y) / SIGMA) / (R * (a2 - I_W * V / SIGMA))


class _Descriptor:
    """The mechanism's dynamics written as ``E dz/dt = (E A) dz`` with a non-trivial ``E``: its eigenvalues are
    those of ``A``, but the Hopf test goes through the generalised eigenproblem (QZ)."""

    E = np.array([[2.0, 0.5, 0.0], [0.3, 1.0, 0.2], [0.0, -0.4, 1.5]])

    def __init__(self, inner):
        self.inner = inner

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def linearise(self, x):
        lin = self.inner.linearise(x)
        return LinearDynamics(self.E @ lin.A, self.E, lin.names)

    def linearise_near(self, x, X, descriptor):
        A, _ = self.inner.linearise_near(x, X, False)
        return self.E @ A, np.repeat(self.E[None], len(A), axis=0)


@pytest.fixture(scope="module")
def pushed():
    model = load_model(str(FILE), P=100.0)
    branch = continuation(model, find_equilibrium(model), "P", hopf=True,
                          options=ContinuationOptions(bounds={"P": (0.0, 20000.0)}, scales={"P": 1000.0}))
    return model, branch


def test_the_hopf_load_against_routh_hurwitz(pushed):
    model, branch = pushed
    hb = branch["HB1"]
    assert hb["P"] == pytest.approx(_hopf_load(100.0), rel=1e-12)
    a1 = K - hb["P"] * R + 100.0 * V / SIGMA + E * (E + T) * C_Y / SIGMA
    assert hb.extra["hopf"].frequency == pytest.approx(np.sqrt(a1 / I_W), rel=1e-12)


@pytest.fixture(scope="module")
def curves(pushed):
    """The Hopf curve from HB1 in (P, c) through the explicit state matrix and through the descriptor form."""
    model, branch = pushed
    return {form: continue_hopf(model, branch["HB1"], "P", "c", options=OPTIONS, dynamics=dyn)
            for form, dyn in (("explicit", dynamics_of(model)), ("descriptor", _Descriptor(dynamics_of(model))))}


@pytest.mark.parametrize("form", ["explicit", "descriptor"])
def test_the_hopf_curve_ends_at_the_closed_form_bogdanov_takens_point(curves, form):
    """Both forms: the curve's points on a2 a1 = I a0 (past BT too: a neutral saddle's pair (kappa, -kappa)
    satisfies it as well), its BT at the closed form to 1e-12."""
    curve = curves[form]
    (bt,) = curve.special("BT")
    assert bt.located
    assert (bt["P"], bt["c"]) == pytest.approx((P_BT, C_BT), rel=1e-12)
    for i in range(0, len(curve), 5):
        p = curve.point(i).values
        assert p["P"] == pytest.approx(_hopf_load(p["c"]), rel=1e-10, abs=1e-10 * P_BT)


def test_the_pair_sums_slope_is_finite_at_the_bogdanov_takens_point_in_both_forms(pushed, curves):
    """At the BT point the pair is a Jordan block (w^H E v = 0): the slope through each eigenvalue's own
    derivative divides by zero; through the invariant plane (ordered Schur form) or the deflating subspaces
    (ordered QZ form) it is finite, and both forms give the same row, which is that of g = -a2 / I + the third
    eigenvalue's share: here checked against central differences of g from the eigenvalues of the linearisation
    along the Hopf curve's unknowns."""
    model, _ = pushed
    x = np.array(curves["explicit"].special("BT")[0].x)  # the closed form's point to 1e-12 (the test above)
    cols = np.array([model.index(n) for n in ("theta_wheel", "y_tyre", "P", "c")])
    rows = []
    for dyn in (dynamics_of(model), _Descriptor(dynamics_of(model))):
        test = HopfTest(dyn, model)
        pair = test.pair(x)
        assert abs(pair.lam[0]) < 1e-6 * C_BT  # the double zero (split by rounding into +-sqrt(eps) |A|)
        rows.append(test.gradient(x, cols, pair))
    assert np.all(np.isfinite(rows[0])) and np.all(np.isfinite(rows[1]))
    assert rows[1] == pytest.approx(rows[0], rel=1e-7, abs=1e-9)
    # g = lambda_1 + lambda_2 = (sum of all eigenvalues) - lambda_3 = -a2 / I - lambda_3, smooth: in c, at fixed P,
    # -1 / I - d lambda_3 / dc; against the eigenvalues
    dyn = dynamics_of(model)

    def g(cv):
        xs = x.copy()
        xs[model.index("c")] = cv
        lam = dyn.linearise(xs).eigenvalues()
        third = lam[np.argmin(lam.real)]
        return float(np.sum(lam).real - third.real)
    h = 1e-3 * C_BT
    assert rows[0][3] == pytest.approx((g(C_BT + h) - g(C_BT - h)) / (2 * h), rel=1e-6)


def test_descriptor_normal_form_slope_at_its_bogdanov_takens_point():
    """The Bogdanov-Takens normal form (x' = y, y' = b1 + b2 x + x^2 - x y) through a descriptor E: at the origin,
    its BT point, g = -x on the whole plane y = 0 (the trace of [[0, 1], [b2 + 2 x, -x]]), so the row over (x, y,
    b1, b2) is (-1, 0, 0, 0) exactly; through each eigenvalue's own derivative it was of order 1e16."""
    bt = load_model(str(Path(__file__).resolve().parent / "corpus" / "ode" / "bogdanov_takens.toml"))

    class Descriptor:
        E = np.array([[2.0, 0.5], [0.3, 1.0]])

        def __init__(self, inner):
            self.inner, self.state_names = inner, inner.state_names

        def __getattr__(self, name):
            return getattr(self.inner, name)

        def linearise(self, x):
            lin = self.inner.linearise(x)
            return LinearDynamics(self.E @ lin.A, self.E, lin.names)

    test = HopfTest(Descriptor(dynamics_of(bt)), bt)
    x0 = bt.vector({"x": 0.0, "y": 0.0, "b1": 0.0, "b2": 0.0})
    assert test.gradient(x0, np.arange(4), test.pair(x0)) == pytest.approx([-1.0, 0.0, 0.0, 0.0], abs=1e-9)
