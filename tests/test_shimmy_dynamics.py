"""Shimmy dynamics of a caster wheel with a stretched-string tyre, through the generated model's
dynamics (``dynamics_of``): these need the generator to make each element state (the tyre's
``y_NAME``) a variable of the system with its steady-state row and rate.

The caster wheel (tests/test_tyre.py's description): a wheel pinned to the ground at its centre of
gravity O (polar inertia ``I`` about the pin), its contact point a caster length ``e`` behind the pin
(``P = -e h``, ``h = (cos psi, sin psi)`` the heading, ``l = (-sin psi, cos psi)``), a torsion spring
``k`` and a shimmy damper ``c`` to the ground, and the tyre (relaxation length ``sigma``, cornering
stiffness ``C``) rolling at ``V`` along +x. The contact point moves at ``dP/dt = -e psi' l``, so
``v_lat = (dP/dt + V e_x) . l = -e psi' - V sin psi``, and the side force ``F(y) l`` at ``P``
has the moment ``(-e h) x (F l) = -e F`` about O. The equations of motion:

    I psi'' = -k psi - c psi' - e F(y),
    y'      = e psi' + V sin psi - (V/sigma) y,        F(y) = C y/sigma  (or F_max tanh(C y/(sigma F_max))).

Linearised about straight running (psi = y = 0) with the linear tyre, the state (psi, psi', y) has
``A = [[0, 1, 0], [-k/I, -c/I, -e C/(sigma I)], [V, e, -V/sigma]]`` and the characteristic cubic

    s^3 + a2 s^2 + a1 s + a0,   a2 = c/I + V/sigma,  a1 = (k + (c V + e^2 C)/sigma)/I,
                                a0 = V (k + e C)/(I sigma)

(expand ``det(s - A)`` along its first row: ``s [(s + c/I)(s + V/sigma) + e^2 C/(sigma I)] +
[(k/I)(s + V/sigma) + V e C/(sigma I)]``). Routh-Hurwitz: with ``a2, a0 > 0`` the wheel is stable
iff ``a2 a1 > a0``; at ``a2 a1 = a0`` the cubic is ``(s + a2)(s^2 + a1)``: a Hopf point with the
pair ``+-i sqrt(a1)``. Multiplying ``a2 a1 - a0 = 0`` by ``I^2 sigma^2 / I`` gives the quadratic in
the speed

    I c V^2 + (c^2 sigma + I e C (e - sigma)) V + c sigma (e^2 C + k sigma) = 0,

whose two positive roots bound the shimmy band when ``e < sigma`` (the middle coefficient must be
negative): ``tests/test_tyre.py::hopf_speeds``. The relaxation after a step in heading: a wheel
held at heading ``psi0`` from ``t = 0`` with ``y(0) = 0`` has ``y' = V sin psi0 - (V/sigma) y``, so
``y(t) = sigma sin psi0 (1 - exp(-V t/sigma))``; its eigenvalue is ``-V/sigma``.

Tolerances: eigenvalues from exact Jacobians agree to 1e-8 relative; integrations at rtol 1e-10
agree with the closed form / an independent scipy integration of the equations above to 1e-8 rad
and 1e-9 m (measured: about 5e-11 and 1e-11; an integration error grows at most with the cycle's
own growth, from 0.09 rad to 0.093 rad here), the limit cycle's amplitude and period to 1e-6
relative between the two, measured over its last two seconds.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_tyre import CASTER3, CD, CS, SIGMA, E, I, K, hopf_speeds, text

from mechcont.continuation import find_equilibrium
from mechcont.mechanism import parse_description

STEP = """
[mechanism]
name = "held_wheel"
dof = 0
[parameters]
V = {V}
psi0 = {psi0}
[ground]
O = [0, 0]
[bodies.wheel]
mass = 2.0
inertia = 0.5
points = {{ contact = [-0.1, 0] }}
[joints.weld]
type = "weld"
a = "ground.O"
b = "wheel.origin"
angle = "psi0"
[tyres.nose]
body = "wheel"
at = "contact"
speed = "V"
relaxation_length = {sigma}
cornering_stiffness = {C}
"""


def dynamics(model):
    from mechcont.equations import dynamics_of

    return dynamics_of(model)


def coefficients(V, c=CD, k=K, e=E, sigma=SIGMA, C=CS, inertia=I):
    """(a2, a1, a0) of the caster's characteristic cubic (see the module docstring)."""
    return c / inertia + V / sigma, (k + (c * V + e * e * C) / sigma) / inertia, V * (k + e * C) / (inertia * sigma)


