"""Torsion springs and rotary dampers (``[torsion_springs.NAME]``, ``[torsion_dampers.NAME]``),
planar and spatial, against closed forms.

A body pinned at its centre of gravity to the ground (no gravity), polar moment of inertia ``J``,
held by a torsion spring ``k`` (free angle ``a0``) and a rotary damper ``c`` and loaded by a moment
``M``:

* equilibrium ``phi = a0 + M/k``;
* small motions ``J phi'' + c phi' + k phi = 0``: natural frequency ``w_n = sqrt(k/J)``, damping ratio
  ``zeta = c / (2 sqrt(k J))``, free decay from ``phi0`` at rest
  ``phi(t) = phi0 e^(-zeta w_n t) (cos w_d t + zeta/sqrt(1-zeta^2) sin w_d t)``, ``w_d = w_n sqrt(1-zeta^2)``;
* the generalised damping matrix ``-dQ/dqdot`` of a damper between two free bodies is
  ``c [[1, -1], [-1, 1]]`` on their angles (the relative angle's gradient squared), and its moment
  ``c w + c2 w |w|`` for the relative rate ``w``.

In space the relative angle is about a revolute joint's axis (tilted here, so the general formula is
exercised): the equilibrium rotation read from the Euler parameters (``2 atan2(eps . n, e0)``) is
``a0 + M/k``, and the damper's virtual power along a rotation about the axis is ``-(c w + c2 w|w|) w``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from cli_helpers import make_runner, one_line_error

from mechcont.continuation import find_equilibrium
from mechcont.equations import velocity_symbol
from mechcont.errors import InputError
from mechcont.mechanism import parse_description

J, K, A0, MOM, C, C2 = 0.8, 200.0, 0.2, 30.0, 4.0, 0.5

PLANAR = """
[mechanism]
name = "rotor"
dof = {dof}
[parameters]
k = {k}
M = {m}
c = {c}
[ground]
O = [0, 0]
[bodies.disc]
mass = 1.0
inertia = {j}
points = {{ rim = [0.3, 0] }}
initial = {{ theta = 0.1 }}
[joints.pin]
type = "revolute"
a = "ground.O"
b = "disc.origin"
[torsion_springs.tor]
a = "ground"
b = "disc"
k = "k"
angle = {a0}
[torsion_dampers.dmp]
a = "ground"
b = "disc"
c = "c"
c2 = {c2}
[loads.m]
type = "moment"
body = "disc"
magnitude = "M"
"""

AXIS = np.array([0.0, 1.0, 1.0]) / math.sqrt(2.0)
SPATIAL = """
[mechanism]
name = "rotor3"
dimension = 3
[parameters]
k = {k}
M = {m}
c = {c}
[ground]
O = [0, 0, 0]
[bodies.disc]
mass = 1.0
inertia = [{j}, {j}, {j}]
points = {{ rim = [0.3, 0, 0] }}
[joints.pin]
type = "revolute"
a = "ground.O"
b = "disc.origin"
axis = [0, 1, 1]
[torsion_springs.tor]
a = "ground"
b = "disc"
k = "k"
angle = {a0}
joint = "pin"
[torsion_dampers.dmp]
a = "ground"
b = "disc"
c = "c"
c2 = {c2}
joint = "pin"
[loads.m]
type = "moment"
body = "disc"
magnitude = "M"
axis = [0, 1, 1]
"""


def planar(**kw):
    v = dict(k=K, m=MOM, c=C, j=J, a0=A0, c2=C2, dof=1) | kw
    return PLANAR.format(**v)


def spatial(**kw):
    v = dict(k=K, m=MOM, c=C, j=J, a0=A0, c2=C2) | kw
    return SPATIAL.format(**v)


@pytest.fixture(scope="module")
def rotor():
    return parse_description(planar())


@pytest.mark.parametrize("reduced", [False, True], ids=["full", "reduced"])
def test_planar_equilibrium_angle_under_a_moment(rotor, reduced):
    model = rotor.build_reduced() if reduced else rotor.build()
    x = find_equilibrium(model)
    assert x[model.index("theta_disc")] == pytest.approx(A0 + MOM / K, abs=1e-10)


def test_spatial_equilibrium_rotation_about_a_tilted_axis():
    model = parse_description(spatial()).build()
    x = find_equilibrium(model)
    e = np.array([x[model.index(f"e{i}_disc")] for i in range(4)])
    # the rotation of the disc from the design pose: about AXIS by 2 atan2(eps . n, e0)
    eps = e[1:]
    assert np.linalg.norm(eps - (eps @ AXIS) * AXIS) < 1e-9            # the joint holds the axis
    assert 2 * math.atan2(eps @ AXIS, e[0]) == pytest.approx(A0 + MOM / K, abs=1e-9)


def _reduced_theta(model):
    """(Q(theta, theta_dot), J_eff) of a 1-coordinate reduced model as SymPy expressions."""
    mech = model.mechanics
    assert mech.coordinates == ("theta_disc",)
    return mech.forces[0], mech.mass_matrix[0, 0]


def test_natural_frequency_and_damping_ratio(rotor):
    model = rotor.build_reduced(M=0.0, c=C)
    Q, mass = _reduced_theta(model)
    th, om = sp.Symbol("theta_disc", real=True), velocity_symbol("theta_disc")
    at = {sp.Symbol(n, real=True): v for n, v in zip(model.names, model.defaults()) if n != "theta_disc"}
    Qn = Q.xreplace(at)
    stiffness = -float(sp.diff(Qn, th).xreplace({th: A0, om: 0}))
    damping = -float(sp.diff(Qn, om).xreplace({th: A0, om: 0}))
    inertia = float(sp.sympify(mass).xreplace(at))
    assert inertia == pytest.approx(J, rel=1e-12)
    assert stiffness == pytest.approx(K, rel=1e-12)
    assert damping == pytest.approx(C, rel=1e-12)   # the quadratic term has no slope at rest
    assert math.sqrt(stiffness / inertia) == pytest.approx(math.sqrt(K / J), rel=1e-12)
    assert damping / (2 * math.sqrt(stiffness * inertia)) == pytest.approx(C / (2 * math.sqrt(K * J)), rel=1e-12)
    # the quadratic moment: Q(a0, w) = -(c w + c2 w |w|)
    for w in (-3.0, 0.7, 2.5):
        assert float(Qn.xreplace({th: A0, om: w})) == pytest.approx(-(C * w + C2 * w * abs(w)), rel=1e-12)


def test_free_decay_matches_the_damped_oscillator():
    from mechcont.dynamics import assemble, simulate

    phi0 = 0.05
    wn, zeta = math.sqrt(K / J), C / (2 * math.sqrt(K * J))
    wd = wn * math.sqrt(1 - zeta ** 2)
    t = np.linspace(0.0, 0.6, 13)
    # the quadratic term changes the decay: the closed form is for c2 = 0
    model0 = parse_description(planar(c2=0.0)).build(M=0.0)
    x0 = assemble(model0, {"theta_disc": A0 + phi0}, hold=["theta_disc"])
    sim = simulate(model0, x0, (0.0, t[-1]), rtol=1e-10, atol=1e-12, t_eval=t)
    exact = phi0 * np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta / math.sqrt(1 - zeta ** 2) * np.sin(wd * t))
    np.testing.assert_allclose(np.asarray(sim["theta_disc"]) - A0, exact, atol=1e-7)


def test_damper_between_two_bodies_gives_c_on_the_relative_angle():
    text = planar(dof=2).replace('a = "ground"\nb = "disc"\nc = "c"', 'a = "hub"\nb = "disc"\nc = "c"') + """
