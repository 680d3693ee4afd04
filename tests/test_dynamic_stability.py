"""Dynamic stability of mechanisms: the linearised equations of motion on the constraint manifold against truth.

* a damped pendulum and a mass-spring-damper on a prismatic joint: eigenvalues of ``I s^2 + c s + k``;
* a closed-loop four-bar: its small-oscillation frequency against an independent Lagrange derivation in the
  crank angle (loop closure solved in numpy, ``omega^2 = V''/J``), and the same eigenvalues with every body's
  frame moved and turned (the answer cannot depend on where a frame sits);
* Ziegler's double pendulum (point masses ``2m`` at the joint and ``m`` at the tip, rotary springs ``k`` and
  dampers ``c`` at both joints, a follower force ``P`` at the tip), written in Cartesian coordinates with pin
  constraints so that the constraint curvature and the non-conservative load both matter. In the angles
  ``phi1, phi2`` from the vertical, ``M = m l^2 [[3, 1], [1, 1]]``, ``C = c [[2, -1], [-1, 1]]``,
  ``K = k [[2 - p, p - 1], [-1, 1]]`` (``p = P l/k``: the follower's generalised forces are
  ``Q1 = -P l sin(phi2 - phi1)``, ``Q2 = 0``). Undamped, ``det(K - mu M) = 0`` gives
  ``2 mu^2 + (2p - 7) mu + 1 = 0`` (``mu = omega^2 m l^2/k``): flutter at ``p = 7/2 - sqrt 2``. Damped, the
  quartic ``det(s^2 M + s C + K)`` has (m = k = l = 1) ``a4 = 2, a3 = 7c, a2 = c^2 - 2p + 7, a1 = 2c, a0 = 1``
  and the Routh–Hurwitz condition ``a3 a2 a1 - a3^2 a0 - a1^2 a4 > 0`` reads ``c^2 (14 c^2 - 28 p + 41) > 0``:
  the damped flutter load is ``p = 41/28 + c^2/2``, whose limit 41/28 lies 30 % below the undamped one;
* a spatial compound pendulum on a tilted revolute (Euler parameters):
  ``omega^2 = m g cos(beta) (L/2) / (I_t + m L^2/4)``;
* the linearisation ``A`` against central differences of the full nonlinear rates (the minimal-coordinate
  ODE, accelerations from the constrained equations of motion): the two are similar through the change of
  variables ``eta = N^T T dq_i`` (``T = dq/dq_i`` on the manifold).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq

from mechcont.analysis import dynamic_stability
from mechcont.continuation import find_equilibrium
from mechcont.equations import MechanicalModel, Model, Variable, dynamics_of, velocity_symbol
from mechcont.equations._mechanism_dynamics import MechanismDynamics
from mechcont.models import load_model, model_from_text

SQRT2 = math.sqrt(2.0)


def _roots(*coeffs) -> np.ndarray:
    r = np.roots(coeffs)
    return r[np.lexsort((-r.imag, -r.real))]


def test_damped_pendulum_eigenvalues_closed_form():
    model = load_model("tests/data/damped_pendulum.toml", c2=0.0)  # c2 is quadratic in v: no linear part
    x = find_equilibrium(model, guess={"theta_bar": -1.5})
    m, L, g, c = 2.0, 1.0, 9.81, 4.0
    P, G = np.array([0.0, -L]), np.array([0.3, 0.8])   # the tip hanging, the damper's ground point
    dl = (P - G) @ np.array([L, 0.0]) / np.linalg.norm(P - G)  # dl/dtheta at theta = -pi/2
    expected = _roots(m * L * L / 3, c * dl * dl, m * g * L / 2)
    lam = dynamics_of(model).linearise(x).eigenvalues()
    assert np.allclose(lam, expected, rtol=1e-12, atol=0)
    assert dynamic_stability(model, x).n_unstable == 0
    # mass-proportional damping d adds d to the damping coefficient per unit inertia
    lam_d = MechanismDynamics(model, damping=0.5).linearise(x).eigenvalues()
    assert np.allclose(lam_d, _roots(m * L * L / 3, c * dl * dl + 0.5 * m * L * L / 3, m * g * L / 2), rtol=1e-12)


SLIDER = """
[mechanism]
name = "msd"
[parameters]
m = 3.0
k = 1200.0
c = 18.0
[ground]
O = [0, 0]
S = [-1.0, 0]
[bodies.block]
mass = "m"
inertia = 0.2
initial = { x = 0.2, y = 0, theta = 0 }
[joints.rail]
type = "prismatic"
a = "ground.O"
b = "block.origin"
[springs.spring]
a = "ground.S"
b = "block.origin"
k = "k"
free_length = 1.1
[dampers.damper]
a = "ground.S"
b = "block.origin"
c = "c"
"""


def test_mass_spring_damper_on_a_slider():
    model = model_from_text(SLIDER, "msd.toml")
    x = find_equilibrium(model)
    assert x[model.index("x_block")] == pytest.approx(0.1, abs=1e-12)
    lam = dynamics_of(model).linearise(x).eigenvalues()
    assert np.allclose(lam, _roots(3.0, 18.0, 1200.0), rtol=1e-12, atol=0)
    res = dynamic_stability(model, x)
    assert res.leading_real == pytest.approx(-3.0, rel=1e-12)
    assert res.leading_frequency == pytest.approx(math.sqrt(1200.0 / 3.0 - 9.0), rel=1e-12)


# -- the four-bar: an independent Lagrange derivation in the crank angle ------------------------------
FB = dict(a=0.3, b=0.8, c=0.6, d=0.7, m1=1.0, m2=2.0, m3=1.5, g=9.81, k=200.0, L0=0.3, S=(0.0, 0.9))


def _fourbar_pose(t1, near):
    """Crank angle -> (B, C, coupler angle, rocker angle), C the circle intersection nearer ``near``."""
    p = FB
    B = p["a"] * np.array([math.cos(t1), math.sin(t1)])
    D = np.array([p["d"], 0.0])
    e = D - B
    dist = np.linalg.norm(e)
    along = (dist ** 2 + p["b"] ** 2 - p["c"] ** 2) / (2 * dist)
    h = math.sqrt(p["b"] ** 2 - along ** 2)
    u = e / dist
    n = np.array([-u[1], u[0]])
    Cs = [B + along * u + s * h * n for s in (1, -1)]
    C = min(Cs, key=lambda P: np.linalg.norm(P - near))
    return B, C, math.atan2(*(C - B)[::-1]), math.atan2(*(C - D)[::-1])


def _fourbar_energy(t1, near):
    """Centres of gravity, angles and potential energy at crank angle ``t1``."""
    p = FB
    B, C, t2, t3 = _fourbar_pose(t1, near)
    D = np.array([p["d"], 0.0])
    cgs = [B / 2, (B + C) / 2, (D + C) / 2]
    V = p["g"] * sum(mi * P[1] for mi, P in zip((p["m1"], p["m2"], p["m3"]), cgs))
    V += p["k"] / 2 * (np.linalg.norm(cgs[1] - np.array(p["S"])) - p["L0"]) ** 2
    return np.concatenate([*cgs, [t1, t2, t3]]), V


def _fourbar_omega2(t1, near):
    """omega^2 = V''/J at the equilibrium crank angle ``t1`` (five-point differences, h = 1e-3: truncation
    ~h^4 ~ 1e-12, rounding ~1e-16/h^2 ~ 1e-10)."""
    p = FB
    h = 1e-3
    pts = [_fourbar_energy(t1 + k * h, near) for k in (-2, -1, 1, 2)]
    d1 = (pts[0][0] - 8 * pts[1][0] + 8 * pts[2][0] - pts[3][0]) / (12 * h)  # d(cgs, angles)/dt1
    V0 = _fourbar_energy(t1, near)[1]
    Vpp = (-pts[0][1] + 16 * pts[1][1] - 30 * V0 + 16 * pts[2][1] - pts[3][1]) / (12 * h * h)
    masses = (p["m1"], p["m2"], p["m3"])
    lengths = (p["a"], p["b"], p["c"])
    J = sum(mi * (d1[2 * i] ** 2 + d1[2 * i + 1] ** 2) + mi * li ** 2 / 12 * d1[6 + i] ** 2
            for i, (mi, li) in enumerate(zip(masses, lengths)))
    Vp = (pts[0][1] - 8 * pts[1][1] + 8 * pts[2][1] - pts[3][1]) / (12 * h)
    return Vpp / J, Vp


@pytest.fixture(scope="module")
def fourbar():
    model = load_model("fourbar")
    return model, find_equilibrium(model, guess={"theta_crank": 1.2})


def test_fourbar_small_oscillation_against_lagrange(fourbar):
    model, x = fourbar
    C = np.array([x[model.index("x_rocker")], x[model.index("y_rocker")]]) * 2 - np.array([FB["d"], 0.0])
    omega2, Vp = _fourbar_omega2(x[model.index("theta_crank")], C)
    assert abs(Vp) < 1e-7  # the program's equilibrium is one of the independent model too
    lam = dynamics_of(model).linearise(x).eigenvalues()
    assert omega2 > 0 and np.allclose(lam.real, 0.0, atol=1e-12 * math.sqrt(omega2))
    assert abs(lam[0].imag) == pytest.approx(math.sqrt(omega2), rel=1e-8)


MOVED = """
[mechanism]
name = "fourbar_moved"
dof = 1
[parameters]
g = 9.81
[ground]
A = [0, 0]
D = [0.7, 0]
S = [0.0, 0.9]
{bodies}
[joints.A]
type = "revolute"
a = "ground.A"
b = "crank.a"
[joints.B]
type = "revolute"
a = "crank.b"
b = "coupler.a"
[joints.C]
type = "revolute"
a = "coupler.b"
b = "rocker.b"
[joints.D]
type = "revolute"
a = "ground.D"
b = "rocker.a"
[springs.spring]
a = "ground.S"
b = "coupler.mid"
k = 200.0
free_length = 0.3
[gravity]
g = "g"
[assembly]
hold = {{ theta_crank = {hold} }}
"""


def _moved_body(name, length, mass, u, v, alpha, theta):
    """A bar of ``length`` whose frame sits at ``(u, v)`` from its end ``a``, its axis turned by ``alpha``."""
    ca, sa = math.cos(alpha), math.sin(alpha)

    def pt(s):  # the point at s along the bar, in the moved frame
        return [-(u * ca + v * sa) + s * ca, -(-u * sa + v * ca) - s * sa]
    a, b, mid = pt(0.0), pt(length), pt(length / 2)
    return (f"[bodies.{name}]\nmass = {mass}\ninertia = {mass * length ** 2 / 12!r}\ncg = {mid}\n"
            f"points = {{ a = {a}, b = {b}, mid = {mid} }}\ninitial = {{ theta = {theta + alpha!r} }}\n")


def test_eigenvalues_do_not_depend_on_where_the_frames_sit(fourbar):
    model, x = fourbar
    lam = dynamics_of(model).linearise(x).eigenvalues()
    t = {n: float(x[model.index(f"theta_{n}")]) for n in ("crank", "coupler", "rocker")}
    bodies = "".join([_moved_body("crank", 0.3, 1.0, 0.11, -0.07, 0.4, t["crank"]),
                      _moved_body("coupler", 0.8, 2.0, -0.2, 0.13, -1.1, t["coupler"]),
                      _moved_body("rocker", 0.6, 1.5, 0.5, 0.3, 2.5, t["rocker"])])
    moved = model_from_text(MOVED.format(bodies=bodies, hold=repr(t["crank"] + 0.4)), "fourbar_moved.toml")
    y = find_equilibrium(moved, guess=moved.defaults())
    assert y[moved.index("theta_crank")] - 0.4 == pytest.approx(t["crank"], abs=1e-9)
    assert moved.mechanics.mass(y).tolist() != moved.mechanics.mass(y * 1.01).tolist()  # M depends on q here
    assert np.allclose(dynamics_of(moved).linearise(y).eigenvalues(), lam, rtol=1e-9, atol=0)


# -- Ziegler's double pendulum in Cartesian coordinates with pin constraints --------------------------
def ziegler(k=1.0, m=1.0, l=1.0, c=0.0, P=0.0):
    """Two massless bars of length ``l``, point masses 2m at the joint and m at the tip (each body's frame at
    its point mass, no rotary inertia), rotary springs k and dampers c at the ground pin and the joint, a
    follower force P at the tip along the second bar, towards the joint. Upright at theta = pi/2."""
    names = ["x1", "y1", "t1", "x2", "y2", "t2", "R1x", "R1y", "R2x", "R2y", "P", "k", "c", "m", "l"]
    x1, y1, t1, x2, y2, t2, *lam, P_, k_, c_, m_, l_ = (sp.Symbol(n, real=True) for n in names)
    q = [x1, y1, t1, x2, y2, t2]
    d1, d2 = velocity_symbol("t1"), velocity_symbol("t2")
    cons = [x1 - l_ * sp.cos(t1), y1 - l_ * sp.sin(t1), x2 - x1 - l_ * sp.cos(t2), y2 - y1 - l_ * sp.sin(t2)]
    Q = [0, 0, -k_ * (t1 - sp.pi / 2) + k_ * (t2 - t1) - c_ * d1 + c_ * (d2 - d1),
         -P_ * sp.cos(t2), -P_ * sp.sin(t2), -k_ * (t2 - t1) - c_ * (d2 - d1)]
    Mm = sp.diag(2 * m_, 2 * m_, 0, m_, m_, 0)
    at_rest = {d1: 0, d2: 0}
    eq = [sp.sympify(Qi).xreplace(at_rest) - sum(sp.diff(ck, qi) * lk for ck, lk in zip(cons, lam))
          for Qi, qi in zip(Q, q)]
    mech = MechanicalModel(names, [str(s) for s in q], cons, Q, Mm)
    values = [0, l, math.pi / 2, 0, 2 * l, math.pi / 2, 0, 0, 0, 0, P, k, c, m, l]
    vs = [Variable(n, "state" if i < 10 else "parameter", float(v)) for i, (n, v) in enumerate(zip(names, values))]
    system = Model("ziegler", vs, [*eq, *cons], mechanics=mech)
    return system, find_equilibrium(system)


@pytest.fixture(scope="module")
def zmodel():
    return ziegler(k=1.0, m=1.0, l=1.0, c=0.0)


def _at(model, x, **values):
    y = np.array(x, float)
    for n, v in values.items():
        y[model.index(n)] = v
    return find_equilibrium(model, guess=y)


@pytest.mark.parametrize("p", [0.5, 1.5, 2.0])
def test_ziegler_undamped_eigenvalues(zmodel, p):
    model, x0 = zmodel
    x = _at(model, x0, P=p)
    mu = np.roots([2.0, 2 * p - 7, 1.0])  # omega^2 m l^2/k, real positive below flutter
    expected = np.sort(np.concatenate([1j * np.sqrt(mu), -1j * np.sqrt(mu)]).imag)
    lam = dynamics_of(model).linearise(x).eigenvalues()
    assert np.allclose(lam.real, 0.0, atol=1e-12)
    assert np.allclose(np.sort(lam.imag), expected, rtol=1e-10)


def test_ziegler_undamped_flutter_load(zmodel):
    model, x0 = zmodel
    p_cr = 3.5 - SQRT2
    below, above = (dynamic_stability(model, _at(model, x0, P=p)) for p in (p_cr * (1 - 1e-6), p_cr * (1 + 1e-6)))
    assert below.n_unstable == 0 and above.n_unstable == 2   # two pairs collide and leave the axis: s = +-a +-ib
    assert above.leading_frequency > 0


@pytest.mark.parametrize("c", [0.05, 0.2])
def test_ziegler_damped_flutter_load_from_routh_hurwitz(c):
    model, x0 = ziegler(c=c)
    p_cr = 41 / 28 + c * c / 2
    assert p_cr < 3.5 - SQRT2  # the destabilising effect of small damping

    def lead(p):
        return dynamic_stability(model, _at(model, x0, P=p)).leading_real
    found = brentq(lead, 1.0, 2.0, xtol=1e-13)
    assert found == pytest.approx(p_cr, rel=1e-9)
    assert lead(p_cr * 0.99) < 0 < lead(p_cr * 1.01)
    # between the damped and the undamped flutter loads the undamped stiffness judges it stable: only the
    # dynamic linearisation, with the damping, sees the flutter
    x = _at(model, x0, P=0.5 * (p_cr + 3.5 - SQRT2))
    assert model.mechanics.stability(x).n_unstable == 0
    assert dynamic_stability(model, x).n_unstable == 2


def _fd_check(model, x, rtol):
    """``A`` of linearise similar to the central-difference Jacobian of the nonlinear minimal rates."""
    dyn = MechanismDynamics(model, reference=x)
    lin = dyn.linearise(x)
    z = dyn.state_at(x)
    assert np.max(np.abs(dyn.rates(z, x))) < 1e-9
    Jz = dyn.rates_jacobian(z, x)
    n = (len(z) - len(model.mechanics.element_states)) // 2
    # T = dq/dq_i on the manifold, by differences of full_vector (dependent coordinates by Newton)
    q = model.mechanics.q_index
    T = np.zeros((len(q), n))
    for j in range(n):
        h = 1e-6
        zp, zm = z.copy(), z.copy()
        zp[j] += h
        zm[j] -= h
        T[:, j] = (dyn.full_vector(zp, x)[q] - dyn.full_vector(zm, x)[q]) / (2 * h)
    N = model.mechanics.allowed_motions(x)
    W = N.T @ T
    ns = len(z) - 2 * n
    S = np.zeros((len(z), len(z)))
    S[:n, :n] = S[n:2 * n, n:2 * n] = W
    S[2 * n:, 2 * n:] = np.eye(ns)
    expected = np.linalg.solve(S, lin.A @ S)
    assert np.allclose(Jz, expected, rtol=0, atol=rtol * np.abs(expected).max())
    assert np.allclose(np.sort_complex(np.linalg.eigvals(Jz)), np.sort_complex(lin.eigenvalues()), rtol=rtol * 10)


def test_linearisation_against_finite_differences_of_the_nonlinear_rates(fourbar):
    _fd_check(*fourbar, rtol=1e-6)
    model, x0 = ziegler(c=0.3)
    _fd_check(model, _at(model, x0, P=1.2), rtol=1e-6)   # follower load, constraint curvature, damping


def test_spatial_pendulum_on_a_revolute():
    model = load_model("tests/data/spatial/pendulum_3d.toml")
    x = find_equilibrium(model, guess=model.defaults())
    L, m, It, beta, g = 0.8, 2.0, 0.15, 0.6, 9.81
    omega = math.sqrt(m * g * math.cos(beta) * L / 2 / (It + m * L * L / 4))
    assert x[model.index("z_bar")] < 0  # hanging (the bar's centre below the hinge): a stable oscillation
    lam = dynamics_of(model).linearise(x).eigenvalues()
    assert len(lam) == 2
    assert np.allclose(lam.real, 0.0, atol=1e-12 * omega)
    assert np.allclose(np.sort(lam.imag), [-omega, omega], rtol=1e-9)


def test_branch_columns_for_an_ode_model():
    """The same columns for an ODE model (the function the ODE side calls): du1 = mu u1 - w u2,
    du2 = w u1 + mu u2 has the eigenvalues mu +- i w at its equilibrium u = 0 for every mu."""
    from mechcont.analysis import with_dynamic_stability
    from mechcont.continuation import ContinuationOptions, continuation
    from mechcont.equations import ode_model

    u1, u2, mu, w = sp.symbols("u1 u2 mu w", real=True)
    model = ode_model("focus", {"u1": 0.0, "u2": 0.0}, {"mu": -1.0, "w": 2.5},
                      {"u1": mu * u1 - w * u2, "u2": w * u1 + mu * u2})
    branch = continuation(model, model.defaults(), "mu", options=ContinuationOptions(bounds={"mu": (-1.0, 1.0)}))
    out = with_dynamic_stability(model, branch)
    m = out["mu"]
    assert len(m) > 5 and m.min() < -0.5 and m.max() > 0.5
    assert np.allclose(out["leading_real"], m, rtol=0, atol=1e-12)
    assert np.allclose(out["leading_frequency"], 2.5, rtol=1e-12)
    tol = 1e-9 * np.hypot(m, 2.5)
    assert np.array_equal(out["n_unstable_dynamic"], np.where(m > tol, 2.0, 0.0))
    assert out.unit("leading_real") == "1/s" and len(branch.names) + 3 == len(out.names)


def test_nonlinear_rates_and_parameter_rates_of_the_damped_pendulum():
    """``rates`` away from the equilibrium is the reduced equation of motion
    ``(m L^2/3) theta'' = -m g (L/2) cos theta - T dl/dtheta``, ``T = c v + c2 v|v|``, ``v = l' theta'``, and
    ``parameter_rates`` its derivative in ``c``: ``-v l' / (m L^2/3)``."""
    model = load_model("tests/data/damped_pendulum.toml")
    x = find_equilibrium(model, guess={"theta_bar": -1.5})
    dyn = dynamics_of(model)
    assert dyn.state_names == ("theta_bar", "theta_bar_dot")
    m, L, g, c, c2 = 2.0, 1.0, 9.81, 4.0, 6.0
    th, om = 0.4, -1.3
    P = L * np.array([math.cos(th), math.sin(th)]) - np.array([0.3, 0.8])
    dl = P @ (L * np.array([-math.sin(th), math.cos(th)])) / np.linalg.norm(P)
    v = dl * om
    acc = (-m * g * L / 2 * math.cos(th) - (c * v + c2 * v * abs(v)) * dl) / (m * L * L / 3)
    f = dyn.rates(np.array([th, om]), x)
    assert f == pytest.approx([om, acc], rel=1e-12)
    dp = dyn.parameter_rates(np.array([th, om]), x, ["c"])
    assert dp[:, 0] == pytest.approx([0.0, -v * dl / (m * L * L / 3)], rel=1e-8, abs=1e-12)


