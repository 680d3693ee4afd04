"""Time simulation (Udwadia–Kalaba): constraints, energy, equilibria, events, bad input."""

import math
import re

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq

from mechcont.continuation import find_equilibrium
from mechcont.dynamics import Crossing, assemble, fundamental_equation, simulate
from mechcont.dynamics._udwadia_kalaba import inverse_sqrt
from mechcont.errors import InputError
from mechcont.models import build_overcentre
from mechcont.models.overcentre import symmetric_force, symmetric_stable

L, M1, M2, G, K = 1.5, 1.0, 1.0, 9.81, 127.0


@pytest.fixture(scope="module")
def oc04():
    return build_overcentre(LU=0.4)


@pytest.fixture(scope="module")
def oc04_damped():
    return build_overcentre(LU=0.4, c=40.0)


def start(system, theta1, **params):
    return assemble(system, {"theta1": theta1, "theta2": math.pi - theta1, **params}, hold=["theta1"])


def energy(system, result):
    """Kinetic 1/2 qdot^T M qdot plus the model's potential (gravity, spring, -F y_apex)."""
    V = sp.lambdify([v.symbol for v in system.variables], system.potential_energy)
    mech = system.mechanics
    return np.array([0.5 * qd @ mech.mass(x) @ qd + V(*x) for x, qd in zip(result.values, result.qdot)])


# -- the fundamental equation against the augmented (KKT) system ---------------------------
def test_fundamental_equation_equals_kkt_solution():
    rng = np.random.default_rng(1)
    for _ in range(20):
        n, p = 6, 4
        R = rng.normal(size=(n, n))
        M = R @ R.T + n * np.eye(n)
        A = rng.normal(size=(p, n))
        Q, b = rng.normal(size=n), rng.normal(size=p)
        kkt = np.block([[M, A.T], [A, np.zeros((p, p))]])
        ref = np.linalg.solve(kkt, np.concatenate([Q, b]))[:n]
        got = fundamental_equation(inverse_sqrt(M), Q, A, b)
        assert np.allclose(got, ref, rtol=1e-10, atol=1e-12)
        # a redundant (repeated) constraint row changes nothing: the pseudo-inverse path
        A2, b2 = np.vstack([A, A[:1]]), np.concatenate([b, b[:1]])
        assert np.allclose(fundamental_equation(inverse_sqrt(M), Q, A2, b2), ref, rtol=1e-8, atol=1e-10)


def test_inverse_sqrt_is_symmetric_inverse_root():
    rng = np.random.default_rng(2)
    R = rng.normal(size=(5, 5))
    M = R @ R.T + np.eye(5)
    S = inverse_sqrt(M)
    assert np.allclose(S, S.T)
    assert np.allclose(S @ M @ S, np.eye(5), atol=1e-12)
    with pytest.raises(InputError, match="mass_matrix"):
        inverse_sqrt(np.diag([1.0, -1.0]))


# -- long simulations: constraint drift and energy -----------------------------------------
@pytest.mark.slow
def test_constraint_drift_stays_small_over_a_long_simulation(oc04):
    # 60 s of free oscillation (no damping): 8 periods or so
    x0 = start(oc04, 1.0)
    r = simulate(oc04, x0, (0.0, 60.0), rtol=1e-8, atol=1e-10)
    assert r.success and r.t[-1] == pytest.approx(60.0)
    assert r.constraint_drift < 1e-8  # m, with Baumgarte (10, 10) 1/s
    assert r.velocity_drift < 1e-7  # m/s
    # the recorded drift is the true max |Phi| of the returned rows
    worst = max(np.max(np.abs(oc04.mechanics.phi(x))) for x in r.values)
    assert r.constraint_drift == pytest.approx(worst)
    # with projection after every step the constraints hold to round-off
    rp = simulate(oc04, x0, (0.0, 60.0), rtol=1e-8, atol=1e-10, baumgarte=None, projection=True)
    assert rp.constraint_drift < 1e-11 and rp.velocity_drift < 1e-11


def test_energy_is_conserved_without_damping_or_load(oc04):
    x0 = start(oc04, 1.0)
    assert oc04.as_dict(x0)["F"] == 0.0 and oc04.as_dict(x0)["c"] == 0.0
    r = simulate(oc04, x0, (0.0, 20.0), rtol=1e-9, atol=1e-11)
    E = energy(oc04, r)
    swing = np.ptp(0.5 * np.einsum("ij,ij->i", r.qdot, r.qdot))  # the motion is not trivial
    assert swing > 1.0
    assert np.max(np.abs(E - E[0])) < 1e-6  # J (E ~ 15 J: 1e-7 relative)


def test_damping_dissipates_energy_monotonically(oc04_damped):
    x0 = start(oc04_damped, 1.0)
    r = simulate(oc04_damped, x0, (0.0, 5.0), rtol=1e-9, atol=1e-11, max_step=0.01)
    E = energy(oc04_damped, r)
    assert np.all(np.diff(E) < 1e-9)
    assert E[-1] < E[0] - 1.0


