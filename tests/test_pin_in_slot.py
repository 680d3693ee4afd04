"""The pin-in-slot joint (mechcont.mechanism.joints.pin_in_slot) on a quick-return mechanism.

A crank of radius r turns about O = (0, 0); its pin P = r (cos theta, sin theta) slides in a slot
along a lever pivoted at C = (-d, 0). Closed forms (d > r):

* lever angle psi = atan2(r sin theta, d + r cos theta), pin distance from C
  rho = sqrt(d^2 + r^2 + 2 d r cos theta);
* psi'(theta) = r (r + d cos theta) / rho^2;
* statics by virtual work, moments Mc on the crank and Ml on the lever:
  Mc + Ml psi'(theta) = 0; the lever's moment balance about C gives the slot's reaction on
  the pin (along the slot's left normal) R = Ml / rho.
"""

from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from cli_helpers import make_runner, one_line_error
from derivative_checks import check_derivatives

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.dynamics import assemble, simulate
from mechcont.errors import InputError
from mechcont.mechanism import load_description, parse_description

DATA = Path(__file__).parent / "data" / "quick_return.toml"
R, D, ML = 1.0, 2.0, 10.0


def psi(theta):
    return np.arctan2(R * np.sin(theta), D + R * np.cos(theta))


def rho(theta):
    return np.sqrt(D**2 + R**2 + 2 * D * R * np.cos(theta))


def dpsi(theta):
    return R * (R + D * np.cos(theta)) / rho(theta) ** 2


@pytest.fixture(scope="module")
def system():
    return load_description(DATA).build()


@pytest.fixture(scope="module")
def branch(system):
    x0 = find_equilibrium(system, hold={"theta_crank": 0.5}, free=["Mc"])
    # moments and reactions of order 10 N m and N (the built scales know no force here: no gravity, no spring)
    scales = {n: 10.0 for n in ("Mc", "R_O_x", "R_O_y", "R_C_x", "R_C_y", "R_slot")}
    opts = ContinuationOptions(bounds={"theta_crank": (-2.5, 2.5)}, scales=scales)
    return continuation(system, x0, "Mc", options=opts)


def test_branch_follows_the_closed_form_kinematics_and_virtual_work(branch):
    th = branch["theta_crank"]
    assert th.min() < -2.4 and th.max() > 2.4  # the crank swept most of a turn, through the folds
    assert np.max(np.abs(branch["theta_lever"] - psi(th))) < 1e-10
    assert np.max(np.abs(branch["Mc"] + ML * dpsi(th))) < 1e-10
    assert np.max(np.abs(branch["R_slot"] - ML / rho(th))) < 1e-10


def test_the_fold_is_where_the_lever_ratio_is_extreme(branch):
    # Mc(theta) = -Ml psi'(theta) turns where psi'' = -r d (d^2 - r^2) sin(theta) / rho^4 = 0 (d > r):
    # at theta = 0 (and pi, out of bounds), where psi'(0) = r / (d + r)
    t, r, d = sp.symbols("t r d", positive=True)
    rho2 = d**2 + r**2 + 2 * d * r * sp.cos(t)
    assert sp.simplify(sp.diff(r * (r + d * sp.cos(t)) / rho2, t) + r * d * (d**2 - r**2) * sp.sin(t) / rho2**2) == 0
    (lp,) = branch.special("LP")
    assert abs(lp["theta_crank"]) < 1e-8
    assert lp["Mc"] == pytest.approx(-ML * R / (D + R), abs=1e-10)


@pytest.mark.parametrize("theta", [-2.0, 0.5, 2.9])
def test_the_reduced_form_keeps_the_slot_row_and_the_same_statics(theta):
    s = load_description(DATA).build_reduced()
    assert s.equation_names == ("M_crank", "M_lever", "slot_n")
    v = s.as_dict(find_equilibrium(s, hold={"theta_crank": theta}, free=["Mc"]))
    assert v["theta_lever"] == pytest.approx(psi(theta), abs=1e-10)
    assert v["Mc"] == pytest.approx(-ML * dpsi(theta), abs=1e-10)
    assert v["R_slot"] == pytest.approx(ML / rho(theta), abs=1e-10)


def test_generated_derivatives_match_finite_differences(system):
    check_derivatives(system)


