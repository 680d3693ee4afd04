"""The batched rates of a mechanism (``MechanismDynamics.rates_batch`` and its Jacobians) against the
point-by-point rates.

Truth: ``rates_batch`` runs the same compiled code and the same Newton iteration row by row as ``rates``
(a row leaves the iteration when its own test passes), so each row must equal the point-by-point rates to
rounding: 1e-12 relative to the row's largest rate (the stacked solves may order their sums differently).
The batched Jacobians are central differences of the same rates with the same steps: they must equal
central differences of the point-by-point ``rates`` computed here to 1e-6 of the largest entry (the
differences divide a rounding of ~1e-15 by a step of ~6e-6: about 1e-10 relative; 1e-6 leaves room
for a step that lands at another Newton iterate). The four-bar has nonlinear constraints (its dependent
coordinates take Newton iterations), the shimmy gear linear ones and a first-order tyre state; the
states are taken well away from the equilibrium with non-zero velocities (the velocity-product and
constraint-curvature terms of the KKT system), with and without mass-proportional damping.
"""

from __future__ import annotations

import numpy as np
import pytest

from mechcont.continuation import find_equilibrium
from mechcont.continuation._cycle_system import RateFunction
from mechcont.equations._mechanism_dynamics import FD_STEP, MechanismDynamics
from mechcont.models import load_model
from mechcont.paper.shimmy import gear_at


@pytest.fixture(scope="module")
def fourbar():
    model = load_model("fourbar")
    return model, find_equilibrium(model, guess={"theta_crank": 1.2})


@pytest.fixture(scope="module")
def shimmy():
    return gear_at(50.0)


def _states(dyn, x, spread, m=12, seed=3):
    z0 = dyn.state_at(x)
    rng = np.random.default_rng(seed)
    return z0 + spread * rng.standard_normal((m, len(z0)))


def _fd_jacobian(dyn, z, x):
    """Central differences of the point-by-point rates (the same steps as the dynamics')."""
    J = np.zeros((len(z), len(z)))
    for j, h in enumerate(FD_STEP * np.maximum(np.abs(z), dyn._steps(z, x) / FD_STEP)):
        zp, zm = z.copy(), z.copy()
        zp[j] += h
        zm[j] -= h
        J[:, j] = (dyn.rates(zp, x) - dyn.rates(zm, x)) / (zp[j] - zm[j])
    return J


@pytest.mark.parametrize("case", ["fourbar", "shimmy"])
@pytest.mark.parametrize("damping", [0.0, 0.7])
def test_batched_rates_and_jacobians_equal_the_point_by_point_ones(case, damping, request):
    model, x = request.getfixturevalue(case)
    dyn = MechanismDynamics(model, damping=damping, reference=x)
    Z = _states(dyn, x, 0.05)
    F = dyn.rates_batch(Z, x)
    for z, f in zip(Z, F):
        expected = dyn.rates(z, x)
        assert np.max(np.abs(f - expected)) <= 1e-12 * np.max(np.abs(expected))
    J = dyn.rates_jacobian_batch(Z, x)
    for z, jac in zip(Z, J):
        expected = _fd_jacobian(dyn, z, x)
        assert np.max(np.abs(jac - expected)) <= 1e-6 * np.max(np.abs(expected))
        assert np.allclose(dyn.rates_jacobian(z, x), jac, rtol=0, atol=1e-12 * np.max(np.abs(jac)))
    name = "V" if case == "shimmy" else "k"
    i = model.index(name)
    P = dyn.parameter_rates_batch(Z, x, [name])
    for z, p in zip(Z, P):
        h = FD_STEP * max(abs(x[i]), model.scales()[i])
        xp, xm = x.copy(), x.copy()
        xp[i] += h
        xm[i] -= h
        expected = (dyn.rates(z, xp) - dyn.rates(z, xm)) / (xp[i] - xm[i])
        assert np.max(np.abs(p[:, 0] - expected)) <= 1e-6 * max(np.max(np.abs(expected)), 1e-300)


def test_batched_rates_reject_a_row_of_the_wrong_length(shimmy):
    from mechcont.errors import InputError

    model, x = shimmy
    dyn = MechanismDynamics(model, reference=x)
    with pytest.raises(InputError, match="Z"):
        dyn.rates_batch(np.zeros((3, len(dyn.state_names) + 1)), x)


