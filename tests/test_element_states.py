"""First-order element states end to end (``Element.states``), with an element defined in this test only.

A Maxwell element (a spring ``k2`` in series with a damper ``c``, free length ``L2``; its internal state
``u`` the damper's extension) carries the tension ``T = k2 (l - L2 - u)`` and ``du/dt = T / c``. On a block
of mass ``m`` on a prismatic joint, in parallel with a spring ``k1`` and pushed by a force ``F``
(``x`` the block's travel from where both springs are free):

* at rest the damper has relaxed (``T = 0``): the static deflection is ``F / k1``, ``u = x``;
* the small motions ``(x, v, u)`` obey ``m x'' = F - k1 x - k2 (x - u)``, ``u' = (k2/c)(x - u)``: the
  eigenvalues are the roots of ``m c s^3 + m k2 s^2 + c (k1 + k2) s + k1 k2``;
* from rest at ``x = u = 0`` the motion is ``z(t) = z_eq + expm(A t)(z0 - z_eq)`` (the system is linear:
  the springs lie along the rail), which the time simulation must follow, the state's column with it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest
import scipy.linalg
import sympy as sp

from mechcont.continuation import find_equilibrium
from mechcont.dynamics import simulate
from mechcont.equations import dynamics_of
from mechcont.mechanism.elements import ELEMENT_TYPES, TwoPointElement
from mechcont.mechanism.elements._base import ElementState
from mechcont.models import model_from_text

M, K1, K2, C, F = 2.0, 100.0, 400.0, 40.0, 30.0

BLOCK = f"""
[mechanism]
name = "zener"
[parameters]
m = {M}
k1 = {K1}
k2 = {K2}
c = {C}
F = {F}
[ground]
O = [0, 0]
S = [-1.0, 0]
[bodies.block]
mass = "m"
inertia = 0.1
initial = {{ x = 0.1, y = 0, theta = 0 }}
[joints.rail]
type = "prismatic"
a = "ground.O"
b = "block.origin"
[springs.parallel]
a = "ground.S"
b = "block.origin"
k = "k1"
free_length = 1.0
[test_maxwell.mx]
a = "ground.S"
b = "block.origin"
[loads.push]
type = "force"
at = "block.origin"
magnitude = "F"
direction = [1, 0]
"""


@pytest.fixture
def maxwell():
    """``[test_maxwell.NAME]``: a spring in series with a damper (for this test only); its state ``u_NAME``."""

    @dataclass(frozen=True)
    class Maxwell(TwoPointElement):
        name: str
        a: str
        b: str
        k: str = "k2"
        c: str = "c"
        free_length: float = 1.0

        table: ClassVar[str] = "test_maxwell"
        KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "k", "c", "free_length"})
        REQUIRED: ClassVar[tuple[str, ...]] = ("a", "b")
        DRAWN: ClassVar[str] = "spring"

        def values(self, mech):
            yield self.field("k"), self.k
            yield self.field("c"), self.c
            yield self.field("free_length"), self.free_length

        def _tension(self, kin):
            v = kin.mech.value
            u = sp.Symbol(f"u_{self.name}", real=True)
            return v(self.field("k")) * (kin.distance(self.a, self.b) - v(self.field("free_length")) - u)

        def apply(self, kin, out) -> None:
            length = kin.distance(self.a, self.b)
            T = self._tension(kin)
            out.add([-T * sp.diff(length, qi) for qi in kin.q])

        def states(self, kin):
            return (ElementState(f"u_{self.name}", "m", self._tension(kin) / kin.mech.value(self.field("c")),
                                 scale=0.1, description="extension of the damper"),)

    try:
        yield Maxwell
    finally:
        del ELEMENT_TYPES["test_maxwell"]


def _closed_form_A():
    return np.array([[0.0, 1.0, 0.0], [-(K1 + K2) / M, 0.0, K2 / M], [K2 / C, 0.0, -K2 / C]])


def test_static_deflection_and_the_state_as_a_variable(maxwell):
    model = model_from_text(BLOCK, "zener.toml")
    assert "u_mx" in model.names and model.variable("u_mx").unit == "m"
    assert "rate_u_mx" in model.equation_names
    assert model.mechanics.element_states == ("u_mx",)
    from mechcont.mechanism import parse_description

    described = parse_description(BLOCK).summary()  # what `check` lists without generating: the same variables
    assert described is not None and [v[0] for v in described[1]] == list(model.names)
    x = find_equilibrium(model)
    assert x[model.index("x_block")] == pytest.approx(F / K1, rel=1e-12)
    assert x[model.index("u_mx")] == pytest.approx(F / K1, rel=1e-12)  # the damper has relaxed: no tension
    # the generated model's start (the assembled pose, x = 0.1 m) has the state at its steady state there
    d = model.defaults()
    assert d[model.index("x_block")] == pytest.approx(0.1, rel=1e-12)
    assert d[model.index("u_mx")] == pytest.approx(0.1, rel=1e-12)


def test_linearisation_eigenvalues_against_the_characteristic_cubic(maxwell):
    model = model_from_text(BLOCK, "zener.toml")
    x = find_equilibrium(model)
    lam = dynamics_of(model).linearise(x).eigenvalues()
    roots = np.roots([M * C, M * K2, C * (K1 + K2), K1 * K2])
    assert np.allclose(np.sort_complex(lam), np.sort_complex(roots), rtol=1e-11, atol=0)
    # the minimal-coordinate rates see the state too: their Jacobian (differences) has the same spectrum
    dyn = dynamics_of(model)
    z = dyn.state_at(x)
    assert dyn.state_names[-1] == "u_mx"
    assert np.allclose(np.sort_complex(np.linalg.eigvals(dyn.rates_jacobian(z, x))), np.sort_complex(roots),
                       rtol=1e-7)


@pytest.mark.parametrize("projection", [False, True])
def test_relaxation_in_time_against_the_closed_form(maxwell, projection):
    model = model_from_text(BLOCK, "zener.toml")
    x0 = model.vector({"x_block": 0.0, "u_mx": 0.0})
    t = np.linspace(0.0, 0.5, 11)
    sim = simulate(model, x0, (0.0, 0.5), rtol=1e-11, atol=1e-12, t_eval=t, method="DOP853", projection=projection)
    z_eq = np.array([F / K1, 0.0, F / K1])
    A = _closed_form_A()
    ref = np.array([z_eq + scipy.linalg.expm(A * ti) @ (np.zeros(3) - z_eq) for ti in t])
    assert np.max(np.abs(sim["x_block"] - ref[:, 0])) < 1e-8
    assert np.max(np.abs(sim["x_block_dot"] - ref[:, 1])) < 1e-7
    assert np.max(np.abs(sim["u_mx"] - ref[:, 2])) < 1e-8
    assert sim.units["u_mx"] == "m"
    assert abs(sim["u_mx"][-1]) > 0.1 * F / K1  # the state did move


# -- a pendulum with a Maxwell element to its tip: planar, reduced and spatial descriptions -------------
# A uniform bar (m, L) hinged at its end hangs; the Maxwell element joins the ground point G to its tip. At
# rest it has relaxed, so the bar hangs straight down; with a = dl/dtheta there and K = m g L/2,
# I = m L^2/3: (I s^2 + K + k2 a^2)(c s + k2) = k2^2 a^2, i.e. I c s^3 + I k2 s^2 + c (K + k2 a^2) s + K k2 = 0.
PL, PM, PG, GX, GZ = 0.8, 2.0, 9.81, 0.3, -1.2
PENDULUM = {
    2: f"""
