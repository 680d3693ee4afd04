"""The drawing scene of generated systems places every primitive where the equations put it."""

import numpy as np
import pytest

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
