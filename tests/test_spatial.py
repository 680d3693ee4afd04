"""Spatial mechanisms against truth: a Bennett linkage (over-constrained and mobile), a compound
pendulum on a tilted hinge (closed-form equilibrium and frequency, and time simulation), and a
door on two hinges (statically indeterminate when rigid; determinate, as the closed form of the
split of its gravity moment, with compliant hinges; a misaligned hinge's misfit)."""

import math
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.dynamics import simulate
from mechcont.errors import InputError
from mechcont.mechanism import assemble, check_report, load, parse_description
from tests.derivative_checks import check_derivatives

DATA = Path(__file__).parent / "data" / "spatial"


def _text(name: str) -> str:
    return (DATA / name).read_text()


# -- Bennett linkage ---------------------------------------------------------------------------
@pytest.fixture(scope="module")
def bennett():
    return load(DATA / "bennett.toml")


def test_bennett_rigid_is_refused_naming_its_joints_and_the_fix():
    text = _text("bennett.toml").replace('redundant = "drop"', "")
    with pytest.raises(InputError) as err:
        parse_description(text, "bennett.toml").build()
    msg = str(err.value)
    assert "over-constrained: 3 redundant constraint(s) among joints" in msg
    assert all(j in msg for j in ("A", "B", "C", "D")) and "norm_" not in msg
    assert "stiffness" in msg and 'redundant = "drop"' in msg


def test_bennett_has_mobility_one_and_three_redundant_rows(bennett):
    # 3 bodies x 7 coordinates; 4 revolutes x 5 rows + 3 normalisation rows = 23 rows of rank 20
    assert bennett.dof.dof == 1 and bennett.dof.rank == 20
    assert len(bennett.dropped_constraints) == 3


def test_bennett_branch_satisfies_every_constraint(bennett):
    x0 = assemble(bennett, hold={"crank": 0.0}, free=["M"])
    b = continuation(bennett, x0, "crank", free=["M"],
                     options=ContinuationOptions(bounds={"crank": (-2.5, 2.5)}, max_steps=400))
    assert b.success and len(b.values) > 50
    assert np.ptp(b["crank"]) > 2.0  # the linkage really moves
    for row in b.values:
        assert np.max(np.abs(bennett.mechanics.phi(row))) < 1e-10
        assert bennett.dropped_residual(row) < 1e-10   # the dropped rows stay implied: true mobility


