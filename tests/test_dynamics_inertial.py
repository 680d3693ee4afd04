"""The complete equations of motion: velocity-product inertial forces against closed forms.

``M(q)`` depends on ``q`` whenever a body's frame origin is not its centre of gravity (planar) and
always for a spatial body (Euler parameters). The terms ``-(Mdot qdot - 1/2 d(qdot^T M qdot)/dq)``
are checked here against truth that does not come from mechcont:

* a body hinged away from its centre of gravity and driven by a constant moment:
  ``theta'' = M0 / (I + m d^2)``, ``d`` the pivot-to-cg distance (planar and spatial);
* a spatial body with a general inertia tensor on a ball joint at its cg, driven by a moment fixed
  in space: its angular momentum is ``M0 t e_z`` exactly (and with no moment it is conserved,
  as is its kinetic energy: Euler's equations, ``omega x J omega``);
* an offset-origin pendulum released horizontal: its energy is conserved;
* frame invariance: the same closed-loop mechanism written with frames at the pivots and at the
  cgs follows the same motion; a spatial pendulum likewise.
"""

import math

import numpy as np
import pytest
import sympy as sp

from mechcont.dynamics import assemble, simulate
from mechcont.mechanism import load
from mechcont.mechanism.spatial._rotation import rotation_matrix
from mechcont.models import load_model

M_BAR, L_BAR, H_OFF, I_CG, M0 = 3.0, 0.8, 0.1, 0.05, 2.0


def _load(tmp_path, name, text):
    p = tmp_path / f"{name}.toml"
    p.write_text(text)
    return load_model(p)


# A bar of the format (frame origin at its centre), hinged at its end a, its cg h across its axis:
# neither the pivot nor the cg is the frame origin, so M(q) couples the frame's translation and turn.
PLANAR_BAR = f"""
[mechanism]
name = "offset_bar"
[parameters]
M0 = {{ value = {M0}, unit = "N m" }}
[ground]
O = [0, 0]
[bodies.bar]
mass = {M_BAR}
length = {L_BAR}
inertia = {I_CG}
cg = [0, {H_OFF}]
initial = {{ theta = 0.0 }}
[joints.pivot]
type = "revolute"
a = "ground.O"
b = "bar.a"
[loads.drive]
type = "moment"
body = "bar"
magnitude = "M0"
"""

SPATIAL_BAR = f"""
[mechanism]
name = "offset_bar_3d"
dimension = 3
dof = 1
[parameters]
M0 = {{ value = {M0}, unit = "N m" }}
[ground]
O = [0, 0, 0]
[bodies.bar]
mass = {M_BAR}
length = {L_BAR}
inertia = [0.02, 0.03, {I_CG}]
cg = [0, {H_OFF}, 0]
initial = {{ x = {L_BAR / 2} }}
[joints.pivot]
type = "revolute"
a = "ground.O"
b = "bar.a"
axis = [0, 0, 1]
[loads.drive]
type = "moment"
body = "bar"
magnitude = "M0"
axis = [0, 0, 1]
"""


def test_offset_cg_bar_planar_closed_form(tmp_path):
    s = _load(tmp_path, "offset_bar", PLANAR_BAR)
    x0 = assemble(s, {"theta_bar": 0.0}, hold=["theta_bar"])
    T = 2.0
    r = simulate(s, x0, (0.0, T), rtol=1e-10, atol=1e-12, t_eval=np.linspace(0, T, 41))
    assert r.success
    alpha = M0 / (I_CG + M_BAR * (L_BAR**2 / 4 + H_OFF**2))
    np.testing.assert_allclose(r["theta_bar"], 0.5 * alpha * r.t**2, rtol=1e-7, atol=1e-9)


def test_offset_cg_bar_spatial_closed_form(tmp_path):
    s = _load(tmp_path, "offset_bar_3d", SPATIAL_BAR)
    x0 = assemble(s, {})
    T = 2.0
    r = simulate(s, x0, (0.0, T), rtol=1e-10, atol=1e-12, t_eval=np.linspace(0, T, 41))
    assert r.success
    alpha = M0 / (I_CG + M_BAR * (L_BAR**2 / 4 + H_OFF**2))
    # the frame's x axis, turned by R(e), gives the angle about z
    e = np.column_stack([r[f"e{i}_bar"] for i in range(4)])
    angle = np.unwrap([math.atan2(2 * (q[1] * q[2] + q[0] * q[3]), q[0]**2 + q[1]**2 - q[2]**2 - q[3]**2) for q in e])
    np.testing.assert_allclose(angle - angle[0], 0.5 * alpha * r.t**2, rtol=1e-7, atol=1e-9)