def test_nonlinear_rates_of_the_closed_loop_conserve_energy(fourbar):
    """The four-bar without damping conserves ``T + V`` along the minimal-coordinate ODE (the velocity-product
    forces of its bars' frames and the dependent coordinates' Newton included), over a large swing."""
    from scipy.integrate import solve_ivp

    model, x = fourbar
    dyn = MechanismDynamics(model, reference=x)
    mech = model.mechanics

    def energy(z):
        y = dyn.full_vector(z, x)
        qd = dyn.coordinate_velocities(z, x)
        return 0.5 * qd @ mech.mass(y) @ qd + mech.potential_energy(y)

    z0 = dyn.state_at(x)
    z0[len(z0) // 2] = 3.0   # a kick of the independent coordinate's velocity
    sol = solve_ivp(lambda t, z: dyn.rates(z, x), (0.0, 1.0), z0, rtol=1e-11, atol=1e-12, method="DOP853")
    assert sol.success
    E = np.array([energy(z) for z in sol.y.T])
    swing = np.ptp(sol.y[0])
    assert swing > 0.2   # a nonlinear motion, not a small oscillation
    assert np.ptp(E) < 1e-8 * abs(E[0] - energy(dyn.state_at(x)))


def test_over_constrained_spatial_loop_against_its_nonlinear_rates():
    """The Bennett linkage (spatial, three redundant rows kept in its mechanics): the linearisation (null
    space of all rows, minimum-norm reactions in the curvature term) and the differences of the nonlinear
    minimal rates (the kept rows' KKT system, the dependent coordinates by Newton) agree; it oscillates."""
    model = load_model("tests/data/spatial/bennett.toml")
    d0 = model.defaults()
    x = find_equilibrium(model, hold={"e1_crank": d0[model.index("e1_crank")]}, free=["M"], guess=d0)
    assert np.max(np.abs(model.mechanics.phi(x))) < 1e-12   # every row, the dropped ones too
    _fd_check(model, x, rtol=1e-6)
    lam = dynamics_of(model).linearise(x).eigenvalues()
    assert len(lam) == 2 and np.allclose(lam.real, 0.0, atol=1e-9 * abs(lam[0]))


def test_a_massless_motion_takes_the_descriptor_form():
    """A mass m on a spring k and damper c, and a massless point on a spring k2 and damper c2: the reduced
    mass is singular, so the linearisation is a descriptor pencil; its finite eigenvalues are the roots of
    ``m s^2 + c s + k`` and the first-order ``c2 s + k2``."""
    names = ["x1", "x2", "k", "c", "k2", "c2", "m"]
    x1, x2, k, c, k2, c2, m = (sp.Symbol(n, real=True) for n in names)
    Q = [-k * x1 - c * velocity_symbol("x1"), -k2 * x2 - c2 * velocity_symbol("x2")]
    mech = MechanicalModel(names, ["x1", "x2"], [], Q, sp.diag(m, 0))
    vs = [Variable(n, "state" if i < 2 else "parameter", v)
          for i, (n, v) in enumerate(zip(names, [0.0, 0.0, 300.0, 6.0, 40.0, 8.0, 2.0]))]
    model = Model("massless", vs, [sp.sympify(q).subs({velocity_symbol("x1"): 0, velocity_symbol("x2"): 0}) for q in Q],
                  mechanics=mech)
    lin = dynamics_of(model).linearise(model.defaults())
    assert lin.E is not None
    expected = np.concatenate([_roots(2.0, 6.0, 300.0), [-40.0 / 8.0]])
    assert np.allclose(np.sort_complex(lin.eigenvalues()), np.sort_complex(expected), rtol=1e-10)
