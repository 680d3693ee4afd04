"""The hydraulic damper (tension c v + c2 v|v|) against an independent reduced equation of motion.

tests/data/damped_pendulum.toml: a uniform bar (mass m, length L) hinged at O falls under gravity;
a damper joins the ground point G to the tip P = L (cos theta, sin theta). With l = |P - G| and
l' = dl/dtheta = (P - G) . dP/dtheta / l, the reduced equation of motion is

    (m L^2 / 3) theta'' = -m g (L/2) cos theta - T l',   T = c v + c2 v |v|,  v = l' theta',

and the energy E = (m L^2/6) theta'^2 + m g (L/2) sin theta falls at the rate dE/dt = -T v.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from mechcont.dynamics import assemble, simulate
from mechcont.errors import InputError
from mechcont.models import load_model, model_from_text

PATH = "tests/data/damped_pendulum.toml"
M, L, G_, C, C2 = 2.0, 1.0, 9.81, 4.0, 6.0
GX, GY = 0.3, 0.8
THETA0 = 0.2


def arm(theta):
    """l (m) and dl/dtheta (m/rad) of the damper at theta."""
    px, py = L * math.cos(theta) - GX, L * math.sin(theta) - GY
    length = math.hypot(px, py)
    return length, (px * -L * math.sin(theta) + py * L * math.cos(theta)) / length


def tension(theta, omega, c=C, c2=C2):
    _, dl = arm(theta)
    v = dl * omega
    return c * v + c2 * v * abs(v), v


def reduced(t_eval, c=C, c2=C2):
    def rhs(t, y):
        T, _ = tension(y[0], y[1], c, c2)
        return [y[1], (-M * G_ * L / 2 * math.cos(y[0]) - T * arm(y[0])[1]) / (M * L * L / 3)]

    return solve_ivp(rhs, (0, t_eval[-1]), [THETA0, 0.0], t_eval=t_eval, rtol=1e-12, atol=1e-13, method="DOP853")


@pytest.mark.parametrize("c, c2", [(4.0, 6.0), (0.0, 6.0), (4.0, 0.0)])
def test_damped_fall_matches_the_reduced_equation(c, c2):
    system = load_model(PATH, c=c, c2=c2)
    t = np.linspace(0.0, 1.5, 16)
    x0 = assemble(system, {"theta_bar": THETA0}, hold=["theta_bar"])
    sim = simulate(system, x0, (0.0, t[-1]), rtol=1e-10, atol=1e-12, t_eval=t)
    ref = reduced(t, c, c2)
    assert np.max(np.abs(sim["theta_bar"] - ref.y[0])) < 1e-6
    assert np.max(np.abs(sim["theta_bar_dot"] - ref.y[1])) < 1e-5
    # the energy lost between rows equals the damper's work, integral of T v dt (Simpson on a fine grid)
    fine = np.linspace(0.0, 1.0, 2001)
    s = simulate(system, x0, (0.0, 1.0), rtol=1e-10, atol=1e-12, t_eval=fine)
    th, om = s["theta_bar"], s["theta_bar_dot"]
    E = M * L * L / 6 * om ** 2 + M * G_ * L / 2 * np.sin(th)
    power = np.array([np.prod(tension(a, b, c, c2)) for a, b in zip(th, om)])
    from scipy.integrate import simpson
    work = simpson(power, x=fine)
    assert E[0] - E[-1] == pytest.approx(work, rel=1e-6, abs=1e-9)
    assert work > 0.1  # the damper does take energy out


def test_damper_exerts_nothing_at_rest():
    """Continuation sees equilibria at rest: the damper's force is zero there, whatever c and c2."""
    damped, free = load_model(PATH, c=50.0, c2=80.0), load_model(PATH, c=0.0, c2=0.0)
    x = assemble(damped, {"theta_bar": 0.7}, hold=["theta_bar"])
    y = free.vector({n: v for n, v in zip(damped.names, x) if n not in ("c", "c2")})
    assert np.allclose(damped.mechanics.applied_forces(x), free.mechanics.applied_forces(y), rtol=0, atol=1e-12)
    assert np.allclose(damped.residual(x), free.residual(y), rtol=0, atol=1e-12)
    # and the force is that of gravity alone: moment -m g (L/2) cos theta about O (the generalised forces act at
    # the bar's frame, its centre: their moment about O adds r x F, r the frame's position from O = (0, 0))
    Q = damped.mechanics.applied_forces(x)
    k = {c: damped.mechanics.coordinates.index(c) for c in ("x_bar", "y_bar", "theta_bar")}
    r = x[[damped.index("x_bar"), damped.index("y_bar")]]
    moment_O = Q[k["theta_bar"]] + r[0] * Q[k["y_bar"]] - r[1] * Q[k["x_bar"]]
    assert moment_O == pytest.approx(-M * G_ * L / 2 * math.cos(0.7), rel=1e-12)
    assert Q[damped.mechanics.coordinates.index("y_bar")] == pytest.approx(-M * G_, rel=1e-12)


def test_negative_quadratic_damping_is_refused():
    text = open(PATH).read().replace('c2 = { value = 6.0', 'c2 = { value = -1.0')
    with pytest.raises(InputError, match=r"dampers\.retraction\.c2: .*non-negative"):
        model_from_text(text, "bad_damper.toml")


def test_unknown_damper_key_is_refused():
    text = open(PATH).read().replace('c2 = "c2"', 'c3 = "c2"')
    with pytest.raises(InputError, match=r"dampers\.retraction\.c3"):
        model_from_text(text, "bad_damper.toml")