BALL = """
[mechanism]
name = "spun_body"
dimension = 3
dof = 3
[parameters]
M0 = {{ value = {m0}, unit = "N m" }}
[ground]
O = [0.1, -0.2, 0.3]
[bodies.body]
mass = 5.0
inertia = [0.8, 0.9, 1.3, 0.12, -0.07, 0.2]
cg = [0.1, -0.2, 0.3]
points = {{ c = [0.1, -0.2, 0.3], tip = [0.6, 0.1, 0.2] }}
initial = {{ rotation = [0.3, -0.5, 0.8] }}
[joints.ball]
type = "spherical"
a = "ground.O"
b = "body.c"
[loads.drive]
type = "moment"
body = "body"
magnitude = "M0"
axis = [0, 0, 1]
"""

_E = sp.symbols("e0:4")
_R = sp.lambdify([_E], rotation_matrix(list(_E)), "numpy")
_J_BODY = np.array([[0.8, 0.12, -0.07], [0.12, 0.9, 0.2], [-0.07, 0.2, 1.3]])


def _angular_momentum(e, ed):
    """Global angular momentum J_global omega of the body from its Euler parameters and rates:
    omega from Rdot R^T (central differences of R along edot: a definition, not mechcont's dynamics)."""
    R = np.asarray(_R(e), float)
    h = 1e-6
    Rd = (np.asarray(_R(e + h * ed), float) - np.asarray(_R(e - h * ed), float)) / (2 * h)
    W = Rd @ R.T
    w = np.array([W[2, 1], W[0, 2], W[1, 0]])
    return R @ _J_BODY @ R.T @ w, 0.5 * w @ (R @ _J_BODY @ R.T) @ w


def _spin(tmp_path, m0, omega0, T):
    s = _load(tmp_path, f"spun_{m0}", BALL.format(m0=m0))
    x0 = assemble(s, {})
    names = list(r_name for r_name in s.mechanics.coordinates)
    e0 = np.array([x0[s.index(f"e{i}_body")] for i in range(4)])
    # initial Euler-parameter rates for a global angular velocity omega0: edot = 1/2 E^T omega
    q0, q1, q2, q3 = e0
    E = np.array([[-q1, q0, -q3, q2], [-q2, q3, q0, -q1], [-q3, -q2, q1, q0]])
    ed0 = 0.5 * E.T @ np.asarray(omega0, float)
    qdot0 = {f"e{i}_body": ed0[i] for i in range(4)}
    r = simulate(s, x0, (0.0, T), qdot0=qdot0, rtol=1e-10, atol=1e-12, t_eval=np.linspace(0, T, 31))
    assert r.success, r.message
    e = np.column_stack([r[f"e{i}_body"] for i in range(4)])
    ed = r.qdot[:, [names.index(f"e{i}_body") for i in range(4)]]
    return r, [_angular_momentum(a, b) for a, b in zip(e, ed)]


def test_body_spun_up_by_a_fixed_moment(tmp_path):
    """From rest under a moment fixed in space, H(t) = M0 t e_z exactly (Euler's equations with the
    gyroscopic term; without it the body's momentum drifts off the moment's axis)."""
    T, m0 = 3.0, 1.5
    r, hk = _spin(tmp_path, m0, [0.0, 0.0, 0.0], T)
    H = np.array([h for h, _ in hk])
    expected = np.outer(r.t, [0.0, 0.0, m0])
    np.testing.assert_allclose(H, expected, atol=1e-6 * m0 * T)


def test_torque_free_asymmetric_body_conserves_momentum_and_energy(tmp_path):
    omega0 = [0.7, 2.5, -1.1]
    r, hk = _spin(tmp_path, 0.0, omega0, 3.0)
    H = np.array([h for h, _ in hk])
    K = np.array([k for _, k in hk])
    assert np.ptp(H, axis=0).max() < 1e-6 * np.linalg.norm(H[0])
    assert np.ptp(K) < 1e-7 * K[0]
    # the body really tumbles: its angular velocity is not constant in the body
    assert np.linalg.norm(H[0]) > 1.0


