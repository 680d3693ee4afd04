"""The stretched-string tyre (``[tyres.NAME]``): its state's rate, its side force's generalised forces
and its bad input, checked on the element's own expressions (the generator's side, which makes the
state a variable of the system, is checked in tests/test_shimmy_dynamics.py).

Truth:

* a wheel at yaw ``psi`` rolling along +x at speed ``V``: ``v_lat = -V sin psi``, steady deflection
  ``y = sigma sin psi``, relaxation rate ``-V/sigma`` (the rate is ``-v_lat - (V/sigma) y``);
* the contact point ``P = o + R(theta) p`` of a free body moving at ``(xdot, ydot, thetadot)``:
  ``v_lat = (xdot + V, ydot) . l + thetadot (e_z x R p) . l`` with ``l = (-sin theta, cos theta)``;
* the side force ``F l`` at ``P - t h`` does the virtual work ``F l . d(P - t h)/dq`` (by central
  differences of a numpy transcription of the geometry): for the caster ``p = (-e, 0)``,
  ``Q_theta = -(e + t) F``;
* ``F = C y / sigma``, or ``F_max tanh(C y / (sigma F_max))`` (slope ``C/sigma`` at 0, bounded by ``F_max``);
* the caster wheel (pin at its centre of gravity, inertia ``I``, torsion spring ``k``, damper ``c``,
  linear tyre): the linearisation of the element's own expressions has the characteristic cubic
  ``s^3 + (c/I + V/sigma) s^2 + (k + (c V + e^2 C)/sigma)/I s + V (k + e C)/(I sigma)`` (derived in
  tests/test_shimmy_dynamics.py), and loses stability at the Routh-Hurwitz Hopf speeds;
* a spatial description of the same wheel (ground plane x-y, pin about z) gives the same rate and,
  along a rotation about z, the same virtual work.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from cli_helpers import make_runner, one_line_error

from mechcont.equations import velocity_symbol
from mechcont.errors import InputError
from mechcont.mechanism import parse_description
from mechcont.mechanism._forces import loads
from mechcont.mechanism._kinematics import PlanarKinematics
from mechcont.mechanism.spatial._kinematics import SpatialKinematics

E, SIGMA, CS, I, K, CD = 0.1, 0.3, 1800.0, 0.5, 20.0, 2.0
V = 10.0

CASTER = """
[mechanism]
name = "caster"
[parameters]
V = {V}
c = {c}
k = {k}
[ground]
O = [0, 0]
[bodies.wheel]
mass = 2.0
inertia = {I}
cg = [0, 0]
points = {{ contact = [{minus_e}, 0] }}
initial = {{ theta = 0.0 }}
[joints.pin]
type = "revolute"
a = "ground.O"
b = "wheel.origin"
[torsion_springs.tor]
a = "ground"
b = "wheel"
k = "k"
[torsion_dampers.shimmy]
a = "ground"
b = "wheel"
c = "c"
[tyres.nose]
body = "wheel"
at = "contact"
speed = "V"
relaxation_length = {sigma}
cornering_stiffness = {C}
{extra}
"""

CASTER3 = """
[mechanism]
name = "caster3"
dimension = 3
[parameters]
V = {V}
c = {c}
k = {k}
[ground]
O = [0, 0, 0]
[bodies.wheel]
mass = 2.0
inertia = [{I}, {I}, {I}]
cg = [0, 0, 0]
points = {{ contact = [{minus_e}, 0, 0] }}
[joints.pin]
type = "revolute"
a = "ground.O"
b = "wheel.origin"
axis = [0, 0, 1]
[torsion_springs.tor]
a = "ground"
b = "wheel"
k = "k"
joint = "pin"
[torsion_dampers.shimmy]
a = "ground"
b = "wheel"
c = "c"
joint = "pin"
[tyres.nose]
body = "wheel"
at = "contact"
speed = "V"
relaxation_length = {sigma}
cornering_stiffness = {C}
{extra}
"""


def text(template=CASTER, extra="", **kw):
    v = dict(V=V, c=CD, k=K, I=I, minus_e=-E, sigma=SIGMA, C=CS) | kw
    return template.format(extra=extra, **v)


def tyre_of(mech):
    return next(el for el in mech.force_elements() if el.table == "tyres")


def at_values(mech, **kw):
    """Parameter symbol -> value (the defaults, ``kw`` overriding)."""
    return {sp.Symbol(p.name, real=True): kw.get(p.name, p.value) for p in mech.parameters}


Y = sp.Symbol("y_nose", real=True)


def planar_parts(extra="", **kw):
    """(kinematics, rate, Q (full planar coordinates)) of the caster's tyre alone, parameters substituted."""
    mech = parse_description(text(extra=extra, **kw))
    kin = PlanarKinematics(mech)
    tyre = tyre_of(mech)
    (state,) = tyre.states(kin)
    from mechcont.mechanism.loads import Loads

    out = Loads(sp.S.Zero, [sp.S.Zero] * len(kin.q), [])
    tyre.apply(kin, out)
    at = at_values(mech, **kw)
    return kin, state, sp.sympify(state.rate).xreplace(at), [sp.sympify(q).xreplace(at) for q in out.Q_nc]


