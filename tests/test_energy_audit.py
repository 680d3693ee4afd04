"""The energy audit of every history (issue 31, item 4): E_kin + E_pot + E_diss - W_ext - E0 closes to what the
integrator's tolerances explain on every shipped kind of simulation, with its terms checked against truth:

* a conservative model does no external work (``W_ext`` stays at zero: ``V`` agrees with the forces);
* a ramped load's work is ``-int F'(t) y_apex dt`` (its potential ``-F y_apex`` changes in time);
* a constant moment about a spatial hinge does ``M0`` times the angle turned;
* an impact dissipates the kinetic energy it removes; a damper the work done against it;
* and the audit can fail: the same pendulum without its velocity-product forces leaves a residual of
  the order of its energy.

The 63-coordinate dual-sidestay gear's audit is in tests/test_dual_sidestay_generated.py (which builds it).
"""

import math

import numpy as np
import pytest

from mechcont.dynamics import assemble, simulate
from mechcont.dynamics._energy import ENERGY_COLUMNS
from mechcont.dynamics.freefall import freefall
from mechcont.equations import MechanicalModel
from mechcont.errors import InputError
from mechcont.models import load_model, model_from_text
from mechcont.models.nose_gear import build_nose_gear
from mechcont.models.overcentre import build_overcentre

# A bar pinned at a point that is neither its frame origin nor its cg, the cg off the line through both:
# the velocity-product forces then turn the bar (a moment about the pivot), not only load the pin.
OFFSET_PENDULUM = """
[mechanism]
name = "offset_pendulum"
[parameters]
g = { value = 9.81, unit = "m/s^2" }
[ground]
O = [0, 0]
[bodies.bar]
mass = 2.0
length = 1.0
inertia = 0.1
cg = [0.2, 0.15]
points = { p = [-0.3, 0] }
initial = { theta = 0.0 }
[joints.pivot]
type = "revolute"
a = "ground.O"
b = "bar.p"
[gravity]
g = "g"
"""


def closes(r):
    """The balance closes within its bound, and its residual is small against the energy exchanged."""
    b = r.balance
    assert b.closes, b.describe()
    assert b.worst < 1e-6 * b.scale, b.describe()
    for c in ENERGY_COLUMNS:
        assert r.unit(c) == "J" and np.all(np.isfinite(r[c]))
    return b


def test_conservative_pendulum_closes_without_external_work():
    system = model_from_text(OFFSET_PENDULUM, "offset_pendulum.toml")
    r = simulate(system, assemble(system, {}), (0.0, 1.0), rtol=1e-9, atol=1e-12)
    b = closes(r)
    assert b.bound < 1e-5 * b.scale  # a bound that means something (the next test exceeds it)
    assert np.max(r["E_kin"]) > 5.0  # it swings
    assert np.max(np.abs(r["W_ext"])) < 1e-7 and np.max(np.abs(r["E_diss"])) == 0.0
    np.testing.assert_allclose(r["E_kin"] + r["E_pot"], b.E0, atol=1e-7)


def test_a_run_without_the_audit_moves_the_same_and_says_it_has_none():
    """audit=False (a bisection's runs) skips the quadrature only: the same steps and rows, no energy columns,
    and asking for the balance is one clear error."""
    system = model_from_text(OFFSET_PENDULUM, "offset_pendulum.toml")
    x0 = assemble(system, {})
    a = simulate(system, x0, (0.0, 1.0), rtol=1e-9, atol=1e-12)
    b = simulate(system, x0, (0.0, 1.0), rtol=1e-9, atol=1e-12, audit=False)
    assert len(a) == len(b) and a.nfev == b.nfev
    np.testing.assert_allclose(b.values, a.values, rtol=0.0, atol=1e-15)
    assert a.energy and not b.energy
    with pytest.raises(InputError, match="energy: this history has no energy audit"):
        _ = b.balance