PENDULUM = """
[mechanism]
name = "offset_pendulum"
[parameters]
g = {{ value = 9.81, unit = "m/s^2" }}
[ground]
O = [0, 0]
[bodies.arm]
mass = 4.0
inertia = 0.3
cg = [{cx}, {cy}]
points = {{ pivot = [{px}, {py}] }}
initial = {{ theta = 0.0 }}
[joints.pin]
type = "revolute"
a = "ground.O"
b = "arm.pivot"
[gravity]
g = "g"
"""


def _pendulum(tmp_path, tag, cg, pivot, T=2.0):
    s = _load(tmp_path, f"pendulum_{tag}", PENDULUM.format(cx=cg[0], cy=cg[1], px=pivot[0], py=pivot[1]))
    x0 = assemble(s, {"theta_arm": 0.0}, hold=["theta_arm"])
    r = simulate(s, x0, (0.0, T), rtol=1e-10, atol=1e-12, t_eval=np.linspace(0, T, 201))
    assert r.success, r.message
    return s, r


# the arm's cg is 0.7 m along and 0.2 m across it from the pivot; each variant puts the frame
# origin elsewhere (body coordinates of the pivot and the cg move together)
FRAMES = {"pivot": (0.0, 0.0), "cg": (0.7, 0.2), "elsewhere": (-0.5, 0.4)}


def _framed_pendulum(tmp_path, tag):
    o = FRAMES[tag]
    return _pendulum(tmp_path, tag, (0.7 - o[0], 0.2 - o[1]), (-o[0], -o[1]))


def test_offset_origin_pendulum_conserves_energy(tmp_path):
    """Frame away from both pivot and cg, released horizontal: energy conserved (without the
    velocity-product forces it grows by tens of joules within a second)."""
    s, r = _framed_pendulum(tmp_path, "elsewhere")
    m, g, I = 4.0, 9.81, 0.3
    th, w = r["theta_arm"], r.qdot[:, list(s.mechanics.coordinates).index("theta_arm")]
    y_cg = 0.7 * np.sin(th) + 0.2 * np.cos(th)
    E = 0.5 * (I + m * (0.7**2 + 0.2**2)) * w**2 + m * g * y_cg
    assert np.ptp(E) < 1e-7 * m * g * 0.73
    assert th.min() < -1.0  # it swung down


def test_motion_does_not_depend_on_where_the_frame_sits(tmp_path):
    """The same pendulum with its frame at the pivot, at the cg and elsewhere: one angle history."""
    runs = {tag: _framed_pendulum(tmp_path, tag)[1]["theta_arm"] for tag in FRAMES}
    np.testing.assert_allclose(runs["elsewhere"], runs["cg"], atol=1e-7)
    np.testing.assert_allclose(runs["pivot"], runs["cg"], atol=1e-7)


FOURBAR = """
[mechanism]
name = "fourbar_frames_{tag}"
[parameters]
g = {{ value = 9.81, unit = "m/s^2" }}
[ground]
A = [0, 0]
D = [1.0, 0.1]
[bodies.crank]
mass = 1.2
inertia = 0.02
cg = [{c1}]
points = {{ A = [{a1}], B = [{b1}] }}
initial = {{ theta = 1.2 }}
[bodies.coupler]
mass = 2.0
inertia = 0.09
cg = [{c2}]
points = {{ B = [{a2}], C = [{b2}] }}
initial = {{ theta = 0.1 }}
[bodies.rocker]
mass = 1.5
inertia = 0.05
cg = [{c3}]
points = {{ C = [{a3}], D = [{b3}] }}
initial = {{ theta = -1.6 }}
[joints.A]
type = "revolute"
a = "ground.A"
b = "crank.A"
[joints.B]
type = "revolute"
a = "crank.B"
b = "coupler.B"
[joints.C]
type = "revolute"
a = "coupler.C"
b = "rocker.C"
[joints.D]
type = "revolute"
a = "rocker.D"
b = "ground.D"
[gravity]
g = "g"
"""


