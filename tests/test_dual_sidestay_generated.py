"""The dual-sidestay gear generated from its spatial description against the hand-formulated model.

``examples/dual_sidestay.toml`` (rigid bodies, Euler parameters, 63 coordinates) and
:mod:`mechcont.models.dual_sidestay` (natural coordinates, 12 states) are independent
formulations of the same gear: their retraction kinematics and the actuator load by virtual
work must agree. The locked gear (both lock-link pairs held aligned) is over-constrained: it has
no solution with rigid sidestays and a determinate one with a compliant aft attachment. The
downlocked file (lock links welded on their stops) is the unlocked gear resting on both stops.
"""

import tomllib
from pathlib import Path

import numpy as np
import pytest
from numeric_text import assert_text_close

from mechcont.analysis import equilibrium_on_stops
from mechcont.continuation import find_equilibrium
from mechcont.errors import ConvergenceError, InputError
from mechcont.mechanism import check_report, parse_description
from mechcont.models import model_from_text
from mechcont.models.dual_sidestay import actuator_tension, build_dual_sidestay_kinematics, points_at
from mechcont.models.dual_sidestay_description import STOP_SINE, dual_sidestay_description
from mechcont.models.dual_sidestay_geometry import DEFAULT_GEOMETRY

EXAMPLE = Path(__file__).parent.parent / "examples" / "dual_sidestay.toml"
LOCKED = EXAMPLE.with_name("dual_sidestay_locked.toml")


def test_example_files_are_the_generated_descriptions():
    """The shipped files are what the generator writes on this machine: the same words, and every number
    within one unit of the 12th significant digit the generator rounds to (absolute 1e-12 for values that
    are zero in exact arithmetic: the hard points are metre-scale), whatever the CPU and BLAS."""
    assert_text_close(EXAMPLE.read_text(), dual_sidestay_description(), rtol=1e-11, atol=1e-12)
    assert_text_close(LOCKED.read_text(), dual_sidestay_description(locked=True), rtol=1e-11, atol=1e-12)


def test_text_comparison_sees_a_changed_number_or_word():
    text = dual_sidestay_description()
    with pytest.raises(AssertionError):
        assert_text_close(text.replace("mass = 45.0", "mass = 45.000001"), text, rtol=1e-11, atol=1e-12)
    with pytest.raises(AssertionError):
        assert_text_close(text.replace('type = "revolute"', 'type = "spherical"', 1), text, rtol=1e-11, atol=1e-12)


def test_locked_file_welds_the_lock_links_on_their_stops():
    """Read from the shipped file's numbers: each welded pair's condition points (K, J on link 1, P on link 2)
    make the sine ``<side>_lock`` = +STOP_SINE (the overcentre side, where the unlocked gear's stop holds
    it), not the design pose's -0.05, and link 2 keeps its length (it is only turned about J). The points
    are rounded to 12 significant digits (<= 5e-13 m on these sub-metre coordinates, over arms of 0.3 m and
    more): the sine to 1e-10, the length to 1e-11 m."""
    locked, unlocked = tomllib.loads(LOCKED.read_text()), tomllib.loads(EXAMPLE.read_text())
    for side in ("fwd", "aft"):
        cond = locked["conditions"][f"{side}_lock"]
        assert cond["points"] == [f"{side}_link1.a", f"{side}_link1.b", f"{side}_link2.b"]
        assert [locked["joints"][f"{side}_{j}"]["type"] for j in "JP"] == ["weld", "inline"]
        K, J = (np.array(locked["bodies"][f"{side}_link1"]["points"][k]) for k in "ab")
        P = np.array(locked["bodies"][f"{side}_link2"]["points"]["b"])
        n = np.array(cond["normal"])
        sine = np.cross(J - K, P - K) @ n / (np.linalg.norm(J - K) * np.linalg.norm(P - K) * np.linalg.norm(n))
        assert sine == pytest.approx(STOP_SINE, abs=1e-10)
        a, b = (np.array(unlocked["bodies"][f"{side}_link2"]["points"][k]) for k in "ab")
        assert np.linalg.norm(P - J) == pytest.approx(np.linalg.norm(b - a), abs=1e-11)


@pytest.fixture(scope="module")
def locked_report():
    """The check of the downlocked file; its model (``.system``, built as ``Mechanism.build`` builds it: the
    file checks clean) also serves the comparison with the unlocked gear, one build of it for the file."""
    return check_report(LOCKED)