[bodies.hub]
mass = 1.0
inertia = 1.0
initial = { theta = 0.0 }
[joints.hubpin]
type = "revolute"
a = "ground.O"
b = "hub.origin"
"""
    model = parse_description(text).build(M=0.0)
    mech = model.mechanics
    i, j = mech.coordinates.index("theta_hub"), mech.coordinates.index("theta_disc")
    qd = [velocity_symbol(c) for c in mech.coordinates]
    wa, wb = 0.3, -1.1
    rest = {s: 0 for s in qd} | {qd[i]: wa, qd[j]: wb}
    at = {sp.Symbol(n, real=True): v for n, v in zip(model.names, model.defaults())}
    D = np.array([[-float(sp.diff(mech.forces[r], qd[s]).xreplace(at).xreplace(rest)) for s in (i, j)] for r in (i, j)])
    w = wb - wa
    dm = C + 2 * C2 * abs(w)    # d(c w + c2 w|w|)/dw
    np.testing.assert_allclose(D, dm * np.array([[1.0, -1.0], [-1.0, 1.0]]), rtol=1e-12)
    moment = C * w + C2 * w * abs(w)
    Qd = float(mech.forces[j].xreplace(at).xreplace(rest))
    # the disc feels -moment from the damper and -k(phi - a0) from its spring to the ground
    th = at[sp.Symbol("theta_disc", real=True)]
    assert Qd == pytest.approx(-moment - K * (th - A0), rel=1e-12)


def test_spatial_damper_power_along_a_rotation_about_the_axis():
    model = parse_description(spatial(m=0.0)).build()
    mech = model.mechanics
    phi, w = 0.4, 1.7
    n = AXIS
    e = np.concatenate([[math.cos(phi / 2)], math.sin(phi / 2) * n])
    de = np.concatenate([[-math.sin(phi / 2) / 2], math.cos(phi / 2) / 2 * n])  # de/dphi
    at = {sp.Symbol(c, real=True): 0.0 for c in mech.coordinates}
    at |= {sp.Symbol(f"e{i}_disc", real=True): e[i] for i in range(4)}
    at |= {velocity_symbol(c): 0.0 for c in mech.coordinates}
    at |= {velocity_symbol(f"e{i}_disc"): de[i] * w for i in range(4)}
    at |= {sp.Symbol(p, real=True): v for p, v in (("k", K), ("M", 0.0), ("c", C))}
    idx = [mech.coordinates.index(f"e{i}_disc") for i in range(4)]
    Q = np.array([float(mech.forces[k].xreplace(at)) for k in idx])
    # virtual work along the rotation: spring -k (phi - a0) plus damper -(c w + c2 w|w|)
    assert Q @ de == pytest.approx(-K * (phi - A0) - (C * w + C2 * w * abs(w)), rel=1e-10)


def test_the_scene_draws_each_rotary_element_as_a_coil_at_its_pin(rotor, tmp_path):
    from mechcont.outputs.drawing import draw

    model = rotor.build()
    scene = model.scene(model.defaults())
    assert sorted((n, k) for n, _, k in scene.coils) == [("dmp", "damper"), ("tor", "spring")]
    for _, p, _ in scene.coils:
        np.testing.assert_allclose(p, [0.0, 0.0], atol=1e-12)   # the pin O
    assert not scene.springs and not scene.dampers                # no line between two ends on one pin
    draw(model, model.defaults(), tmp_path / "rotor.svg")
    svg = (tmp_path / "rotor.svg").read_text()
    assert 'id="coil:tor"' in svg and 'id="coil:dmp"' in svg


@pytest.mark.parametrize("edit, field, words", [
    (("k = \"k\"", "k = -1.0"), "torsion_springs.tor.k", "torsional stiffness"),
    (("c = \"c\"", "c = -2.0"), "torsion_dampers.dmp.c", "torsional damping"),
    (("c2 = 0.5", "c2 = -0.5"), "torsion_dampers.dmp.c2", "quadratic"),
    (('b = "disc"\nk', 'b = "ground"\nk'), "torsion_springs.tor.b", "must differ"),
    (('b = "disc"\nk', 'b = "rotor"\nk'), "torsion_springs.tor.b", "bodies: disc"),
    (('b = "disc"\nk', 'b = "disc"\njoint = "nope"\nk'), "torsion_springs.tor.joint", "unknown joint"),
])
def test_bad_rotary_input_is_one_line(edit, field, words):
    text = planar().replace(*edit, 1)
    with pytest.raises(InputError) as info:
        parse_description(text).build()
    msg = str(info.value)
    assert "\n" not in msg and field in msg and words in msg, msg


@pytest.mark.parametrize("edit, words", [
    (('joint = "pin"\n[torsion_dampers', '[torsion_dampers'), "is required in a spatial description"),
    (('type = "revolute"', 'type = "spherical"'), "needs a joint with an axis"),
])
def test_bad_spatial_rotary_input_is_one_line(edit, words):
    text = spatial().replace(*edit, 1)
    if "spherical" in edit[1]:
        text = text.replace("axis = [0, 1, 1]\n", "", 1)
    with pytest.raises(InputError) as info:
        parse_description(text).build()
    msg = str(info.value)
    assert "\n" not in msg and ("torsion_springs.tor.joint" in msg or "torsion_dampers.dmp.joint" in msg), msg
    assert words in msg, msg


def test_cli_refuses_a_negative_torsional_stiffness(tmp_path):
    path = tmp_path / "rotor.toml"
    path.write_text(planar(k=-5.0))
    one_line_error(make_runner()("check", path), "torsion_springs.tor.k")
