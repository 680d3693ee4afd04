"""Periodic orbits by orthogonal collocation (issue 35, item 4) against closed forms and independent simulations.

The collocation (NCOL Gauss points per interval) is superconvergent: at the mesh points, and in the
period, the error is of order h^(2 NCOL) (h the interval length); between them h^(NCOL+1). Tolerances
below follow from that and from measured errors (NTST = 20, NCOL = 4: period of the Stuart-Landau
orbit 1.2e-11 off, 3e-9 at NTST = 10, a ratio 2^8).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from mechcont.continuation import ContinuationOptions, cycles_from_hopf, cycles_from_samples, hopf_point
from mechcont.equations import dynamics_of, ode_model
from mechcont.errors import ConvergenceError, InputError

x, y, w1, w2, mu, om = sp.symbols("x y w1 w2 mu omega", real=True)
R2 = x**2 + y**2


def _stuart_landau(omega=2.0):
    """dx/dt = mu x - omega y - x r^2, dy/dt = omega x + mu y - y r^2: orbit radius sqrt(mu), period 2 pi/omega,
    non-trivial multiplier exp(-2 mu T)."""
    return ode_model("sl", {"x": 0.0, "y": 0.0}, {"mu": 0.0, "omega": omega},
                     {"x": mu * x - om * y - x * R2, "y": om * x + mu * y - y * R2})


def _mesh_radius(family, i):
    """The orbit's radius at its mesh points (every NCOL-th node: there the error is O(h^(2 NCOL)))."""
    mesh, u = family.orbits[i]
    return np.hypot(*u[::mesh.ncol].T)


def test_stuart_landau_family_radius_period_and_multiplier():
    m = _stuart_landau()
    fam = cycles_from_hopf(m, m.vector({"mu": 1e-3}), "mu", options=ContinuationOptions(ds=0.01, dsmax=0.2,
                           bounds={"mu": (-1.0, 1.0)}), at=[0.25, 0.5])
    assert fam.labels[0] == "HB" and fam.p[0] == pytest.approx(0.0, abs=1e-12)  # refined from mu = 1e-3
    assert fam.period[0] == pytest.approx(np.pi, rel=1e-12)
    assert [n for n, _ in fam.point_names()] == ["HB1", "UZ1", "UZ2", "EP1"]
    assert fam.p[fam.row("UZ1")] == pytest.approx(0.25, abs=1e-12)
    assert fam.p[fam.row("EP1")] == pytest.approx(1.0, abs=1e-12)
    for i in range(1, len(fam)):
        p, T = fam.p[i], fam.period[i]
        assert np.max(np.abs(_mesh_radius(fam, i) - math.sqrt(p))) < 1e-9, (i, p)
        assert abs(T - np.pi) < 1e-9
        assert len(fam.multipliers[i]) == 1
        assert fam.multipliers[i][0] == pytest.approx(math.exp(-2 * p * T), rel=1e-7)
        assert fam.stability()[i] == "stable"


def test_collocation_error_falls_as_h_to_the_2_ncol():
    m = _stuart_landau()
    errors = []
    for ntst in (8, 16):
        fam = cycles_from_hopf(m, m.defaults(), "mu", ntst=ntst, ncol=3, adapt=0, at=[0.5],
                               options=ContinuationOptions(ds=0.05, dsmax=0.2, bounds={"mu": (-1.0, 0.6)}))
        errors.append(abs(fam.period[fam.row("UZ1")] - np.pi))
    assert 2**6 / 2 < errors[0] / errors[1] < 2**6 * 2  # order 2 NCOL = 6


