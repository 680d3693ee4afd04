"""Compliant stops in the time simulation (issue 23, item 1: "optionally a compliant contact") against
closed forms, on tests/data/bar_drop.toml with ``contact = "compliant"``.

The bar (mass m, length L, hinged at O, I = m L^2 / 3 about O) rests on or drops onto a stop on its
angle, theta >= -phi_s. The stop's condition is the angle itself, so its gradient is 1 on theta and
the contact is a torsional spring-damper of stiffness k (N m/rad) and damping c (N m s/rad) on the
penetration p = -phi_s - theta: k_eff = k, and the linearised contact oscillator has
omega = sqrt(k / I).
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipk, ellipkinc

from mechcont.dynamics import assemble, simulate
from mechcont.errors import InputError
from mechcont.models import model_from_text

DATA = "tests/data"
M, L, G, PHI_S = 2.0, 1.0, 9.81, 1.2
I_O = M * L**2 / 3
K3 = 3 * G / L
RTOL, ATOL = 1e-10, 1e-12


def bar_text(contact: str) -> str:
    text = open(f"{DATA}/bar_drop.toml").read()
    assert "restitution = 0.5" in text
    return text.replace("restitution = 0.5", contact)


def soft_bar(k, c=0.0):
    return model_from_text(bar_text(f'contact = "compliant"\nstiffness = {float(k)!r}\ndamping = {float(c)!r}'), "bar_soft.toml")


def run(system, theta0, until, **kw):
    x0 = assemble(system, {"theta_bar": theta0}, hold=["theta_bar"])
    return simulate(system, x0, (0.0, until), stops=True, rtol=RTOL, atol=ATOL, **kw)


def penetration(r):
    return np.maximum(0.0, -(r["angle"] + PHI_S))


def events(r, kind):
    return [ev for ev in r.stop_events if ev.kind == kind]


def fall_time():
    """Time from the horizontal to the stop (the elliptic closed form of tests/test_sim_stops.py)."""
    u0 = math.asin(math.sqrt(2) * math.sin((math.pi / 2 - PHI_S) / 2))
    return math.sqrt(2 / K3) * (ellipk(0.5) - ellipkinc(u0, 0.5))


def test_resting_penetration_is_the_rest_moment_over_the_stiffness():
    k = 1e4
    c = 2 * 0.5 * math.sqrt(k * I_O)  # half the critical damping: settled to e^-30 within the run
    r = run(soft_bar(k, c), -PHI_S, 0.6)
    assert r.status.name == "FINISHED"
    # closed form: k p = rest moment m g (L/2) cos(phi_s + p), the gravity moment at the resting pose
    p = brentq(lambda p: k * p - M * G * L / 2 * math.cos(PHI_S + p), 0.0, 0.1, xtol=1e-16)
    assert penetration(r)[-1] == pytest.approx(p, rel=1e-6)
    assert r["R_rest"][-1] == pytest.approx(k * p, rel=1e-6)  # the history's reaction is the penalty
    assert abs(r["theta_bar_dot"][-1]) < 1e-8
    assert [ev.kind for ev in r.stop_events] == ["contact"]  # pressed from the start, never lifted off


def test_undamped_contact_conserves_energy_through_a_bounce():
    k = 1e4
    r = run(soft_bar(k), 0.0, 0.7)
    assert [ev.kind for ev in r.stop_events] == ["contact", "release"]
    assert events(r, "contact")[0].time == pytest.approx(fall_time(), rel=1e-8)  # free fall until the touch
    p = penetration(r)
    assert p.max() > 0.03  # it went well into the spring
    energy = 0.5 * I_O * r["theta_bar_dot"] ** 2 + M * G * (L / 2) * np.sin(r["theta_bar"]) + 0.5 * k * p**2
    # 0 at the start; the integrator's error, a few hundred rtol of the energy scale m g L / 2
    assert np.max(np.abs(energy)) < 1000 * RTOL * M * G * L / 2
    # the rebound speed equals the impact speed (no loss), v0 = sqrt(3 g / L sin phi_s)
    rows = [ev.row for ev in r.stop_events]
    v0 = math.sqrt(K3 * math.sin(PHI_S))
    assert -r["theta_bar_dot"][rows[0]] == pytest.approx(v0, rel=1e-7)
    assert r["theta_bar_dot"][rows[1]] == pytest.approx(v0, rel=1e-7)


def test_damped_contact_lasts_half_a_period_of_the_linearised_oscillator():
    # Justification of the comparison: in contact p'' = (M_g(p) - k p - c p') / I. The linear damped
    # oscillator started at p = 0 with speed v returns to p = 0 after exactly pi / omega_d; the differences are
    # (a) damping, omega_d = omega sqrt(1 - zeta^2): 0.1 % at zeta = 0.05; (b) the penalty never pulls, so
    # contact ends where k p + c p' = 0 at p ~ 2 zeta v / omega, flown through freely with the oscillator's
    # speed and no acceleration there: a second-order change; (c) gravity, a static offset p_s = M_g / k small
    # against the amplitude v / omega (2.6e-3 here): (2 / pi) p_s omega / v ~ 0.2 % longer. Together well under 3 %.
    k, zeta = 1e5, 0.05
    omega = math.sqrt(k / I_O)
    r = run(soft_bar(k, 2 * zeta * math.sqrt(k * I_O)), 0.0, 0.56)
    assert [ev.kind for ev in r.stop_events] == ["contact", "release"]
    duration = r.stop_events[1].time - r.stop_events[0].time
    assert duration == pytest.approx(math.pi / omega, rel=0.03)
    # and, by (a)-(c) again, its speed decays as the oscillator's amplitude over half a period
    rows = [ev.row for ev in r.stop_events]
    e_eff = -r["theta_bar_dot"][rows[1]] / r["theta_bar_dot"][rows[0]]
    assert e_eff == pytest.approx(math.exp(-math.pi * zeta / math.sqrt(1 - zeta**2)), rel=0.03)


def test_stiffer_compliant_stop_converges_to_the_elastic_rigid_impact():
    # rigid, e = 1: the bar is back on the stop at 3 t0 (fall, rise to the horizontal, fall again). Undamped, the
    # compliant bounce gives the bar back at the limit with the speed it arrived with (energy), so after it the
    # motion is the rigid one delayed by the contact's duration, ~ pi sqrt(I / k): the error falls like k^-1/2
    rigid = model_from_text(bar_text("restitution = 1.0"), "bar_rigid.toml")
    r = run(rigid, 0.0, 3 * fall_time() + 0.05)
    t_rigid = [ev.time for ev in events(r, "impact")]
    assert t_rigid[1] == pytest.approx(3 * fall_time(), rel=1e-8)
    stiffness = np.array([1e3, 1e4, 1e5, 1e6])
    errors, durations = [], []
    for k in stiffness:
        soft = run(soft_bar(k), 0.0, 3 * fall_time() + 0.2)
        contacts, releases = events(soft, "contact"), events(soft, "release")
        assert len(contacts) >= 2, k
        errors.append(contacts[1].time - t_rigid[1])
        durations.append(releases[0].time - contacts[0].time)
    errors = np.array(errors)
    # the delay is the contact's duration, up to the integrator's energy error (~1e-8 relative, see the energy
    # test) carried over the ~0.8 s flight after the bounce: ~1e-8 s
    np.testing.assert_allclose(errors, durations, rtol=0, atol=1e-7)
    np.testing.assert_allclose(errors[:-1] / errors[1:], math.sqrt(10), rtol=0.1)  # the k^-1/2 rate
    # and the duration tends to the half-period (gravity's static offset matters less and less)
    rel = errors / (math.pi * np.sqrt(I_O / stiffness)) - 1
    assert np.all(np.diff(rel) < 0) and rel[-1] < 2e-3
    assert errors[-1] / t_rigid[1] < 3e-3


@pytest.mark.parametrize("keys, field, words", [
    ('contact = "soft"\nstiffness = 1e4', "stops.rest.contact", "'rigid', 'compliant'"),
    ('contact = "compliant"', "stops.rest.stiffness", "required"),
    ('contact = "compliant"\nstiffness = -1e4', "stops.rest.stiffness", "positive"),
    ('contact = "compliant"\nstiffness = 0', "stops.rest.stiffness", "positive"),
    ('contact = "compliant"\nstiffness = 1e4\ndamping = -3', "stops.rest.damping", "negative"),
    ('contact = "compliant"\nstiffness = true', "stops.rest.stiffness", "number or an expression"),
    ('contact = "compliant"\nstiffness = "1e4 * q"', "stops.rest.stiffness", "q"),
    ('stiffness = 1e4', "stops.rest.stiffness", "compliant"),
    ('contact = "compliant"\nstiffness = 1e4\nrestitution = 0.5', "stops.rest.restitution", "rigid"),
])
def test_bad_compliant_keys_are_one_line_errors_naming_the_key(keys, field, words):
    with pytest.raises(InputError) as exc:
        model_from_text(bar_text(keys), "bad_soft.toml")
    assert exc.value.field.endswith(field), exc.value.field
    assert words in str(exc.value) and "\n" not in str(exc.value)


def test_stiffness_and_damping_may_be_expressions_in_parameters():
    system = model_from_text(bar_text('contact = "compliant"\nstiffness = "5000 * m"\ndamping = "m / 2"'), "expr.toml")
    stop = system.stops[0]
    assert (stop.contact, stop.stiffness, stop.damping) == ("compliant", pytest.approx(1e4), pytest.approx(1.0))
    changed = system.with_values({"m": 3.0}).stops[0]
    assert (changed.stiffness, changed.damping) == (pytest.approx(1.5e4), pytest.approx(1.5))


def test_rigid_is_the_default():
    stop = model_from_text(open(f"{DATA}/bar_drop.toml").read(), "bar.toml").stops[0]
    assert stop.contact == "rigid"


def test_spatial_compliant_stop_conserves_energy_with_its_spring():
    # the 3-D pendulum on a floor (tests/data/spatial/pendulum_stop_3d.toml), its stop a distance condition (N/m)
    text = open(f"{DATA}/spatial/pendulum_stop_3d.toml").read()
    k = 1e5
    system = model_from_text(text.replace('min = "d_min"', f'min = "d_min"\ncontact = "compliant"\nstiffness = {k}'),
                             "pendulum_soft.toml")
    x0 = assemble(system, {"gap": 1.0}, hold=["gap"])
    r = simulate(system, x0, (0.0, 1.2), stops=True, rtol=1e-9, atol=1e-12)
    kinds = [ev.kind for ev in r.stop_events]
    assert r.success and kinds[:2] == ["contact", "release"] and len(kinds) >= 4
    p = np.maximum(0.0, system.variable("d_min").value - r["gap"])
    assert p.max() > 1e-3
    mech, mg = system.mechanics, 2.0 * 9.81
    energy = np.array([0.5 * v @ mech.mass(x) @ v + mg * x[system.index("z_bar")] for x, v in zip(r.values, r.qdot)])
    energy += 0.5 * k * p**2
    assert np.ptp(energy) < 1000 * 1e-9 * mg * 0.8  # a few hundred rtol of the energy scale m g L
    np.testing.assert_allclose(r["R_floor"], k * p, rtol=1e-12, atol=0)  # the history's reaction is the penalty


def test_spatial_compliant_stiffness_must_be_positive():
    text = open(f"{DATA}/spatial/pendulum_stop_3d.toml").read()
    with pytest.raises(InputError) as exc:
        model_from_text(text.replace('min = "d_min"', 'min = "d_min"\ncontact = "compliant"\nstiffness = -5'), "bad.toml")
    assert exc.value.field.endswith("stops.floor.stiffness") and "positive" in str(exc.value)