def test_steady_state_of_a_held_wheel_is_sigma_sin_psi_and_relaxes_at_v_over_sigma():
    V, psi0 = 12.0, 0.15
    model = parse_description(STEP.format(V=V, psi0=psi0, sigma=SIGMA, C=CS)).build()
    x = find_equilibrium(model)
    assert x[model.index("y_nose")] == pytest.approx(SIGMA * math.sin(psi0), rel=1e-10)
    dyn = dynamics(model)
    lam = dyn.linearise(x).eigenvalues()
    assert np.min(np.abs(lam + V / SIGMA)) < 1e-8 * V / SIGMA
    # the step in heading: y(0) = 0 at heading psi0, then y -> sigma sin psi0 at the rate V/sigma
    z0 = dyn.state_at(x)
    iy = dyn.state_names.index("y_nose")
    z0[iy] = 0.0
    t = np.linspace(0.0, 5 * SIGMA / V, 11)
    sol = solve_ivp(lambda _t, z: dyn.rates(z, x), (0.0, t[-1]), z0, t_eval=t, rtol=1e-10, atol=1e-13,
                    method="DOP853")
    exact = SIGMA * math.sin(psi0) * (1 - np.exp(-V * t / SIGMA))
    np.testing.assert_allclose(sol.y[iy], exact, atol=1e-9)


@pytest.fixture(scope="module")
def caster():
    return parse_description(text())


@pytest.fixture(scope="module")
def caster3():
    return parse_description(text(CASTER3))


def _eigenvalues(mech, V, **kw):
    model = mech.build(V=V, **kw)
    x = find_equilibrium(model)
    return dynamics(model).linearise(x).eigenvalues()


@pytest.mark.parametrize("V", [0.5, 3.0, 10.0, 25.0])
def test_linearised_caster_has_the_roots_of_the_cubic(caster, V):
    lam = _eigenvalues(caster, V)
    roots = np.roots([1.0, *coefficients(V)])
    assert len(lam) == 3, lam          # the pin's constraints leave psi, psi' and y
    for r in roots:
        assert np.min(np.abs(lam - r)) < 1e-8 * max(1.0, abs(r)), (r, lam)


def test_hopf_speeds_from_routh_hurwitz(caster):
    v1, v2 = hopf_speeds()
    assert 0 < v1 < v2
    for vh in (v1, v2):
        lam = _eigenvalues(caster, vh)
        a2, a1, _ = coefficients(vh)
        pair = lam[np.argmax(lam.imag)]
        assert abs(pair.real) < 1e-8 * math.sqrt(a1)
        assert pair.imag == pytest.approx(math.sqrt(a1), rel=1e-8)      # the Hopf frequency sqrt(a1)
        assert np.min(np.abs(lam + a2)) < 1e-8 * a2                      # the third root -a2
    assert max(_eigenvalues(caster, 0.5 * (v1 + v2)).real) > 0            # shimmy inside the band
    assert max(_eigenvalues(caster, 2 * v2).real) < 0                    # stable above it


def _reduced_eigenvalues(mech, V):
    model = mech.build_reduced(V=V)
    x = find_equilibrium(model)
    return dynamics(model).linearise(x).eigenvalues()