def test_energy_is_conserved_in_free_motion_under_gravity():
    s = load_description(DATA).build(g=9.81, Ml=0.0)
    x0 = assemble(s, {"theta_crank": 0.5}, hold=["theta_crank"])
    r = simulate(s, x0, (0.0, 3.0), rtol=1e-10, atol=1e-12)
    assert r.success
    V = sp.lambdify([v.symbol for v in s.variables], s.potential_energy)
    E = np.array([0.5 * qd @ s.mechanics.mass(x) @ qd + V(*x) for x, qd in zip(r.values, r.qdot)])
    kinetic = max(0.5 * qd @ s.mechanics.mass(x) @ qd for x, qd in zip(r.values, r.qdot))
    assert kinetic > 1.0  # J: the bodies really move
    assert np.max(np.abs(E - E[0])) < 1e-6 * kinetic
    th = np.array([s.as_dict(x)["theta_crank"] for x in r.values])
    lever = np.array([s.as_dict(x)["theta_lever"] for x in r.values])
    assert np.max(np.abs(np.angle(np.exp(1j * (lever - psi(th)))))) < 1e-6  # on the constraint (drift only)


def test_check_continue_and_draw_from_the_command_line(tmp_path):
    run = make_runner()
    r = run("check", DATA)
    assert r.exit_code == 0, r.output
    assert "findings: none" in r.output and "R_slot" in r.output
    out, fig = tmp_path / "b.csv", tmp_path / "b.png"
    r = run("continue", DATA, "--start", "theta_crank=0.5", "--vary", "Mc", "--bounds", "theta_crank=0.45:0.55",
            "--out", out, "--plot", fig)
    assert r.exit_code == 0, r.output
    assert out.exists() and fig.stat().st_size > 0


def test_drawing_shows_the_slot_along_the_lever_and_the_pin_in_it(system):
    from mechcont.outputs.drawing import draw

    x = system.defaults()
    scene = system.scene(x)
    ((name, a, b),) = scene.slots
    v = system.as_dict(x)
    lever = np.array([v["x_lever"], v["y_lever"]])
    u = np.array([np.cos(v["theta_lever"]), np.sin(v["theta_lever"])])
    assert name == "slot"
    assert np.allclose(a, lever - 2.0 * u, atol=1e-12) and np.allclose(b, lever + 2.0 * u, atol=1e-12)
    pin = R * np.array([np.cos(v["theta_crank"]), np.sin(v["theta_crank"])])
    assert any(np.allclose(p, pin, atol=1e-12) for p in scene.pins)
    ax = draw(system, x)
    lines = [ln for ln in ax.lines if ln.get_gid() == "slot"]
    assert len(lines) == 2 and all(np.allclose(ln.get_xydata(), [a, b]) for ln in lines)


BAD = [
    ('slot = ["lever.a", "lever.b"]', 'slot = ["lever.a"]', "joints.slot.slot", "[start, end]"),
    ('slot = ["lever.a", "lever.b"]', 'slot = ["lever.a", "crank.a"]', "joints.slot.slot", "one body"),
    ('slot = ["lever.a", "lever.b"]', 'slot = ["lever.a", "lever.a"]', "joints.slot.slot", "two different points"),
    ('slot = ["lever.a", "lever.b"]', 'slot = ["lever.a", "lever.q"]', "joints.slot.slot", "unknown point 'q'"),
    ('pin = "crank.b"', 'pin = "lever.cg"', "joints.slot", "joins a body to itself"),
    ('pin = "crank.b"\n', "", "joints.slot.pin", "is required"),
    ('type = "pin_in_slot"', 'type = "pin_in_slit"', "joints.slot.type", "pin_in_slot"),
    ('pin = "crank.b"', 'pin = "crank.b"\nangle = 0', "joints.slot", "angle"),
]


@pytest.mark.parametrize("old, new, field, words", BAD)
def test_bad_joint_tables_give_one_line_errors_naming_the_field(old, new, field, words):
    text = DATA.read_text()
    assert old in text
    with pytest.raises(InputError) as err:
        parse_description(text.replace(old, new, 1), "q.toml")
    msg = str(err.value)
    assert field in msg and words in msg and "\n" not in msg


def test_a_slot_of_zero_length_is_refused_naming_the_slot():
    text = DATA.read_text().replace("length = \"L\"", "length = \"L\"\npoints = { s = [\"L/2 - z\", 0] }", 2)
    text = text.replace("[parameters]", "[parameters]\nz = { value = 0.0, unit = \"m\" }")
    text = text.replace('slot = ["lever.a", "lever.b"]', 'slot = ["lever.s", "lever.b"]')
    mech = parse_description(text, "q.toml")
    with pytest.raises(InputError, match=r"joints\.slot\.slot.*slot length"):
        mech.build()


def test_the_cli_refuses_an_unknown_joint_type_listing_the_registered_ones(tmp_path):
    bad = tmp_path / "q.toml"
    bad.write_text(DATA.read_text().replace('type = "pin_in_slot"', 'type = "pin_in_slit"'))
    one_line_error(make_runner()("check", bad), "joints.slot.type", "revolute, slider, prismatic, weld, pin_in_slot")
