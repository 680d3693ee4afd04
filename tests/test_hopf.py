"""Hopf points (HB) along equilibrium branches against truth: the Hopf normal form, Routh–Hurwitz, the AUTO
``ab`` demo solved independently (scipy fsolve on the hand-derived system f = 0, tr J = 0), neutral saddles
that must not be called HB, a descriptor system through the generic (finite-difference) path, and UZ rows."""

import math

import numpy as np
import pytest
from hopf_models import S, ab_hopf_independent, ab_jacobian, ab_model, l1_sympy, normal_form

from mechcont.continuation import ContinuationOptions, continuation, locate_hopf
from mechcont.equations import dynamics_of, ode_model
from mechcont.equations._dynamics import LinearDynamics
from mechcont.errors import InputError


def _branch(model, vary, bounds, **kw):
    return continuation(model, model.vector({}), vary, hopf=True, options=ContinuationOptions(bounds=bounds), **kw)


@pytest.mark.parametrize("a", [-1.5, 0.8])
def test_normal_form_hopf_at_zero_with_exact_frequency_and_lyapunov(a):
    br = _branch(normal_form(a), "mu", {"mu": (-1.0, 1.0)})
    assert [p.label for p in br.special_points].count("HB") == 1
    hb = br["HB1"]
    h = hb.extra["hopf"]
    assert abs(hb["mu"]) < 1e-13 and hb.located and hb.residual < 1e-13
    assert h.frequency == pytest.approx(2.0, rel=1e-13) and h.period == pytest.approx(math.pi, rel=1e-13)
    # Kuznetsov's l1 with <q, q> = 1: x = z q + conj(z q) with q = (1, -i)/sqrt(2) makes |x|^2 = 2 |z|^2, so the
    # cubic coefficient of the normalised complex form is c1 = 2 (a + i b) and l1 = Re c1 / omega = 2 a / omega
    assert h.lyapunov == pytest.approx(2 * a / 2.0, rel=1e-8)
    assert h.criticality == ("supercritical (stable cycles)" if a < 0 else "subcritical (unstable cycles)")
    assert abs(abs(h.eigenvector[0]) - 1 / math.sqrt(2)) < 1e-12


def test_third_order_linear_system_hopf_from_routh_hurwitz():
    """x''' + a1 x'' + a2 x' + a3 x = 0: the pair crosses at a1 a2 = a3 with omega^2 = a2 (Routh–Hurwitz)."""
    x, y, z = S["x"], S["y"], S["z"]
    m = ode_model("rh", {"x": 0.0, "y": 0.0, "z": 0.0}, {"a1": 3.0, "a2": 2.5, "a3": 4.0},
                  {"x": y, "y": z, "z": -S["a3"] * x - S["a2"] * y - S["a1"] * z})
    br = _branch(m, "a1", {"a1": (0.5, 3.0)})
    hb = br["HB1"]
    assert hb["a1"] == pytest.approx(4.0 / 2.5, rel=1e-13)
    assert hb.extra["hopf"].frequency == pytest.approx(math.sqrt(2.5), rel=1e-13)


def test_ab_hopf_point_against_an_independent_solution():
    m = ab_model()
    br = _branch(m, "D", {"D": (0.0, 0.2), "u2": (-1.0, 10.0)})
    hbs = br.special("HB")
    assert len(hbs) == 1
    hb = hbs[0]
    u1, u2, D = ab_hopf_independent([hb["u1"], hb["u2"], hb["D"]], 14.0, 3.0)
    assert hb["D"] == pytest.approx(D, rel=1e-9) and hb["u1"] == pytest.approx(u1, rel=1e-9)
    assert hb["u2"] == pytest.approx(u2, rel=1e-9)
    omega = math.sqrt(np.linalg.det(ab_jacobian(u1, u2, D, 14.0, 3.0)))
    assert hb.extra["hopf"].frequency == pytest.approx(omega, rel=1e-9)
    assert hb.residual < 1e-13
    # l1 from Kuznetsov's formula with SymPy's exact second and third derivatives (independent of the code's
    # generated second derivatives and its central differences for the third)
    assert hb.extra["hopf"].lyapunov == pytest.approx(l1_sympy(hb.values, omega), rel=1e-7)


