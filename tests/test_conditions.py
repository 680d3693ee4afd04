"""Conditions: named relations of the configuration as extra state columns, checked by hand geometry.

The shipped overcentre description gains four conditions. In the symmetric pose (L1 = L2 = L,
bar 1 at angle theta from the ground pin O, slider end S = (2 L cos theta, 0)):

* ``aligned``, collinear O, apex, S: cross(apex - O, S - O) / (|apex - O| |S - O|) = -sin(theta);
* ``apex_y`` = "y1 + L1/2*sin(theta1)" = L sin(theta);
* ``rel``, angle of bar 2 relative to bar 1: theta2 - theta1 = pi - 2 theta;
* ``gap``, distance O - S: 2 L cos(theta).
"""

import math

import numpy as np
import pytest
from derivative_checks import check_derivatives

from mechcont.continuation import ContinuationOptions, ValueEvent, continuation, find_equilibrium
from mechcont.errors import InputError
from mechcont.mechanism import find_description, parse_description
from mechcont.models.overcentre import symmetric_force

OVERCENTRE = find_description("overcentre").read_text()
CONDITIONS = '''
[conditions]
aligned = {type = "collinear", points = ["1.a", "1.b", "2.a"]}
apex_y = "y1 + L1/2*sin(theta1)"
rel = {type = "angle", bodies = ["1", "2"], description = "bar 2 relative to bar 1"}
gap = {type = "distance", points = ["ground.O", "2.a"], target = 2.5}
'''
TEXT = OVERCENTRE + CONDITIONS
P = dict(L=1.5, m1=1.0, m2=1.0, g=9.81, k=127.0, LU=0.4)


@pytest.fixture(scope="module", params=[False, True], ids=["full", "reduced"])
def system(request):
    mech = parse_description(TEXT, "oc.toml")
    return mech.build_reduced() if request.param else mech.build()


def test_condition_columns_follow_the_geometry_along_a_branch(system):
    assert system.state_names[-4:] == ("aligned", "apex_y", "rel", "gap")
    assert system.equation_names[-4:] == ("cond_aligned", "cond_apex_y", "cond_rel", "cond_gap")
    assert [system.variable(n).unit for n in ("aligned", "apex_y", "rel", "gap")] == ["", "", "rad", "m"]
    assert system.conditions == {"aligned": 0.0, "apex_y": 0.0, "rel": 0.0, "gap": 2.5}
    x0 = find_equilibrium(system, hold={"theta1": 0.5}, free=["F"])
    br = continuation(system, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}))
    assert br.success and len(br) > 20
    th = br["theta1"]
    assert np.allclose(br["aligned"], -np.sin(th), atol=1e-12, rtol=0)
    assert np.allclose(br["apex_y"], 1.5 * np.sin(th), atol=1e-12, rtol=0)
    assert np.allclose(br["rel"], np.pi - 2 * th, atol=1e-12, rtol=0)
    assert np.allclose(br["gap"], 3.0 * np.cos(th), atol=1e-12, rtol=0)


def test_conditions_leave_the_mechanics_and_stability_alone(system):
    plain = parse_description(OVERCENTRE, "plain.toml")
    plain = plain.build_reduced() if system.name.endswith("_reduced") else plain.build()
    mech = system.mechanics
    assert mech.coordinates == plain.mechanics.coordinates
    assert not set(system.conditions) & set(mech.coordinates)
    assert len(mech.constraints) == len(plain.mechanics.constraints)
    for th in (-1.0, -0.5, 0.3, 0.95, 1.1):
        x = find_equilibrium(system, hold={"theta1": th}, free=["F"])
        y = find_equilibrium(plain, hold={"theta1": th}, free=["F"])
        assert x[system.index("F")] == pytest.approx(y[plain.index("F")], rel=1e-12)
        a, b = mech.stability(x), plain.mechanics.stability(y)
        assert a.n_unstable == b.n_unstable and np.allclose(a.eigenvalues, b.eigenvalues, rtol=1e-10)


def test_holding_a_condition_solves_the_force_of_the_closed_form(system):
    for target in (-0.2, 0.0, 0.3):
        x = find_equilibrium(system, hold={"aligned": target}, free=["F"])
        th = x[system.index("theta1")]
        assert th == pytest.approx(math.asin(-target), abs=1e-12)
        assert x[system.index("F")] == pytest.approx(symmetric_force(th, **P), rel=1e-10, abs=1e-10)


def test_a_value_event_finds_the_condition():
    system = parse_description(TEXT, "oc.toml").build_reduced()
    x0 = find_equilibrium(system, hold={"theta1": 0.5}, free=["F"])
    br = continuation(system, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}),
                      events=[ValueEvent("aligned", -0.3, label="AL"), ValueEvent("gap", 2.5, label="GP")])
    (al,) = br.special("AL")
    assert al["aligned"] == pytest.approx(-0.3, abs=1e-12) and al["theta1"] == pytest.approx(math.asin(0.3), abs=1e-12)
    assert al["F"] == pytest.approx(symmetric_force(math.asin(0.3), **P), rel=1e-9)
    assert len(br.special("GP")) == 2  # cos(theta) = 2.5/3 on both sides of the aligned pose


