"""Live reactions (issue 31, item 2): every reaction column of a time history is the Lagrange multiplier at
that row, checked against Newton's second law for the body written out here, not against mechcont:

* a planar pendulum whose frame is neither at the pivot nor at its cg (the velocity-product forces
  matter): the pivot force along the bar ``m (g_along + L_cg theta'^2)`` and across it
  ``m (L_cg theta'' - g_across)``, with ``theta''`` from the pendulum's own equation;
* the same pendulum hanging at rest: the live reaction is the static one;
* examples/freefall_leg.toml at release: Newton for the leg with its applied forces, far from the static value;
* the spatial pendulum of tests/data/spatial/pendulum_3d.toml (a tilted hinge): the hinge force
  ``m a_cg - m g`` with ``a_cg`` from the circle the cg runs on and the moment about the hinge axis.
"""

import math

import numpy as np

from mechcont.dynamics import assemble, simulate
from mechcont.dynamics.freefall import freefall
from mechcont.models import load_model, model_from_text

M, I_CG, G, D_CG, D_PIVOT = 2.0, 0.1, 9.81, 0.2, 0.3
L_CG = D_CG + D_PIVOT  # pivot to cg (m)
I_O = I_CG + M * L_CG**2

PENDULUM = f"""
[mechanism]
name = "offset_pendulum"
[parameters]
g = {{ value = {G}, unit = "m/s^2" }}
[ground]
O = [0, 0]
[bodies.bar]
mass = {M}
length = 1.0
inertia = {I_CG}
cg = [{D_CG}, 0.0]
points = {{ p = [-{D_PIVOT}, 0] }}
initial = {{ theta = 0.0 }}
[joints.pivot]
type = "revolute"
a = "ground.O"
b = "bar.p"
[gravity]
g = "g"
"""


def pendulum():
    return model_from_text(PENDULUM, "offset_pendulum.toml")


def newton_pivot_force(theta, omega):
    """Force (N) of the pivot on the bar, ``m a_cg - m g``, and its components along (towards the pivot)
    and across the bar; ``theta`` from +x, the cg at ``L_CG`` along the bar from the pivot."""
    theta_dd = -M * G * L_CG * np.cos(theta) / I_O
    e = np.array([np.cos(theta), np.sin(theta)])   # pivot -> cg
    n = np.array([-np.sin(theta), np.cos(theta)])
    a_cg = L_CG * (theta_dd * n - omega**2 * e)
    R = M * a_cg - M * np.array([0.0, -G])[:, None]
    return R, -(R * e).sum(axis=0), (R * n).sum(axis=0)


def test_pendulum_pivot_force_is_newtons_along_and_across_the_bar():
    system = pendulum()
    r = simulate(system, assemble(system, {}), (0.0, 1.5), rtol=1e-10, atol=1e-12)
    th, w = r["theta_bar"], r["theta_bar_dot"]
    R, along, across = newton_pivot_force(th, w)
    live = np.array([r["R_pivot_x"], r["R_pivot_y"]])
    e = np.array([np.cos(th), np.sin(th)])
    n = np.array([-np.sin(th), np.cos(th)])
    # the closed form of the issue: m (g cos(phi) + L theta'^2) along the bar, phi from the downward vertical
    phi = th + math.pi / 2
    np.testing.assert_allclose(-(live * e).sum(axis=0), M * (G * np.cos(phi) + L_CG * w**2), atol=1e-7 * M * G)
    np.testing.assert_allclose(-(live * e).sum(axis=0), along, atol=1e-7 * M * G)
    np.testing.assert_allclose((live * n).sum(axis=0), across, atol=1e-7 * M * G)
    assert np.ptp(along) > M * G  # the force changes along the swing: not the frozen start value
    assert np.max(np.abs(w)) > 5.0  # and the centripetal term is large