def test_bennett_time_simulation_keeps_its_energy_with_minimum_norm_reactions(bennett):
    """Issue 31: the over-constrained linkage (three redundant rigid rows, all kept by the mechanics) falls
    under gravity conserving its energy (the audit); its reactions are the minimum-norm multipliers, reported
    as such: orthogonal to every self-stress (the left null space of Phi_q)."""
    from mechcont.dynamics import assemble as assemble_dynamics

    r = simulate(bennett, assemble_dynamics(bennett, {}), (0.0, 0.3), rtol=1e-8, atol=1e-10)
    b = r.balance
    assert b.closes and b.worst < 1e-9 * b.scale and b.E_kin > 0.1, b.describe()
    assert r.indeterminate_rows == len(r) and r.nfev < 5000
    mech = bennett.mechanics
    names = bennett.reaction_names[:mech.n_constraints]
    for i in (0, len(r) // 2, len(r) - 1):
        x = r.values[i]
        lam = np.array([x[bennett.index(n)] for n in names])
        U, sv, _ = np.linalg.svd(mech.phi_q(x))
        self_stress = U[:, int(np.count_nonzero(sv > 1e-8 * sv[0])):]
        assert self_stress.shape[1] == 3
        assert np.max(np.abs(self_stress.T @ lam)) < 1e-6 * np.max(np.abs(lam))


def test_bennett_derivatives_match_finite_differences(bennett):
    check_derivatives(bennett)


# -- compound pendulum on a tilted hinge -------------------------------------------------------
@pytest.fixture(scope="module")
def pendulum():
    return load(DATA / "pendulum_3d.toml")


def _closed_form(v):
    return v["m"] * v["g"] * math.cos(v["beta"]) * v["L"] / 2 / (v["It"] + v["m"] * v["L"] ** 2 / 4)


@pytest.mark.parametrize("beta", [0.0, 0.6, 1.2])
def test_pendulum_hangs_below_the_hinge_and_its_frequency_is_the_closed_form(pendulum, beta):
    x = find_equilibrium(pendulum, values={"beta": beta})
    v = pendulum.as_dict(x)
    # the CG hangs at L/2 from the hinge along gravity's component normal to the axis
    n = np.array([0.0, math.cos(beta), math.sin(beta)])
    down = np.array([0.0, 0.0, -1.0]) - (-math.sin(beta)) * n
    down /= np.linalg.norm(down)
    assert np.allclose([v["x_bar"], v["y_bar"], v["z_bar"]], v["L"] / 2 * down, atol=1e-12)
    mech = pendulum.mechanics
    st = mech.stability(x)
    assert st.stable
    Z = mech.allowed_motions(x)
    assert Z.shape[1] == 1
    omega2 = scipy.linalg.eigvals(Z.T @ mech.tangent_stiffness(x) @ Z, Z.T @ mech.mass(x) @ Z).real
    assert omega2[0] == pytest.approx(_closed_form(v), rel=1e-10)
    # the hinge carries the weight: vertical reaction m g, no horizontal force
    assert v["R_hinge_z"] == pytest.approx(v["m"] * v["g"], rel=1e-12)
    assert abs(v["R_hinge_x"]) + abs(v["R_hinge_y"]) < 1e-9


def test_pendulum_time_simulation_oscillates_at_the_closed_form_frequency(pendulum):
    x = find_equilibrium(pendulum)
    v = pendulum.as_dict(x)
    omega = math.sqrt(_closed_form(v))
    # start turned by 0.01 rad about the hinge axis (angular velocity kick instead: at rest it is
    # the same small oscillation), integrate three periods
    Z = pendulum.mechanics.allowed_motions(x)[:, 0]
    qdot = 0.01 * omega * Z / np.sqrt(Z @ pendulum.mechanics.mass(x) @ Z) * 1.0
    T = 2 * math.pi / omega
    res = simulate(pendulum, x, (0.0, 3 * T), qdot0=qdot, rtol=1e-10, atol=1e-12,
                   t_eval=np.linspace(0.0, 3 * T, 3001))
    y = res.y[pendulum.index("x_bar")] if hasattr(res, "y") else res["x_bar"]
    t = res.t
    s = y - y.mean()
    ups = [t[i] - s[i] * (t[i + 1] - t[i]) / (s[i + 1] - s[i]) for i in range(len(s) - 1) if s[i] < 0 <= s[i + 1]]
    assert len(ups) >= 2
    assert np.mean(np.diff(ups)) == pytest.approx(T, rel=1e-4)


def test_pendulum_derivatives_match_finite_differences(pendulum):
    check_derivatives(pendulum)


# -- a door on two hinges -----------------------------------------------------------------------
def _compliant_door(misalign: float = 0.0):
    text = _text("door_3d.toml").replace('''[joints.lower]
type = "revolute"
a = "ground.low"
b = "door.low"
axis = [0, 0, 1]''', '''[joints.lower]
type = "revolute"
a = "ground.low"
b = "door.low"
axis = [0, 0, 1]
rotational_stiffness = "kr"''').replace('''[joints.upper]
type = "revolute"''', '''[joints.upper]
type = "spherical"
stiffness = "k"''').replace('axis = [0, 0, 1]\n\n[gravity]', '\n[gravity]')
    return parse_description(text, "door_compliant.toml").build(misalign=misalign)


def test_rigid_door_is_statically_indeterminate():
    with pytest.raises(InputError) as err:
        load(DATA / "door_3d.toml")
    msg = str(err.value)
    assert "5 redundant constraint(s) among joints upper, lower" in msg
    assert "R_upper_x" in msg and "joints.NAME.stiffness" in msg


def test_misaligned_rigid_hinges_report_their_misfit():
    with pytest.raises(InputError) as err:
        load(DATA / "door_3d.toml", misalign=0.002)
    msg = str(err.value)
    assert "cannot be assembled: misfit" in msg and "stiffness" in msg
    misfit = float(msg.split("misfit (m or rad, least squares) ")[1].split()[1].rstrip(","))
    assert 1e-4 < misfit < 0.002 + 1e-9


def test_misfit_names_joints_only():
    """The closest configuration's rounding in a normalisation row is not reported as a joint's misfit."""
    with pytest.raises(InputError) as err:
        load(DATA / "door_3d.toml", misalign=0.002)
    assert "norm_" not in str(err.value) and "upper" in str(err.value) and "lower" in str(err.value)


@pytest.mark.parametrize("misalign", [0.0, 0.002])
def test_compliant_hinges_make_the_reactions_determinate(misalign):
    door = _compliant_door(misalign)
    x = find_equilibrium(door, hold={"swing": 0.3}, free=["M"], guess=door.defaults())
    v = door.as_dict(x)
    mga = v["m"] * v["g"] * v["a"]
    h, k, kr = v["h"], v["k"], v["kr"]
    # the door swung by 0.3 rad about z; in that pose, with d = (cos 0.3, sin 0.3, 0) the CG's
    # direction from the hinge line, small tilts phi (in the plane of z and d) and psi (normal to it):
    # m g a + k h (delta c) = (kr + k h^2) phi and k h (delta s) = (kr + k h^2) psi
    c, s = math.cos(0.3), math.sin(0.3)
    phi = (mga + k * h * misalign * c) / (kr + k * h ** 2)
    psi = k * h * misalign * s / (kr + k * h ** 2)
    # holding the swing needs no moment but for second-order terms (the prestressed hinge's force
    # acting on the tilted door: k delta h psi ~ 2e-4 m g a with the misalignment)
    assert abs(v["M"]) <= (1e-9 if misalign == 0 else 1e-3 * mga)
    assert c * v["R_upper_x"] + s * v["R_upper_y"] == pytest.approx(k * (misalign * c - h * phi), rel=1e-5, abs=1e-6)
    assert -s * v["R_upper_x"] + c * v["R_upper_y"] == pytest.approx(-k * (misalign * s - h * psi), rel=1e-5,
                                                                        abs=1e-6)
    assert math.hypot(v["T_lower_1"], v["T_lower_2"]) == pytest.approx(kr * math.hypot(phi, psi), rel=1e-5)
    # the whole door balances: horizontal reactions cancel, vertical ones carry the weight
    assert v["R_lower_x"] + v["R_upper_x"] == pytest.approx(0.0, abs=1e-6)
    assert v["R_lower_z"] + v["R_upper_z"] == pytest.approx(v["m"] * v["g"], rel=1e-9)
    assert door.mechanics.stability(x).stable
    check_derivatives(door)


def test_check_reports_dof_redundancy_and_compliance():
    rep = check_report(DATA / "bennett.toml")
    assert rep.dof == 1 and len(rep.redundant) == 3
    text = rep.to_text()
    assert "redundant constraints: 3 row(s) dropped" in text and "norm_" not in text.split("loop closure")[0]
    door = check_report(DATA / "door_3d.toml")
    assert any("over-constrained" in f for f in door.findings)


def test_custom_load_equal_to_gravity_gives_the_same_equilibrium_and_derivatives(pendulum):
    """A custom load (fz = -m g at the CG, a moment expression in the coordinates that vanishes at
    rest) in place of gravity: same equilibrium, reactions and stiffness; every derivative exact."""
    text = _text("pendulum_3d.toml").replace('[gravity]\ng = "g"', """[loads.weight]
type = "custom"
at = "bar.cg"
fz = "-m*g"
my = "0.2*M*cos(beta)"
""")
    custom = parse_description(text, "pendulum_custom.toml").build()
    x = find_equilibrium(custom, guess=custom.vector(pendulum.as_dict(find_equilibrium(pendulum))))
    xg = find_equilibrium(pendulum)
    for name in ("x_bar", "y_bar", "z_bar", "R_hinge_z", "T_hinge_1"):
        assert custom.as_dict(x)[name] == pytest.approx(pendulum.as_dict(xg)[name], abs=1e-10)
    check_derivatives(custom)


def test_default_inertia_does_not_depend_on_where_the_frame_origin_is():
    """The design-pose conventions promise that points in aircraft coordinates (origin at the global
    origin) and points about the body's own origin describe the same body: the default inertia too."""
    from mechcont.mechanism.spatial._kinematics import SpatialKinematics

    def inertia(points: str, cg: str):
        text = (f'[mechanism]\ndimension = 3\ndof = 3\n[ground]\nO = [0, 0, 0]\n[bodies.link]\nmass = 2\n'
                f'cg = {cg}\npoints = {points}\n[joints.J]\ntype = "spherical"\na = "ground.O"\nb = "link.p"\n')
        mech = parse_description(text, "link.toml")
        return np.array(SpatialKinematics(mech).inertia_tensor(mech.bodies[0]), dtype=float)

    far = inertia("{ p = [3, -1, 2], q = [3.4, -1, 2.3] }", "[3.2, -1, 2.15]")
    own = inertia("{ p = [0, 0, 0], q = [0.4, 0, 0.3] }", "[0.2, 0, 0.15]")
    np.testing.assert_allclose(far, own, rtol=1e-14)
    np.testing.assert_allclose(own, np.eye(3) * 2 / 5 * 2 * 0.25 ** 2, rtol=1e-14)   # r = |q - p| / 2


def test_check_of_a_compliant_mechanism_reports_a_true_equilibrium():
    """The assembly closes compliant rows as if rigid; where they carry a reaction that is no
    equilibrium yet (Phi - lambda/k != 0): check must solve on, and not call the compliant joint
    closed by a reduced form (a spatial mechanism has none)."""
    text = _text("door_3d.toml").replace('b = "door.high"\naxis = [0, 0, 1]',
                                         'b = "door.high"\naxis = [0, 0, 1]\nstiffness = "k"\n'
                                         'rotational_stiffness = "kr"')
    rep = check_report(parse_description(text, "door_compliant.toml"))
    assert rep.ok and not rep.redundant and rep.eliminated_joints == ()
    assert rep.x_equilibrium is not None
    assert np.max(np.abs(rep.system.residual(rep.x_equilibrium))) < 1e-8
    assert rep.imbalance.name.startswith("upper_") and rep.imbalance.unit in ("m", "rad")
    text = rep.to_text()
    assert "closed exactly by the reduced form" not in text and "compliant joint rows" in text
    assert "the assembled configuration is not one" in text


def test_spatial_model_has_declared_fields_and_compiles_once_per_structure():
    """A spatial build is a typed Model (nothing attached afterwards, pickles whole); a build at other
    values reuses the generated structure and equals a fresh build."""
    import dataclasses
    import pickle

    from mechcont.equations import Model
    from mechcont.mechanism import load_description

    mech = load_description(DATA / "pendulum_3d.toml")
    a = mech.build()
    assert type(a) is Model and set(vars(a)) <= {f.name for f in dataclasses.fields(Model)}
    with pytest.raises(AttributeError):
        a.something = 1
    b = mech.build(beta=1.0)   # same structure: no new generation
    assert mech._generated["spatial"].variants[()].model is not None
    fresh = load_description(DATA / "pendulum_3d.toml").build(beta=1.0)
    assert np.array_equal(b.defaults(), fresh.defaults())
    xb, xf = find_equilibrium(b), find_equilibrium(fresh)
    assert np.allclose(xb, xf, atol=1e-12)
    c = pickle.loads(pickle.dumps(b))
    assert np.array_equal(c.residual(xb), b.residual(xb))
    assert [p.tobytes() for _, p in c.scene(xb).bars] == [p.tobytes() for _, p in b.scene(xb).bars]


def test_messages_name_every_spatial_joint_type_and_the_spatial_collinear_sign():
    from mechcont.mechanism._description import Revolute
    from mechcont.mechanism.spatial import JOINT_TYPES, SpatialBody, SpatialMechanism

    with pytest.raises(InputError) as err:
        SpatialMechanism(name="m", parameters=[], bodies=[SpatialBody("b", 1.0)],
                         joints=[Revolute("J", "ground.O", "b.origin")], ground={"O": (0, 0, 0)})
    assert all(kind in str(err.value) for kind in JOINT_TYPES)
    text = _text("pendulum_3d.toml") + ('\n[conditions]\nc = { type = "collinear", points = ["ground.O", "bar.cg", '
                                        '"bar.b"], normal = [0, 1, 0] }\n')
    system = parse_description(text, "pendulum_c.toml").build()
    assert "right-handed about the normal" in system.variable("c").description


@pytest.mark.parametrize("kind", ["spherical", "inline"])
def test_rotational_stiffness_on_a_joint_without_rotational_rows_is_refused(kind):
    text = (DATA / "pendulum_3d.toml").read_text().replace('type = "revolute"', f'type = "{kind}"').replace(
        'axis = [0, "cos(beta)", "sin(beta)"]\n\n[gravity]',
        ('axis = [0, "cos(beta)", "sin(beta)"]\n' if kind == "inline" else "") + 'rotational_stiffness = 1e4\n\n[gravity]')
    with pytest.raises(InputError) as err:
        parse_description(text, "p.toml")
    msg = str(err.value)
    assert "joints.hinge.rotational_stiffness" in msg and f"a {kind} joint leaves the rotation free" in msg
    assert "revolute, universal, cylindrical, prismatic, weld" in msg