@pytest.mark.slow
def test_check_of_the_locked_gear_reports_its_misfit_and_the_compliance_that_resolves_it(locked_report):
    """Downlocked (lock links welded on their stops), each sidestay is a strut: the two over-constrain the
    fitting's one degree of freedom and, rigid, disagree on where it stands (a few micrometres), so the
    rigid gear cannot be assembled: one line names the misfit and the fix, a stiffness. With the compliant
    aft attachment every reaction is determinate."""
    with pytest.raises(InputError, match="the rigid closure cannot be assembled: misfit .* stiffness"):
        check_report(parse_description(dual_sidestay_description(locked=True, compliant_aft=False),
                                       "locked_rigid.toml"))
    compliant = locked_report
    assert compliant.ok and compliant.dof == 0 and not compliant.redundant
    assert [q.name for q in compliant.compliant] == ["aft_A_x", "aft_A_y", "aft_A_z"]
    assert all("stiffness 5e+07 N/m" in q.description for q in compliant.compliant)


@pytest.fixture(scope="module")
def rigid():
    return parse_description(dual_sidestay_description(compliant_aft=False), "dual_sidestay_rigid.toml").build()


@pytest.fixture(scope="module")
def hand():
    return build_dual_sidestay_kinematics()


def _generated_points(system, x):
    """Every named point of the generated gear at ``x`` (m), from its drawing scene."""
    return {name: p for name, p in system.scene(x).points}


def test_rigid_gear_has_one_degree_of_freedom_and_no_redundancy(rigid):
    assert rigid.dof.dof == 1 and not rigid.dropped_constraints
    assert len(rigid.mechanics.coordinates) == 63


@pytest.mark.parametrize("theta", [0.2, 0.7, 1.2])
def test_retraction_kinematics_and_actuator_load_equal_the_hand_model(rigid, hand, theta):
    # lock links (nearly) massless and no lock springs: the hand model's loads
    values = {"m_link1": 1e-9, "m_link2": 1e-9, "k_lock": 0.0}
    x = find_equilibrium(rigid, values=values, hold={"theta": theta}, free=["F_act"])
    pts = _generated_points(rigid, x)
    # the generated knees and lock-link joints solve the hand model's twelve equations at theta
    # (the lock-link joint may sit on either side of its K-P line: both are solutions)
    named = {f"{side}_{pt}_{c}": pts[f"{side}_{body}.b"][i] for side in ("fwd", "aft")
             for pt, body in (("K", "upper"), ("J", "link1")) for i, c in enumerate("xyz")}
    xh = hand.vector({**named, "theta": theta}, base=hand.defaults())
    assert np.max(np.abs(hand.residual(xh))) < 1e-9
    ph = points_at(hand, xh)
    for side in ("fwd", "aft"):
        assert np.allclose(pts[f"fitting.B_{side}"], ph[f"{side}_B"], atol=1e-9)
        assert np.allclose(pts[f"fitting.P_{side}"], ph[f"{side}_P"], atol=1e-9)
    assert np.allclose(pts["fitting.axle"], ph["axle"], atol=1e-9)
    # the actuator tension holding the gear against gravity: virtual work in the hand model
    assert rigid.as_dict(x)["F_act"] == pytest.approx(actuator_tension(hand, xh), rel=1e-8)


@pytest.fixture(scope="module")
def compliant():
    # parse_description(text).build() through the disk cache: the entry load_model(EXAMPLE) uses (other test
    # files build this 63-coordinate gear too; the suite's session shares one cache)
    return model_from_text(EXAMPLE.read_text(), "dual_sidestay.toml")


@pytest.mark.slow
def test_locked_gear_needs_compliance(rigid, compliant):
    hold = {"fwd_lock": 0.0, "aft_lock": 0.0}
    with pytest.raises(ConvergenceError):
        find_equilibrium(rigid, hold=hold, free=["F_fwd", "F_aft"])
    x = find_equilibrium(compliant, hold=hold, free=["F_fwd", "F_aft"])
    v = compliant.as_dict(x)
    # the aft attachment deflects by reaction / stiffness: its reactions are determinate
    k = v["k_att"]
    R = np.array([v[f"R_aft_A_{c}"] for c in "xyz"])
    assert np.linalg.norm(R) > 0
    assert np.max(np.abs(compliant.residual(x))) < 1e-6
    defl = np.linalg.norm(R) / k
    assert 0 < defl < 0.05   # a real rigging misfit taken up by the attachment (m)