def _fourbar(tmp_path, tag, shift, reduced=False):
    """Links along their x axes (crank 0.4 m, coupler 1.1 m, rocker 0.8 m) with cgs off the axis; the
    frame origin moved by ``shift[k]`` (body coordinates) on each body; ``reduced``: the reduced form
    (the tree of pins eliminated, M = J^T M J)."""
    links = [((0.0, 0.0), (0.4, 0.0), (0.25, 0.06)), ((0.0, 0.0), (1.1, 0.0), (0.5, -0.1)),
             ((0.0, 0.0), (0.8, 0.0), (0.3, 0.08))]
    fields = {}
    for k, ((a, b, c), sh) in enumerate(zip(links, shift), start=1):
        for key, p in (("a", a), ("b", b), ("c", c)):
            fields[f"{key}{k}"] = f"{p[0] - sh[0]}, {p[1] - sh[1]}"
    path = tmp_path / f"fourbar_{tag}.toml"
    path.write_text(FOURBAR.format(tag=tag, **fields))
    s = load(path, reduced=reduced)
    x0 = assemble(s, {"theta_crank": 1.2}, hold=["theta_crank"])
    T = 1.5
    r = simulate(s, x0, (0.0, T), rtol=1e-10, atol=1e-12, t_eval=np.linspace(0, T, 151))
    assert r.success, r.message
    return r, links


def test_closed_loop_frame_invariance(tmp_path):
    """A four-bar under gravity with frames at the cgs and with frames away from pivots and cgs: the
    same motion (angles, and the coupler's cg path) to integrator tolerance, through a large angle."""
    away = [(-0.2, 0.15), (0.3, 0.25), (0.9, -0.1)]
    at_away, links = _fourbar(tmp_path, "away", away)
    at_cgs, _ = _fourbar(tmp_path, "cgs", [c for _, _, c in links])
    for body in ("crank", "coupler", "rocker"):
        np.testing.assert_allclose(at_away[f"theta_{body}"], at_cgs[f"theta_{body}"], atol=1e-6)
    assert np.ptp(at_away["theta_crank"]) > 1.0

    def coupler_cg(r, sh):
        th = r["theta_coupler"]
        cx, cy = 0.5 - sh[0], -0.1 - sh[1]
        return r["x_coupler"] + cx * np.cos(th) - cy * np.sin(th), r["y_coupler"] + cx * np.sin(th) + cy * np.cos(th)

    for u, v in zip(coupler_cg(at_away, away[1]), coupler_cg(at_cgs, (0.5, -0.1))):
        np.testing.assert_allclose(u, v, atol=1e-6)
    # the reduced form of the frames-away four-bar (its velocity-product forces from J^T M J alone)
    reduced, _ = _fourbar(tmp_path, "away_reduced", away, reduced=True)
    assert len(reduced.coordinates) < len(at_away.coordinates)
    np.testing.assert_allclose(reduced["theta_crank"], at_cgs["theta_crank"], atol=1e-6)


SPATIAL_PENDULUM = """
[mechanism]
name = "spatial_pendulum_{tag}"
dimension = 3
dof = 1
[parameters]
g = {{ value = 9.81, unit = "m/s^2" }}
[ground]
O = [0, 0, 0]
[bodies.bar]
mass = 2.0
inertia = [0.01, 0.15, 0.15, 0.0, 0.004, 0.0]
cg = [{c[0]}, {c[1]}, {c[2]}]
points = {{ P = [{p[0]}, {p[1]}, {p[2]}] }}
initial = {{ x = {o[0]}, y = {o[1]}, z = {o[2]} }}
[joints.hinge]
type = "revolute"
a = "ground.O"
b = "bar.P"
axis = [0, 0.8253356149096783, 0.5646424733950354]
[gravity]
g = "g"
"""


def _spatial_pendulum(tmp_path, tag, o):
    """A compound pendulum on a hinge tilted 0.6 rad from horizontal, cg (0.4, 0.05, 0) from the pivot,
    a product of inertia; frame origin at ``o`` (pivot coordinates). Returns the cg height history and
    the energy history."""
    cg = np.array([0.4, 0.05, 0.0]) - o
    s = _load(tmp_path, f"spatial_pendulum_{tag}", SPATIAL_PENDULUM.format(tag=tag, c=cg, p=-np.asarray(o), o=o))
    x0 = assemble(s, {})
    T = 2.0
    r = simulate(s, x0, (0.0, T), rtol=1e-10, atol=1e-12, t_eval=np.linspace(0, T, 101))
    assert r.success, r.message
    e = np.column_stack([r[f"e{i}_bar"] for i in range(4)])
    z_cg = np.array([r["z_bar"][k] + (np.asarray(_R(e[k]), float) @ cg)[2] for k in range(len(r))])
    KE = np.array([0.5 * qd @ s.mechanics.mass(x) @ qd for x, qd in zip(r.values, r.qdot)])
    return z_cg, KE + 2.0 * 9.81 * z_cg