class _PointByPoint:
    """The Dynamics protocol of ``dyn`` without its batch methods."""

    def __init__(self, dyn):
        self._dyn = dyn
        self.state_names = dyn.state_names

    def state_at(self, x):
        return self._dyn.state_at(x)

    def rates(self, z, x):
        return self._dyn.rates(z, x)

    def rates_jacobian(self, z, x):
        return self._dyn.rates_jacobian(z, x)

    def parameter_rates(self, z, x, names):
        return self._dyn.parameter_rates(z, x, names)


def test_cycle_rate_function_uses_the_batch_with_the_same_values(shimmy):
    model, x = shimmy
    dyn = MechanismDynamics(model, reference=x)
    Z = _states(dyn, x, 0.05, m=8)
    batched = RateFunction(model, dyn, "V", x)
    plain = RateFunction(model, _PointByPoint(dyn), "V", x)
    assert batched._dyn_batch and not plain._dyn_batch
    for a, b in zip(batched(Z, 50.0), plain(Z, 50.0)):
        assert np.allclose(a, b, rtol=0, atol=1e-10 * np.max(np.abs(b)))


class _Counting(_PointByPoint):
    """The protocol with the batched rates and Jacobian too, counting the calls of each."""

    def __init__(self, dyn):
        super().__init__(dyn)
        self.calls = {"rates_jacobian": 0, "rates_jacobian_batch": 0, "rates_batch": 0}

    def rates_batch(self, Z, x):
        self.calls["rates_batch"] += 1
        return self._dyn.rates_batch(Z, x)

    def rates_jacobian(self, z, x):
        self.calls["rates_jacobian"] += 1
        return self._dyn.rates_jacobian(z, x)

    def rates_jacobian_batch(self, Z, x):
        self.calls["rates_jacobian_batch"] += 1
        return self._dyn.rates_jacobian_batch(Z, x)


def test_lyapunov_coefficient_takes_its_rates_in_two_batches_with_the_same_value(shimmy):
    """``first_lyapunov`` on a mechanism: the rates its directional differences need in two batched calls
    where the dynamics offers them (the second and third derivatives along q's parts, then the products with
    h11 and h20), one Jacobian, and the same ``l1`` as rate by rate. The third differences amplify a
    rounding difference of the rates (1e-16) to about eps / eps^(3/7) ~ 1e-9 relative: 1e-6 relative. The point
    is the gear's Hopf point (its speed and frequency from
    the linearisation's leading pair, bisected by ``onset_speed``)."""
    from mechcont.continuation._hopf_point import first_lyapunov
    from mechcont.paper.shimmy import onset_speed

    model, x = gear_at(onset_speed())
    dyn = MechanismDynamics(model, reference=x)
    lam = np.linalg.eigvals(dyn.linearise(x).A)
    omega = float(np.max(np.abs(lam[np.argsort(-lam.real)[:2]].imag)))
    counting = _Counting(dyn)
    l1_batch = first_lyapunov(counting, x, omega)[0]
    assert counting.calls == {"rates_jacobian": 1, "rates_jacobian_batch": 0, "rates_batch": 2}
    l1_plain = first_lyapunov(_PointByPoint(dyn), x, omega)[0]
    assert l1_batch == pytest.approx(l1_plain, rel=1e-6)
    assert l1_batch != 0.0


def test_shimmy_simulation_keeps_interpolants_only_at_its_end_with_solve_ivps_values():
    """``simulate_onto`` steps DOP853 itself and builds the interpolants (three more rates per step) only
    over the last ``WINDOW`` seconds: its samples there must be solve_ivp's dense output of the same
    integration (the same steps: equal to rounding, 1e-12 rad), and start within one step of the window."""
    from scipy.integrate import solve_ivp

    from mechcont.equations import dynamics_of
    from mechcont.paper import _shimmy_analysis as an
    from mechcont.paper.shimmy import shimmy_mechanism

    mech = shimmy_mechanism()
    until = 0.3
    sim = an.simulate_onto(60.0, mech, until=until)
    model, x = gear_at(60.0, mech)
    dyn = dynamics_of(model)
    z0 = np.array(dyn.state_at(x), float)
    k = dyn.state_names.index(an.TORSION)
    z0[k] = sim.disturbance
    ref = solve_ivp(lambda _t, z: dyn.rates(z, x), (0.0, until), z0, method="DOP853", rtol=1e-8, atol=1e-10,
                    dense_output=True)
    assert np.max(np.abs(sim.torsion - ref.sol(sim.t)[k])) < 1e-12
    steps = np.diff(ref.t)
    assert until - an.WINDOW - steps.max() <= sim.t[0] <= until - an.WINDOW + 1e-4