@pytest.mark.slow
def test_locked_file_is_the_unlocked_gear_resting_on_both_stops(compliant, locked_report):
    """The downlocked file's equilibrium against the unlocked gear's with both stops in contact (reactions
    >= 0), the two independent descriptions of one state. With massless lock links they model the same
    thing but for one second-order detail: the unlocked link 2 keeps |J - P| = L5 with P a distance d out of
    the fold plane, the welded one keeps P's in-plane position (|J - P'| = L5 at d = 0), so the sidestay's
    strut differs by d^2 / (2 L5); at the locked pose d <= 1.2e-5 m (measured here), under 2.2e-10 m, which
    moves the retraction angle by that over the metre-scale levers and the aft attachment reaction by
    k_att times that, 0.011 N. Tolerances: 1e-9 rad and 0.05 N (1 nm of attachment deflection). With the
    links' mass (the default) the joints differ in earnest: the unlocked pair's spherical joint at P carries
    half of link 2's weight along the fold-plane normal n, which the locked pair's inline joint (free along
    n) cannot, so that force reaches the airframe through K instead."""
    massless = {"m_link1": 1e-9, "m_link2": 1e-9}
    xu, contact = equilibrium_on_stops(compliant, compliant.defaults(), values=massless,
                                       contact=["fwd_stop", "aft_stop"])
    u = compliant.as_dict(xu)
    assert sorted(contact) == ["aft_stop", "fwd_stop"] and u["R_fwd_stop"] > 0 and u["R_aft_stop"] > 0
    assert locked_report.ok  # no findings: its model is Mechanism.build()'s, built on the first try
    locked = locked_report.system
    xl = find_equilibrium(locked, values=massless)
    v = locked.as_dict(xl)
    assert np.max(np.abs(locked.residual(xl))) < 1e-6
    for side in ("fwd", "aft"):
        assert u[f"{side}_lock"] == pytest.approx(STOP_SINE, abs=1e-12)
        assert v[f"{side}_lock"] == pytest.approx(STOP_SINE, abs=1e-10)   # the weld, read from rounded points
    pts = _generated_points(compliant, xu)
    geo = {st.name: st for st in (DEFAULT_GEOMETRY.forward, DEFAULT_GEOMETRY.aft)}
    d = max(abs((pts[f"fitting.P_{s}"] - pts[f"{s}_link1.a"]) @ geo[s].normal) for s in geo)
    assert d < 1.2e-5
    assert v["theta"] == pytest.approx(u["theta"], abs=1e-9)
    assert v["theta"] < -1e-4     # locked, the gear stands a few thousandths of a degree off its design pose
    R_u, R_l = (np.array([w[f"R_aft_A_{c}"] for c in "xyz"]) for w in (u, v))
    assert np.linalg.norm(R_u) > 2000.0   # the locked-in load of the two struts' misfit
    assert np.linalg.norm(R_l - R_u) < 0.05


def test_drawing_of_the_generated_gear_names_its_bodies_readably(compliant):
    """Issue 25: the generated gear (nine bodies, 42 named points) drawn with its bodies named, no two labels
    overlapping, all inside the figure, type >= 9 pt; with every point named, still no overlap."""
    from figure_checks import check_figure, check_labels, smallest_font

    from mechcont.outputs.drawing3d import draw3d

    x = compliant.defaults()
    for points in (False, True):
        axes = draw3d(compliant, x, label_points=points)
        fig = axes["front"].figure
        check_figure(fig, "generated gear")
        check_labels(fig, "generated gear")
        assert smallest_font(fig) >= 9
        gids = [t.get_gid() or "" for t in axes["top"].texts]
        assert sum(g.startswith("body:") for g in gids) == 9
        assert any(g.startswith("point:") for g in gids) == points


@pytest.mark.slow
def test_locked_gear_starts_a_simulation_from_its_static_pose(locked_report):
    """Issue 31, item 7. The downlocked gear (no degree of freedom: the two struts over-constrain the fitting and
    disagree by a rigging misfit, which the compliant aft attachment takes up) assembled for a time simulation
    is its static equilibrium, the one Newton finds on the static equations, and released it stays at rest;
    the kinematic assembly leaves the attachment where the misfit put it, a millimetre from that."""
    from mechcont.dynamics import ConstrainedDynamics, assemble

    locked = locked_report.system
    x = assemble(locked, locked.defaults())
    xe = find_equilibrium(locked, guess=x)
    q = [locked.index(c) for c in locked.mechanics.coordinates]
    assert np.max(np.abs(x[q] - xe[q])) < 1e-12
    dyn = ConstrainedDynamics(locked, x, baumgarte=None)
    assert np.max(np.abs(dyn.acceleration(0.0, x[dyn.q_index], np.zeros(dyn.nq)))) < 1e-8
    kinematic = assemble(locked, locked.defaults(), kinematic=True)
    assert np.max(np.abs(kinematic[q] - xe[q])) > 1e-4


def test_energy_audit_closes_as_the_gear_settles_on_its_stops(compliant):
    """Issue 31: the gear released at rest in its described pose settles onto both lock stops (impacts, the
    compliant attachment's damping) in 0.05 s; its energy balance closes to the tolerance's bound."""
    from mechcont.dynamics import simulate

    r = simulate(compliant, compliant.defaults(), (0.0, 0.05), stops=True, rtol=1e-8, atol=1e-10)
    b = r.balance
    assert b.closes and b.worst < 1e-6 * b.scale, b.describe()
    assert b.E_diss > 1.0 and abs(b.W_ext) < 1e-5
    assert {ev.stop for ev in r.stop_events if ev.kind == "impact"} == {"fwd_stop", "aft_stop"}