def test_van_der_pol_period_at_mu_1():
    # y' = (mu - x^2) y - x has a non-degenerate Hopf point at mu = 0 and is Van der Pol's equation at mu = 1
    m = ode_model("vdp", {"x": 0.0, "y": 0.0}, {"mu": 0.0}, {"x": y, "y": (mu - x**2) * y - x})
    fam = cycles_from_hopf(m, m.defaults(), "mu", ntst=80, ncol=4, at=[1.0],
                           options=ContinuationOptions(ds=0.05, dsmax=0.5, bounds={"mu": (-1.0, 1.2)}))
    i = fam.row("UZ1")
    assert fam.p[i] == pytest.approx(1.0, abs=1e-13)
    assert abs(fam.period[i] - 6.6632868593231301896996820305) < 1e-10
    assert fam.stability()[i] == "stable"


def _subcritical():
    """r' = r (mu + 2 r^2 - r^4), theta' = 1: cycles at mu = r^4 - 2 r^2, a fold of cycles at mu = -1, r = 1;
    the non-trivial multiplier exp(4 r^2 (1 - r^2) T), T = 2 pi."""
    g = mu + 2 * R2 - R2**2
    return ode_model("sub", {"x": 0.0, "y": 0.0}, {"mu": 0.0}, {"x": x * g - y, "y": y * g + x})


def test_subcritical_family_has_its_fold_of_cycles_at_mu_minus_1():
    m = _subcritical()
    fam = cycles_from_hopf(m, m.defaults(), "mu", ntst=40, options=ContinuationOptions(ds=0.01, dsmax=0.2,
                           bounds={"mu": (-2.0, 0.5)}))
    names = [n for n, _ in fam.point_names()]
    assert names == ["HB1", "LPC1", "EP1"], names
    k = fam.row("LPC1")
    assert fam.p[k] == pytest.approx(-1.0, abs=1e-9)
    assert np.max(np.abs(_mesh_radius(fam, k) - 1.0)) < 1e-8
    stab = fam.stability()
    assert set(stab[1:k]) == {"unstable"} and set(stab[k + 1:]) == {"stable"}
    for i in range(1, len(fam)):
        r = float(np.mean(_mesh_radius(fam, i)))
        assert fam.p[i] == pytest.approx(r**4 - 2 * r**2, abs=1e-9)
        want = math.exp(4 * r**2 * (1 - r**2) * 2 * np.pi)
        assert abs(fam.multipliers[i][0]) == pytest.approx(want, rel=1e-6, abs=1e-12)


def _circle(samples=400, turns=2):
    t = np.linspace(0.0, 2 * np.pi * turns, samples)
    return t, np.column_stack([np.cos(t), np.sin(t)])


def test_period_doubling_where_a_multiplier_crosses_minus_1():
    # the unit circle (x, y) carries w = (w1, w2) in a frame turning at half the orbit's rate: w = R(theta/2) v,
    # v' = diag(mu, -1) v. After one turn R(pi) = -I: multipliers -exp(2 pi mu), -exp(-2 pi), and exp(-4 pi) of (x, y)
    c, s = x, y  # cos(theta), sin(theta) on the circle
    A = sp.Matrix([[(mu - 1) / 2 + (mu + 1) / 2 * c, (mu + 1) / 2 * s], [(mu + 1) / 2 * s, (mu - 1) / 2 - (mu + 1) / 2 * c]])
    A += sp.Rational(1, 2) * sp.Matrix([[0, -1], [1, 0]])
    wv = A * sp.Matrix([w1, w2])
    m = ode_model("pd", {"x": 1.0, "y": 0.0, "w1": 0.0, "w2": 0.0}, {"mu": -0.5},
                  {"x": x * (1 - R2) - y, "y": y * (1 - R2) + x, "w1": wv[0], "w2": wv[1]})
    t, Z = _circle()
    fam = cycles_from_samples(m, m.defaults(), t, np.column_stack([Z, 0 * Z]), "mu",
                              options=ContinuationOptions(ds=0.05, dsmax=0.2, bounds={"mu": (-1.0, 0.5)}))
    assert [n for n, _ in fam.point_names()] == ["PD1", "EP1"]
    k = fam.row("PD1")
    assert fam.p[k] == pytest.approx(0.0, abs=1e-10)
    for i in range(len(fam)):
        mus = np.sort_complex(fam.multipliers[i])
        want = np.sort_complex(np.array([-math.exp(2 * np.pi * fam.p[i]), -math.exp(-2 * np.pi), math.exp(-4 * np.pi)],
                                        complex))
        np.testing.assert_allclose(mus, want, rtol=1e-7, atol=1e-10)
        assert fam.period[i] == pytest.approx(2 * np.pi, rel=1e-9)
    assert fam.stability()[k - 1] == "stable" and fam.stability()[k + 1] == "unstable"


