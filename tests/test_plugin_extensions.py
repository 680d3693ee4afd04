"""The two measured extensions of issue 34, each one module registered through the plug-in mechanism
(``tests/plugins``): a rotary spring (an element whose two points sit on one pin) and a follower load
(a force fixed in a body), read from a description file in the plane and in space and checked against
the closed-form equilibrium of a pendulum pinned at its end ``a``; and a condition kind defined in a
test, read by its class.

Pendulum of mass ``m``, length ``L``, angle ``theta`` from +x, gravity ``g`` along -y: potential
``m g L/2 sin theta``. A rotary spring ``k`` about the pin adds ``k/2 theta^2``: equilibrium
``m g L/2 cos theta + k theta = 0``. A follower force ``F`` at the tip, perpendicular to the bar, adds
the moment ``F L``: equilibrium ``F = m g cos(theta) / 2``.
"""

from __future__ import annotations

import importlib
import math
import sys

import numpy as np
import pytest

from mechcont.continuation import find_equilibrium
from mechcont.errors import InputError
from mechcont.mechanism import parse_description
from mechcont.mechanism._plugin import registry

M, G, L = 2.0, 9.81, 1.0

PENDULUM = """
[mechanism]
name = "pendulum"
dimension = {dimension}
[parameters]
m = {m}
g = {g}
k = 5.0
F = 4.0
[ground]
O = {origin}
[bodies.bar]
mass = "m"
length = {L}
initial = {{ {initial} }}
[joints.pin]
type = "revolute"
a = "ground.O"
b = "bar.a"
{axis}
[gravity]
g = "g"
{gravity}
{extra}
"""
PLANE = dict(dimension=2, origin="[0, 0]", initial="theta = -0.5", axis="", gravity="", m=M, g=G, L=L)
SPACE = dict(dimension=3, origin="[0, 0, 0]", initial="rotation = [0, 0, -0.5]", axis="axis = [0, 0, 1]",
             gravity="direction = [0, -1, 0]", m=M, g=G, L=L)
SPRING = {2: '[test_rotary_springs.coil]\na = "ground.O"\nb = "bar.a"\nk = "k"',
          3: '[test_rotary_springs.coil]\na = "ground.O"\nb = "bar.a"\nk = "k"\naxis = [0, 0, 1]'}
FOLLOWER = {2: '[loads.push]\ntype = "test_follower"\nat = "bar.b"\nmagnitude = "F"\ndirection = [0, 1]',
            3: '[loads.push]\ntype = "test_follower"\nat = "bar.b"\nmagnitude = "F"\ndirection = [0, 1, 0]'}


def _plugin(module: str, family: str, key: str):
    """Import the one module ``tests/plugins/<module>`` (its class registers itself); unregistered afterwards."""
    name = f"plugins.{module}"
    mod = importlib.import_module(name)
    try:
        yield mod
    finally:
        for space in ("plane", "space"):
            registry(family, space).pop(key, None)
        sys.modules.pop(name, None)


@pytest.fixture
def rotary_spring():
    yield from _plugin("rotary_spring", "elements", "test_rotary_springs")


@pytest.fixture
def follower():
    yield from _plugin("follower_load", "loads", "test_follower")


def _angle(model, x) -> float:
    """The bar's angle (rad) from +x: its coordinate in the plane, from its Euler parameters (about z) in space."""
    names = list(model.names)
    if "theta_bar" in names:
        return float(x[names.index("theta_bar")])
    e0, e3 = (x[i] for i, n in enumerate(names) if n.startswith("e") and n.endswith("_bar") and n[1] in "03")
    return 2 * math.atan2(e3, e0)


@pytest.mark.parametrize("space", [PLANE, SPACE], ids=["plane", "space"])
def test_a_rotary_spring_module_on_one_pin_is_built_and_meets_the_closed_form(rotary_spring, space):
    # its two points coincide: the drawing anchors are not a line of action, the build must not refuse it
    model = parse_description(PENDULUM.format(**space, extra=SPRING[space["dimension"]])).build()
    x = find_equilibrium(model)
    theta = _angle(model, x)
    k = x[model.index("k")]
    assert -1.5 < theta < 0
    assert M * G * L / 2 * math.cos(theta) + k * theta == pytest.approx(0, abs=1e-8)
    # the other way round: the stiffness that holds the bar at -0.3 rad (plane: the angle held directly)
    if space is PLANE:
        y = find_equilibrium(model, hold={"theta_bar": -0.3}, free=["k"])
        assert y[model.index("k")] == pytest.approx(M * G * L * math.cos(0.3) / (2 * 0.3), rel=1e-10)


@pytest.mark.parametrize("space", [PLANE, SPACE], ids=["plane", "space"])
def test_a_follower_load_module_meets_the_closed_form(follower, space):
    model = parse_description(PENDULUM.format(**space, extra=FOLLOWER[space["dimension"]])).build()
    x = find_equilibrium(model)
    theta = _angle(model, x)
    assert math.cos(theta) == pytest.approx(2 * x[model.index("F")] / (M * G), rel=1e-9)
    if space is PLANE:
        y = find_equilibrium(model, hold={"theta_bar": -0.3}, free=["F"])
        assert y[model.index("F")] == pytest.approx(M * G * math.cos(0.3) / 2, rel=1e-10)
        # away from equilibrium too: with the bar's centre (x, y) and angle theta as coordinates, the
        # follower force F (-sin, cos) at the tip and gravity give Q = (-F sin, F cos - m g, F L/2)
        z = model.vector({"theta_bar": 0.7, "F": 3.0})
        np.testing.assert_allclose(model.mechanics.applied_forces(z),
                                   [-3.0 * math.sin(0.7), 3.0 * math.cos(0.7) - M * G, 3.0 * L / 2], rtol=1e-12)