def test_spatial_pendulum_energy_and_frame(tmp_path):
    """Frame at the cg and away from pivot and cg: energy conserved, and the same cg height history."""
    z_cg, E_cg = _spatial_pendulum(tmp_path, "cg", np.array([0.4, 0.05, 0.0]))
    z_away, E_away = _spatial_pendulum(tmp_path, "away", np.array([-0.3, 0.2, 0.1]))
    assert np.ptp(z_cg) > 0.1
    for E in (E_cg, E_away):
        assert np.ptp(E) < 1e-7 * 2.0 * 9.81 * 0.4
    np.testing.assert_allclose(z_away, z_cg, atol=1e-7)


def _moved_frames(text: str, offsets: dict[str, tuple[float, float, float]]) -> str:
    """A spatial description whose bars become general bodies with their frame origins moved by
    ``offsets[body]`` (body coordinates, m): ends, points and cg written about the new origin, the
    bar's default inertia written out (as numbers, at the parameters' defaults), and the starting guess
    moved so the design pose is the same. The ``[bodies.*]`` tables (before the first ``[joints.*]``)
    are written anew."""
    import tomllib

    from mechcont.mechanism._expr import float_value, symbol, to_expr

    d = tomllib.loads(text)
    params = {k: (v["value"] if isinstance(v, dict) else v) for k, v in d["parameters"].items()}
    known = {k: symbol(k) for k in params}
    at = {symbol(k): float(v) for k, v in params.items()}

    def num(v) -> float:  # the value at the parameters' defaults, through mechcont's whitelist parser
        return float_value(to_expr(v, "test", known), at)

    def vec(v) -> str:
        return "[" + ", ".join(repr(num(c)) for c in v) + "]"

    out = []
    for name, b in d["bodies"].items():
        o = offsets[name]
        L, m = b["length"], b["mass"]
        pts = {"a": [f"-({L})/2", 0, 0], "b": [f"({L})/2", 0, 0], **b.get("points", {})}
        rot = b.get("initial", {}).get("rotation", [0.0, 0.0, 0.0])
        assert rot[0] == rot[1] == 0
        c, s_ = math.cos(rot[2]), math.sin(rot[2])
        start = (c * o[0] - s_ * o[1], s_ * o[0] + c * o[1], o[2])
        out += [f"[bodies.{name}]", f'mass = "{m}"', f"cg = {vec([-v for v in o])}",
                f"inertia = {vec([f'({m})*(({L})/20)^2/2', f'({m})*({L})^2/12', f'({m})*({L})^2/12'])}",
                f"initial = {{ x = {start[0]!r}, y = {start[1]!r}, z = {start[2]!r}, rotation = {vec(rot)} }}",
                f"[bodies.{name}.points]",
                *(f"{k} = {vec([num(v) - oc for v, oc in zip(p, o)])}" for k, p in pts.items()), ""]
    head, tail = text[:text.index("[bodies.")], text[text.index("[joints."):]
    return head.replace('name = "nose_gear_3d"', 'name = "nose_gear_3d_moved"') + "\n".join(out) + tail


@pytest.mark.slow
def test_spatial_gear_frame_invariance(tmp_path):
    """The spatial nose gear (tests/data/spatial/nose_gear_3d.toml: bars with frames at their cgs) and
    the same gear with every frame moved off its body, out of the plane too, pushed through its unlock
    by an upward force: the same motion of every body (orientations, main-fitting cg) to integrator
    tolerance, through a large swing."""
    from pathlib import Path

    src = Path(__file__).parent / "data" / "spatial" / "nose_gear_3d.toml"
    text = src.read_text()
    offsets = {"1": (0.3, 0.1, -0.2), "2": (-0.5, 0.2, 0.1), "3": (0.9, -0.15, 0.25), "4": (0.2, 0.3, 0.0),
               "5": (-0.1, -0.2, 0.3)}
    runs: list = []
    for tag in ("cgs", "moved"):  # the shipped file itself (its build is shared with test_spatial_planar)
        s = load_model(src) if tag == "cgs" else _load(tmp_path, "nose_gear_3d_moved", _moved_frames(text, offsets))
        # one start pose for both: the lock link held where the first assembly put it
        x0 = assemble(s, {"F": 3000.0, **({"theta4": runs[0]["theta4"][0]} if runs else {})},
                      hold=["theta4"] if runs else ())
        T = 0.3
        r = simulate(s, x0, (0.0, T), rtol=1e-10, atol=1e-12, t_eval=np.linspace(0, T, 31))
        assert r.success, r.message
        runs.append(r)
    a, b = runs
    for body in "12345":
        for i in range(4):
            np.testing.assert_allclose(a[f"e{i}_{body}"], b[f"e{i}_{body}"], atol=1e-7)
    assert np.ptp(a["theta4"]) > 0.5  # the lock links swung through
    e = np.column_stack([b[f"e{i}_3"] for i in range(4)])
    cg_b = np.array([[b[f"{c}3"][k] for c in "xyz"] + np.asarray(_R(e[k]), float) @ (-np.asarray(offsets["3"]))
                     for k in range(len(b))])
    cg_a = np.column_stack([a[f"{c}3"] for c in "xyz"])
    np.testing.assert_allclose(cg_b, cg_a, atol=1e-7)