def test_torus_bifurcation_where_a_complex_pair_crosses_the_circle():
    # w' = mu w + alpha J w on the unit circle: multipliers exp(2 pi mu) exp(+-2 pi i alpha)
    alpha = 0.3
    m = ode_model("ns", {"x": 1.0, "y": 0.0, "w1": 0.0, "w2": 0.0}, {"mu": -0.3},
                  {"x": x * (1 - R2) - y, "y": y * (1 - R2) + x, "w1": mu * w1 - alpha * w2, "w2": mu * w2 + alpha * w1})
    t, Z = _circle()
    fam = cycles_from_samples(m, m.defaults(), t, np.column_stack([Z, 0 * Z]), "mu",
                              options=ContinuationOptions(ds=0.05, dsmax=0.2, bounds={"mu": (-1.0, 0.3)}))
    assert [n for n, _ in fam.point_names()] == ["NS1", "EP1"]
    k = fam.row("NS1")
    assert fam.p[k] == pytest.approx(0.0, abs=1e-10)
    pair = fam.multipliers[k][fam.multipliers[k].imag > 0][0]
    assert pair == pytest.approx(np.exp(2j * np.pi * alpha), abs=1e-8)
    assert fam.floquet_max[-1] == pytest.approx(math.exp(2 * np.pi * 0.3), rel=1e-7)


def test_time_simulation_converges_onto_the_computed_stable_cycle():
    from scipy.integrate import solve_ivp

    m = ode_model("vdp", {"x": 0.0, "y": 0.0}, {"mu": 1.0}, {"x": y, "y": (mu - x**2) * y - x})
    dyn = dynamics_of(m)
    xv = m.defaults()

    def rhs(_, z):
        return dyn.rates(z, xv)

    def top(_, z):  # y = 0 going down: the largest x of a turn
        return z[1]

    top.direction = -1
    sol = solve_ivp(rhs, (0.0, 80.0), [0.5, 0.0], method="DOP853", rtol=1e-12, atol=1e-12, events=top,
                    dense_output=True)
    t_top, z_top = sol.t_events[0], sol.y_events[0]
    sim_period, sim_xmax = t_top[-1] - t_top[-2], z_top[-1][0]
    ts = np.linspace(60.0, 80.0, 4000)
    fam = cycles_from_samples(m, xv, ts, sol.sol(ts).T, "mu", ntst=60, ncol=4, at=[1.5],
                              options=ContinuationOptions(ds=0.05, dsmax=0.2, bounds={"mu": (0.5, 2.0)}))
    assert fam.p[0] == 1.0 and fam.stability()[0] == "stable"
    assert fam.period[0] == pytest.approx(sim_period, abs=1e-8)
    # the largest x of the orbit: where y = 0 between its samples (the polynomial's own root)
    tt, Z = fam.orbit(0, 4000)
    k = int(np.argmax(Z[:, 0]))
    mesh, u = fam.orbits[0]
    from mechcont._roots import brentq

    tau = brentq(lambda s: mesh.evaluate(u, np.array([s]))[0, 1], tt[k - 1] / fam.period[0], tt[k + 1] / fam.period[0])
    assert mesh.evaluate(u, np.array([tau]))[0, 0] == pytest.approx(sim_xmax, abs=1e-8)
    assert fam.maximum[0, 0] == pytest.approx(sim_xmax, abs=1e-4)  # over the nodes and Gauss points only
    # the family continues from the simulated orbit towards larger mu: Van der Pol's cycle lengthens
    assert fam.period[fam.row("UZ1")] > fam.period[0]