def test_at_rest_the_live_reaction_is_the_static_one():
    system = pendulum()
    x0 = assemble(system, {"theta_bar": -math.pi / 2}, hold=["theta_bar"])  # hanging: an equilibrium
    static = system.mechanics.multipliers(x0)  # the statics: Q - Phi_q^T lambda = 0
    np.testing.assert_allclose(static, [0.0, M * G], atol=1e-9)
    r = simulate(system, x0, (0.0, 0.2))
    np.testing.assert_allclose(r["R_pivot_x"], 0.0, atol=1e-9)
    np.testing.assert_allclose(r["R_pivot_y"], M * G, rtol=1e-9)


def test_freefall_leg_pivot_reaction_at_release_is_newtons_not_the_static_one():
    system = load_model("examples/freefall_leg.toml")
    run = freefall(system, {"angle": 3.0}, lock="downlock", until=0.05)
    h = run.history
    x = h.values[0]
    live = np.array([h["R_pivot_x"][0], h["R_pivot_y"][0]])
    # Newton for the leg at release (at rest): R + F = m a_cg, F the applied force resultant (the generalised
    # forces on the frame's x, y), a_cg = theta'' k x r_cg, theta'' from the moments about the pivot
    mech = system.mechanics
    Q = mech.applied_forces(x)
    F, moment_frame = Q[:2], Q[2]
    m, L = system.variable("m").value, system.variable("L").value
    th = x[system.index("theta_leg")]
    r_frame = x[[system.index("x_leg"), system.index("y_leg")]]   # the bar's frame: its centre
    r_cg = 0.55 * L * np.array([math.cos(th), math.sin(th)])       # from the pivot O = (0, 0), 0.55 L along the leg
    moment_O = moment_frame + r_frame[0] * F[1] - r_frame[1] * F[0]
    theta_dd = moment_O / (m * L**2 / 10 + m * (r_cg @ r_cg))
    a_cg = theta_dd * np.array([-r_cg[1], r_cg[0]])
    np.testing.assert_allclose(live, m * a_cg - F, rtol=1e-9, atol=1e-6)
    printed = system.defaults()[[system.index("R_pivot_x"), system.index("R_pivot_y")]]  # frozen before: (-2003, -1008)
    assert np.linalg.norm(live - printed) > 5 * np.linalg.norm(printed)
    # held there by the uplock (a moment about the pivot alone) the pivot would carry the applied forces, -F:
    # released, it carries m a_cg less (whatever frame the leg's coordinates use)
    static = -F
    assert np.linalg.norm(live - static) > 0.2 * np.linalg.norm(static)


def test_spatial_pendulum_hinge_force_is_newtons():
    system = load_model("tests/data/spatial/pendulum_3d.toml")
    L, m, It, beta = (system.variable(n).value for n in ("L", "m", "It", "beta"))
    x0 = assemble(system, {})
    r = simulate(system, x0, (0.0, 1.0), rtol=1e-10, atol=1e-12)
    n = np.array([0.0, math.cos(beta), math.sin(beta)])
    rho = L / 2
    g = np.array([0.0, 0.0, -G])
    worst, swing = 0.0, 0.0
    for i in range(len(r)):
        c = np.array([r["x_bar"][i], r["y_bar"][i], r["z_bar"][i]])  # the cg, at the bar's centre
        v = np.array([r["x_bar_dot"][i], r["y_bar_dot"][i], r["z_bar_dot"][i]])
        radial = c - (c @ n) * n
        e_r = radial / np.linalg.norm(radial)
        e_t = np.cross(n, e_r)
        phi_dd = np.cross(c, m * g) @ n / (It + m * rho**2)
        a_cg = phi_dd * rho * e_t - (v @ v) / rho * e_r
        R = m * a_cg - m * g
        live = np.array([r["R_hinge_x"][i], r["R_hinge_y"][i], r["R_hinge_z"][i]])
        worst = max(worst, float(np.max(np.abs(live - R))))
        swing = max(swing, float(v @ v))
    assert worst < 1e-6 * m * G
    assert swing > 1.0  # it swings fast enough for the centripetal term to count
    assert r.indeterminate_rows == 0