def test_the_state_is_declared_with_its_name_unit_and_scale():
    _, state, _, _ = planar_parts()
    assert (state.name, state.unit) == ("y_nose", "m")
    assert state.scale == pytest.approx(SIGMA / 10)
    assert "tyre nose" in state.description


@pytest.mark.parametrize("psi", [0.0, 0.2, -0.5, 1.2])
def test_steady_deflection_at_a_yaw_angle_is_sigma_sin_psi(psi):
    kin, _, rate, _ = planar_parts()
    rest = {velocity_symbol(c): 0.0 for c in kin.coords}
    q = {sp.Symbol("x_wheel", real=True): 0.0, sp.Symbol("y_wheel", real=True): 0.0,
         sp.Symbol("theta_wheel", real=True): psi}
    r = rate.xreplace(rest).xreplace(q)
    assert float(r.xreplace({Y: SIGMA * math.sin(psi)})) == pytest.approx(0.0, abs=1e-12)
    assert float(sp.diff(r, Y)) == pytest.approx(-V / SIGMA, rel=1e-12)          # relaxation rate
    assert float(r.xreplace({Y: 0.0})) == pytest.approx(V * math.sin(psi), rel=1e-12, abs=1e-12)  # -v_lat


def test_lateral_velocity_of_a_moving_body():
    kin, _, rate, _ = planar_parts()
    rng = np.random.default_rng(7)
    for _ in range(4):
        x, y, th, xd, yd, thd = rng.normal(size=6)
        vals = dict(zip(("x_wheel", "y_wheel", "theta_wheel"), (x, y, th)))
        subs = {sp.Symbol(n, real=True): v for n, v in vals.items()}
        subs |= {velocity_symbol(n): v for n, v in zip(("x_wheel", "y_wheel", "theta_wheel"), (xd, yd, thd))}
        lat = np.array([-math.sin(th), math.cos(th)])
        p = np.array([-E, 0.0])
        Rp = np.array([math.cos(th) * p[0] - math.sin(th) * p[1], math.sin(th) * p[0] + math.cos(th) * p[1]])
        v_lat = np.array([xd + V, yd]) @ lat + thd * np.array([-Rp[1], Rp[0]]) @ lat
        assert float(rate.xreplace(subs).xreplace({Y: 0.02})) == pytest.approx(-v_lat - V / SIGMA * 0.02, rel=1e-12)


def _numeric_force_work(q, y, trail, force):
    """``F l . d(P - t h)/dq`` by central differences (numpy geometry of the caster)."""
    def point(qq):
        x, yy, th = qq
        h = np.array([math.cos(th), math.sin(th)])
        R = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
        return np.array([x, yy]) + R @ np.array([-E, 0.0]) - trail * h
    th = q[2]
    f = force(y) * np.array([-math.sin(th), math.cos(th)])
    out = []
    for i in range(3):
        d = np.zeros(3)
        d[i] = 1e-6
        out.append(f @ (point(q + d) - point(q - d)) / 2e-6)
    return np.array(out)


@pytest.mark.parametrize("trail, fmax", [(0.0, None), (0.04, None), (0.04, 500.0)])
def test_generalised_forces_are_the_virtual_work_of_the_side_force(trail, fmax):
    extra = f"pneumatic_trail = {trail}" + (f"\nmax_force = {fmax}" if fmax else "")
    kin, _, _, Q = planar_parts(extra=extra)

    def force(y):
        return CS * y / SIGMA if fmax is None else fmax * math.tanh(CS * y / (SIGMA * fmax))

    rng = np.random.default_rng(11)
    for _ in range(3):
        q, y = rng.normal(size=3), 0.05 * rng.normal()
        subs = {s: v for s, v in zip(kin.q, q)} | {Y: y}
        got = np.array([float(e.xreplace(subs)) for e in Q])
        np.testing.assert_allclose(got, _numeric_force_work(q, y, trail, force), rtol=1e-7, atol=1e-7)
        assert got[2] == pytest.approx(-(E + trail) * force(y), rel=1e-12)   # Q_theta = -(e + t) F


