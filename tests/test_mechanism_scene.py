"""The drawing scene of generated systems places every primitive where the equations put it."""

from pathlib import Path

import numpy as np
import pytest

import mechcont
from mechcont.mechanism import assemble, load


@pytest.mark.parametrize("reduced", [False, True])
def test_fourbar_scene_matches_the_configuration(reduced):
    system = load("fourbar", reduced=reduced)
    x = assemble(system, hold={"theta_crank": 0.7}, free=["T"])
    c = system.coordinates_of(x)
    scene = system.scene(x)
    bars = dict(scene.bars)
    assert set(bars) == {"crank", "coupler", "rocker"}
    for name, L in (("crank", 0.3), ("coupler", 0.8), ("rocker", 0.6)):
        a, b = bars[name]
        assert np.linalg.norm(b - a) == pytest.approx(L, abs=1e-12)
        assert (a + b) / 2 == pytest.approx([c[f"x_{name}"], c[f"y_{name}"]], abs=1e-12)
    # ground pins at A = (0, 0) and D = (d, 0); moving pins where the bars meet
    assert sorted(map(tuple, np.round(scene.grounds, 12))) == [(0.0, 0.0), (0.7, 0.0)]
    assert bars["crank"][1] == pytest.approx(bars["coupler"][0], abs=1e-10)
    assert any(np.allclose(p, bars["coupler"][1], atol=1e-10) for p in scene.pins)
    (name, s0, s1), = scene.springs
    assert name == "spring" and s0 == pytest.approx([0.0, 0.9]) and s1 == pytest.approx(
        (bars["coupler"][0] + bars["coupler"][1]) / 2, abs=1e-12)


def test_slider_and_force_in_scene():
    system = load("slidercrank")
    x = assemble(system, hold={"theta_crank": 0.5}, free=["P"])
    scene = system.scene(x)
    (pos, direction), = scene.sliders
    assert pos[1] == pytest.approx(0.0, abs=1e-12) and direction == pytest.approx([1.0, 0.0])
    (name, at, vec), = scene.forces
    assert name == "P" and at == pytest.approx(pos) and vec == pytest.approx([x[system.index("P")], 0.0])


FOURBAR = Path(mechcont.__file__).parent / "data" / "fourbar.toml"


def variant(tmp_path, old, new, name="variant"):
    """The shipped four-bar description with ``old`` replaced by ``new`` (must occur once)."""
    text = FOURBAR.read_text()
    assert text.count(old) == 1
    path = tmp_path / f"{name}.toml"
    path.write_text(text.replace(old, new))
    return path


@pytest.mark.parametrize("reduced", [False, True])
def test_fourbar_crank_moment_at_its_ground_pin_with_the_T_value(reduced):
    """T acts on the crank, which is pinned to the ground at A = (0, 0): drawn there, value = the T column."""
    system = load("fourbar", reduced=reduced)
    signs = set()
    for theta in (0.7, 2.0, 3.3, 4.5, 5.8):
        x = assemble(system, hold={"theta_crank": theta}, free=["T"])
        scene = system.scene(x)
        (name, at, value), = scene.moments
        assert name == "T" and at == pytest.approx([0.0, 0.0], abs=1e-12)
        assert dict(scene.bars)["crank"][0] == pytest.approx(at, abs=1e-12)
        assert value == x[system.index("T")]
        signs.add(np.sign(value))
    assert signs == {-1.0, 1.0}          # both senses occur, so the sign is really carried


def test_moment_on_a_floating_body_is_drawn_at_its_centre(tmp_path):
    system = load(variant(tmp_path, 'body = "crank"', 'body = "coupler"'))
    x = assemble(system, hold={"theta_crank": 1.0}, free=["T"])
    scene = system.scene(x)
    (name, at, value), = scene.moments
    a, b = dict(scene.bars)["coupler"]
    assert name == "T" and value == x[system.index("T")] != 0 and at == pytest.approx((a + b) / 2, abs=1e-12)


def test_spring_ground_anchors_get_a_symbol():
    # four-bar: the spring's ground point S = (sx, sy) is an anchor; the pins A and D are not
    system = load("fourbar", sx=0.1, sy=0.95)
    scene = system.scene(assemble(system, hold={"theta_crank": 1.0}, free=["T"]))
    (anchor,) = scene.anchors
    assert anchor == pytest.approx([0.1, 0.95]) and len(scene.grounds) == 2
    # five-bar: two springs from two ground points
    five = load("fivebar")
    scene = five.scene(five.vector({}))
    assert len(scene.anchors) == 2 and len(scene.springs) == 2
    starts = sorted(map(tuple, np.round([s0 for _, s0, _ in scene.springs], 12)))
    assert sorted(map(tuple, np.round(scene.anchors, 12))) == starts
    ext = scene.extent()
    for p in scene.anchors:
        assert ext[0] <= p[0] <= ext[1] and ext[2] <= p[1] <= ext[3]


def test_no_anchor_where_a_pin_already_holds_the_spring(tmp_path):
    system = load(variant(tmp_path, 'a = "ground.S"', 'a = "ground.D"'))
    scene = system.scene(assemble(system, hold={"theta_crank": 1.0}, free=["T"]))
    assert scene.anchors == [] and len(scene.grounds) == 2


def test_damper_to_ground_is_drawn_and_anchored(tmp_path):
    path = variant(tmp_path, "[gravity]", '[dampers.dash]\na = "ground.S"\nb = "rocker.origin"\nc = 3.0\n\n[gravity]')
    system = load(path)
    scene = system.scene(assemble(system, hold={"theta_crank": 1.0}, free=["T"]))
    (name, d0, d1), = scene.dampers
    bars = dict(scene.bars)
    assert name == "dash" and d0 == pytest.approx([0.0, 0.9]) and d1 == pytest.approx(bars["rocker"].mean(axis=0))
    assert len(scene.anchors) == 1      # spring and damper share S: one symbol
