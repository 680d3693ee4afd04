"""Finite-difference checks of every generated derivative, and the less common description features
(polar points, centre-of-gravity offsets, welds, prismatic joints, preload, dampers, drag, custom loads)."""

import math

import numpy as np
import pytest

from mechcont.mechanism import (
    Body,
    CustomLoad,
    Damper,
    Drag,
    Gravity,
    Mechanism,
    Moment,
    Parameter,
    PointForce,
    Polar,
    Prismatic,
    Revolute,
    Spring,
    Weld,
    assemble,
    builtin_descriptions,
    load,
)


def kitchen_sink() -> Mechanism:
    params = [Parameter("psi", 0.3, "rad"), Parameter("k", 150.0, "N/m"), Parameter("F", 4.0, "N"),
              Parameter("U", 30.0, "m/s"), Parameter("rho", 1.225, "kg/m^3"), Parameter("alpha", 0.2, "rad"),
              Parameter("d", 0.08, "m"), Parameter("C_D", 1.17), Parameter("c1", 2.0, "N/m"),
              Parameter("cd", 5.0, "N s/m"), Parameter("T", 1.5, "N m"), Parameter("g", 9.81, "m/s^2")]
    bodies = [
        Body("arm", mass=2.0, length=1.0, cg=(0.1, 0.05), points={"tip": Polar(0.4, "psi")}, initial={"theta": 0.5}),
        Body("plate", mass=1.0, inertia=0.05, cg=(0.1, 0.02), points={"p1": (0, 0), "p2": (0.3, 0.1)}),
        Body("rod", mass=0.7, length=1.2, initial={"theta": -0.4}),
        Body("block", mass=0.5, inertia=0.01, initial={"x": 1.9, "y": 0.3, "theta": 0.3}),
    ]
    joints = [Revolute("O", "ground.O", "arm.a"), Weld("w", "arm.tip", "plate.p1", angle=0.2),
              Revolute("r1", "plate.p2", "rod.a"), Revolute("r2", "rod.b", "block.origin"),
              Prismatic("pr", "ground.G", "block.origin", angle=0.3, relative_angle=0.3)]
    loads = [PointForce("F", "block.origin", "F", direction=2.0), Moment("T", "arm", "T"),
             Drag("drag", "arm"),
             CustomLoad("custom", "rod.b", fx="-c1*y_rod", fy="0.5*sin(theta_arm)", moment="0.1*x_block")]
    return Mechanism("sink", params, bodies, joints, ground={"O": (0, 0), "G": (1.0, 0), "S": (0.2, 1.5)},
                     springs=[Spring("s", "ground.S", "plate.p1", "k", 0.4, preload=3.0)],
                     dampers=[Damper("dmp", "ground.S", "rod.origin", "cd")], loads=loads, gravity=Gravity(),
                     hold={"theta_arm": 0.5})


SYSTEMS = [(name, red) for name in builtin_descriptions() for red in (False, True)]


def _build(name, reduced):
    if name == "sink":
        m = kitchen_sink()
        return m.build_reduced() if reduced else m.build()
    return load(name, reduced=reduced)


def _fd(f, x, h):
    cols = []
    for i in range(len(x)):
        e = np.zeros(len(x))
        e[i] = h
        cols.append((f(x + e) - f(x - e)) / (2 * h))
    return np.array(cols).T


def _close(A, B, tol=1e-6):
    scale = max(1.0, np.abs(B).max())
    assert np.abs(A - B).max() <= tol * scale


@pytest.mark.parametrize("name,reduced", SYSTEMS + [("sink", False), ("sink", True)])
def test_every_generated_derivative_matches_finite_differences(name, reduced):
    system = _build(name, reduced)
    rng = np.random.default_rng(1)
    x = system.defaults() + 0.01 * rng.standard_normal(len(system.names))
    h = 1e-6
    _close(system.jacobian(x), _fd(system.residual, x, h))
    v = rng.standard_normal(len(x))
    _close(system.jacobian_derivative(x, v), _fd(lambda y: system.jacobian(y) @ v, x, h))
    mech = system.mechanics
    qi = mech.q_index
    nq = len(qi)

    def with_q(q):
        y = x.copy()
        y[qi] = q
        return y

    q0 = x[qi]
    qd = rng.standard_normal(nq)
    _close(mech.phi_q(x), _fd(lambda q: mech.phi(with_q(q)), q0, h))
    # gamma = -(d/dq (Phi_q qdot)) qdot
    dphiq = _fd(lambda q: mech.phi_q(with_q(q)) @ qd, q0, h)
    _close(mech.gamma(x, qd), -dphiq @ qd)
    # tangent stiffness without multipliers is -dQ/dq (velocities held)
    _close(mech.tangent_stiffness(x, np.zeros(len(mech.constraints))),
           -_fd(lambda q: mech.applied_forces(with_q(q), qd * 0), q0, h))
    _close(mech.damping_matrix(x), -_fd(lambda w: mech.applied_forces(x, w), np.zeros(nq), h))
    # the curvature term: sum_k lambda_k Hess(Phi_k) by differences of Phi_q^T lambda
    lam = rng.standard_normal(len(mech.constraints))
    curv = mech.tangent_stiffness(x, lam) - mech.tangent_stiffness(x, np.zeros_like(lam))
    _close(curv, _fd(lambda q: mech.phi_q(with_q(q)).T @ lam, q0, h))