def test_rayleigh_damping_is_dissipated():
    # --damping d: the force -d M qdot dissipates d qdot^T M qdot (the part across the joints is taken by them)
    system = model_from_text(OFFSET_PENDULUM, "offset_pendulum.toml")
    r = simulate(system, assemble(system, {}), (0.0, 3.0), rtol=1e-9, atol=1e-12, damping=0.8)
    b = closes(r)
    assert b.E_diss > 1.0 and b.E_diss > b.E_kin and np.all(np.diff(r["E_diss"]) >= 0.0)
    assert np.max(np.abs(r["W_ext"])) < 1e-6


def test_reduced_form_keeps_the_potential_in_its_coordinates():
    # the reduced form (the pin's coordinates eliminated, M = J^T M J) has the same motion and the potential
    # V(q(r)); the four-bar (a closed loop: two angles and a loop constraint left), moved by its crank moment T
    from mechcont.mechanism import parse_description

    text = open("src/mechcont/data/fourbar.toml").read()
    reduced = parse_description(text).build_reduced(T=5.0)
    full = parse_description(text).build(T=5.0)
    assert len(reduced.mechanics.coordinates) < len(full.mechanics.coordinates) and reduced.mechanics.n_constraints
    runs = []
    for model in (reduced, full):
        r = simulate(model, assemble(model, {}), (0.0, 1.0), rtol=1e-9, atol=1e-12)
        closes(r)
        assert np.max(np.abs(r["W_ext"])) < 1e-6 * r.balance.scale
        runs.append(r)
    assert runs[0].balance.scale > 0.1
    np.testing.assert_allclose(runs[0].balance.E_pot, runs[1].balance.E_pot, rtol=1e-6)


def test_the_audit_fails_without_the_inertial_forces(monkeypatch):
    system = model_from_text(OFFSET_PENDULUM, "offset_pendulum.toml")
    monkeypatch.setattr(MechanicalModel, "inertial_forces", lambda self, x, qd: np.zeros(len(qd)))
    r = simulate(system, assemble(system, {}), (0.0, 1.0), rtol=1e-9, atol=1e-12)
    b = r.balance
    assert not b.closes
    assert b.worst > 1.0 and b.worst > 1e5 * b.bound


def test_overcentre_damper_and_ramped_load():
    system = build_overcentre(LU=0.4, c=40.0)
    x0 = assemble(system, {"theta1": 1.0, "theta2": math.pi - 1.0}, hold=["theta1"])
    times = np.linspace(0.0, 2.0, 4001)
    r = simulate(system, x0, (0.0, 2.0), loads={"F": lambda t: 5.0 * t}, rtol=1e-9, atol=1e-12, t_eval=times)
    b = closes(r)
    assert b.E_diss > 1.0
    # the ramp's work: d(-F y_apex)/dt at fixed q, integrated (Simpson on 4001 rows of a smooth history)
    from scipy.integrate import simpson

    L1 = system.variable("L1").value
    y_apex = r["y1"] + L1 / 2 * np.sin(r["theta1"])
    np.testing.assert_allclose(r["W_ext"][-1], -5.0 * simpson(y_apex, x=r.t), rtol=1e-7)
    # the damper's dissipation is c (dl/dt)^2 integrated: positive and growing
    assert np.all(np.diff(r["E_diss"]) >= -1e-12)


def test_nose_gear_with_its_dampers_and_drag():
    gear = build_nose_gear(c=3000.0, c3=200.0, U=60.0, F=-800.0)
    r = simulate(gear, gear.defaults(), (0.0, 0.5), rtol=1e-8, atol=1e-10)
    b = closes(r)
    assert b.E_diss > 1.0 and abs(b.W_ext) > 1.0 and b.E_kin > 1.0
    assert np.ptp(r["theta4"]) > 0.3  # the lock links fold: a real motion
    still = build_nose_gear(c=3000.0, c3=200.0, U=0.0, F=-800.0)  # no airflow: every load in the potential
    r = simulate(still, still.defaults(), (0.0, 0.5), rtol=1e-8, atol=1e-10)
    closes(r)
    assert np.max(np.abs(r["W_ext"])) < 1e-6 * r.balance.scale and r.balance.E_diss > 1.0


