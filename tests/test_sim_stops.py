"""Stops in the time simulation (issue 23, item 1) against closed forms and a separate 1-DOF integrator.

The mechanism is tests/data/bar_drop.toml: a uniform bar (mass m, length L) hinged at one end,
released at rest from the horizontal onto a stop at theta = -phi_s. With phi = -theta the
equation of motion is phi'' = (k / 2) cos phi, k = 3 g / L, and energy gives phi'^2 = k sin phi:

* impact speed v0 = sqrt(k sin phi_s);
* fall time t0 = (1/sqrt k) int_0^phi_s dphi / sqrt(sin phi)
              = sqrt(2 / k) (K(1/2) - F(u0 | 1/2)),  sin u0 = sqrt 2 sin((pi/2 - phi_s) / 2)
  (substitute psi = pi/2 - phi, then sin(psi/2) = sin(u)/sqrt 2);
* the reaction at rest on the stop: (m g L / 2) cos phi_s.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp
from scipy.special import ellipk, ellipkinc

from mechcont.analysis import continuation_with_stops, equilibrium_on_stops
from mechcont.dynamics import assemble, simulate
from mechcont.errors import InputError
from mechcont.models import load_model, model_from_text

DATA = "tests/data"
M, L, G, PHI_S = 2.0, 1.0, 9.81, 1.2
K = 3 * G / L
RTOL, ATOL = 1e-10, 1e-12


def bar(e):
    text = open(f"{DATA}/bar_drop.toml").read()
    assert "restitution = 0.5" in text
    return model_from_text(text.replace("restitution = 0.5", f"restitution = {e}"), f"bar_drop_e{e}.toml")


def drop(e, until, **kw):
    system = bar(e)
    x0 = assemble(system, {"theta_bar": 0.0}, hold=["theta_bar"])
    return system, simulate(system, x0, (0.0, until), stops=True, rtol=RTOL, atol=ATOL, **kw)


def fall_time():
    u0 = math.asin(math.sqrt(2) * math.sin((math.pi / 2 - PHI_S) / 2))
    return math.sqrt(2 / K) * (ellipk(0.5) - ellipkinc(u0, 0.5))


def impacts(result):
    return [ev for ev in result.stop_events if ev.kind == "impact"]


def reduced_bounces(e, n, v_rest=1e-3):
    """Impact times and speeds of the reduced 1-DOF model phi'' = (k/2) cos phi, integrated
    separately (SciPy, event at phi = phi_s, velocity reversed times e): the independent engine."""
    def rhs(t, y):
        return [y[1], 0.5 * K * math.cos(y[0])]

    def hit(t, y):
        return y[0] - PHI_S

    def top(t, y):
        return y[1]
    hit.terminal, hit.direction = True, 1
    top.terminal, top.direction = True, 1

    def until(event, t, y):
        sol = solve_ivp(rhs, (t, t + 10), y, events=event, rtol=1e-12, atol=1e-14, method="DOP853")
        return float(sol.t_events[0][0]), list(sol.y_events[0][0])

    t, y, out = 0.0, [0.0, 0.0], []
    while len(out) < n:
        t, y = until(hit, t, y)
        out.append((t, y[1]))
        if e * y[1] < v_rest:
            break
        t, y = until(top, t, [PHI_S, -e * y[1]])  # up to the top of the rebound, then down to the stop
    return out


def test_fall_time_closed_form_matches_the_energy_integral():
    # the closed form against high-accuracy quadrature of the energy integral (x = phi_s - s^2 removes the
    # 1/sqrt(phi) end singularity)
    val, _ = quad(lambda s: 2 * s / math.sqrt(K * math.sin(s * s)), 0, math.sqrt(PHI_S), epsabs=1e-14, epsrel=1e-13)
    assert fall_time() == pytest.approx(val, rel=1e-11)


def test_dropped_bar_hits_the_stop_at_the_elliptic_fall_time_with_the_energy_speed():
    system, r = drop(0.0, 0.8)
    first = r.stop_events[0]
    assert [ev.kind for ev in r.stop_events] == ["impact", "contact"]
    assert first.stop == "rest" and first.rebound == 0.0
    assert first.time == pytest.approx(fall_time(), abs=1e-6)
    assert first.speed == pytest.approx(math.sqrt(K * math.sin(PHI_S)), abs=1e-6)
    # plastic impact: the bar stays on the stop, at rest, with no penetration
    after = r.t > first.time
    assert np.max(np.abs(r["theta_bar_dot"][after])) < 1e-9
    assert np.max(np.abs(r["angle"][after] + PHI_S)) < 1e-9
    # a row at the event: the last row before it and the row after it are both at its time
    assert r.t[first.row] == first.time and r.t[first.row - 1] == first.time
    assert r["theta_bar_dot"][first.row - 1] == pytest.approx(-first.speed, abs=1e-12)


def test_independent_reduced_integrator_agrees_on_the_impact_time():
    (t_ref, v_ref), = reduced_bounces(0.0, 1)
    _, r = drop(0.0, 0.6)
    assert r.stop_events[0].time == pytest.approx(t_ref, abs=1e-8)
    assert r.stop_events[0].speed == pytest.approx(v_ref, rel=1e-8)


def test_half_restitution_rebounds_geometrically_and_comes_to_rest_in_finite_time():
    system, r = drop(0.5, 3.0)
    hits = impacts(r)
    v0 = math.sqrt(K * math.sin(PHI_S))
    speeds = np.array([ev.speed for ev in hits])
    n = len(hits)
    assert 8 < n < 40  # finite: the rebounds stop when too small to resolve
    np.testing.assert_allclose(speeds, v0 * 0.5 ** np.arange(n), rtol=1e-6, atol=1e-9)
    for ev in hits[:-1]:
        assert ev.rebound == pytest.approx(0.5 * ev.speed, rel=1e-12)
    assert hits[-1].rebound == 0.0 and r.stop_events[-1].kind == "contact"
    t_rest = r.stop_events[-1].time
    assert t_rest < 2.0 and r.success
    # the impact times of every bounce match the reduced model's
    ref = reduced_bounces(0.5, n)
    np.testing.assert_allclose([ev.time for ev in hits[:len(ref)]], [t for t, _ in ref], atol=1e-6)
    # at rest on the stop after that, with the static reaction
    after = r.t > t_rest
    assert np.max(np.abs(r["theta_bar_dot"][after])) < 1e-9
    np.testing.assert_allclose(r["R_rest"][after], 0.5 * M * G * L * math.cos(PHI_S), rtol=1e-9)


def test_elastic_stop_conserves_energy_over_several_bounces():
    system, r = drop(1.0, 3.0)
    hits = impacts(r)
    assert len(hits) == 4
    v0 = math.sqrt(K * math.sin(PHI_S))
    for ev in hits:
        assert ev.speed == pytest.approx(v0, rel=1e-7) and ev.rebound == pytest.approx(ev.speed, rel=1e-12)
    # period of a bounce = twice the fall time
    np.testing.assert_allclose(np.diff([ev.time for ev in hits]), 2 * fall_time(), rtol=1e-7)
    th, w = r["theta_bar"], r["theta_bar_dot"]
    energy = 0.5 * (M * L**2 / 3) * w**2 + M * G * (L / 2) * np.sin(th)  # 0 at the start
    # the integrator's error per unit of time, a few rtol on the energy scale m g L / 2
    assert np.max(np.abs(energy)) < 100 * RTOL * M * G * L / 2


def test_reaction_at_rest_equals_the_static_reaction_of_equilibrium_on_stops():
    system, r = drop(0.0, 1.5)
    x_guess = assemble(system, {"theta_bar": -PHI_S}, hold=["theta_bar"])
    x_eq, contact = equilibrium_on_stops(system, x_guess)
    assert contact == ["rest"]
    R_static = x_eq[system.index("R_rest")]
    assert R_static == pytest.approx(0.5 * M * G * L * math.cos(PHI_S), rel=1e-12)
    # at rest the reaction is algebraic in the state: its error is the Baumgarte residual of the contact row
    # (beta^2 |gap| + 2 alpha |gap'| ~ 1e-11 rad/s^2 here) times the inertia, far below 1e-9
    assert r["R_rest"][-1] == pytest.approx(R_static, rel=1e-9)


def test_spatial_stop_reaction_at_rest_equals_the_static_one():
    system = load_model(f"{DATA}/spatial/pendulum_stop_3d.toml")
    x0 = assemble(system, {"gap": 1.0}, hold=["gap"])
    assert x0[system.index("gap")] == pytest.approx(1.0, abs=1e-12)
    r = simulate(system, x0, (0.0, 1.0), stops=True, rtol=1e-9, atol=1e-12)
    kinds = [ev.kind for ev in r.stop_events]
    assert kinds == ["impact", "contact"] and r.success
    d_min = system.variable("d_min").value
    x_eq, contact = equilibrium_on_stops(system, r.values[-1])
    assert contact == ["floor"]
    assert r["R_floor"][-1] == pytest.approx(x_eq[system.index("R_floor")], rel=1e-9)
    assert r["R_floor"][-1] == pytest.approx(2.0 * 9.81 * d_min / (2 * 0.8), rel=1e-9)
    assert r["gap"][-1] == pytest.approx(d_min, abs=1e-9)


def test_stop_releases_when_a_growing_moment_lifts_the_bar_off():
    system = load_model(f"{DATA}/pendulum_stop.toml")
    x0 = assemble(system, {"theta_bar": -1.2}, hold=["theta_bar"])
    rate = 10.0  # N m/s
    r = simulate(system, x0, (0.0, 0.6), stops=True, loads={"T": lambda t: rate * t}, rtol=1e-9, atol=1e-12)
    kinds = [(ev.kind, ev.stop) for ev in r.stop_events]
    assert kinds == [("contact", "rest"), ("release", "rest")]
    # the reaction is m g L/2 cos(1.2) - T: it reaches zero when T equals the gravity moment
    T_release = 2.0 * 9.81 * 0.5 * math.cos(1.2)
    assert r.stop_events[1].time == pytest.approx(T_release / rate, abs=1e-7)
    before = r.t < r.stop_events[1].time
    np.testing.assert_allclose(r["R_rest"][before], T_release - rate * r.t[before], atol=1e-8)
    assert r["theta_bar"][-1] > -1.2 + 1e-3  # it has lifted off


def test_restitution_must_be_between_0_and_1():
    text = open(f"{DATA}/bar_drop.toml").read()
    for bad in ("1.5", "-0.1", '"high"', "nan"):
        with pytest.raises(InputError) as exc:
            model_from_text(text.replace("restitution = 0.5", f"restitution = {bad}"), "bad_e.toml")
        assert exc.value.field.endswith("stops.rest.restitution") and "from 0" in str(exc.value)


def test_start_past_a_stop_is_refused():
    system = bar(0.0)
    x0 = assemble(system, {"theta_bar": -1.3}, hold=["theta_bar"])
    with pytest.raises(InputError, match="past the limit of stop rest"):
        simulate(system, x0, (0.0, 0.1), stops=True)


def test_sweep_with_stops_contact_load_converges_to_sc_as_the_rate_falls_and_releases_at_sr():
    from mechcont.continuation import ContinuationOptions
    from mechcont.dynamics import sweep

    system = load_model(f"{DATA}/pendulum_stop.toml", T=6.0)
    x_free, contact = equilibrium_on_stops(system, assemble(system, {"theta_bar": -0.9}, hold=["theta_bar"]))
    assert contact == []
    run = continuation_with_stops(system, x_free, "T", direction=-1, options=ContinuationOptions(bounds={"T": (0.0, 7.0)}))
    (T_sc,) = [p["T"] for p in run.branch.special_points if p.label == "SC"]
    # lowering the moment lets the bar down onto the stop; the simulated bar lags the equilibrium (damping), so it
    # touches later, at a lower moment, by a gap that shrinks with the rate
    loads = []
    for rate in (2.0, 0.5, 0.125):
        r = sweep(system, x_free, [("T", 6.0, 0.0, rate)], watch="theta_bar", damping=5.0, stops=True, rtol=1e-7)
        (T_contact,) = r.stop_loads("contact", "rest")
        loads.append(T_contact)
    gaps = T_sc - np.array(loads)
    assert np.all(gaps > 0) and np.all(gaps[1:] < gaps[:-1] / 3)  # monotone, about proportional to the rate
    assert gaps[-1] < 0.06
    # raising it again from the stop: in contact the bar is at rest, so it lets go exactly at SR
    x_on, contact = equilibrium_on_stops(system, x_free, values={"T": 3.0}, contact=["rest"])
    assert contact == ["rest"]
    up = continuation_with_stops(system, x_on, "T", direction=1, options=ContinuationOptions(bounds={"T": (0.0, 4.0)}))
    (T_sr,) = [p["T"] for p in up.branch.special_points if p.label == "SR"]
    r = sweep(system, x_on, [("T", 3.0, 4.0, 1.0)], watch="theta_bar", stops=True, rtol=1e-9)
    assert [ev.kind for ev in r.stop_events] == ["contact", "release"]
    assert r.stop_loads("release")[0] == pytest.approx(T_sr, abs=1e-8)


def test_condition_columns_follow_the_motion_with_or_without_stops():
    system = bar(0.0)
    x0 = assemble(system, {"theta_bar": 0.0}, hold=["theta_bar"])
    for stops in (False, True):
        r = simulate(system, x0, (0.0, 0.3), stops=stops)
        assert np.ptp(r["angle"]) > 0.1
        np.testing.assert_allclose(r["angle"], r["theta_bar"], atol=1e-12)  # angle = theta_bar - theta_ground


def test_spatial_elastic_stop_conserves_energy():
    text = open(f"{DATA}/spatial/pendulum_stop_3d.toml").read()
    system = model_from_text(text.replace('min = "d_min"', 'min = "d_min"\nrestitution = 1'), "pendulum_stop_3d_e1.toml")
    x0 = assemble(system, {"gap": 1.0}, hold=["gap"])
    r = simulate(system, x0, (0.0, 1.2), stops=True, rtol=1e-9, atol=1e-12)
    hits = impacts(r)
    assert len(hits) == 3 and all(ev.rebound == pytest.approx(ev.speed, rel=1e-12) for ev in hits)
    np.testing.assert_allclose([ev.speed for ev in hits], hits[0].speed, rtol=1e-7)
    mech, mg = system.mechanics, 2.0 * 9.81
    energy = np.array([0.5 * v @ mech.mass(x) @ v + mg * x[system.index("z_bar")] for x, v in zip(r.values, r.qdot)])
    assert np.ptp(energy) < 100 * 1e-9 * mg * 0.8  # a few rtol of the energy scale m g L