[mechanism]
name = "maxwell_pendulum"
[parameters]
k2 = {K2}
c = {C}
[ground]
O = [0, 0]
G = [{GX}, {GZ}]
[bodies.bar]
mass = {PM}
length = {PL}
initial = {{ theta = -1.5 }}
[joints.pin]
type = "revolute"
a = "ground.O"
b = "bar.a"
[test_maxwell.mx]
a = "ground.G"
b = "bar.b"
free_length = 0.5
[gravity]
g = {PG}
""",
    3: f"""
[mechanism]
name = "maxwell_pendulum_3d"
dimension = 3
dof = 1
[parameters]
k2 = {K2}
c = {C}
[ground]
O = [0, 0, 0]
G = [{GX}, 0, {GZ}]
[bodies.bar]
mass = {PM}
length = {PL}
inertia = [0.01, {PM * PL * PL / 12}, {PM * PL * PL / 12}]
initial = {{ x = 0.0, z = {-PL / 2}, rotation = [0, 1.5, 0] }}
[joints.pin]
type = "revolute"
a = "ground.O"
b = "bar.a"
axis = [0, 1, 0]
[test_maxwell.mx]
a = "ground.G"
b = "bar.b"
free_length = 0.5
[gravity]
g = {PG}
"""}


@pytest.mark.parametrize("form", ["plane", "reduced", "space"])
def test_pendulum_with_a_maxwell_element_in_every_form(maxwell, form):
    from mechcont.mechanism import parse_description

    mech = parse_description(PENDULUM[3 if form == "space" else 2])
    model = mech.build_reduced() if form == "reduced" else mech.build()
    x = find_equilibrium(model, guess=model.defaults())
    tip, G = np.array([0.0, -PL]), np.array([GX, GZ])
    a = (tip - G) @ np.array([PL, 0.0]) / np.linalg.norm(tip - G)   # dl/dtheta, the tip moving sideways
    u = np.linalg.norm(tip - G) - 0.5
    assert x[model.index("u_mx")] == pytest.approx(u, rel=1e-10)    # relaxed at the hanging pose
    I, K = PM * PL * PL / 3, PM * PG * PL / 2
    roots = np.roots([I * C, I * K2, C * (K + K2 * a * a), K * K2])
    lam = dynamics_of(model).linearise(x).eigenvalues()
    assert np.allclose(np.sort_complex(lam), np.sort_complex(roots), rtol=1e-9, atol=0)


def test_the_compiled_rates_and_their_cache_key():
    """The rates and their exact derivatives are compiled with the model; the disk cache's key holds them
    (two models that differ only in a rate never share compiled code), and a model without states keeps
    the key it had before states existed (its cached code stays valid)."""
    from mechcont.equations import MechanicalModel, velocity_symbol

    q, s, k, c = (sp.Symbol(n, real=True) for n in ("q", "s", "k", "c"))
    qd = velocity_symbol("q")
    names = ["q", "s", "k", "c"]

    def model(rate):
        return MechanicalModel(names, ["q"], [], [-k * (q - s)], sp.Matrix([[2.0]]), state_rates={"s": rate})

    a, b = model(k * (q - s) / c), model(k * (q - s) / c + qd)
    assert a._content_digest() != b._content_digest()
    plain = MechanicalModel(names, ["q"], [], [-k * (q - s)], sp.Matrix([[2.0]]))
    again = MechanicalModel(names, ["q"], [], [-k * (q - s)], sp.Matrix([[2.0]]), state_rates={})
    assert plain._content_digest() == again._content_digest() != a._content_digest()
    x = np.array([0.3, 0.1, 50.0, 4.0])
    assert b.element_state_rates(x, [0.7]) == pytest.approx([50.0 * 0.2 / 4.0 + 0.7], rel=1e-14)
    Rq, Rv, Rs, dQs = b.element_state_jacobians(x, [0.7])
    assert (Rq[0, 0], Rv[0, 0], Rs[0, 0], dQs[0, 0]) == pytest.approx((12.5, 1.0, -12.5, 50.0), rel=1e-14)
    assert plain.element_state_rates(x).shape == (0,) and plain.element_state_jacobians(x)[3].shape == (1, 0)
    import pickle

    for fresh in (model(k * (q - s) / c + qd), b):  # pickled before and after its rates were compiled
        back = pickle.loads(pickle.dumps(fresh))
        assert back.element_states == ("s",) and back._content_digest() == b._content_digest()
        assert back.element_state_rates(x, [0.7]) == pytest.approx(b.element_state_rates(x, [0.7]), rel=1e-14)


def test_a_state_name_that_clashes_is_refused(maxwell):
    from mechcont.errors import InputError

    clash = BLOCK.replace("F = 30.0\n", "F = 30.0\nu_mx = 1.0\n")
    with pytest.raises(InputError) as err:
        model_from_text(clash, "clash.toml")
    assert err.value.field.endswith("states.u_mx") and "clashes" in str(err.value)


def test_an_event_sees_the_element_state(maxwell):
    """A terminal event on the state (``u = 0.15 m``) stops the run when the closed form says it crosses."""
    from scipy.optimize import brentq

    model = model_from_text(BLOCK, "zener.toml")
    iu = model.index("u_mx")

    def reached(t, x, qd):
        return x[iu] - 0.15
    reached.terminal = True
    reached.direction = 1
    sim = simulate(model, model.vector({"x_block": 0.0, "u_mx": 0.0}), (0.0, 2.0), rtol=1e-11, atol=1e-12,
                   method="DOP853", events=[reached])
    z_eq = np.array([F / K1, 0.0, F / K1])
    A = _closed_form_A()
    t_cross = brentq(lambda t: (z_eq - scipy.linalg.expm(A * t) @ z_eq)[2] - 0.15, 0.01, 2.0, xtol=1e-14)
    assert sim.t_events[0][0] == pytest.approx(t_cross, abs=1e-8)
    assert sim["u_mx"][-1] == pytest.approx(0.15, abs=1e-9)


HELD = f"""
[mechanism]
name = "held"
dof = 0
[parameters]
k2 = {K2}
c = {C}
[ground]
O = [0, 0]
S = [-1.0, 0]
[bodies.block]
mass = 1.0
inertia = 0.1
initial = {{ x = 0.3, y = 0, theta = 0 }}
[joints.fix]
type = "weld"
a = "ground.O"
b = "block.origin"
[test_maxwell.mx]
a = "ground.S"
b = "block.origin"
free_length = 0.8
"""


def test_relaxation_of_a_held_maxwell_element_is_exponential(maxwell):
    """Both ends held 1 m apart (free length 0.8 m): from u = 0 the damper creeps as
    ``u(t) = 0.2 (1 - exp(-k2 t / c))`` m and the tension ``k2 (0.2 - u)`` relaxes with it."""
    model = model_from_text(HELD, "held.toml")
    t = np.linspace(0.0, 0.4, 9)
    sim = simulate(model, model.vector({"u_mx": 0.0}), (0.0, 0.4), rtol=1e-12, atol=1e-14, t_eval=t)
    assert np.allclose(sim["u_mx"], 0.2 * (1 - np.exp(-K2 * t / C)), rtol=0, atol=1e-10)
    assert np.allclose(sim["x_block"], 0.0, atol=1e-12)   # the weld holds: only the state moves