def _ab():
    """AUTO's demo ab (the A -> B reaction) at B = 14, beta = 3."""
    u1, u2, D, B, beta = sp.symbols("u1 u2 D B beta", real=True)
    e = sp.exp(u2)
    return ode_model("ab", {"u1": 0.0, "u2": 0.0}, {"D": 0.0, "B": 14.0, "beta": 3.0},
                     {"u1": -u1 + D * (1 - u1) * e, "u2": -u2 + D * B * (1 - u1) * e - beta * u2})


def _ab_hopf_values(B=14.0, beta=3.0):
    """The ab equilibria have u1 = (1 + beta) u2 / B and D = u1 exp(-u2) / (1 - u1); the trace of the Jacobian is
    -1/(1 - u1) - 1 - beta + B u1 (its determinant is positive there): Hopf points where it vanishes (Routh-Hurwitz)."""
    roots = np.roots([-B, B + 1 + beta, -(2 + beta)])  # (1 - u1)(-1 - beta + B u1) - 1 = 0
    out = []
    for u1 in sorted(r.real for r in roots if abs(r.imag) < 1e-14 and 0 < r.real < 1):
        u2 = B * u1 / (1 + beta)
        out.append(u1 * math.exp(-u2) / (1 - u1))
    return out


def test_ab_family_joins_its_two_hopf_points_and_matches_a_simulation():
    from scipy.integrate import solve_ivp

    m = _ab()
    d_low, d_high = _ab_hopf_values()
    # a rough equilibrium near the first Hopf point: hopf_point solves for the equilibrium and the Hopf point
    x0 = m.vector({"D": d_low + 1e-3, "u1": 0.35, "u2": 1.2})
    fam = cycles_from_hopf(m, x0, "D", ntst=50, ncol=4, at=[0.2],
                           options=ContinuationOptions(ds=0.01, dsmax=0.5, bounds={"D": (0.0, 0.5)}))
    assert [n for n, _ in fam.point_names()] == ["HB1", "LPC1", "UZ1", "HB2"], fam.point_names()
    assert fam.p[0] == pytest.approx(d_low, abs=1e-12)
    assert fam.p[-1] == pytest.approx(d_high, abs=1e-12)
    assert "Hopf point" in fam.message
    i = fam.row("UZ1")
    assert fam.stability()[i] == "stable"

    def rhs(_, u, D=0.2, B=14.0, beta=3.0):  # the demo's equations typed again
        e = math.exp(u[1])
        return [-u[0] + D * (1 - u[0]) * e, -u[1] + D * B * (1 - u[0]) * e - beta * u[1]]

    def section(_, z):
        return z[0] - 0.5

    section.direction = 1
    sol = solve_ivp(rhs, (0.0, 40.0), [0.9, 6.0], method="DOP853", rtol=1e-12, atol=1e-12, dense_output=True,
                    events=section)
    cross = sol.t_events[0]
    assert cross[-1] > 30.0  # the cycle attracts by a factor of about 1e-13 a turn: converged long before
    assert fam.period[i] == pytest.approx(cross[-1] - cross[-2], rel=1e-8)
    Z = sol.sol(np.linspace(30.0, 40.0, 20000)).T
    assert fam.maximum[i, 1] == pytest.approx(Z[:, 1].max(), rel=1e-4)
    assert fam.minimum[i, 1] == pytest.approx(Z[:, 1].min(), rel=1e-4)