TUMBLER = """
[mechanism]
name = "tumbler"
dimension = 3
dof = 3
[ground]
O = [0, 0, 0]
[bodies.body]
mass = 2.0
inertia = [1.0, 2.0, 3.0]
[joints.ball]
type = "spherical"
a = "ground.O"
b = "body.origin"
"""


def test_intermediate_axis_flip_period_closed_form(tmp_path):
    """A torque-free body spun about its intermediate axis, slightly off it, flips over periodically
    (the Dzhanibekov effect). With I1 < I2 < I3, energy E and momentum H, H^2 > 2 E I2, the body-frame
    angular velocity has the period T = 4 K(k) / sqrt((I3 - I2)(H^2 - 2 E I1) / (I1 I2 I3)),
    k^2 = (I2 - I1)(2 E I3 - H^2) / ((I3 - I2)(H^2 - 2 E I1)) (Landau & Lifshitz, Mechanics, sec. 37);
    omega_2 changes sign twice a period."""
    from scipy.interpolate import CubicSpline
    from scipy.special import ellipk

    I1, I2, I3 = 1.0, 2.0, 3.0
    w0 = np.array([0.2, 1.5, 0.3])
    E = 0.5 * (I1 * w0[0] ** 2 + I2 * w0[1] ** 2 + I3 * w0[2] ** 2)
    H2 = (I1 * w0[0]) ** 2 + (I2 * w0[1]) ** 2 + (I3 * w0[2]) ** 2
    assert H2 > 2 * E * I2
    k2 = (I2 - I1) * (2 * E * I3 - H2) / ((I3 - I2) * (H2 - 2 * E * I1))
    period = 4 * ellipk(k2) / math.sqrt((I3 - I2) * (H2 - 2 * E * I1) / (I1 * I2 * I3))
    s = _load(tmp_path, "tumbler", TUMBLER)
    x0 = assemble(s, {})
    e0 = np.array([x0[s.index(f"e{i}_body")] for i in range(4)])
    np.testing.assert_allclose(e0, [1, 0, 0, 0], atol=1e-12)  # design pose: body axes = global axes
    ed0 = 0.5 * np.array([[-0, -0, -0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]) @ w0  # edot = 1/2 E^T omega at e = (1, 0, 0, 0)
    T = 1.3 * period
    r = simulate(s, x0, (0.0, T), qdot0={f"e{i}_body": ed0[i] for i in range(4)}, method="DOP853", rtol=1e-10, atol=1e-12,
                 t_eval=np.linspace(0, T, 2001))
    assert r.success, r.message
    names = list(s.mechanics.coordinates)
    e = np.column_stack([r[f"e{i}_body"] for i in range(4)])
    ed = r.qdot[:, [names.index(f"e{i}_body") for i in range(4)]]
    w_body = []
    for a, b in zip(e, ed):  # body-frame angular velocity 2 G edot, G = [-eps, e0 I - [eps]x]
        eps = a[1:]
        G = np.column_stack([-eps, a[0] * np.eye(3) - np.array([[0, -eps[2], eps[1]], [eps[2], 0, -eps[0]],
                                                                 [-eps[1], eps[0], 0]])])
        w_body.append(2 * G @ b)
    w2 = CubicSpline(r.t, np.array(w_body)[:, 1])
    flips = w2.roots(extrapolate=False)
    assert len(flips) >= 2
    np.testing.assert_allclose(np.diff(flips), period / 2, rtol=1e-6)