def test_neutral_saddle_is_not_a_hopf_point():
    """x' = p x + y, y' = x + z, z' = -z: the real pair (kappa, -kappa) of the first block at p = 0 changes the
    bialternate test function's sign, but no eigenvalue crosses the imaginary axis."""
    x, y, z, p = S["x"], S["y"], S["z"], S["p"]
    m = ode_model("saddle", {"x": 0.0, "y": 0.0, "z": 0.0}, {"p": -1.0},
                  {"x": p * x + y + x**3, "y": x + z, "z": -z})
    br = _branch(m, "p", {"p": (-1.0, 1.0)})
    assert br.special("HB") == [] and abs(br.column("p")[-1] - 1.0) < 1e-12
    with pytest.raises(InputError, match="neutral saddle"):
        locate_hopf(m, m.vector({"p": 1e-3}), "p")


class _Descriptor:
    """The dynamics of ``model`` written as E dz/dt = (E A) dz with a non-trivial E, and not an OdeDynamics: the
    generic path (generalised eigenproblem, finite-difference gradients and l1)."""

    def __init__(self, model):
        self.inner = dynamics_of(model)
        self.state_names = self.inner.state_names
        self.E = np.array([[2.0, 0.5], [0.3, 1.0]])

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def linearise(self, x):
        lin = self.inner.linearise(x)
        return LinearDynamics(self.E @ lin.A, self.E, lin.names)


def test_generic_dynamics_with_a_descriptor_matrix_give_the_same_hopf_point():
    m = ab_model()
    exact = _branch(m, "D", {"D": (0.0, 0.2), "u2": (-1.0, 10.0)})["HB1"]
    generic = continuation(m, m.vector({}), "D", hopf=_Descriptor(m),
                           options=ContinuationOptions(bounds={"D": (0.0, 0.2), "u2": (-1.0, 10.0)}))["HB1"]
    assert generic.located and generic["D"] == pytest.approx(exact["D"], rel=1e-9)
    assert generic.extra["hopf"].frequency == pytest.approx(exact.extra["hopf"].frequency, rel=1e-9)
    assert generic.extra["hopf"].lyapunov == pytest.approx(exact.extra["hopf"].lyapunov, rel=1e-6)
    assert "finite differences" in generic.extra["hopf"].lyapunov_method


def test_user_points_are_rows_exactly_at_the_values():
    m = ab_model()
    at = [0.05, 0.1234567, 0.19]
    br = continuation(m, m.vector({}), "D", at=at, options=ContinuationOptions(bounds={"D": (0.0, 0.2)}))
    uz = br.special("UZ")
    assert [p.label for p in br.special_points if p.label == "UZ"] == ["UZ"] * 3
    for p, v in zip(uz, at):
        assert p["D"] == pytest.approx(v, rel=4e-16, abs=0) and p.located
        assert np.max(np.abs(m.residual(p.x))) < ContinuationOptions().engine.residual_tol  # the engine's own points' tolerance
    with pytest.raises(InputError, match="at"):
        continuation(m, m.vector({}), "D", at=[math.nan])


def test_branch_json_carries_the_hopf_payload(tmp_path):
    import json

    br = _branch(normal_form(-1.5), "mu", {"mu": (-1.0, 1.0)})
    doc = json.loads(br.to_json(tmp_path / "b.json").read_text())
    (hb,) = [p for p in doc["special_points"] if p["label"] == "HB"]
    assert hb["name"] == "HB1" and hb["frequency"] == pytest.approx(2.0, rel=1e-13)
    assert hb["l1"] == pytest.approx(-1.5, rel=1e-8) and hb["criticality"] == "supercritical (stable cycles)"


def test_two_hopf_points_numbered_along_the_branch():
    """ab at beta = 4: the equilibrium gains and loses the oscillation again (HB1 then HB2 as D grows)."""
    m = ab_model(beta=4.0)
    br = _branch(m, "D", {"D": (0.0, 1.0), "u2": (-1.0, 10.0)})
    names = [n for n in br.point_names() if n.startswith("HB")]
    assert names == ["HB1", "HB2"] and br["HB1"]["D"] < br["HB2"]["D"]
    for name in names:
        hb = br[name]
        u1, u2, D = ab_hopf_independent([hb["u1"], hb["u2"], hb["D"]], 14.0, 4.0)
        assert hb["D"] == pytest.approx(D, rel=1e-9) and hb["u1"] == pytest.approx(u1, rel=1e-9)
