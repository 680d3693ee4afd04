"""The dynamic model against independent formulations of the same overcentre.

* Kane's method (sympy.physics.mechanics) in the single minimal coordinate theta1: a
  different derivation (no constraints, no multipliers), integrated by SciPy.
* Exudyn, a C++ multibody code with index-3 constraints and an implicit (generalized-alpha
  / trapezoidal) integrator, as the paper checked its Matlab model with ADAMS. Skipped
  when Exudyn is not installed (``pip install exudyn``).

Geometry deliberately unsymmetric (L1 != L2, spring offsets m, n != 0), with the damper
and a time-varying apex force, so that every term of the model is exercised.
"""

import math

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from scipy.integrate import solve_ivp

from mechcont.dynamics import assemble, simulate
from mechcont.dynamics._exudyn import exudyn_overcentre
from mechcont.models import build_overcentre

P = dict(L1=1.2, L2=1.5, m1=1.0, m2=0.8, g=9.81, k=127.0, LU=0.4, m=0.1, n=0.2, F=0.0, c=3.0)
F0, F_RATE = 10.0, -4.0  # apex force F(t) = F0 + F_RATE t (N)
TH0, T_END = 1.0, 3.0


def theta2_of(theta1):
    return math.pi - math.asin(P["L1"] * math.sin(theta1) / P["L2"])


@pytest.fixture(scope="module")
def mechcont_run():
    s = build_overcentre(**P)
    x0 = assemble(s, {"theta1": TH0, "theta2": theta2_of(TH0)}, hold=["theta1"])
    r = simulate(s, x0, (0.0, T_END), loads={"F": lambda t: F0 + F_RATE * t}, rtol=1e-11, atol=1e-13,
                 t_eval=np.linspace(0.0, T_END, 6001))  # contains both Exudyn time grids below
    assert r.success
    return s, x0, r


def kane_rhs():
    """(theta1, omega1)' from Kane's equations with theta1 as the only coordinate."""
    q, u = me.dynamicsymbols("q u")
    t = me.dynamicsymbols._t
    L1, L2, m1, m2, g, k, LU, m, n, c = (P[k_] for k_ in ("L1", "L2", "m1", "m2", "g", "k", "LU", "m", "n", "c"))
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    A = N.orientnew("A", "Axis", [q, N.z])
    B = N.orientnew("B", "Axis", [sp.pi - sp.asin(L1 * sp.sin(q) / L2), N.z])  # slider end stays on y = 0
    G1, apex = O.locatenew("G1", L1 / 2 * A.x), O.locatenew("P", L1 * A.x)
    G2 = apex.locatenew("G2", -L2 / 2 * B.x)
    S1, S2 = G1.locatenew("S1", m * A.x), G2.locatenew("S2", n * B.x)
    for pt in (G1, apex, G2, S1, S2):
        pt.set_vel(N, pt.pos_from(O).dt(N).subs(q.diff(), u))
    A.set_ang_vel(N, u * N.z)
    B.set_ang_vel(N, B.ang_vel_in(N).subs(q.diff(), u))
    bar1 = me.RigidBody("bar1", G1, A, m1, (me.inertia(A, 0, 0, m1 * L1**2 / 12), G1))
    bar2 = me.RigidBody("bar2", G2, B, m2, (me.inertia(B, 0, 0, m2 * L2**2 / 12), G2))
    d = S2.pos_from(S1)
    length = sp.sqrt(d.dot(d))
    tension = k * (length - LU) + c * (S2.vel(N) - S1.vel(N)).dot(d) / length
    e = d / length
    loads = [(G1, -m1 * g * N.y), (G2, -m2 * g * N.y), (apex, (F0 + F_RATE * t) * N.y), (S1, tension * e),
             (S2, -tension * e)]
    km = me.KanesMethod(N, q_ind=[q], u_ind=[u], kd_eqs=[q.diff() - u])
    km.kanes_equations([bar1, bar2], loads)
    f = sp.lambdify([t, q, u], km.rhs(), "numpy")
    return lambda tt, y: np.asarray(f(tt, y[0], y[1]), float).ravel()


def test_matches_kanes_method_in_the_minimal_coordinate(mechcont_run):
    _, _, r = mechcont_run
    sol = solve_ivp(kane_rhs(), (0.0, T_END), [TH0, 0.0], rtol=1e-11, atol=1e-13, dense_output=True)
    ref = sol.sol(r.t)
    assert np.ptp(ref[0]) > 0.5  # a large motion, not a neighbourhood of equilibrium
    assert np.max(np.abs(r["theta1"] - ref[0])) < 1e-8  # rad
    assert np.max(np.abs(r["theta1_dot"] - ref[1])) < 1e-7  # rad/s


def exudyn_theta1(h):
    pytest.importorskip("exudyn", reason="Exudyn (pip install exudyn) is not installed: "
                                         "independent multibody check skipped")
    return exudyn_overcentre(P, TH0, lambda t: F0 + F_RATE * t, T_END, h)


def test_matches_exudyn_multibody_model(mechcont_run):
    _, _, r = mechcont_run
    errors = {}
    for h in (1e-3, 5e-4):
        t, th = exudyn_theta1(h)
        assert t[-1] == pytest.approx(T_END)
        i = np.rint(t / 5e-4).astype(int)
        assert np.allclose(r.t[i], t)
        errors[h] = np.max(np.abs(th - r["theta1"][i]))
    assert errors[5e-4] < 2e-5  # rad, over a 1 rad swing
    # the difference is Exudyn's second-order time discretisation, not a model difference
    assert 3.0 < errors[1e-3] / errors[5e-4] < 5.0
