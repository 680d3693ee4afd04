"""The paper-style 25-equation nose gear: assembly, exact derivatives, balance, closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from mechcont.errors import InputError
from mechcont.models.nose_gear import COORDINATES, FORCES, build_nose_gear, overcentre_angle
from mechcont.models.nose_gear_geometry import (
    aligned_downlock_force,
    aligned_lock_lug,
    defaults,
    downlocked_pose,
    pose,
)


@pytest.fixture(scope="module")
def gear():
    return build_nose_gear()


def _solve(gear, **values):
    """Equilibrium with theta4 held at 0 and F free (scipy-free: plain Newton on the 25 equations)."""
    from mechcont.continuation import find_equilibrium

    return find_equilibrium(gear, values=values, hold={"theta4": 0.0}, free=["F"], guess=gear.downlock.pose)


def test_counts_match_the_paper(gear):
    assert len(gear.equations) == 25
    assert len(gear.state_names) == 25
    assert set(gear.state_names) == set(COORDINATES) | set(FORCES)
    assert len(gear.mechanics.constraints) == 14


def test_downlocked_pose_is_level_and_aligned(gear):
    v = gear.as_dict(gear.downlock.pose)
    assert v["theta4"] == 0.0
    assert abs(v["theta5"]) < 1e-12
    assert abs(overcentre_angle(v["theta4"], v["theta5"]) - np.pi) < 1e-12
    assert np.max(np.abs(gear.residual(gear.downlock.pose))) < 1e-9


def test_closed_form_pose_satisfies_the_constraints(gear):
    p = defaults()
    for t3 in (1.2, 1.3, 1.38):
        for side in (-1, 1):
            q = pose(p, t3, lock_side=side)
            x = gear.vector(q)
            assert np.max(np.abs(gear.mechanics.phi(x))) < 1e-12


def test_downlock_force_matches_virtual_work_closed_form(gear):
    """The 25-equation solution and the dead-centre virtual-work formula are independent derivations."""
    F = gear.as_dict(gear.downlock.pose)["F"]
    assert F == pytest.approx(aligned_downlock_force(defaults()), rel=1e-12)
    # the weight of the lock links alone, with no spring
    assert gear.as_dict(_solve(gear, k=0.0))["F"] == pytest.approx((2.5 + 2.0) * 9.81 / 2, rel=1e-12)


def test_jacobian_matches_finite_differences(gear):
    rng = np.random.default_rng(1)
    x = gear.downlock.pose + 0.05 * rng.standard_normal(len(gear.names)) * gear.scales()
    J = gear.jacobian(x)
    h = 1e-6 * gear.scales()
    fd = np.empty_like(J)
    for j in range(len(x)):
        e = np.zeros_like(x)
        e[j] = h[j]
        fd[:, j] = (gear.residual(x + e) - gear.residual(x - e)) / (2 * h[j])
    scale = np.maximum(1.0, np.abs(J))
    assert np.max(np.abs(J - fd) / scale) < 1e-6


def test_inter_link_forces_are_the_multipliers_of_the_energy_model(gear):
    """Phi_q^T lambda = Q with lambda built from the R states: free-body rows vs sympy energy."""
    g = gear
    for U, l_sp1 in ((0.0, 0.1), (80.0, -0.05)):
        x = _solve(gear, U=U, l_sp1=l_sp1)
        v = g.as_dict(x)
        R = {n: np.array([v[f"{n}x"], v[f"{n}y"]]) for n in ("R12", "R14", "R23", "R45", "R53")}
        mech = g.mechanics
        RA = R["R12"] + R["R14"] + np.array([0, v["m1"] * v["g"]])
        # constraint order: A, knee12, lug23, pivotO, knee14, joint45, lug53 (see the module)
        Q = mech.applied_forces(x)
        lam_A = -RA
        # O: residual of the bar-3 force balance gives the ground reaction; solve it from Q
        rest = np.concatenate([lam_A, R["R12"], R["R23"], [0, 0], R["R14"], R["R45"], R["R53"]])
        A = mech.phi_q(x).T
        lam_O = np.linalg.lstsq(A[:, 6:8], Q - A @ rest, rcond=None)[0]
        rest[6:8] = lam_O
        assert np.max(np.abs(A @ rest - Q)) < 1e-8 * max(1.0, np.max(np.abs(Q)))


def test_static_balance_by_virtual_work(gear):
    x = gear.downlock.pose
    Z = gear.mechanics.allowed_motions(x)
    assert Z.shape[1] == 1
    assert abs(float(Z[:, 0] @ gear.mechanics.applied_forces(x))) < 1e-9


def test_dead_centre_makes_drag_and_gear_weight_irrelevant(gear):
    F0 = gear.as_dict(gear.downlock.pose)["F"]
    for kw in ({"U": 100.0}, {"m3": 200.0, "m1": 30.0}):
        assert gear.as_dict(_solve(gear, **kw))["F"] == pytest.approx(F0, abs=1e-9)


def test_misaligned_lug_lets_drag_in(gear):
    L35, psi2 = aligned_lock_lug(defaults(), offset=0.002)
    v0 = gear.as_dict(_solve(gear, L35=L35, psi2=psi2))
    v1 = gear.as_dict(_solve(gear, L35=L35, psi2=psi2, U=100.0))
    assert abs(overcentre_angle(v0["theta4"], v0["theta5"]) - np.pi) > 1e-4
    assert abs(v1["F"] - v0["F"]) > 0.1


def test_stability_is_physical_and_matches_energy(gear):
    """Reduced stiffness equals V'' along the one allowed motion (finite differences of V on the manifold)."""
    x = gear.downlock.pose
    st = gear.mechanics.stability(x)
    assert st.conservative and st.n_unstable == 0
    # V along the mechanism's motion parametrised by theta4 (closed-form assembly)
    import sympy as sp

    V = sp.lambdify([sp.Symbol(n, real=True) for n in gear.names], gear.potential_energy)
    p = gear.as_dict(x)

    def energy(t4):
        q = downlocked_pose(p, t4)
        return V(*gear.vector(q, base=x))

    h = 1e-4
    d2V = (energy(h) - 2 * energy(0.0) + energy(-h)) / h**2
    Z = gear.mechanics.allowed_motions(x)[:, 0]
    i4 = COORDINATES.index("theta4")
    z = Z / Z[i4]  # motion per unit theta4
    K = gear.mechanics.tangent_stiffness(x)
    assert float(z @ K @ z) == pytest.approx(d2V, rel=1e-4)


def test_scene_draws_five_bars(gear):
    sc = gear.scene(gear.downlock.pose)
    assert len(sc.bars) == 5 and len(sc.grounds) == 2 and len(sc.springs) == 1
    xmin, xmax, ymin, ymax = sc.extent()
    assert ymin < -1.9 and xmin <= -1.4 + 1e-12


def test_bad_parameter_names_and_values():
    with pytest.raises(InputError, match="l_sp3"):
        build_nose_gear(l_sp3=0.1)
    with pytest.raises(InputError, match="k"):
        defaults(k=float("nan"))
    with pytest.raises(InputError, match="theta4"):
        downlocked_pose(defaults(), 2.5)


def test_drag_enters_the_tangent_stiffness(gear):
    """With drag (a moment depending on theta3) the reduced stiffness is -d(generalised force)/d(theta4)
    along the mechanism's motion, by finite differences of Q . dq/dtheta4 on closed-form poses."""
    L35, psi2 = aligned_lock_lug(defaults(), offset=-0.03)  # far from the dead centre: drag matters
    vals = {"L35": L35, "psi2": psi2, "U": 100.0}
    x = _solve(gear, **vals)
    p = gear.as_dict(x)
    mech = gear.mechanics
    iq = [gear.index(n) for n in COORDINATES]

    def q_of(t4):
        return np.array([downlocked_pose(p, t4)[n] for n in COORDINATES])

    def generalised_force(t4, h=1e-6):
        y = x.copy()
        y[iq] = q_of(t4)
        dq = (q_of(t4 + h) - q_of(t4 - h)) / (2 * h)
        return float(mech.applied_forces(y) @ dq)

    assert abs(generalised_force(0.0)) < 1e-6  # equilibrium by virtual work, drag included
    h = 1e-4
    k_fd = -(generalised_force(h) - generalised_force(-h)) / (2 * h)
    Z = mech.allowed_motions(x)[:, 0]
    z = Z / Z[COORDINATES.index("theta4")]
    k_model = float(z @ mech.tangent_stiffness(x) @ z)
    assert k_model == pytest.approx(k_fd, rel=1e-5)
    # the drag's own derivative is a visible part of it: dropping it would fail the check above
    i3 = COORDINATES.index("theta3")
    d_drag = -mech._dQdq(mech._args(x))[i3, i3] + mech._dQdq(mech._args(gear.vector({"U": 0.0}, base=x)))[i3, i3]
    assert abs(d_drag * z[i3] ** 2) > 10 * 1e-5 * abs(k_model)  # 10x the tolerance of the check above