def test_kitchen_sink_assembles_and_reduced_form_agrees():
    mech = kitchen_sink()
    full, red = mech.build(), mech.build_reduced()
    assert full.dof.dof == 1 and red.dof.dof == 1
    assert set(red.state_names) == {"theta_arm", "theta_rod", "theta_block", "R_pr", "T_pr"}
    xf = assemble(full, hold={"theta_arm": 0.45}, free=["F"])
    xr = assemble(red, hold={"theta_arm": 0.45}, free=["F"])
    assert xf[full.index("F")] == pytest.approx(xr[red.index("F")], rel=1e-10)
    cf, cr = full.coordinates_of(xf), red.coordinates_of(xr)
    for k in cf:
        assert cf[k] == pytest.approx(cr[k], abs=1e-10)
    assert full.mechanics.stability(xf).n_unstable == red.mechanics.stability(xr).n_unstable
    # weld and prismatic hold their angles; polar point places the weld
    assert cf["theta_plate"] - cf["theta_arm"] == pytest.approx(0.2, abs=1e-12)
    assert cf["theta_block"] == pytest.approx(0.3, abs=1e-12)
    tip = np.array([cf["x_arm"], cf["y_arm"]]) + 0.4 * np.array([math.cos(0.45 + 0.3), math.sin(0.45 + 0.3)])
    assert np.allclose(tip, [cf["x_plate"], cf["y_plate"]], atol=1e-12)


def test_mass_matrix_equals_kinetic_energy_with_cg_offsets():
    system = kitchen_sink().build()
    x = system.defaults()
    v = system.as_dict(x)
    rng = np.random.default_rng(3)
    qd = rng.standard_normal(len(system.mechanics.coordinates))
    rate = dict(zip(system.mechanics.coordinates, qd))
    T = 0.0
    for body, m, inertia, c in (("arm", 2.0, 2.0 / 12, (0.1, 0.05)), ("plate", 1.0, 0.05, (0.1, 0.02)),
                                ("rod", 0.7, 0.7 * 1.44 / 12, (0, 0)), ("block", 0.5, 0.01, (0, 0))):
        th, w = v[f"theta_{body}"], rate[f"theta_{body}"]
        # velocity of the CG: origin velocity + w x R c
        rc = np.array([math.cos(th) * c[0] - math.sin(th) * c[1], math.sin(th) * c[0] + math.cos(th) * c[1]])
        vel = np.array([rate[f"x_{body}"], rate[f"y_{body}"]]) + w * np.array([-rc[1], rc[0]])
        T += 0.5 * m * vel @ vel + 0.5 * inertia * w * w
    assert 0.5 * qd @ system.mechanics.mass(x) @ qd == pytest.approx(T, rel=1e-12)


def test_drag_moment_is_paper_eq_12():
    """A bar pinned at its end with only drag and a moment T: T balances
    D = 1/4 rho (U cos(alpha - theta + pi/2))^2 d L^2 C_D (eq. 12) with the sign of the normal flow."""
    params = [Parameter(n, v) for n, v in (("rho", 1.225), ("U", 40.0), ("alpha", 0.1), ("d", 0.1), ("C_D", 1.17),
                                            ("L", 1.3), ("T", 0.0))]
    mech = Mechanism("drag", params, [Body("bar", mass=1.0, length="L", initial={"theta": -1.2})],
                     [Revolute("pin", "ground.O", "bar.a")], ground={"O": (0, 0)},
                     loads=[Drag("drag", "bar"), Moment("T", "bar", "T")])
    system = mech.build_reduced()
    for theta in (-1.2, -0.3, 0.4, 2.0):
        x = assemble(system, hold={"theta_bar": theta}, free=["T"])
        u_n = 40.0 * math.sin(0.1 - theta)  # flow component along the bar's left normal
        D = 0.25 * 1.225 * (40.0 * math.cos(0.1 - theta + math.pi / 2)) ** 2 * 0.1 * 1.3 ** 2 * 1.17
        # the drag pushes along +normal when u_n > 0: a counter-clockwise moment D that T balances
        assert x[system.index("T")] == pytest.approx(-math.copysign(D, u_n), rel=1e-9)


