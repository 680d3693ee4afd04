"""Cycles of a mechanism (issue 35, item 4): the saturating caster of tests/test_shimmy_dynamics.py, continued from its
Hopf speed through MechanismDynamics' minimal-coordinate rates, against an independent integration of the
caster's three equations (psi, psi_dot, the tyre's lateral deflection y) typed again in test_shimmy_dynamics."""

from __future__ import annotations

import numpy as np
import pytest
from test_shimmy_dynamics import _amplitude_and_period, _reference
from test_tyre import hopf_speeds, text

from mechcont.continuation import ContinuationOptions, cycles_from_hopf, find_equilibrium
from mechcont.equations import dynamics_of
from mechcont.mechanism import parse_description

FMAX = 50.0


@pytest.mark.slow
def test_caster_cycle_from_its_hopf_speed_matches_a_long_simulation_and_keeps_its_constraints():
    v1, v2 = hopf_speeds()
    V = 5.0
    assert v1 < V < v2  # inside the shimmy band: the saturating tyre bounds the oscillation
    model = parse_description(text(extra=f"max_force = {FMAX}")).build(V=v1 * 1.001)
    x = find_equilibrium(model)
    fam = cycles_from_hopf(model, x, "V", at=[V], options=ContinuationOptions(bounds={"V": (0.5 * v1, V + 0.5)}))
    assert fam.p[0] == pytest.approx(v1, rel=1e-8)
    i = fam.row("UZ1")
    assert fam.stability()[i] == "stable"
    # the reference: the independent integration over 30 s, its last 5 s (converged onto the cycle)
    t = np.linspace(0.0, 30.0, 60001)
    psi = _reference(V, FMAX, t)[0]
    last = t >= 25.0
    amp, period = _amplitude_and_period(t[last], psi[last])
    k = fam.state_names.index("theta_wheel")
    assert fam.period[i] == pytest.approx(period, rel=1e-6)
    _, Z = fam.orbit(i, samples=20000)  # the table's max_X is over the nodes only: sample the polynomials densely
    assert Z[:, k].max() == pytest.approx(amp, rel=1e-6)
    assert -Z[:, k].min() == pytest.approx(amp, rel=1e-6)
    assert fam.maximum[i, k] == pytest.approx(amp, rel=1e-4)
    # the constraints hold along the orbit (every node, as full vectors), and only the trivial multiplier is at 1
    dyn = dynamics_of(model)
    mesh, u = fam.orbits[i]
    xv = fam.x_base.copy()
    xv[model.index("V")] = fam.p[i]
    mech = model.mechanics
    full = [dyn.full_vector(z, xv) for z in u]
    phis = np.array([mech.phi(f) for f in full])
    assert phis.shape[1] > 0 and np.max(np.abs(phis)) < 1e-10  # the caster's pin: the swivel on the strut
    vel = np.array([mech.phi_q(f) @ dyn.coordinate_velocities(z, xv) for f, z in zip(full, u)])
    assert np.max(np.abs(vel)) < 1e-9
    # away from the Hopf speed (where the critical pair's multiplier tends to 1) no spurious multiplier at 1 from the
    # constraints: the non-trivial ones are those of psi, psi_dot, y (Floquet of the independent 3-state caster)
    assert len(fam.multipliers[i]) == len(dyn.state_names) - 1
    assert np.min(np.abs(fam.multipliers[i] - 1.0)) > 1e-2