def test_a_geometry_change_keeps_the_meaning_of_aligned():
    mech = parse_description(TEXT, "oc.toml")
    system = mech.build(L1=1.2, L2=1.2, LU=0.5)
    x = find_equilibrium(system, hold={"aligned": -0.25}, free=["F"])
    th = math.asin(0.25)
    assert x[system.index("theta1")] == pytest.approx(th, abs=1e-12)
    assert x[system.index("F")] == pytest.approx(symmetric_force(th, **{**P, "L": 1.2, "LU": 0.5}), rel=1e-10)


@pytest.mark.parametrize("reduced", [False, True])
def test_exact_derivatives_with_conditions(reduced):
    mech = parse_description(TEXT, "oc.toml")
    check_derivatives(mech.build_reduced() if reduced else mech.build())


@pytest.mark.parametrize("conditions, words", [
    ('cc = {type = "collinear", points = ["1.a", "1.b"]}', ("conditions.cc.points", "needs 3 point references")),
    ('cc = {type = "collinear", points = ["1.a", "1.b", "3.a"]}', ("conditions.cc.points", "unknown body '3'")),
    ('cc = {type = "collinear", points = ["1.a", "1.b", "1.zz"]}', ("conditions.cc.points", "unknown point 'zz'")),
    ('cc = {type = "collinear", points = ["1.a", "1.b", "1.a"]}', ("conditions.cc.points", "different")),
    ('cc = {type = "distance", points = ["ground.Q", "1.a"]}', ("conditions.cc.points", "unknown ground point")),
    ('cc = {type = "angle", bodies = ["1", "9"]}', ("conditions.cc.bodies", "unknown body '9'")),
    ('cc = {type = "angle", bodies = ["1"]}', ("conditions.cc.bodies", "two body names")),
    ('cc = {type = "parallel", points = ["1.a"]}', ("conditions.cc.type", "collinear")),
    ('cc = {type = "angle", bodies = ["1", "2"], points = ["1.a"]}', ("conditions.cc.points", "unknown key")),
    ('cc = "theta1 - thet2"', ("conditions.cc", "unknown name 'thet2'")),
    ('cc = 3', ("conditions.cc", "expression string or a table")),
    ('cc = {type = "expression"}', ("conditions.cc.expr", "is required")),
    ('L1 = "theta1"', ("conditions.L1", "clashes with the parameter")),
    ('theta2 = "theta1"', ("conditions.theta2", "clashes with the coordinate")),
    ('R_pin_x = "theta1"', ("conditions.R_pin_x", "clashes with a generated")),
    ('spring = "theta1"', ("conditions.spring", "already used in springs")),
    ('cc = {type = "angle", bodies = ["1", "2"], target = "LX"}', ("conditions.cc.target", "unknown name 'LX'")),
])
def test_bad_conditions_give_one_line_errors(conditions, words):
    with pytest.raises(InputError) as info:
        parse_description(OVERCENTRE + "\n[conditions]\n" + conditions + "\n", "c.toml").build()
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith("c.toml:"), msg
    for w in words:
        assert w in msg, msg


@pytest.mark.parametrize("downlock, words", [
    ('{condition = "nope", force = "F"}', ("mechanism.downlock.condition", "unknown condition 'nope'", "aligned, apex_y")),
    ('{condition = "aligned", force = "theta1"}', ("mechanism.downlock.force", "must be a parameter")),
    ('{condition = "aligned"}', ("mechanism.downlock.force", "is required")),
    ('{condition = "aligned", force = "F", sense = 1}', ("mechanism.downlock.sense", "unknown key")),
    ('"aligned"', ("mechanism.downlock", "must be a table")),
])
def test_bad_downlock_specs_give_one_line_errors(downlock, words):
    text = TEXT.replace('dof = 1', f'dof = 1\ndownlock = {downlock}')
    with pytest.raises(InputError) as info:
        parse_description(text, "d.toml")
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith("d.toml:"), msg
    for w in words:
        assert w in msg, msg


def test_a_distance_held_by_the_downlock_needs_a_target():
    text = TEXT.replace('dof = 1', 'dof = 1\ndownlock = {condition = "gap", force = "F"}').replace(", target = 2.5", "")
    with pytest.raises(InputError, match="conditions.gap.target.*needs a target"):
        parse_description(text, "d.toml")
    system = parse_description(TEXT.replace('dof = 1', 'dof = 1\ndownlock = {condition = "gap", force = "F"}'),
                               "d.toml").build()
    assert system.downlock.hold == {"gap": 2.5} and system.downlock.force == "F"