def test_freefall_leg_damper_drag_and_plastic_impact():
    system = load_model("examples/freefall_leg.toml")
    h = freefall(system, {"angle": 3.0}, lock="downlock", until=2.0).history
    b = closes(h)
    assert b.E_diss > 1000.0 and b.W_ext < -100.0  # the actuator damper, the drag against the fall
    impact = [ev for ev in h.stop_events if ev.kind == "impact"]
    assert len(impact) == 1
    i = impact[0].row  # the row after the plastic impact: its kinetic energy went into E_diss
    lost = h["E_kin"][i - 1] - h["E_kin"][i]
    assert lost > 1.0
    np.testing.assert_allclose(h["E_diss"][i] - h["E_diss"][i - 1], lost, rtol=1e-12)


def test_compliant_stop_dissipates_in_its_damper():
    text = open("tests/data/bar_drop.toml").read()
    soft = model_from_text(text.replace("restitution = 0.5", 'contact = "compliant"\nstiffness = 2000.0\ndamping = 5.0'),
                           "bar_soft.toml")
    r = simulate(soft, assemble(soft, {"theta_bar": 0.0}, hold=["theta_bar"]), (0.0, 1.5), stops=True,
                 rtol=1e-10, atol=1e-12)
    b = closes(r)
    assert [ev.kind for ev in r.stop_events][:2] == ["contact", "release"]
    assert b.E_diss > 0.5 and abs(b.W_ext) < 1e-6
    undamped = model_from_text(text.replace("restitution = 0.5", 'contact = "compliant"\nstiffness = 2000.0'),
                               "bar_spring.toml")
    r = simulate(undamped, assemble(undamped, {"theta_bar": 0.0}, hold=["theta_bar"]), (0.0, 1.5), stops=True,
                 rtol=1e-10, atol=1e-12)
    b = closes(r)
    assert abs(b.E_diss) < 1e-5  # the spring gives back all it took


def test_spatial_hinge_moment_does_m0_times_the_angle():
    M0 = 1.5
    system = load_model("tests/data/spatial/pendulum_3d.toml", M=M0)
    r = simulate(system, assemble(system, {}), (0.0, 1.0), rtol=1e-9, atol=1e-12)
    b = closes(r)
    beta = system.variable("beta").value
    n = np.array([0.0, math.cos(beta), math.sin(beta)])
    c = np.stack([r["x_bar"], r["y_bar"], r["z_bar"]], axis=1)
    c0 = c[0]
    angle = np.arctan2(np.cross(c0, c) @ n, c @ c0)  # turned about n since the start (less than a turn)
    np.testing.assert_allclose(r["W_ext"], M0 * angle, atol=1e-7)
    assert abs(b.W_ext) > 0.5


def test_cli_prints_the_balance_in_one_line_and_warns_when_it_does_not_close(tmp_path, monkeypatch):
    from cli_helpers import make_runner

    run = make_runner()
    path = tmp_path / "offset_pendulum.toml"
    path.write_text(OFFSET_PENDULUM)
    args = ("simulate", path, "--start", "theta_bar=0", "--until", 1.0, "--rtol", 1e-8, "--no-progress")
    res = run(*args)
    assert res.exit_code == 0, res.output
    lines = [ln for ln in res.stdout.splitlines() if "energy [J]" in ln]
    assert len(lines) == 1 and "residual" in lines[0] and "bound" in lines[0]
    assert "does not close" not in res.stderr
    monkeypatch.setattr(MechanicalModel, "inertial_forces", lambda self, x, qd: np.zeros(len(qd)))
    res = run(*args)
    assert res.exit_code == 0, res.output
    warning = [ln for ln in res.stderr.splitlines() if ln.strip()]
    assert len(warning) == 1 and warning[0].startswith("warning: the energy balance does not close"), res.stderr


def test_freefall_cli_prints_the_balance(tmp_path):
    from cli_helpers import make_runner

    res = make_runner()("freefall", "examples/freefall_leg.toml", "--start", "angle=3.0", "--lock", "downlock",
                        "--until", 2.0)
    assert res.exit_code == 0, res.output
    assert len([ln for ln in res.stdout.splitlines() if ln.startswith("# energy [J]: start")]) == 1
    assert "does not close" not in res.stderr
