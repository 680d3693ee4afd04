"""Hopf points (HB) along equilibrium branches against truth: the Hopf normal form, Routh–Hurwitz, the AUTO
``ab`` demo solved independently (scipy fsolve on the hand-derived system f = 0, tr J = 0), neutral saddles
that must not be called HB, a descriptor system through the generic (finite-difference) path, and UZ rows."""

import math

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import fsolve

from mechcont.continuation import ContinuationOptions, continuation, locate_hopf
from mechcont.equations import dynamics_of, ode_model
from mechcont.equations._dynamics import LinearDynamics
from mechcont.errors import InputError

S = {n: sp.Symbol(n, real=True) for n in "x y z mu w a b a1 a2 a3 u1 u2 D B beta p".split()}


def normal_form(a: float, w: float = 2.0, b: float = 0.7):
    """z' = (mu + i w) z + (a + i b) |z|^2 z in z = x + i y."""
    x, y, mu = S["x"], S["y"], S["mu"]
    r2 = x**2 + y**2
    return ode_model("hopf_nf", {"x": 0.0, "y": 0.0}, {"mu": -1.0, "w": w, "a": a, "b": b},
                     {"x": mu * x - S["w"] * y + (S["a"] * x - S["b"] * y) * r2,
                      "y": S["w"] * x + mu * y + (S["b"] * x + S["a"] * y) * r2})


def ab_model(B: float = 14.0, beta: float = 3.0):
    """AUTO's demo ab: u1' = -u1 + D (1 - u1) e^u2, u2' = -u2 + D B (1 - u1) e^u2 - beta u2."""
    u1, u2, D = S["u1"], S["u2"], S["D"]
    return ode_model("ab", {"u1": 0.0, "u2": 0.0}, {"D": 0.0, "B": B, "beta": beta},
                     {"u1": -u1 + D * (1 - u1) * sp.exp(u2),
                      "u2": -u2 + D * S["B"] * (1 - u1) * sp.exp(u2) - S["beta"] * u2})


def ab_jacobian(u1, u2, D, B, beta):
    """The ab Jacobian, differentiated by hand."""
    e = math.exp(u2)
    return np.array([[-1 - D * e, D * (1 - u1) * e], [-D * B * e, -1 + D * B * (1 - u1) * e - beta]])


def ab_hopf_independent(guess, B, beta):
    """(u1, u2, D) of the ab Hopf point from f = 0, trace J = 0 (planar: the pair +-i omega, omega^2 = det J)."""
    def F(v):
        u1, u2, D = v
        e = math.exp(u2)
        return [-u1 + D * (1 - u1) * e, -u2 + D * B * (1 - u1) * e - beta * u2,
                np.trace(ab_jacobian(u1, u2, D, B, beta))]

    sol, _, ier, msg = fsolve(F, guess, xtol=1e-14, full_output=True)
    assert ier == 1, msg
    return sol


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
    assert hb.extra["hopf"].lyapunov == pytest.approx(_l1_sympy(m, hb, omega), rel=1e-7)


def _l1_sympy(model, point, omega):
    u1, u2, D = S["u1"], S["u2"], S["D"]
    f = sp.Matrix([-u1 + D * (1 - u1) * sp.exp(u2), -u2 + D * 14 * (1 - u1) * sp.exp(u2) - 3 * u2])
    X = [u1, u2]
    at = {u1: point["u1"], u2: point["u2"], D: point["D"]}
    A = np.array(f.jacobian(X).subs(at), dtype=float)
    d2 = [[[float(sp.diff(f[i], X[j], X[k]).subs(at)) for k in range(2)] for j in range(2)] for i in range(2)]
    d3 = [[[[float(sp.diff(f[i], X[j], X[k], X[m]).subs(at)) for m in range(2)] for k in range(2)]
           for j in range(2)] for i in range(2)]
    d2, d3 = np.array(d2), np.array(d3)

    def B(a, b):
        return np.einsum("ijk,j,k->i", d2, a, b)

    lam, V = np.linalg.eig(A)
    q = V[:, np.argmin(abs(lam - 1j * omega))]
    q /= np.linalg.norm(q)
    lamT, W = np.linalg.eig(A.T)
    p = W[:, np.argmin(abs(lamT + 1j * omega))]
    p = p / np.conj(np.vdot(p, q))
    C = np.einsum("ijkm,j,k,m->i", d3, q, q, q.conj())
    h11 = np.linalg.solve(A, B(q, q.conj()))
    h20 = np.linalg.solve(2j * omega * np.eye(2) - A, B(q, q))
    return float(np.real(np.vdot(p, C) - 2 * np.vdot(p, B(q, h11)) + np.vdot(p, B(q.conj(), h20))) / (2 * omega))


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
        assert np.max(np.abs(m.residual(p.x))) < ContinuationOptions().residual_tol  # the engine's own points' tolerance
    with pytest.raises(InputError, match="at"):
        continuation(m, m.vector({}), "D", at=[math.nan])
