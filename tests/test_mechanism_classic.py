"""Classic mechanisms generated from their descriptions against independent derivations.

The four-bar and the slider-crank are parametrised here by their input angle with closed-form
position analysis (circle intersection, slider law), and their potential energy is
differentiated numerically. Nothing below uses the generated equations to build the reference.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from mechcont.continuation import find_equilibrium
from mechcont.mechanism import assemble, load

FB = dict(a=0.3, b=0.8, c=0.6, d=0.7, m_crank=1.0, m_coupler=2.0, m_rocker=1.5, g=9.81, k=200.0, L0=0.3,
          sx=0.0, sy=0.9)


def fourbar_pose(phi, p=FB, branch=1):
    """Closed-form pose: body (x, y, theta) of crank, coupler, rocker at crank angle phi."""
    B = np.array([p["a"] * math.cos(phi), p["a"] * math.sin(phi)])
    D = np.array([p["d"], 0.0])
    BD = D - B
    r = math.hypot(*BD)
    beta = math.atan2(BD[1], BD[0])
    gamma = math.acos((p["b"] ** 2 + r ** 2 - p["c"] ** 2) / (2 * p["b"] * r))
    th_c = beta + branch * gamma
    C = B + p["b"] * np.array([math.cos(th_c), math.sin(th_c)])
    th_r = math.atan2(C[1] - D[1], C[0] - D[0])
    return [(B / 2, phi), ((B + C) / 2, th_c), ((C + D) / 2, th_r)]


def fourbar_V(phi, p=FB, branch=1):
    """Potential energy (J) of the four-bar at crank angle phi (without the moment T)."""
    pose = fourbar_pose(phi, p, branch)
    masses = (p["m_crank"], p["m_coupler"], p["m_rocker"])
    V = sum(m * p["g"] * cg[1] for m, (cg, _) in zip(masses, pose))
    mid = pose[1][0]
    ell = math.hypot(mid[0] - p["sx"], mid[1] - p["sy"])
    return V + p["k"] / 2 * (ell - p["L0"]) ** 2


def d1(f, x, h=1e-3):
    return (f(x - 2 * h) - 8 * f(x - h) + 8 * f(x + h) - f(x + 2 * h)) / (12 * h)


def d2(f, x, h=1e-3):
    return (-f(x - 2 * h) + 16 * f(x - h) - 30 * f(x) + 16 * f(x + h) - f(x + 2 * h)) / (12 * h * h)


def fourbar_dq(phi, p=FB, branch=1):
    """dq/dphi of the coordinates (x, y, theta per body) by finite differences of the closed form."""
    def q(ph):
        return np.concatenate([[cg[0], cg[1], th] for cg, th in fourbar_pose(ph, p, branch)])
    return np.array([d1(lambda t, i=i: q(t)[i], phi) for i in range(9)])


@pytest.fixture(scope="module")
def fourbar():
    return load("fourbar")


def _branch_sign(system, x):
    """Which circle intersection the assembled four-bar uses."""
    v = system.as_dict(x)
    for s in (1, -1):
        if abs(fourbar_pose(v["theta_crank"], branch=s)[1][1] - v["theta_coupler"]) < 1e-6:
            return s
    raise AssertionError("assembled pose is neither closed-form branch")


@pytest.mark.parametrize("phi", [0.2, 1.2, 2.5, 3.6, 5.0])
def test_fourbar_moment_and_stiffness_equal_potential_derivatives(fourbar, phi):
    x = assemble(fourbar, hold={"theta_crank": phi}, free=["T"])
    s = _branch_sign(fourbar, x)
    V = lambda t: fourbar_V(t, branch=s)  # noqa: E731
    v = fourbar.as_dict(x)
    # pose equals the closed form
    for (cg, th), body in zip(fourbar_pose(phi, branch=s), ("crank", "coupler", "rocker")):
        assert v[f"x_{body}"] == pytest.approx(cg[0], abs=1e-11)
        assert v[f"y_{body}"] == pytest.approx(cg[1], abs=1e-11)
        assert math.remainder(v[f"theta_{body}"] - th, 2 * math.pi) == pytest.approx(0.0, abs=1e-11)
    # equilibrium moment: T = dV/dphi
    assert v["T"] == pytest.approx(d1(V, phi), rel=1e-8, abs=1e-9)
    # reduced tangent stiffness along the one degree of freedom = V'' / |dq/dphi|^2
    mech = fourbar.mechanics
    Z = mech.allowed_motions(x)
    assert Z.shape[1] == 1
    Kr = (Z.T @ mech.tangent_stiffness(x) @ Z).item()
    dq = fourbar_dq(phi, branch=s)
    assert Kr * (dq @ dq) == pytest.approx(d2(V, phi), rel=1e-6, abs=1e-6)
    assert mech.stability(x).n_unstable == (1 if d2(V, phi) < 0 else 0)


def _omega2_generated(system, x, with_curvature=True):
    mech = system.mechanics
    Z = mech.allowed_motions(x)
    lam = mech.multipliers(x) if with_curvature else np.zeros(len(mech.constraints))
    K = mech.tangent_stiffness(x, lam)
    return (Z.T @ K @ Z).item() / (Z.T @ mech.mass(x) @ Z).item()


def _pose_vector(system, phi, s, T):
    x = system.vector({"T": T})
    for (cg, th), body in zip(fourbar_pose(phi, branch=s), ("crank", "coupler", "rocker")):
        x = system.vector({f"x_{body}": cg[0], f"y_{body}": cg[1], f"theta_{body}": th}, base=x)
    nq = len(system.mechanics.coordinates)
    x[nq:nq + len(system.reaction_names)] = system.mechanics.multipliers(x)
    return x


def test_brute_force_potential_scan_minima_are_the_stable_equilibria(fourbar):
    for T in (0.0, 3.0, -4.0):
        x = assemble(fourbar, hold={"theta_crank": 1.2}, free=["T"])
        s = _branch_sign(fourbar, x)
        grid = np.linspace(0, 2 * np.pi, 3601)[:-1]
        h = grid[1] - grid[0]
        V = np.array([fourbar_V(t, branch=s) for t in grid])  # periodic in phi
        up = np.roll(V, -1) - V - T * h  # W(phi_{i+1}) - W(phi_i), W = V - T phi: periodic too
        down = np.roll(up, 1)  # W(phi_i) - W(phi_{i-1})
        minima = grid[(down < 0) & (up > 0)]
        maxima = grid[(down > 0) & (up < 0)]
        assert len(minima) >= 1
        for phi, expect in [(p, 0) for p in minima] + [(p, 1) for p in maxima]:
            xe = find_equilibrium(fourbar, values={"T": T}, guess=_pose_vector(fourbar, phi, s, T))
            phi_eq = xe[fourbar.index("theta_crank")]
            assert abs(math.remainder(phi_eq - phi, 2 * math.pi)) < 2 * (grid[1] - grid[0])
            assert fourbar.mechanics.stability(xe).n_unstable == expect


def test_fourbar_small_oscillation_frequency_matches_time_simulation(fourbar):
    """omega^2 from the reduced stiffness (with the lambda-Hessian term) = closed form = simulation;
    without the constraint-curvature term it is clearly wrong."""
    x = assemble(fourbar, hold={"theta_crank": 1.2}, free=["T"])
    s = _branch_sign(fourbar, x)
    xe = find_equilibrium(fourbar, values={"T": 0.0}, guess=_pose_vector(fourbar, 1.2, s, 0.0))
    phi0 = xe[fourbar.index("theta_crank")]
    assert fourbar.mechanics.stability(xe).n_unstable == 0
    w2 = _omega2_generated(fourbar, xe)
    # closed form: omega^2 = V'' / m_eff, m_eff = dq^T M dq with M = diag(m, m, m L^2/12)
    dq = fourbar_dq(phi0, branch=s)
    masses = [(FB["m_crank"], FB["a"]), (FB["m_coupler"], FB["b"]), (FB["m_rocker"], FB["c"])]
    Mdiag = np.concatenate([[m, m, m * L * L / 12] for m, L in masses])
    w2_closed = d2(lambda t: fourbar_V(t, branch=s), phi0) / (dq @ (Mdiag * dq))
    assert w2 == pytest.approx(w2_closed, rel=1e-6)
    w2_wrong = _omega2_generated(fourbar, xe, with_curvature=False)
    assert abs(w2_wrong - w2) > 0.05 * w2
    # time simulation of the generated constrained equations (Baumgarte-stabilised index 1)
    mech, nq = fourbar.mechanics, len(fourbar.mechanics.coordinates)
    qi = mech.q_index
    alpha = 20.0

    def rhs(t, y):
        xx = xe.copy()
        xx[qi] = y[:nq]
        qd = y[nq:]
        A = mech.phi_q(xx)
        M = mech.mass(xx)
        nc = A.shape[0]
        rhs_c = mech.gamma(xx, qd) - 2 * alpha * (A @ qd) - alpha ** 2 * mech.phi(xx)
        KKT = np.block([[M, A.T], [A, np.zeros((nc, nc))]])
        sol = np.linalg.solve(KKT, np.concatenate([mech.applied_forces(xx, qd), rhs_c]))
        return np.concatenate([qd, sol[:nq]])

    amp = 2e-3
    start = _pose_vector(fourbar, phi0 + amp, s, 0.0)
    y0 = np.concatenate([start[qi], np.zeros(nq)])
    period_guess = 2 * np.pi / math.sqrt(w2)
    crank = list(fourbar.mechanics.coordinates).index("theta_crank")
    sol = solve_ivp(rhs, (0, 3.2 * period_guess), y0, method="DOP853", rtol=1e-11, atol=1e-13, dense_output=True)
    t = np.linspace(0, 3.2 * period_guess, 6401)
    dev = sol.sol(t)[crank] - phi0
    cross = [t[i] - dev[i] * (t[i + 1] - t[i]) / (dev[i + 1] - dev[i]) for i in range(len(t) - 1)
             if dev[i] > 0 >= dev[i + 1]]
    assert len(cross) >= 3
    w2_sim = (2 * np.pi / np.mean(np.diff(cross))) ** 2
    assert w2_sim == pytest.approx(w2, rel=1e-4)


# -- slider-crank ----------------------------------------------------------------------------
SC = dict(r=0.2, l=0.6, m_crank=0.5, m_rod=1.0, g=9.81, k=500.0, L0=0.3, xs=1.2)


def slider_x(phi, p=SC):
    return p["r"] * math.cos(phi) + math.sqrt(p["l"] ** 2 - (p["r"] * math.sin(phi)) ** 2)


def slider_V0(phi, p=SC):
    """Potential (J) without the force P: weights (rod CG at half the crank-pin height) + spring."""
    y_pin = p["r"] * math.sin(phi)
    spring = abs(p["xs"] - slider_x(phi, p)) - p["L0"]
    return p["g"] * (p["m_crank"] * y_pin / 2 + p["m_rod"] * y_pin / 2) + p["k"] / 2 * spring ** 2


@pytest.mark.parametrize("reduced", [False, True])
@pytest.mark.parametrize("phi", [0.4, 1.3, 2.2, -0.9, -2.5])
def test_slider_crank_force_and_stability_equal_closed_form(reduced, phi):
    system = load("slidercrank", reduced=reduced)
    x = assemble(system, hold={"theta_crank": phi}, free=["P"])
    v = system.coordinates_of(x)
    P = x[system.index("P")]
    # equilibrium of V0(phi) - P x_B(phi): P = V0' / x_B'
    P_closed = d1(slider_V0, phi) / d1(slider_x, phi)
    assert P == pytest.approx(P_closed, rel=1e-8, abs=1e-9)
    assert v["theta_rod"] == pytest.approx(math.atan2(-SC["r"] * math.sin(phi), slider_x(phi) - SC["r"] * math.cos(phi)),
                                           abs=1e-11)
    W2 = d2(lambda t: slider_V0(t) - P * slider_x(t), phi)
    assert system.mechanics.stability(x).n_unstable == (1 if W2 < 0 else 0)


def test_fourbar_time_simulation_conserves_closed_form_energy_full_and_reduced():
    """The dynamic model generated from the same description (mass matrix, constraint Jacobian and
    its derivative terms) conserves the closed-form energy; the reduced form (tree coordinates
    eliminated, velocity-product terms generated) follows the same motion."""
    from mechcont.dynamics import simulate

    masses = [(FB["m_crank"], FB["a"]), (FB["m_coupler"], FB["b"]), (FB["m_rocker"], FB["c"])]
    t_eval = np.linspace(0.0, 3.0, 301)
    runs = {}
    for reduced in (False, True):
        system = load("fourbar", reduced=reduced)
        x0 = assemble(system, hold={"theta_crank": 0.3}, free=["T"])
        x0[system.index("T")] = 0.0  # released from rest out of equilibrium
        runs[reduced] = (system, simulate(system, x0, (0.0, 3.0), rtol=1e-10, atol=1e-12, t_eval=t_eval))
    system, r = runs[False]
    s = _branch_sign(system, r.values[0])
    crank = r.values[:, system.index("theta_crank")]
    assert np.ptp(crank) > 2.0  # a large motion, through several configurations
    E = []
    for x, qd in zip(r.values, r.qdot):
        v = system.as_dict(x)
        T = sum(0.5 * m * (qd[3 * i] ** 2 + qd[3 * i + 1] ** 2) + 0.5 * m * L * L / 12 * qd[3 * i + 2] ** 2
                for i, (m, L) in enumerate(masses))
        E.append(T + fourbar_V(v["theta_crank"], branch=s))
    assert np.ptp(E) < 1e-6 * abs(E[0])
    red_system, rr = runs[True]
    crank_r = rr.values[:, red_system.index("theta_crank")]
    assert np.max(np.abs(crank_r - crank)) < 1e-6
