"""The force-element protocol: an element kind defined in one class is registered by its table name,
read from a description file (planar or spatial) and generates its forces, rows and drawing through
the kinematics.

Checked against an independent formulation and a closed form: a rope of constant tension ``T``
(a new class, potential ``T l``) gives the same residual and Jacobian as the shipped force-mode
actuator of force ``T``, and the generalised forces ``-T dl/dq`` written out by hand.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from mechcont.errors import InputError
from mechcont.mechanism import parse_description
from mechcont.mechanism.elements import ELEMENT_TYPES, TwoPointElement

PENDULUM = """
[mechanism]
name = "pendulum"
dimension = {dimension}
dof = {dof}
[parameters]
m = 2.0
T = 3.0
[ground]
O = {origin}
A = {anchor}
[bodies.bar]
mass = "m"
length = 1.0
initial = {{ {initial} }}
[joints.pin]
type = "{pin}"
a = "ground.O"
b = "bar.a"
{element}
"""
PLANE = dict(dimension=2, dof=1, origin="[0, 0]", anchor="[0.3, -2.0]", initial="theta = -1.2", pin="revolute")
SPACE = dict(dimension=3, dof=3, origin="[0, 0, 0]", anchor="[0.3, -2.0, 0.4]", initial="rotation = [0, 0, -1.2]",
             pin="spherical")


@pytest.fixture
def ropes():
    """An element table ``[test_ropes.NAME]``: a rope of constant tension between two points (for the test only)."""

    @dataclass(frozen=True)
    class Rope(TwoPointElement):
        name: str
        a: str
        b: str
        tension: str = "T"

        table: ClassVar[str] = "test_ropes"
        KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "tension"})
        REQUIRED: ClassVar[tuple[str, ...]] = ("a", "b")
        DRAWN: ClassVar[str] = "spring"

        def values(self, mech):
            yield self.field("tension"), self.tension

        def apply(self, kin, out) -> None:
            out.V += kin.mech.value(self.field("tension")) * kin.distance(self.a, self.b)

    try:
        yield Rope
    finally:
        del ELEMENT_TYPES["test_ropes"]


@pytest.mark.parametrize("space", [PLANE, SPACE], ids=["plane", "space"])
def test_an_element_class_is_read_by_its_table_and_matches_the_actuator(ropes, space):
    mine = parse_description(PENDULUM.format(**space, element='[test_ropes.rope]\na = "ground.A"\nb = "bar.b"')).build()
    shipped = parse_description(PENDULUM.format(**space, element='[actuators.rope]\na = "ground.A"\nb = "bar.b"\n'
                                                                 'force = "T"')).build()
    assert mine.names == shipped.names
    rng = np.random.default_rng(3)
    for _ in range(3):
        x = shipped.defaults() + 0.3 * rng.standard_normal(len(shipped.names))
        np.testing.assert_allclose(mine.residual(x), shipped.residual(x), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(mine.jacobian(x), shipped.jacobian(x), rtol=1e-12, atol=1e-12)
    scene = mine.scene(mine.defaults())
    assert [name for name, _, _ in scene.springs] == ["rope"]
    assert len(scene.anchors) == 1  # the ground end A (no joint there) is drawn as an anchor


def test_the_generalised_forces_are_minus_tension_times_the_length_gradient(ropes):
    mine = parse_description(PENDULUM.format(**PLANE, element='[test_ropes.rope]\na = "ground.A"\nb = "bar.b"')).build()
    x = mine.defaults()
    xc, yc, theta, T = (x[mine.index(n)] for n in ("x_bar", "y_bar", "theta_bar", "T"))
    # closed form: tip b = centre + L/2 (cos, sin) (L = 1 m), l = |b - A|, Q = -T dl/dq
    tip = np.array([xc, yc]) + 0.5 * np.array([np.cos(theta), np.sin(theta)])
    d = tip - np.array([0.3, -2.0])
    u = d / np.linalg.norm(d)
    expected = -T * np.array([u[0], u[1], u @ (0.5 * np.array([-np.sin(theta), np.cos(theta)]))])
    np.testing.assert_allclose(mine.mechanics.applied_forces(x), expected, rtol=1e-12, atol=1e-12)


def test_an_element_table_is_checked_by_its_class(ropes):
    base = '[test_ropes.rope]\na = "ground.A"\nb = "bar.b"'
    for element, field, words in [
        (base + "\nlength = 2", "test_ropes.rope.length", "unknown key"),
        ('[test_ropes.rope]\na = "ground.A"', "test_ropes.rope.b", "is required"),
        (base + '\ntension = "Q"', "test_ropes.rope.tension", "unknown name 'Q'"),
        (base.replace("bar.b", "bar.tip"), "test_ropes.rope.b", "unknown point 'tip'"),
        (base.replace("[test_ropes.rope]", "[test_ropes.pin]"), "test_ropes.pin", "already used in joints"),
    ]:
        with pytest.raises(InputError) as info:
            parse_description(PENDULUM.format(**PLANE, element=element), "p.toml").build()
        msg = str(info.value)
        assert "\n" not in msg and field in msg and words in msg, msg


def test_an_unregistered_table_is_refused_naming_the_tables():
    with pytest.raises(InputError, match=r"test_ropes.*unknown key; valid keys: .*actuators.*dampers.*springs"):
        parse_description(PENDULUM.format(**PLANE, element='[test_ropes.rope]\na = "ground.A"\nb = "bar.b"'))