# -- released mechanisms settle on the stable equilibria continuation predicts ---------------
@pytest.mark.parametrize("F, theta_release", [(0.0, 1.0), (20.0, 0.9), (20.0, 0.6), (-40.0, 1.4)])
def test_released_mechanism_settles_on_predicted_stable_equilibrium(oc04_damped, F, theta_release):
    system = oc04_damped
    x0 = start(system, theta_release, F=F)
    r = simulate(system, x0, (0.0, 30.0), rtol=1e-9, atol=1e-11)
    th_end = r["theta1"][-1]
    assert np.max(np.abs(r.qdot[-1])) < 1e-5
    # continuation's equilibrium from the settled angle: same point, and stable
    xe = find_equilibrium(system, values={"LU": 0.4, "F": F, "c": 40.0}, guess={"theta1": th_end, "theta2": math.pi - th_end})
    assert system.mechanics.stability(xe).stable
    assert th_end == pytest.approx(xe[system.index("theta1")], abs=1e-6)
    # and the closed form agrees: F(theta) = F and V'' > 0 there
    assert symmetric_force(th_end, L, M1, M2, G, K, 0.4) == pytest.approx(F, abs=1e-3)
    assert symmetric_stable(th_end, L, 0.4)
    # the basin is the side of the unstable equilibrium the release was on
    roots = _equilibria(F)
    unstable = [t for t in roots if not symmetric_stable(t, L, 0.4)]
    side = np.sign(theta_release - unstable[0])
    expected = min((t for t in roots if symmetric_stable(t, L, 0.4) and np.sign(t - unstable[0]) == side),
                   key=lambda t: abs(t - unstable[0]))
    assert th_end == pytest.approx(expected, abs=1e-6)


def _equilibria(F):
    th = np.linspace(-math.pi / 2 + 1e-6, math.pi / 2 - 1e-6, 20001)
    f = symmetric_force(th, L, M1, M2, G, K, 0.4) - F
    idx = np.flatnonzero(np.sign(f[:-1]) != np.sign(f[1:]))
    return [brentq(lambda t: symmetric_force(t, L, M1, M2, G, K, 0.4) - F, th[i], th[i + 1]) for i in idx]


# -- the same for a generated mechanism: the four-bar description (spring, gravity) -----------
@pytest.fixture(scope="module")
def fourbar_at_rest():
    """The four-bar of fourbar.toml at T = 0: its potential over a full crank turn, and the
    equilibria continuation predicts there (branch in T round the crank turn, events at T = 0)."""
    from mechcont.continuation import ContinuationOptions, ValueEvent, continuation
    from mechcont.models import load_model

    s = load_model("fourbar.toml")
    V = sp.lambdify([v.symbol for v in s.variables], s.potential_energy)
    ic = s.index("theta_crank")
    grid = np.linspace(0.0, 2 * math.pi, 721)
    x, pot = s.vector({}), []
    for th in grid:  # closed-loop assembly at each crank angle (one DOF): V(theta_crank)
        x = x.copy()
        x[ic] = th
        x = assemble(s, x, hold=["theta_crank"])
        pot.append(V(*x))
    x0 = find_equilibrium(s, values={"T": 0.0}, guess=s.as_dict(assemble(s, {"theta_crank": 2.4}, hold=["theta_crank"])))
    b = continuation(s, x0, "T", events=[ValueEvent("T", 0.0)],
                     options=ContinuationOptions(bounds={"T": (-50.0, 50.0), "theta_crank": (0.0, 2 * math.pi)}))
    i0 = int(np.argmin(np.linalg.norm(b.values - x0, axis=1)))  # the start (T = 0) is a row, not an event
    assert np.allclose(b.values[i0], x0)
    at_rest = [(b.values[i0], bool(b.stable[i0]))] + [(p.x, bool(b.stable[p.index])) for p in b.special("UZ")]
    return s, grid, np.array(pot), [(float(xe[ic]), st) for xe, st in at_rest]


def test_fourbar_continuation_equilibria_are_the_extrema_of_the_potential(fourbar_at_rest):
    _, grid, pot, eq = fourbar_at_rest
    inner = np.arange(1, len(grid) - 1)
    minima = grid[inner[(pot[inner] < pot[inner - 1]) & (pot[inner] <= pot[inner + 1])]]
    maxima = grid[inner[(pot[inner] > pot[inner - 1]) & (pot[inner] >= pot[inner + 1])]]
    assert len(minima) == 2 and len(maxima) == 2  # bistable: two wells, two barriers
    assert len(eq) == 4
    assert sorted(th for th, st in eq if st) == pytest.approx(sorted(minima), abs=0.01)  # grid step 0.0087 rad
    assert sorted(th for th, st in eq if not st) == pytest.approx(sorted(maxima), abs=0.01)