def test_not_a_hopf_point_and_bad_samples_are_one_line_errors():
    m = ode_model("lin", {"x": 0.0, "y": 0.0}, {"mu": -1.0}, {"x": mu * x, "y": -y})  # real eigenvalues only
    with pytest.raises(InputError, match="not a Hopf point"):
        hopf_point(m, dynamics_of(m), m.defaults(), "mu")
    sl = _stuart_landau()
    with pytest.raises(InputError, match="lies at 0, far from it: not a Hopf point"):  # its Hopf point: mu = 0
        hopf_point(sl, dynamics_of(sl), sl.vector({"mu": 0.8}), "mu")
    assert hopf_point(sl, dynamics_of(sl), sl.vector({"mu": 0.05}), "mu").x[sl.index("mu")] == pytest.approx(0, abs=1e-14)
    t = np.linspace(0, 1.0, 50)  # a third of a turn: no return to the section
    with pytest.raises(InputError, match="samples"):
        cycles_from_samples(sl, sl.vector({"mu": 0.25}), t, np.column_stack([np.cos(2 * t), np.sin(2 * t)]), "mu")
    with pytest.raises(InputError, match="ncol"):
        cycles_from_hopf(sl, sl.defaults(), "mu", ncol=9)
    with pytest.raises(InputError, match="bound"):
        cycles_from_hopf(sl, sl.defaults(), "mu", options=ContinuationOptions(bounds={"omega": (0.0, 1.0)}))


def test_a_family_that_cannot_start_raises_with_its_start():
    # the rates are not finite beyond r = 0.01 and the smallest step is larger than that
    g = mu - R2 + sp.sqrt(sp.Rational(1, 10000) - R2) - sp.Rational(1, 100)
    m = ode_model("dom", {"x": 0.0, "y": 0.0}, {"mu": 0.0}, {"x": x * g - y, "y": y * g + x})
    with pytest.raises(ConvergenceError, match="cannot start") as exc:
        cycles_from_hopf(m, m.defaults(), "mu", options=ContinuationOptions(ds=0.05, dsmin=0.05, dsmax=0.05))
    assert exc.value.partial is not None and exc.value.partial.labels == ["HB"]


@pytest.mark.parametrize("ntst,ncol", [(7, 2), (12, 4), (5, 7)])
def test_condensed_solve_equals_the_whole_sparse_system(ntst, ncol):
    # the condensation of parameters solves the same linear system as the whole sparse Jacobian (SuperLU)
    from scipy.sparse.linalg import splu

    from mechcont.continuation._collocation import Mesh
    from mechcont.continuation._cycle_system import CycleSystem, RateFunction, phase_reference

    m = ode_model("vdp", {"x": 0.0, "y": 0.0}, {"mu": 1.0}, {"x": y, "y": (mu - x**2) * y - x})
    system = CycleSystem(RateFunction(m, dynamics_of(m), "mu", m.defaults()), Mesh(ntst, ncol), np.ones(2), 1.0)
    tau = system.mesh.times()
    X = system.pack(2 * np.column_stack([np.cos(2 * np.pi * tau), -np.sin(2 * np.pi * tau)]), 6.6, 1.0)
    rng = np.random.default_rng(1)
    closing = system.row(rng.standard_normal(system.size))
    res, J = system.linearise(X, phase_reference(system, X), closing, 0.3)
    res2, lu = system.factored(X, phase_reference(system, X), closing, 0.3)
    np.testing.assert_array_equal(res, res2)
    b = rng.standard_normal(system.size)
    d_sparse, d_condensed = splu(J.tocsc()).solve(b), lu.solve(b)
    assert np.max(np.abs(d_condensed - d_sparse)) <= 1e-10 * np.max(np.abs(d_sparse))
    np.testing.assert_allclose(J @ d_condensed, b, atol=1e-10 * np.max(np.abs(b)) * np.linalg.norm(J.toarray(), 1))
    # the intervals' transfer matrices multiply to the monodromy matrix
    Phi = lu.transfer()
    M = np.eye(2)
    for P in Phi:
        M = P @ M
    np.testing.assert_allclose(M, system.monodromy(X), rtol=1e-10, atol=1e-12)