def test_planar_spatial_reduced_and_moved_frame_casters_agree(caster, caster3):
    """The same wheel described in space, in the reduced form, and with its frame origin at the
    contact point instead of the pin (the pin at ``wheel.swivel``) has the same eigenvalues."""
    moved_text = text().replace("cg = [0, 0]", f"cg = [{E}, 0]").replace(
        f"points = {{ contact = [{-E}, 0] }}", f"points = {{ swivel = [{E}, 0], contact = [0, 0] }}").replace(
        'b = "wheel.origin"', 'b = "wheel.swivel"')
    assert "wheel.swivel" in moved_text and f"cg = [{E}, 0]" in moved_text
    moved = parse_description(moved_text)
    for V in (2.0, 12.0):
        lam2 = _eigenvalues(caster, V)
        others = (_eigenvalues(caster3, V), _reduced_eigenvalues(caster, V), _eigenvalues(moved, V))
        for lam in others:
            assert len(lam) == len(lam2) == 3
            for r in lam2:
                assert np.min(np.abs(lam - r)) < 1e-8 * max(1.0, abs(r))


PSI0 = 0.09


def _reference(V, fmax, t):
    def rhs(_t, z):
        psi, w, y = z
        F = fmax * math.tanh(CS * y / (SIGMA * fmax))
        return [w, (-K * psi - CD * w - E * F) / I, E * w + V * math.sin(psi) - V / SIGMA * y]

    return solve_ivp(rhs, (0.0, t[-1]), [PSI0, 0.0, 0.0], t_eval=t, rtol=1e-11, atol=1e-13, method="DOP853").y


def _amplitude_and_period(t, psi):
    up = [t[i] - psi[i] * (t[i + 1] - t[i]) / (psi[i + 1] - psi[i]) for i in range(len(t) - 1)
          if psi[i] < 0 <= psi[i + 1]]
    return float(np.max(np.abs(psi))), float(np.mean(np.diff(up)))


def test_saturating_tyre_limit_cycle_matches_an_independent_integration():
    """Inside the shimmy band the saturating tyre bounds the oscillation: a limit cycle (amplitude
    0.0926568 rad, period 0.5001 s at V = 5 m/s, F_max = 50 N, by a 30 s reference run), approached
    from psi = 0.09 rad at rest: after 4 s within 3e-5 of its amplitude."""
    V, fmax = 5.0, 50.0
    model = parse_description(text(extra=f"max_force = {fmax}")).build(V=V)
    x = find_equilibrium(model)
    dyn = dynamics(model)
    z0 = dyn.state_at(x)
    ipsi, iy = dyn.state_names.index("theta_wheel"), dyn.state_names.index("y_nose")
    z0[ipsi] = PSI0
    t = np.linspace(0.0, 6.0, 12001)
    sol = solve_ivp(lambda _t, z: dyn.rates(z, x), (0.0, t[-1]), z0, t_eval=t, rtol=1e-11, atol=1e-13,
                    method="DOP853")
    ref = _reference(V, fmax, t)
    np.testing.assert_allclose(sol.y[ipsi], ref[0], atol=1e-8)
    np.testing.assert_allclose(sol.y[iy], ref[2], atol=1e-9)
    last = t >= 4.0
    amp, period = _amplitude_and_period(t[last], sol.y[ipsi][last])
    amp_ref, period_ref = _amplitude_and_period(t[last], ref[0][last])
    assert amp == pytest.approx(amp_ref, rel=1e-6) and period == pytest.approx(period_ref, rel=1e-6)
    assert amp == pytest.approx(0.0926568, rel=1e-4) and period == pytest.approx(0.5001, rel=1e-3)


def test_check_reports_the_tyre_state_and_the_speed_parameter():
    from cli_helpers import make_runner

    result = make_runner()("check", "examples/shimmy.toml")
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert any(ln.split()[:1] == ["y_nose"] and "lateral deflection" in ln and "speed V" in ln for ln in lines), \
        result.output
    assert any(ln.split()[:1] == ["V"] and "m/s" in ln for ln in lines), result.output


def test_the_drawing_shows_the_contact_point_and_the_side_force(caster):
    model = caster.build(V=10.0)
    x = find_equilibrium(model)
    x[model.index("theta_wheel")] = 0.1
    x[model.index("y_nose")] = 0.004
    scene = model.scene(x)
    (force,) = [f for f in scene.forces if f[0] == "nose"]
    psi = 0.1
    np.testing.assert_allclose(force[1], [-E * math.cos(psi), -E * math.sin(psi)], atol=1e-12)
    np.testing.assert_allclose(force[2], CS * 0.004 / SIGMA * np.array([-math.sin(psi), math.cos(psi)]), rtol=1e-12)
    assert any(name == "tyre nose" for name, _ in scene.points)