def test_saturating_force_has_the_linear_slope_and_its_bound():
    _, _, _, Q = planar_parts(extra="max_force = 500.0")
    q = {sp.Symbol("x_wheel", real=True): 0, sp.Symbol("y_wheel", real=True): 0,
         sp.Symbol("theta_wheel", real=True): 0}
    Fy = Q[1].xreplace(q)                       # at theta = 0 the lateral axis is +y: Q_y = F
    assert float(sp.diff(Fy, Y).xreplace({Y: 0})) == pytest.approx(CS / SIGMA, rel=1e-12)
    assert float(Fy.xreplace({Y: 1.0})) == pytest.approx(500.0, rel=1e-9)
    assert float(Fy.xreplace({Y: -1.0})) == pytest.approx(-500.0, rel=1e-9)


def _caster_matrix(V_, c=CD):
    """A of (psi, omega, y) linearised from the element expressions (the pin holds x = y = 0)."""
    mech = parse_description(text(V=V_, c=c))
    kin = PlanarKinematics(mech)
    ld = loads(kin)
    at = at_values(mech, V=V_, c=c)
    th, om = sp.Symbol("theta_wheel", real=True), velocity_symbol("theta_wheel")
    pin = {sp.Symbol("x_wheel", real=True): 0, sp.Symbol("y_wheel", real=True): 0,
           velocity_symbol("x_wheel"): 0, velocity_symbol("y_wheel"): 0}
    Qth = (-sp.diff(ld.V, th) + ld.Q_nc[2]).xreplace(at).xreplace(pin)
    inertia = float(kin.mass_matrix()[2, 2].xreplace(at))
    (state,) = tyre_of(mech).states(kin)
    rate = sp.sympify(state.rate).xreplace(at).xreplace(pin)
    rows = [[0.0, 1.0, 0.0]]
    for f, scale in ((Qth, 1 / inertia), (rate, 1.0)):
        rows.append([scale * float(sp.diff(f, s).xreplace({th: 0, om: 0, Y: 0})) for s in (th, om, Y)])
    return np.array(rows)


def hopf_speeds(c=CD, k=K, e=E, sigma=SIGMA, C=CS, inertia=I):
    """Roots of I c V^2 + (c^2 sigma + I e C (e - sigma)) V + c sigma (e^2 C + k sigma) = 0 (m/s)."""
    r = np.roots([inertia * c, c * c * sigma + inertia * e * C * (e - sigma), c * sigma * (e * e * C + k * sigma)])
    return np.sort(r.real[(abs(r.imag) < 1e-12) & (r.real > 0)])


def test_element_linearisation_has_the_caster_cubic_and_its_hopf_speeds():
    for V_ in (3.0, 10.0):
        A = _caster_matrix(V_)
        coeffs = np.poly(A)   # s^3 + a2 s^2 + a1 s + a0
        a2, a1, a0 = CD / I + V_ / SIGMA, (K + (CD * V_ + E * E * CS) / SIGMA) / I, V_ * (K + E * CS) / (I * SIGMA)
        np.testing.assert_allclose(coeffs, [1.0, a2, a1, a0], rtol=1e-12)
    v1, v2 = hopf_speeds()
    assert 0 < v1 < v2
    for vh in (v1, v2):
        lam = np.linalg.eigvals(_caster_matrix(vh))
        pair = lam[np.argmax(abs(lam.imag))]
        assert abs(pair.real) < 1e-9 * abs(pair.imag)          # a pure imaginary pair at the Hopf speed
    mid = np.linalg.eigvals(_caster_matrix(0.5 * (v1 + v2)))
    assert max(mid.real) > 0                                   # shimmy between the two speeds
    for outside in (0.5 * v1, 1.5 * v2):
        assert max(np.linalg.eigvals(_caster_matrix(outside)).real) < 0


