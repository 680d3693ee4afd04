"""A bar's points measured from a hinge instead of its centre (issue 37, item 1): ``check`` warns, and the
shipped freefall leg hangs from its pivot in its drawing.

A body with a ``length`` is a bar centred on its origin; a description that measures its points from one
end draws the bar half on the wrong side of its hinge. The truth here is the geometry written by hand:
the bar's ends at -+length/2 on its axis, the leg's hinge at the pivot O = (0, 0) and its axle a length
L from O along the leg's angle.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner

from mechcont.mechanism import check_report, find_description
from mechcont.mechanism._bar_points import bar_point_warnings
from mechcont.mechanism._file import load_description
from mechcont.mechanism._values import parameter_values
from mechcont.models import load_model

ROOT = Path(__file__).resolve().parent.parent
run = make_runner()

#: A pendulum bar whose points are written from its hinge (the trap): tip at L, lug at 0.3 L, cg at 0.5 L.
HINGED = """
[mechanism]
name = "hinged"
[parameters]
L = { value = 2.0, unit = "m" }
[ground]
O = [0, 0]
[bodies.bar]
mass = 1.0
length = "L"
cg = [CG, 0]
points = { tip = [TIP, 0.1], lug = { r = "0.3*L", angle = 0.2 } }
initial = { theta = -1.5 }
[joints.pin]
type = "revolute"
a = "ground.O"
b = "bar.JOINT"
[gravity]
g = 9.81
"""


def _hinged(tmp_path, cg="0.5*L", tip="L", joint="origin"):
    text = HINGED.replace("CG", f'"{cg}"').replace("TIP", f'"{tip}"').replace("JOINT", joint)
    path = tmp_path / "hinged.toml"
    path.write_text(text)
    return path


def test_points_beyond_a_bars_ends_are_warned_by_name_and_place(tmp_path):
    mech = load_description(_hinged(tmp_path, cg="0.55*L", tip="L"))
    warnings = bar_point_warnings(mech, parameter_values(mech, {}))
    # beyond the end b at +0.5 lengths: the tip at L (+1 length from the centre), the cg at 0.55 L (+0.55);
    # the lug at r = 0.3 L, 0.2 rad off the axis: 0.3 cos(0.2) = 0.294 lengths along it, within the bar
    assert [w.split(":")[0] for w in warnings] == ["bodies.bar.cg", "bodies.bar.points.tip"]
    assert "+0.55 of its length" in warnings[0] and "+1 of its length" in warnings[1]
    assert all("end b" in w and "bar.a and bar.b" in w for w in warnings)
    assert bar_point_warnings(mech, {**parameter_values(mech, {}), "L": 10.0})  # the same fraction at any L
    # measured from the centre (tip at +L/2: on the end, not beyond; cg -0.05 L) nothing is said
    fixed = load_description(_hinged(tmp_path, cg="-0.05*L", tip="L/2", joint="a"))
    assert bar_point_warnings(fixed, parameter_values(fixed, {})) == ()
    below = load_description(_hinged(tmp_path, cg="-0.6*L", tip="0.1*L"))
    assert [w.split(":")[0] for w in bar_point_warnings(below, parameter_values(below, {}))] == ["bodies.bar.cg"]
    assert "end a" in bar_point_warnings(below, parameter_values(below, {}))[0]


def test_check_prints_the_warning_and_exits_clean(tmp_path):
    path = _hinged(tmp_path)
    report = check_report(path)
    assert [w.split(":")[0] for w in report.warnings] == ["bodies.bar.points.tip"] and report.ok
    res = run("check", path)
    assert res.exit_code == 0, res.output
    assert "warnings: 1" in res.output and "bodies.bar.points.tip: beyond the bar's end b" in res.output
    quiet = run("check", path, "--quiet")
    assert quiet.exit_code == 0 and quiet.stdout == ""
    assert quiet.stderr.startswith("warning: bodies.bar.points.tip: beyond")


@pytest.mark.parametrize("name", ["overcentre", "fourbar", "fivebar", "slidercrank", "nose_gear", "lockstay",
                                  "examples/freefall_leg.toml", "examples/main_gear.toml",
                                  "examples/dual_sidestay.toml", "examples/dual_sidestay_locked.toml"])
def test_shipped_descriptions_have_their_points_on_their_bars(name):
    path = find_description(name) if "/" not in name else ROOT / name
    mech = load_description(path)
    assert bar_point_warnings(mech, parameter_values(mech, {})) == ()


def test_the_freefall_leg_hangs_from_its_pivot():
    """Drawn at release (angle 3.0) and locked (4.45): the leg's bar runs from the pivot O = (0, 0) to the axle
    L = 1.6 m away along its angle, the lock spring ends on the leg 0.7 L from O and the actuator 0.35 L
    from O: every point within the bar, as the file's comments measure them from the hinge."""
    from mechcont.dynamics import assemble

    system = load_model(ROOT / "examples" / "freefall_leg.toml")
    L = system.variable("L").value
    for theta in (3.0, 4.45):
        scene = system.scene(assemble(system, {"angle": theta}, hold=["angle"]))  # the joints closed by mechcont
        e = np.array([math.cos(theta), math.sin(theta)])
        (name, bar), = scene.bars
        assert name == "leg"
        np.testing.assert_allclose(np.asarray(bar, float), [[0.0, 0.0], L * e], atol=1e-12)
        spring = {n: (a, b) for n, a, b in scene.springs}["lock"]
        np.testing.assert_allclose(spring[1], 0.7 * L * e, atol=1e-12)
        np.testing.assert_allclose(spring[0], [0.3, -0.6], atol=1e-12)
        damper = {n: (a, b) for n, a, b in scene.dampers}["actuator"]
        np.testing.assert_allclose(damper[1], 0.35 * L * e, atol=1e-12)