def test_mesh_adaptation_follows_a_relaxation_orbit():
    # at mu = 3 the orbit of y' = (mu - x^2) y - x has fast jumps: a uniform mesh of 20 intervals is 1.5e-3 off in
    # the period (against 200 uniform intervals, whose own error is below 1e-10), the adapted one 4e-6
    m = ode_model("vdp", {"x": 0.0, "y": 0.0}, {"mu": 0.0}, {"x": y, "y": (mu - x**2) * y - x})
    periods = {}
    for ntst, adapt in ((200, 0), (20, 0), (20, 3)):
        fam = cycles_from_hopf(m, m.defaults(), "mu", ntst=ntst, adapt=adapt, at=[3.0],
                               options=ContinuationOptions(ds=0.05, dsmax=0.5, bounds={"mu": (-1.0, 3.2)}))
        i = fam.row("UZ1")
        periods[ntst, adapt] = fam.period[i]
        if adapt:
            assert fam.orbits[i][0].uniformity() > 3  # the intervals gathered where the orbit turns fast
    uniform, adapted = (abs(periods[20, a] - periods[200, 0]) for a in (0, 3))
    assert uniform > 1e-4 and adapted < uniform / 100


def test_family_ends_at_a_period_bound_or_after_max_steps_and_runs_either_way_from_samples():
    m = ode_model("vdp", {"x": 0.0, "y": 0.0}, {"mu": 1.0}, {"x": y, "y": (mu - x**2) * y - x})
    fam1 = cycles_from_hopf(m, m.vector({"mu": 0.0}), "mu", at=[1.0], ntst=40,
                            options=ContinuationOptions(ds=0.05, dsmax=0.5, bounds={"mu": (-1.0, 5.0)}))
    t, Z = fam1.orbit(fam1.row("UZ1"), 800)
    t = np.concatenate([t, t[1:] + t[-1]])  # two turns of the computed orbit at mu = 1, as a simulation gives them
    Z = np.vstack([Z, Z[1:]])
    up = cycles_from_samples(m, m.defaults(), t, Z, "mu", ntst=40,
                             options=ContinuationOptions(ds=0.05, dsmax=0.5, bounds={"period": (0.0, 7.0)}))
    assert up.labels[-1] == "EP" and up.period[-1] == pytest.approx(7.0, abs=1e-12) and up.p[-1] > 1.0
    assert "reached a bound" in up.message
    down = cycles_from_samples(m, m.defaults(), t, Z, "mu", ntst=40, direction=-1,
                               options=ContinuationOptions(ds=0.05, dsmax=0.5, max_steps=3))
    assert len(down) == 4 and down.p[-1] < 1.0 and down.labels[-1] == "EP"
    assert down.message == "stopped after max_steps=3"
    assert down.period[0] == pytest.approx(6.6632868593231302, abs=1e-7)  # ntst = 40: the collocation's own error