def test_spatial_tyre_agrees_with_the_planar_one():
    mech2, mech3 = parse_description(text(extra="pneumatic_trail = 0.03\nmax_force = 900.0")), \
        parse_description(text(CASTER3, extra="pneumatic_trail = 0.03\nmax_force = 900.0"))
    kin2, kin3 = PlanarKinematics(mech2), SpatialKinematics(mech3)
    rates, works = [], []
    psi, w, y = 0.35, -1.3, 0.012
    for mech, kin in ((mech2, kin2), (mech3, kin3)):
        tyre = tyre_of(mech)
        from mechcont.mechanism.loads import Loads

        out = Loads(sp.S.Zero, [sp.S.Zero] * len(kin.q), [])
        tyre.apply(kin, out)
        (state,) = tyre.states(kin)
        at = at_values(mech)
        if kin is kin2:
            q = {"x_wheel": 0.0, "y_wheel": 0.0, "theta_wheel": psi}
            dq = {"x_wheel": 0.0, "y_wheel": 0.0, "theta_wheel": 1.0}       # d q / d psi
        else:
            q = {f"{c}_wheel": 0.0 for c in "xyz"} | {"e0_wheel": math.cos(psi / 2), "e1_wheel": 0.0,
                                                      "e2_wheel": 0.0, "e3_wheel": math.sin(psi / 2)}
            dq = {f"{c}_wheel": 0.0 for c in "xyz"} | {"e0_wheel": -math.sin(psi / 2) / 2, "e1_wheel": 0.0,
                                                       "e2_wheel": 0.0, "e3_wheel": math.cos(psi / 2) / 2}
        assert set(q) == set(kin.coords)
        subs = at | {sp.Symbol(n, real=True): v for n, v in q.items()} | {Y: y}
        subs |= {velocity_symbol(n): dq[n] * w for n in kin.coords}
        rates.append(float(sp.sympify(state.rate).xreplace(subs)))
        works.append(sum(float(sp.sympify(Qi).xreplace(subs)) * dq[n] for Qi, n in zip(out.Q_nc, kin.coords)))
    assert rates[1] == pytest.approx(rates[0], rel=1e-12)
    assert works[1] == pytest.approx(works[0], rel=1e-12)
    assert works[0] == pytest.approx(-(E + 0.03) * 900.0 * math.tanh(CS * y / (SIGMA * 900.0)), rel=1e-12)


@pytest.mark.parametrize("extra, edit, field, words", [
    ("", ("relaxation_length = 0.3", "relaxation_length = 0.0"), "tyres.nose.relaxation_length", "relaxation length"),
    ("", ("relaxation_length = 0.3", "relaxation_length = -0.3"), "tyres.nose.relaxation_length", "relaxation length"),
    ("", ("cornering_stiffness = 1800.0", "cornering_stiffness = -1.0"), "tyres.nose.cornering_stiffness",
     "cornering stiffness"),
    ("max_force = 0.0", None, "tyres.nose.max_force", "maximum side force"),
    ("max_force = -10.0", None, "tyres.nose.max_force", "maximum side force"),
    ("", ('body = "wheel"\nat', 'body = "ground"\nat'), "tyres.nose.body", "not \"ground\""),
    ("", ('body = "wheel"\nat', 'body = "rim"\nat'), "tyres.nose.body", "unknown body"),
    ("", ('at = "contact"', 'at = "ground.O"'), "tyres.nose.at", "must be on the tyre's body"),
    ("", ('at = "contact"', 'at = "hub"'), "tyres.nose.at", "unknown point"),
    ("grip = 1.0", None, "tyres.nose.grip", "unknown key"),
])
def test_bad_tyre_input_is_one_line(extra, edit, field, words):
    src = text(extra=extra)
    if edit:
        assert edit[0] in src
        src = src.replace(*edit)
    with pytest.raises(InputError) as info:
        parse_description(src).build()
    msg = str(info.value)
    assert "\n" not in msg and field in msg and words in msg, msg


def test_cli_refuses_a_zero_relaxation_length(tmp_path):
    path = tmp_path / "caster.toml"
    path.write_text(text(sigma=0.0))
    one_line_error(make_runner()("check", path), "tyres.nose.relaxation_length")


def test_zero_speed_is_refused_naming_why(tmp_path):
    with pytest.raises(InputError, match=r"tyres\.nose\.speed.*undetermined"):
        parse_description(text(V=0.0)).build()
