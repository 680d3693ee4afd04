"""Models and independent solutions shared by the Hopf tests: the Hopf normal form and AUTO's ab demo (its
Hopf and Bogdanov-Takens points by scipy's fsolve on hand-derived systems, its l1 from SymPy's derivatives)."""

import math

import numpy as np
import sympy as sp
from scipy.optimize import fsolve

from mechcont.equations import ode_model

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

    return _solve(F, guess)



def _solve(F, guess):
    """fsolve from ``guess`` moved by 0.1 % (so it solves, not just accepts), its residual checked."""
    sol, _, ier, msg = fsolve(F, np.asarray(guess, float) * 1.001, xtol=1e-13, full_output=True)
    assert ier == 1 or np.max(np.abs(F(sol))) < 1e-13, msg
    assert np.max(np.abs(F(sol))) < 1e-12
    return sol


def ab_bt_independent(guess, B):
    """(u1, u2, D, beta) of ab's Bogdanov-Takens point: f = 0, trace J = 0, det J = 0."""
    def F(v):
        u1, u2, D, beta = v
        e = math.exp(u2)
        J = ab_jacobian(u1, u2, D, B, beta)
        return [-u1 + D * (1 - u1) * e, -u2 + D * B * (1 - u1) * e - beta * u2, np.trace(J), np.linalg.det(J)]

    return _solve(F, guess)


def l1_sympy(point, omega):
    """Kuznetsov's l1 of ab at ``point`` ({name: value}) with SymPy's exact second and third derivatives."""
    u1, u2, D, B, beta = (S[n] for n in ("u1", "u2", "D", "B", "beta"))
    f = sp.Matrix([-u1 + D * (1 - u1) * sp.exp(u2), -u2 + D * B * (1 - u1) * sp.exp(u2) - beta * u2])
    X = [u1, u2]
    at = {S[n]: point[n] for n in ("u1", "u2", "D", "B", "beta")}
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