def test_spring_preload_and_custom_load_expressions():
    """A bar hanging from a pin: preloaded spring tension and a custom moment expression in the
    coordinates enter the equilibrium exactly as written."""
    params = [Parameter("k", 100.0), Parameter("P0", 7.0), Parameter("M0", 2.0), Parameter("F", 0.0)]
    mech = Mechanism("custom", params, [Body("bar", mass=1.0, length=1.0, initial={"theta": 0.3})],
                     [Revolute("pin", "ground.O", "bar.a")], ground={"O": (0, 0), "S": (0, 2.0)},
                     springs=[Spring("s", "ground.S", "bar.b", "k", 1.0, preload="P0")],
                     loads=[CustomLoad("c", "bar.b", moment="M0*cos(theta_bar)"),
                            PointForce("F", "bar.b", "F", direction=(1, 0))])
    system = mech.build_reduced()
    th = 0.3
    x = assemble(system, hold={"theta_bar": th}, free=["F"])
    tip = np.array([math.cos(th), math.sin(th)])
    ell = np.linalg.norm(np.array([0, 2.0]) - tip)
    tension = 7.0 + 100.0 * (ell - 1.0)
    f_spring = tension * (np.array([0, 2.0]) - tip) / ell
    # moments about the pin: spring + custom + F (horizontal at the tip) = 0
    moment = tip[0] * f_spring[1] - tip[1] * f_spring[0] + 2.0 * math.cos(th)
    F = moment / tip[1]
    assert x[system.index("F")] == pytest.approx(F, rel=1e-10)


@pytest.mark.parametrize("start,end", [("a", "b"), ("b", "a"), ("a", "lug"), ("lug", "tip")])
@pytest.mark.parametrize("reduced", [False, True])
def test_drag_on_a_parameter_length_bar_builds_and_differentiates(start, end, reduced):
    """Drag with both ends on one bar whose length is a parameter (the main fitting of a nose
    gear): no |L| in the equations, every derivative equals finite differences, and the drag
    moment about the pin equals eq. 12 for the segment (force at its midpoint)."""
    import sympy as sp

    params = [Parameter(n, v) for n, v in (("rho", 1.225), ("U", 40.0), ("alpha", 0.3), ("d", 0.15),
                                            ("C_D", 1.17), ("L3", 2.0), ("L32", 1.2), ("psi", 0.2),
                                            ("T", 0.0), ("g", 9.81))]
    points = {"lug": ("L3/2 - L32", 0), "tip": Polar("L3/3", "psi")}
    mech = Mechanism("drag3", params, [Body("3", mass=120.0, length="L3", points=points, initial={"theta": 1.4})],
                     [Revolute("pivot", "ground.O", "3.b")], ground={"O": (0, 0)}, gravity=Gravity(),
                     loads=[Drag("drag", "3", start=start, end=end, CD="C_D"), Moment("T", "3", "T")])
    system = mech.build_reduced() if reduced else mech.build()
    assert not any(e.has(sp.Abs) for e in system.equations)
    rng = np.random.default_rng(3)
    x = system.defaults() + 0.01 * rng.standard_normal(len(system.names))
    _close(system.jacobian(x), _fd(system.residual, x, 1e-6))
    # moment balance about the pivot: T = -(gravity + drag moments), drag from eq. 12 by hand
    L3, L32, psi = 2.0, 1.2, 0.2
    local = {"a": (-L3 / 2, 0.0), "b": (L3 / 2, 0.0), "lug": (L3 / 2 - L32, 0.0),
             "tip": (L3 / 3 * math.cos(psi), L3 / 3 * math.sin(psi))}
    for th in (1.4, 0.2, -2.0):
        x = assemble(system, hold={"theta3": th}, free=["T"])
        R = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
        O = -R @ np.array(local["b"])  # frame origin: the pivot end b sits at the ground point O
        A, B = O + R @ np.array(local[start]), O + R @ np.array(local[end])
        seg = B - A
        ell = math.hypot(*seg)
        n = np.array([-seg[1], seg[0]]) / ell
        u_n = 40.0 * (math.cos(0.3) * n[0] + math.sin(0.3) * n[1])
        f = 0.5 * 1.225 * 1.17 * 0.15 * ell * u_n * abs(u_n) * n
        mid = (A + B) / 2
        m_drag = mid[0] * f[1] - mid[1] * f[0]
        m_grav = -O[0] * 120.0 * 9.81
        assert x[system.index("T")] == pytest.approx(-(m_drag + m_grav), rel=1e-9, abs=1e-9)
