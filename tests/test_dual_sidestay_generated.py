"""The dual-sidestay gear generated from its spatial description against the hand-formulated model.

``examples/dual_sidestay.toml`` (rigid bodies, Euler parameters, 63 coordinates) and
:mod:`mechcont.models.dual_sidestay` (natural coordinates, 12 states) are independent
formulations of the same gear: their retraction kinematics and the actuator load by virtual
work must agree. The locked gear (both lock-link pairs held aligned) is over-constrained: it has
no solution with rigid sidestays and a determinate one with a compliant aft attachment.
"""

from pathlib import Path

import numpy as np
import pytest
from numeric_text import assert_text_close

from mechcont.continuation import find_equilibrium
from mechcont.errors import ConvergenceError
from mechcont.mechanism import check_report, parse_description
from mechcont.models.dual_sidestay import actuator_tension, build_dual_sidestay_kinematics, points_at
from mechcont.models.dual_sidestay_description import dual_sidestay_description

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


@pytest.mark.slow
def test_check_of_the_locked_gear_reports_its_redundancy_and_the_compliance_that_resolves_it():
    """Downlocked (lock links welded), each sidestay is a strut: the two over-constrain the fitting's one
    degree of freedom. Rigid, check names one redundant row among the joints of both sidestays and the
    trunnion; with the compliant aft attachment every reaction is determinate."""
    rigid = check_report(parse_description(dual_sidestay_description(locked=True, compliant_aft=False),
                                           "locked_rigid.toml"))
    assert rigid.dof == 0 and len(rigid.redundant) == 1
    joints = set(rigid.redundant[0][1])
    assert {"fwd_A", "fwd_P", "aft_A", "aft_P", "trunnion_fwd"} <= joints
    assert any("over-constrained: 1 redundant constraint(s)" in f for f in rigid.findings)
    compliant = check_report(LOCKED)
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


@pytest.mark.slow
def test_locked_gear_needs_compliance(rigid):
    hold = {"fwd_lock": 0.0, "aft_lock": 0.0}
    with pytest.raises(ConvergenceError):
        find_equilibrium(rigid, hold=hold, free=["F_fwd", "F_aft"])
    compliant = parse_description(EXAMPLE.read_text(), "dual_sidestay.toml").build()
    x = find_equilibrium(compliant, hold=hold, free=["F_fwd", "F_aft"])
    v = compliant.as_dict(x)
    # the aft attachment deflects by reaction / stiffness: its reactions are determinate
    k = v["k_att"]
    R = np.array([v[f"R_aft_A_{c}"] for c in "xyz"])
    assert np.linalg.norm(R) > 0
    assert np.max(np.abs(compliant.residual(x))) < 1e-6
    defl = np.linalg.norm(R) / k
    assert 0 < defl < 0.05   # a real rigging misfit taken up by the attachment (m)