def _power_check(system, x, qd, damper, c, c2):
    """(Q(x, qd) - Q(x, 0)) . qd against -(c v + c2 v|v|) v, v = dl/dt from the damper's drawn ends."""
    mech = system.mechanics
    Qd = mech.applied_forces(x, qd) - mech.applied_forces(x, np.zeros_like(qd))
    q_index = np.array([system.index(n) for n in mech.coordinates])

    def length(y):
        (a, b), = [(a, b) for name, a, b in system.scene(y).dampers if name == damper]
        return float(np.linalg.norm(np.asarray(b) - np.asarray(a)))

    h = 1e-6
    xp, xm = x.copy(), x.copy()
    xp[q_index] += h * qd
    xm[q_index] -= h * qd
    v = (length(xp) - length(xm)) / (2 * h)
    assert abs(v) > 1e-3  # the damper strokes
    assert Qd @ qd == pytest.approx(-(c * v + c2 * v * abs(v)) * v, rel=1e-8)


def test_planar_damper_power_is_minus_tension_times_rate():
    system = load_model(PATH)
    x = assemble(system, {"theta_bar": 0.4}, hold=["theta_bar"])
    _power_check(system, x, np.array([0.3, -0.7, 1.9]), "retraction", C, C2)


def test_spatial_damper_takes_the_quadratic_term():
    """The spatial worked example's damper with c2 added: the same law along the 3-D distance."""
    import re

    from mechcont.mechanism import parse_description

    doc = open("docs/spatial-format.md").read()
    (text,) = re.findall(r"```toml\n(.*?)```", doc.split("## Worked example")[1], re.S)
    name = re.search(r"\[dampers\.(\w+)\]", text).group(1)
    text = re.sub(rf"(\[dampers\.{name}\]\n(?:.*\n)*?c = [^\n]*\n)", r"\1c2 = 7000.0\n", text, count=1)
    assert "c2 = 7000.0" in text
    system = parse_description(text, "side_brace.toml").build()
    x = system.defaults()
    c = re.search(rf"\[dampers\.{name}\]\n(?:.*\n)*?c = ([^\n]*)\n", text).group(1).strip('"')
    c = float(c) if c[0].isdigit() else float(x[system.index(c)])  # a number or a parameter's name
    qd = np.random.default_rng(3).normal(size=len(system.mechanics.coordinates))
    _power_check(system, x, qd, name, c, 7000.0)


def test_damper_tensions_are_compiled_into_the_model():
    """A run's damper tensions come from the model's own dampers (``Model.dampers``, compiled from the description
    when it was built): with the description taken away they still equal the closed form ``c v + c2 v |v|`` at
    each row; the coefficients follow ``with_values``, and a row that carries other parameter values (a ramp) is
    taken at those."""
    from mechcont.dynamics.freefall import DamperTension, damper_tensions

    system = load_model(PATH, c=3.0).with_values({"c2": 1.5})
    assert [(d.name, d.c, d.c2) for d in system.dampers] == [("retraction", 3.0, 1.5)]
    t = np.linspace(0.0, 1.0, 11)
    x0 = assemble(system, {"theta_bar": THETA0}, hold=["theta_bar"])
    sim = simulate(system, x0, (0.0, t[-1]), rtol=1e-10, atol=1e-12, t_eval=t)
    bare = system.evolve(mechanism=None)  # as if the description were not at hand
    T = damper_tensions(bare, sim)["retraction"]
    expected = [tension(th, om, 3.0, 1.5)[0] for th, om in zip(sim["theta_bar"], sim["theta_bar_dot"])]
    assert np.max(np.abs(expected)) > 1.0  # the damper strokes: the check can tell
    assert np.allclose(T, expected, rtol=1e-6, atol=1e-9)
    row = np.array(sim.values[6], dtype=float)
    row[bare.index("c")] = 7.0
    at_row = DamperTension(bare, sim.coordinates)(row, sim.qdot[6])["retraction"]
    assert at_row == pytest.approx(tension(sim["theta_bar"][6], sim["theta_bar_dot"][6], 7.0, 1.5)[0], rel=1e-6)


def test_damper_coefficients_are_not_evaluated_again_for_each_contact_reaction():
    """A stop's contact reaction changes at every row in contact; the damper coefficients depend on the description's
    parameters only, so rows differing in a reaction reuse them (the model's value fields are not evaluated again),
    while a row with another damper coefficient is still taken at it."""
    from mechcont.dynamics.freefall import DamperTension

    model = load_model("tests/data/freefall_pendulum.toml", c=3.0)
    real = model.fields_at
    assert real is not None and model.stops
    calls = []

    def counting(values):
        calls.append(dict(values))
        return real(values)

    system = model.evolve(fields_at=counting)
    tension_of = DamperTension(system, system.mechanics.coordinates)
    x = system.defaults()
    qd = np.array([0.4])
    first = tension_of(x, qd)
    assert abs(first["retraction"]) > 0
    for k, stop in enumerate(system.stops):
        row = x.copy()
        row[system.index(stop.reaction)] = 1234.5 * (k + 1)
        assert tension_of(row, qd) == first
    assert calls == []
    row = x.copy()
    row[system.index("c")] = 6.0
    assert tension_of(row, qd)["retraction"] == pytest.approx(2 * first["retraction"], rel=1e-12)
    assert len(calls) == 1 and not any(s.reaction in calls[0] for s in system.stops)
