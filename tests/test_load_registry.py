"""The load protocol: a load type defined in one class is registered by its ``type``, read by the
description parser of its space and generates its forces through the kinematics.

Checked against an independent formulation: a constant force written as virtual work
(``kin.force_work``, a new class) gives the same residual and Jacobian as the shipped point force,
which enters through the potential ``-F u . P``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest
import sympy as sp

from mechcont.mechanism import parse_description
from mechcont.mechanism.loads import LOAD_TYPES, Load

PENDULUM = """
[mechanism]
name = "pendulum"
[parameters]
m = 2.0
F = 3.0
[ground]
O = [0, 0]
[bodies.bar]
mass = "m"
length = 1.0
initial = {{ theta = -1.2 }}
[joints.pin]
type = "revolute"
a = "ground.O"
b = "bar.a"
[loads.push]
{load}
"""


@pytest.fixture
def sideways_force():
    """A load type ``test_sideways``: the force ``(F, 0)`` at a point, as virtual work (registered for the test only)."""

    @dataclass(frozen=True)
    class Sideways(Load):
        name: str
        at: str
        magnitude: str = "F"

        kind: ClassVar[str] = "test_sideways"
        KEYS: ClassVar[frozenset[str]] = frozenset({"at", "magnitude"})
        REQUIRED: ClassVar[tuple[str, ...]] = ("at",)

        def check(self, mech) -> None:
            mech.point_ref(self.at, self.field("at"))

        def values(self, mech):
            yield self.field("magnitude"), self.magnitude

        def apply(self, kin, out) -> None:
            force = sp.Matrix([kin.mech.value(self.field("magnitude")), 0])
            P = kin.point(self.at)
            out.add(kin.force_work(P, force))
            out.arrow(self.name, P, force)

    try:
        yield Sideways
    finally:
        del LOAD_TYPES["plane"]["test_sideways"]


def test_a_load_class_is_read_by_its_type_and_matches_the_potential_formulation(sideways_force):
    mine = parse_description(PENDULUM.format(load='type = "test_sideways"\nat = "bar.b"')).build()
    shipped = parse_description(PENDULUM.format(load='type = "force"\nat = "bar.b"\nmagnitude = "F"\n'
                                                     'direction = [1, 0]')).build()
    assert mine.names == shipped.names
    rng = np.random.default_rng(1)
    for _ in range(3):
        x = shipped.defaults() + 0.3 * rng.standard_normal(len(shipped.names))
        np.testing.assert_allclose(mine.residual(x), shipped.residual(x), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(mine.jacobian(x), shipped.jacobian(x), rtol=1e-12, atol=1e-12)
    # closed form: (F, 0) at the end b = centre + L/2 (cos theta, sin theta) of the bar (L = 1 m)
    # gives Q_x = F, Q_y = 0 and the moment about the centre -F L/2 sin theta
    x = mine.defaults()
    theta, F = x[mine.index("theta_bar")], x[mine.index("F")]
    Q = mine.mechanics.applied_forces(x)
    np.testing.assert_allclose(Q, [F, 0.0, -F * 0.5 * np.sin(theta)], rtol=1e-12, atol=1e-12)
    scene = mine.scene(x)
    assert [name for name, _, _ in scene.forces] == ["push"]


def test_a_load_type_of_the_other_space_is_refused_with_the_valid_types(sideways_force):
    from mechcont.errors import InputError

    text = """
[mechanism]
dimension = 3
[ground]
O = [0, 0, 0]
[bodies.bar]
mass = 1.0
length = 1.0
[joints.pin]
type = "spherical"
a = "ground.O"
b = "bar.a"
[loads.push]
type = "test_sideways"
at = "bar.b"
"""
    with pytest.raises(InputError, match=r"loads\.push\.type.*must be one of force, moment, drag, custom"):
        parse_description(text)