def test_rossler_period_doubling_checked_by_shooting():
    # Roessler (a = b = 0.2): the period-1 cycle doubles near c = 2.832. The located PD orbit is checked by an
    # independent formulation: the flow and its variational equations integrated over one period (solve_ivp)
    from scipy.integrate import solve_ivp

    z_ = sp.Symbol("z", real=True)
    a, b, c = sp.symbols("a b c", real=True)
    m = ode_model("ross", {"x": 0.0, "y": 0.0, "z": 0.0}, {"a": 0.2, "b": 0.2, "c": 2.5},
                  {"x": -y - z_, "y": x + a * y, "z": b + z_ * (x - c)})
    dyn = dynamics_of(m)
    xv = m.defaults()
    sim = solve_ivp(lambda _, u: dyn.rates(u, xv), (0.0, 100.0), [1.0, 1.0, 0.0], rtol=1e-10, atol=1e-10,
                    dense_output=True)
    ts = np.linspace(80.0, 100.0, 2000)
    fam = cycles_from_samples(m, xv, ts, sim.sol(ts).T, "c", ntst=40,
                              options=ContinuationOptions(ds=0.05, dsmax=0.2, bounds={"c": (2.5, 3.0)}))
    k = fam.row("PD1")
    cpd, T = fam.p[k], fam.period[k]
    assert 2.8 < cpd < 2.86
    z0 = fam.orbits[k][1][0]

    def flow(_, v, c=cpd):  # the Roessler equations and their variational equations, typed again
        px, py, pz = v[:3]
        J = np.array([[0.0, -1.0, -1.0], [1.0, 0.2, 0.0], [pz, 0.0, px - c]])
        return np.concatenate([[-py - pz, px + 0.2 * py, 0.2 + pz * (px - c)], (J @ v[3:].reshape(3, 3)).ravel()])

    end = solve_ivp(flow, (0.0, T), np.concatenate([z0, np.eye(3).ravel()]), method="DOP853", rtol=1e-12,
                    atol=1e-12).y[:, -1]
    assert np.max(np.abs(end[:3] - z0)) < 1e-7  # the orbit closes
    mus = np.linalg.eigvals(end[3:].reshape(3, 3))
    assert np.min(np.abs(mus - 1.0)) < 1e-6 and np.min(np.abs(mus + 1.0)) < 1e-6


def test_any_dynamics_through_the_protocol_gives_the_same_family(monkeypatch):
    # a mechanism's dynamics is evaluated point by point through the Dynamics protocol (no batch): same orbits
    import mechcont.equations as eq

    class Protocol:  # the protocol's members only, forwarding to the ODE's own dynamics
        def __init__(self, model):
            self._d = eq.OdeDynamics(model)
            self.state_names = self._d.state_names

        def __getattr__(self, name):
            if name in ("state_at", "full_vector", "full_vectors", "rates", "rates_jacobian", "parameter_rates",
                        "linearise"):
                return getattr(self._d, name)
            raise AttributeError(name)

    m = _stuart_landau()
    opts = ContinuationOptions(ds=0.05, dsmax=0.2, bounds={"mu": (-1.0, 0.5)})
    batch = cycles_from_hopf(m, m.defaults(), "mu", ntst=10, at=[0.3], options=opts)
    monkeypatch.setattr(eq, "dynamics_of", Protocol)
    each = cycles_from_hopf(m, m.defaults(), "mu", ntst=10, at=[0.3], options=opts)
    assert each.labels == batch.labels
    np.testing.assert_allclose(each.period, batch.period, rtol=1e-12)
    np.testing.assert_allclose(each.maximum, batch.maximum, rtol=1e-10, atol=1e-12)


def test_mesh_quadrature_mean_inner_product_and_phase_row():
    from mechcont.continuation._collocation import Mesh

    tau = np.sort(np.concatenate([[0.0, 1.0], np.random.default_rng(3).uniform(0.02, 0.98, 11)]))
    mesh = Mesh(12, 5, tau)  # a non-uniform mesh
    t = mesh.times()
    u = np.column_stack([1.5 + np.cos(2 * np.pi * t), np.sin(2 * np.pi * t)])
    np.testing.assert_allclose(mesh.mean(u), [1.5, 0.0], atol=1e-5)  # the interpolant's error: h^(NCOL+1)
    w = np.column_stack([np.cos(2 * np.pi * t), 0 * t])
    assert mesh.gram_row(w) @ u.ravel() == pytest.approx(0.5, abs=1e-5)  # integral of cos^2
    # the phase row: integral of u . v' for v = u is 0 for a periodic u; for v = (sin, -cos) it is 2 pi (1/2 + 1/2)
    assert mesh.phase_row(u) @ u.ravel() == pytest.approx(0.0, abs=1e-5)
    v = np.column_stack([np.sin(2 * np.pi * t), -np.cos(2 * np.pi * t)])
    assert mesh.phase_row(v) @ u.ravel() == pytest.approx(2 * np.pi, rel=1e-5)