def test_onset_speed_by_bisection_is_the_lower_routh_hurwitz_speed(caster):
    from mechcont.paper.shimmy import leading_eigenvalue, onset_speed

    v1, v2 = hopf_speeds()
    assert onset_speed(caster, speeds=(0.2, 0.5 * (v1 + v2)), samples=4, tol=1e-9) == pytest.approx(v1, rel=1e-8)
    lam = leading_eigenvalue(v1, caster)
    assert lam.imag == pytest.approx(math.sqrt(coefficients(v1)[1]), rel=1e-8) and abs(lam.real) < 1e-7


def test_the_example_runs_straight_at_its_steady_state_and_more_damping_delays_shimmy():
    from mechcont.paper.shimmy import gear_at, onset_speed

    model, x = gear_at(40.0)
    for name in ("theta_wheel", "y_strut", "y_nose"):
        assert abs(x[model.index(name)]) < 1e-12
    low, high = onset_speed(c_psi=10.0, samples=6, tol=1e-3), onset_speed(c_psi=30.0, samples=6, tol=1e-3)
    assert low is not None and high is not None and low < high   # a stiffer damper shimmies later


def test_simulate_relaxes_the_tyre_after_a_step_in_heading():
    """``simulate`` integrates the state with the mechanism: the held wheel from y = 0 at heading psi0."""
    from mechcont.dynamics import simulate

    V, psi0 = 12.0, 0.15
    model = parse_description(STEP.format(V=V, psi0=psi0, sigma=SIGMA, C=CS)).build()
    x0 = find_equilibrium(model)
    x0[model.index("y_nose")] = 0.0
    t = np.linspace(0.0, 5 * SIGMA / V, 11)
    sim = simulate(model, x0, (0.0, t[-1]), rtol=1e-10, atol=1e-12, t_eval=t)
    exact = SIGMA * math.sin(psi0) * (1 - np.exp(-V * t / SIGMA))
    np.testing.assert_allclose(np.asarray(sim["y_nose"]), exact, atol=1e-9)


def test_simulate_follows_the_saturating_caster_onto_its_cycle():
    """``simulate`` (the constrained equations of motion on all coordinates, not the dynamics' minimal
    coordinates) against the same independent integration as above, over its first 3 s."""
    from mechcont.dynamics import simulate

    V, fmax = 5.0, 50.0
    model = parse_description(text(extra=f"max_force = {fmax}")).build(V=V)
    x0 = find_equilibrium(model)
    x0[model.index("theta_wheel")] = PSI0        # the frame origin is on the pin: still assembled
    t = np.linspace(0.0, 3.0, 601)
    sim = simulate(model, x0, (0.0, t[-1]), rtol=1e-10, atol=1e-12, t_eval=t)
    ref = _reference(V, fmax, t)
    np.testing.assert_allclose(np.asarray(sim["theta_wheel"]), ref[0], atol=1e-8)   # measured 5e-11
    np.testing.assert_allclose(np.asarray(sim["y_nose"]), ref[2], atol=1e-9)        # measured 1e-11


def test_stability_grid_has_the_sign_of_the_routh_hurwitz_condition(caster):
    """Unstable exactly where ``a2 a1 < a0`` (with ``a2, a0 > 0``), over speeds x damper rates."""
    from mechcont.paper.shimmy import stability_grid

    speeds, rates = [0.5, 3.0, 10.0, 20.0, 60.0], [0.5, 2.0, 8.0]
    grid = stability_grid(speeds, "c", rates, caster)
    for row, c in zip(grid, rates):
        for re, V in zip(row, speeds):
            a2, a1, a0 = coefficients(V, c=c)
            assert (re > 0) == (a2 * a1 < a0), (V, c, re, a2 * a1 - a0)