@pytest.mark.parametrize("theta_release, damping", [(1.2, 20.0), (4.2, 20.0), (5.9, 20.0), (4.6, 5.0)])
def test_released_fourbar_settles_on_a_stable_equilibrium_of_the_continuation(fourbar_at_rest, theta_release,
                                                                              damping):
    s, grid, pot, eq = fourbar_at_rest
    x0 = assemble(s, {"theta_crank": theta_release}, hold=["theta_crank"])
    r = simulate(s, x0, (0.0, 15.0), damping=damping, rtol=1e-8, atol=1e-10)
    assert r.success and r.constraint_drift < 1e-8
    assert np.max(np.abs(r.qdot[-1])) < 1e-6  # at rest
    th_end = r["theta_crank"][-1] % (2 * math.pi)
    stable = [th for th, st in eq if st]
    assert min(abs(th_end - th) for th in stable) < 1e-6
    # the basin: walking downhill on V from the release angle ends at the same minimum
    i = int(np.argmin(np.abs(grid - theta_release)))
    step = -1 if pot[i - 1] < pot[i] else 1
    while pot[(i + step) % len(grid)] < pot[i]:
        i = (i + step) % len(grid)
    assert th_end == pytest.approx(grid[i], abs=0.01)


# -- loads, events, results ------------------------------------------------------------------
def test_time_varying_load_is_applied_and_recorded(oc04_damped):
    x0 = start(oc04_damped, 1.3)
    r = simulate(oc04_damped, x0, (0.0, 2.0), loads={"F": lambda t: 5.0 * t}, max_step=0.05)
    assert np.allclose(r["F"], 5.0 * r.t)
    assert r["LU"] == pytest.approx(np.full(len(r), 0.4))
    assert r.names == oc04_damped.names
    assert r["theta1_dot"].shape == r.t.shape


def test_terminal_crossing_event_stops_there(oc04):
    x0 = start(oc04, 1.0)
    r = simulate(oc04, x0, (0.0, 10.0), events=[Crossing("theta1", 1.2, direction=1, terminal=True)], rtol=1e-9)
    assert r.message.startswith("A terminal event")
    assert r.t_events[0].size == 1
    assert r["theta1"][-1] == pytest.approx(1.2, abs=1e-9)
    assert r.x_events[0][0, oc04.index("theta1")] == pytest.approx(1.2, abs=1e-9)
    assert r.t[-1] == pytest.approx(r.t_events[0][0])


def test_t_eval_and_initial_velocities_are_made_consistent(oc04):
    x0 = start(oc04, 1.0)
    r = simulate(oc04, x0, (0.0, 1.0), qdot0={"theta1": 0.5, "x1": 3.0}, t_eval=np.linspace(0, 1, 11))
    assert np.allclose(r.t, np.linspace(0, 1, 11))
    qd0 = r.qdot[0]
    assert np.max(np.abs(oc04.mechanics.phi_q(r.values[0]) @ qd0)) < 1e-12


def test_csv_has_named_columns(tmp_path, oc04):
    r = simulate(oc04, start(oc04, 1.0), (0.0, 0.2))
    path = tmp_path / "sim.csv"
    r.to_csv(path)
    lines = path.read_text().splitlines()
    assert lines[0].split(",")[:4] == ["t [s]", "x1 [m]", "y1 [m]", "theta1 [rad]"]
    assert lines[0].endswith("theta2_dot [rad/s],E_kin [J],E_pot [J],E_diss [J],W_ext [J],E_residual [J]")
    assert len(lines) == len(r) + 1


@pytest.mark.parametrize("kwargs, field", [
    ({"t_span": (1.0, 0.0)}, "t_span"),
    ({"method": "Euler"}, "method"),
    ({"loads": {"L1": lambda t: 1.5}}, "L1"),
    ({"loads": {"theta1": lambda t: 0.0}}, "theta1"),
    ({"loads": {"nope": lambda t: 0.0}}, "nope"),
    ({"baumgarte": (-1.0, 1.0)}, "baumgarte"),
    ({"damping": -1.0}, "damping"),
    ({"projection": True, "method": "Radau"}, "projection"),
    ({"qdot0": [1.0, 2.0]}, "qdot0"),
])
def test_bad_input_names_the_field(oc04, kwargs, field):
    args = {"t_span": (0.0, 1.0), **kwargs}
    t_span = args.pop("t_span")
    with pytest.raises(InputError, match=f"^{field}"):
        simulate(oc04, start(oc04, 1.0), t_span, **args)


def test_failed_integration_says_where_and_returns_what_it_computed(oc04):
    # a load that stops being a number at t = 0.5 s: the integrator cannot go past it
    x0 = start(oc04, 1.0)
    r = simulate(oc04, x0, (0.0, 2.0), loads={"F": lambda t: math.nan if t > 0.5 else 0.0})
    assert not r.success
    m = re.search(r"Stopped at t = ([0-9.e+-]+) s \(RK45: ", r.message)
    assert m and float(m.group(1)) == pytest.approx(0.5, abs=1e-9)
    assert r.t[-1] == pytest.approx(0.5, abs=1e-9) and len(r) > 10  # the part before the failure is kept
    assert np.all(np.isfinite(r.values)) and np.all(r["F"] == 0.0)


def test_unassembled_start_is_refused(oc04):
    with pytest.raises(InputError, match="^x0.*assemble"):
        simulate(oc04, oc04.vector({"theta1": 1.2}), (0.0, 1.0))