def test_equilibrium_rows_are_in_newtons(gear):
    """Plain SI, no row scaling: 1 N more of F changes bar 4's vertical force row by 1 N and
    its moment row by 1 N times the arm L4/2 (m) from the centre to J."""
    x = gear.downlock.pose
    J = gear.jacobian(x)
    rows = {n: i for i, n in enumerate(gear.equation_names)}
    iF = gear.index("F")
    v = gear.as_dict(x)
    assert J[rows["force4_y"], iF] == pytest.approx(1.0, rel=1e-14)
    assert J[rows["force4_x"], iF] == 0.0
    assert J[rows["moment4"], iF] == pytest.approx(v["L4"] / 2 * np.cos(v["theta4"]), rel=1e-14)


def test_structure_from_the_disk_cache_is_the_derived_one():
    """A new process loads the gear's equations from the disk cache: the same system as deriving them."""
    import pickle

    from mechcont.equations import Model
    from mechcont.models import nose_gear

    system = nose_gear._structure()
    derived, V2 = nose_gear._derive_structure()
    assert system.potential_energy == V2 and system.equation_names == derived.equation_names
    assert system.equations == derived.equations
    back = pickle.loads(pickle.dumps(Model.from_system(derived, potential_energy=V2)))  # what the cache stores and loads
    assert back.potential_energy == V2
    rng = np.random.default_rng(2)
    x0 = system.defaults()
    for _ in range(5):
        x = x0 * (1 + 0.01 * rng.normal(size=len(x0)))
        for s in (derived, back):
            assert np.array_equal(s.residual(x), system.residual(x))
            assert np.array_equal(s.jacobian(x), system.jacobian(x))