def test_predictor_is_second_order_along_the_family(monkeypatch):
    """Each step predicts ``X + sigma t + sigma^2/2 dt/ds`` (the tangent's turn estimated from the last step): on the
    Stuart-Landau family (radius sqrt(mu): a curved family in (orbit, mu)) at equal steps, the prediction lands an
    order of magnitude nearer the corrected orbit than the tangent's alone (its error sigma^2/2 times the curvature),
    and the family stays on its closed form."""
    from mechcont.continuation import _cycle_system, _cycle_tests

    newton = _cycle_system.CycleSystem.newton

    def run():
        errors = []

        def recording(self, X0, *args):
            out = newton(self, X0, *args)
            errors.append(float(np.max(np.abs(out[0][:-2] - X0[:-2]))))  # the orbit's move from its prediction
            return out

        monkeypatch.setattr(_cycle_system.CycleSystem, "newton", recording)
        m = _stuart_landau()
        # equal steps (dsmin = dsmax = ds), no mesh adaptation: the same sigma and mesh for every step
        fam = cycles_from_hopf(m, m.vector({"mu": 0.0}), "mu", adapt=0, options=ContinuationOptions(
            ds=0.04, dsmin=0.04, dsmax=0.04, bounds={"mu": (-1.0, 0.6)}))
        return fam, np.array(errors[2:-1])  # the steps from a point with a turn (not the start's or the bound's)

    fam, second = run()
    monkeypatch.setattr(_cycle_tests._Point, "curvature", property(lambda self: None, lambda self, value: None))
    _, first = run()
    assert len(second) == len(first) > 20
    assert np.median(second) < 0.1 * np.median(first)
    inner = [i for i, lab in enumerate(fam.labels) if not lab]
    for i in inner:
        assert _mesh_radius(fam, i) == pytest.approx(math.sqrt(fam.p[i]), rel=1e-9)
        assert fam.period[i] == pytest.approx(np.pi, rel=1e-9)


def test_orbit_extremes_are_refined_between_the_nodes():
    """Mesh.extremes: the table's min_X/max_X. On a coarse uneven mesh the nodes and Gauss points of cos(2 pi tau),
    sin(2 pi tau) miss the extremes +-1 by up to d^2 (2 pi)^2 / 8 (d their spacing); refined between them, the
    polynomial's own extremes (a dense sampling's) are found to 1e-5 (the refined samples' spacing, 2 / 23^2 of an
    interval of up to 0.24: (9e-4)^2 (2 pi)^2 / 8 = 4e-6)."""
    from mechcont.continuation._collocation import Mesh

    tau = np.array([0.0, 0.07, 0.2, 0.41, 0.5, 0.66, 0.9, 1.0])
    mesh = Mesh(7, 2, tau)
    t = mesh.times()
    u = np.column_stack([np.cos(2 * np.pi * t + 0.3), np.sin(2 * np.pi * t + 0.3)])
    uc, _ = mesh.at_collocation(u)
    every = np.vstack([u, uc.reshape(-1, 2)])
    lo, hi = mesh.extremes(u)
    fine = mesh.evaluate(u, np.linspace(0.0, 1.0, 100001))  # the polynomial's own extremes, sampled densely
    np.testing.assert_allclose(hi, fine.max(axis=0), rtol=0, atol=1e-5)
    np.testing.assert_allclose(lo, fine.min(axis=0), rtol=0, atol=1e-5)
    assert np.max(np.abs(every.max(axis=0) - fine.max(axis=0))) > 5e-5  # the samples alone miss by far more
    np.testing.assert_allclose(hi, 1.0, atol=0.02)  # degree 2 on intervals up to 0.24 long: its interpolation error
    np.testing.assert_allclose(lo, -1.0, atol=0.02)
