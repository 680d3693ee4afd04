"""Actuators: a crank held by a jack, in force mode and in length mode, against hand statics.

The crank (length L, pinned at O) carries a moment M; the jack joins the ground point A to the
crank tip P. Virtual work with the jack tension F (positive pulling P towards A) gives
``F dl/dtheta = M`` with ``l = |P - A|``: the force mode must reproduce it along a branch, and
the length mode's reaction ``T_jack`` must equal the force mode's F at the same configuration.
"""

import math
from pathlib import Path

import numpy as np
import pytest
from derivative_checks import check_derivatives

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.errors import InputError
from mechcont.mechanism import parse_description

TEXT = (Path(__file__).resolve().parent / "data" / "crank_jack.toml").read_text()
A = np.array([-0.8, 0.5])


def length_mode(text=TEXT):
    return (text.replace('force = "Fa"', 'length = "La"').replace("dof = 1", "dof = 0")
            .replace("hold = { theta_crank = 0.6 }", ""))


def hand(theta, M=20.0, L=1.0):
    """Jack length l (m) and tension F (N) that balance M at crank angle theta (virtual work)."""
    P = L * np.array([math.cos(theta), math.sin(theta)])
    ell = float(np.linalg.norm(P - A))
    dl = float((P - A) @ (L * np.array([-math.sin(theta), math.cos(theta)]))) / ell
    return ell, M / dl


@pytest.fixture(scope="module", params=[False, True], ids=["full", "reduced"])
def systems(request):
    force, length = parse_description(TEXT, "f.toml"), parse_description(length_mode(), "l.toml")
    build = (lambda m: m.build_reduced()) if request.param else (lambda m: m.build())
    return build(force), build(length)


def test_force_mode_matches_virtual_work_along_a_branch(systems):
    sf, _ = systems
    x0 = find_equilibrium(sf, hold={"theta_crank": 0.6}, free=["Fa"])
    br = continuation(sf, x0, "theta_crank", free=["Fa"],
                      options=ContinuationOptions(bounds={"theta_crank": (0.2, 1.4)}))
    assert br.success and len(br) > 5
    for th, Fa in zip(br["theta_crank"], br["Fa"]):
        assert Fa == pytest.approx(hand(th)[1], rel=1e-10)


def test_length_mode_reaction_equals_the_force_mode_force(systems):
    sf, sl = systems
    assert sl.dof.dof == 0 and "T_jack" in sl.state_names and "T_jack" not in sf.names
    x0 = find_equilibrium(sl)
    br = continuation(sl, x0, "La", options=ContinuationOptions(bounds={"La": (1.0, 1.6)}))
    assert br.success and len(br) > 5
    for th, La, T in zip(br["theta_crank"], br["La"], br["T_jack"]):
        ell, F = hand(th)
        assert La == pytest.approx(ell, abs=1e-12)
        xf = find_equilibrium(sf, hold={"theta_crank": th}, free=["Fa"])
        assert T == pytest.approx(xf[sf.index("Fa")], rel=1e-9, abs=1e-9)
        assert T == pytest.approx(F, rel=1e-9)


def test_actuator_in_the_scene_and_the_drawing(systems, tmp_path):
    from mechcont.outputs.drawing import draw

    sf, sl = systems
    x = find_equilibrium(sl)
    (name, a, b, tension), = sl.scene(x).actuators
    th = x[sl.index("theta_crank")]
    assert name == "jack" and np.allclose(a, A) and np.allclose(b, [math.cos(th), math.sin(th)], atol=1e-12)
    assert tension == pytest.approx(x[sl.index("T_jack")], rel=1e-12)
    xf = find_equilibrium(sf, hold={"theta_crank": 0.6}, free=["Fa"])
    assert sf.scene(xf).actuators[0][3] == pytest.approx(hand(0.6)[1], rel=1e-10)
    out = tmp_path / "jack.svg"
    draw(sl, x, out)
    svg = out.read_text()
    assert 'id="actuator:jack"' in svg and "compression" in svg


@pytest.mark.parametrize("mode", ["force", "length"])
@pytest.mark.parametrize("reduced", [False, True])
def test_exact_derivatives(mode, reduced):
    mech = parse_description(TEXT if mode == "force" else length_mode(), "j.toml")
    check_derivatives(mech.build_reduced() if reduced else mech.build())


@pytest.mark.parametrize("edit, words", [
    (lambda t: t.replace('force = "Fa"', 'force = "Fa"\nlength = "La"'), ("actuators.jack", "exactly one", "not both")),
    (lambda t: t.replace('force = "Fa"', ""), ("actuators.jack", "exactly one of force")),
    (lambda t: t.replace('b = "crank.b"\nforce', 'b = "crank.tip"\nforce'), ("actuators.jack.b", "unknown point 'tip'")),
    (lambda t: t.replace('a = "ground.A"', 'a = "ground.Q"'), ("actuators.jack.a", "unknown ground point")),
    (lambda t: t.replace('a = "ground.A"', 'a = "crank.a"'), ("actuators.jack.b", "both ends")),
    (lambda t: t.replace('force = "Fa"', 'force = "Fb"'), ("actuators.jack.force", "unknown name 'Fb'")),
    (lambda t: t.replace('force = "Fa"', 'force = "Fa"\nstroke = 1'), ("actuators.jack.stroke", "unknown key")),
    (lambda t: t.replace('b = "crank.b"\nforce', 'force'), ("actuators.jack.b", "is required")),
    (lambda t: t.replace("[actuators.jack]", "[actuators.O]"), ("actuators.O", "already used in joints")),
    (lambda t: length_mode(t).replace("dof = 0", "dof = 1"), ("mechanism.dof", "length locks one degree")),
    (lambda t: length_mode(t).replace('La = { value = 1.3', 'La = { value = -1.3'), ("actuators.jack.length", "positive")),
    (lambda t: length_mode(t).replace('La = { value = 1.3', 'La = { value = 3.3'), ("actuators.jack.length", "cannot be met")),
])
def test_bad_actuators_give_one_line_errors(edit, words):
    with pytest.raises(InputError) as info:
        parse_description(edit(TEXT), "j.toml").build()
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith("j.toml:")
    for w in words:
        assert w in msg, msg