@pytest.mark.parametrize("space", [PLANE, SPACE], ids=["plane", "space"])
def test_a_plug_in_limit_is_enforced_by_its_key_path(rotary_spring, space):
    """The rotary spring's one limit (stiffness >= 0, given through the plug-in signature ``limits(kin, solve)``)
    is the model's, named by its key path: a negative stiffness is refused, zero is allowed."""
    mech = parse_description(PENDULUM.format(**space, extra=SPRING[space["dimension"]]))
    model = mech.build()
    (limit,) = [lim for lim in model.limits if lim.name == "test_rotary_springs.coil.k"]
    assert not limit.strict and limit.description == "rotary stiffness (N m/rad)"
    with pytest.raises(InputError, match=r"test_rotary_springs\.coil\.k.*non-negative, got -1"):
        mech.build(k=-1.0)
    with pytest.raises(InputError, match=r"test_rotary_springs\.coil\.k"):
        model.check_limits(model.vector({"k": -1.0}))
    model.check_limits(model.vector({"k": 0.0}))


def test_every_plug_in_has_the_one_limits_signature():
    """Elements, loads and joints of both spaces (and conditions) answer ``limits(kin, solve)`` with
    :class:`~mechcont.equations.Limit` records (issue 34: three signatures before)."""
    import inspect

    import mechcont.mechanism.spatial  # noqa: F401 (registers the spatial joints)
    from mechcont.equations import Limit
    from mechcont.mechanism import parse_description as parse
    from mechcont.mechanism._plugin import PlugIn

    classes = {cls for family in ("elements", "loads", "joints", "conditions") for space in ("plane", "space")
               for cls in registry(family, space).values()}
    assert len(classes) > 20
    for cls in classes:
        assert issubclass(cls, PlugIn)
        assert list(inspect.signature(cls.limits).parameters) == ["self", "kin", "solve"], cls.__name__
    # one of each kind, through the one call: a drag load, a pin-in-slot joint, a spring
    mech = parse(SLOT)
    kin = mech.kinematics()
    found = {lim.name: lim for p in (*mech.force_elements(), *mech.loads, *mech.joints) for lim in p.limits(kin, True)}
    assert all(isinstance(lim, Limit) for lim in found.values())
    assert {"springs.s.k", "springs.s.free_length", "loads.air.d", "loads.air.rho", "loads.air.CD",
            "joints.guide.slot"} <= found.keys()
    assert not found["springs.s.k"].strict  # zero allowed for an analysis (solve)
    assert float(found["joints.guide.slot"].expr) == pytest.approx(0.5)  # |(0.3, 0.4)|


#: a crank whose pin runs in a ground slot, with a spring and a drag load: one plug-in with limits of each kind
SLOT = """
[mechanism]
name = "slot"
[ground]
O = [0, 0]
S0 = [0.5, 0]
S1 = [0.8, 0.4]
[bodies.crank]
mass = 1.0
length = 0.6
initial = { x = 0.3, theta = 0.0 }
[joints.pivot]
type = "revolute"
a = "ground.O"
b = "crank.a"
[joints.guide]
type = "pin_in_slot"
pin = "crank.b"
slot = ["ground.S0", "ground.S1"]
[springs.s]
a = "ground.O"
b = "crank.b"
k = 10.0
free_length = 0.5
[loads.air]
type = "drag"
body = "crank"
start = "a"
end = "b"
rho = 1.2
U = 10.0
alpha = 0.0
d = 0.05
CD = 1.0
"""


def test_the_extensions_are_read_from_the_registry_and_unknown_without_it():
    """Without the module, the tables are refused by name (nothing else knows them)."""
    with pytest.raises(InputError, match="test_follower"):
        parse_description(PENDULUM.format(**PLANE, extra=FOLLOWER[2]))
    with pytest.raises(InputError, match="test_rotary_springs"):
        parse_description(PENDULUM.format(**PLANE, extra=SPRING[2]))


@pytest.fixture
def height_condition():
    """A condition kind ``test_height`` (the second coordinate of a point, m), defined here only."""
    from dataclasses import dataclass
    from typing import ClassVar

    from mechcont.mechanism._conditions import Condition

    @dataclass(frozen=True)
    class Height(Condition):
        point: str = ""

        kind: ClassVar[str] = "test_height"
        UNIT: ClassVar[str] = "m"
        KEYS: ClassVar[frozenset[str]] = frozenset({"point"})

        def check(self, mech) -> None:
            mech.point_ref(self.point, self.field("point"))

        def expression(self, kin):
            return kin.point(self.point)[1]

    try:
        yield Height
    finally:
        registry("conditions", "plane").pop("test_height", None)


def test_a_condition_kind_is_one_registered_class(height_condition):
    """Read from ``[conditions.NAME] type = ...`` by its class (no switch on the kind): the tip's height
    ``L sin theta`` of the hanging pendulum (theta = -pi/2), with its unit."""
    text = PENDULUM.format(**PLANE, extra='[conditions.tip]\ntype = "test_height"\npoint = "bar.b"')
    model = parse_description(text).build()
    y = find_equilibrium(model)
    assert y[model.index("theta_bar")] == pytest.approx(-math.pi / 2, abs=1e-10)
    assert y[model.index("tip")] == pytest.approx(-L, rel=1e-10)
    assert model.variable("tip").unit == "m"
    with pytest.raises(InputError, match="conditions.tip.point"):
        parse_description(text.replace('point = "bar.b"', 'point = "bar.nowhere"')).build()
