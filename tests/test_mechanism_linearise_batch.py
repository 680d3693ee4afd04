"""A mechanism's batch of linearisations near a point (``MechanismDynamics.linearise_near``, the Hopf polish's five
per Newton iteration) against an independent construction, row by row, from the mechanics' per-point values:
each row's own singular value decomposition of ``Phi_q`` (its row space ``V``, its reactions ``lam = U S^-1 V^T Q``
at the point's rank), the point's allowed motions ``N0`` projected onto the row's null space (``N = N0 - V^T V
N0``), ``K = -dQ/dq + sum lam_k Hess(Phi_k)``, the mass, damping (plus ``d M``) and element-state derivatives, and
``A = [[0, I, 0], [-Mr^-1 Kr, -Mr^-1 Cr, Mr^-1 Br], [Rq N, Rv N, Rs]]``. Cases: the planar four-bar caster (a
closed loop: the projection moves with the row), the shimmy gear (two allowed motions), the Bennett linkage (three
redundant rows: the rank held at the point's), and rows too far from the point for its decomposition to stand for
theirs. And the cost: the batch decomposes the point's ``Phi_q`` only, not every row's."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mechcont.continuation import find_equilibrium
from mechcont.equations import dynamics_of
from mechcont.models import load_model

DATA = Path(__file__).resolve().parent / "data"


@pytest.fixture(scope="module")
def fourbar():
    model = load_model(str(DATA / "fourbar_shimmy.toml"))
    return model, find_equilibrium(model)


@pytest.fixture(scope="module")
def gear():
    from mechcont.paper.shimmy import gear_at

    model, x = gear_at(1.0)
    return model, np.asarray(x, float)


@pytest.fixture(scope="module")
def bennett():
    model = load_model(str(DATA / "spatial" / "bennett.toml"))
    d0 = model.defaults()
    return model, find_equilibrium(model, hold={"e1_crank": d0[model.index("e1_crank")]}, free=["M"], guess=d0)


def _stencil(model, x, step: float, seed: int = 0, vary: str = "V") -> np.ndarray:
    """``x`` then ``x +- step d`` along two random directions of the states (coordinates, reactions, element
    states) and the parameter ``vary``, each component moved by about ``step`` of its value or scale: the rows of
    a Hopf polish's batch."""
    cols = np.array([i for i, v in enumerate(model.variables) if v.kind == "state"] + [model.index(vary)])
    size = np.maximum(np.abs(x[cols]), np.asarray(model.scales(), float)[cols])
    D = np.random.default_rng(seed).standard_normal((2, len(cols))) * size * step
    X = np.repeat(x[None], 5, axis=0)
    X[1:3, cols] += D
    X[3:5, cols] -= D
    return X


def _truth(model, x, X, damping: float) -> tuple[np.ndarray, np.ndarray]:
    """``(N0, A)``: the point's allowed motions and each row's state matrix in the projected basis, row by row."""
    mech = model.mechanics
    _, s, Vt = np.linalg.svd(mech.phi_q(x))
    r = int(np.count_nonzero(s > 1e-10 * s[0]))
    N0 = Vt[r:].T
    out = []
    for xi in X:
        U, s, Vt = np.linalg.svd(mech.phi_q(xi))
        V = Vt[:r]
        N = N0 - V.T @ (V @ N0)
        lam = U[:, :r] @ ((V @ mech.applied_forces(xi)) / s[:r])
        M = mech.mass(xi)
        K, C = mech.tangent_stiffness(xi, lam), mech.damping_matrix(xi) + damping * M
        Rq, Rv, Rs, dQs = mech.element_state_jacobians(xi)
        Mr = N.T @ M @ N
        d, ns = N.shape[1], Rs.shape[0]
        A = np.zeros((2 * d + ns, 2 * d + ns))
        A[:d, d:2 * d] = np.eye(d)
        A[d:2 * d] = np.linalg.solve(Mr, np.hstack([-N.T @ K @ N, -N.T @ C @ N, N.T @ dQs]))
        A[2 * d:] = np.hstack([Rq @ N, Rv @ N, Rs])
        out.append(A)
    return N0, np.array(out)


def _check(model, x, X, damping: float = 0.0) -> None:
    """The batch's ``A`` of every row against :func:`_truth`, turned by the rotation between the two bases of the
    point's allowed motions (an SVD's null vectors are unique only up to one): within 1e-12 of each row of ``A``
    (its largest entry). Both sides are backward-stable decompositions, products and solves of the same small
    matrices, so they agree to rounding: measured 2e-15 (four-bar, gear) and 7e-14 (the Bennett linkage: 21
    coordinates, 23 constraint rows)."""
    dyn = dynamics_of(model, damping=damping)
    A, E = dyn.linearise_near(x, X)
    assert E is None
    N0, truth = _truth(model, x, X, damping)
    d = N0.shape[1]
    T = dyn.linearisation_basis(x)  # the batch's basis on the independent coordinates: N0_batch = N0 R
    indep = [model.mechanics.coordinates.index(n) for n in dyn.state_names[:d]]
    R = np.linalg.solve(N0[indep], T[:d, :d])
    S = np.eye(A.shape[1])
    S[:d, :d] = S[d:2 * d, d:2 * d] = R
    for got, want in zip(A, truth):
        want = np.linalg.solve(S, want @ S)
        scale = np.max(np.abs(want), axis=1, keepdims=True)
        assert np.all(np.abs(got - want) <= 1e-12 * scale)
    # without the point's own row (the Hopf test's gradient asks so): the same rows, in the same basis
    rest, _ = dyn.linearise_near(x, X[1:])
    for got, want in zip(rest, A[1:]):
        assert np.all(np.abs(got - want) <= 1e-12 * np.max(np.abs(want), axis=1, keepdims=True))


@pytest.mark.parametrize("damping", [0.0, 0.7])
def test_closed_loop_batch_against_row_by_row_truth(fourbar, damping):
    """The four-bar caster near its equilibrium (one allowed motion, a closed loop), with and without mass
    proportional damping, at a Hopf polish's step (6e-6) and at a larger one (1e-3)."""
    model, x = fourbar
    for step in (6e-6, 1e-3):
        _check(model, x, _stencil(model, x, step), damping)


def test_two_allowed_motions_batch_against_row_by_row_truth(gear):
    """The shimmy gear (two allowed motions: the reduced mass a 2 x 2 matrix)."""
    model, x = gear
    _check(model, x, _stencil(model, x, 6e-6))


def test_redundant_rows_batch_against_row_by_row_truth(bennett):
    """The Bennett linkage (spatial): three redundant rows, which turn independent off the constraint manifold by
    the size of the step; every row held at the point's rank."""
    model, x = bennett
    _check(model, x, _stencil(model, x, 6e-6, vary="M"))


def test_rows_far_from_the_point_are_decomposed_each(fourbar):
    """Rows whose constraint Jacobians differ from the point's by more than its smallest singular value (a step
    of 0.3 in every coordinate's scale) are each decomposed: the same truth."""
    model, x = fourbar
    _check(model, x, _stencil(model, x, 0.3, seed=2))


def test_a_batch_decomposes_only_the_points_constraint_jacobian(fourbar, monkeypatch):
    """The cost: a Hopf polish's batch of five near its point decomposes one ``Phi_q`` (the point's); each
    other row's allowed motions and reactions come from that decomposition by one small stacked solve. Rows far
    from the point are decomposed each."""
    from mechcont import _dense

    model, x = fourbar
    dyn = dynamics_of(model)
    rows = {"n": 0}
    svd, dense_svd = np.linalg.svd, _dense.svd

    def counted_svd(a, *args, **kwargs):
        rows["n"] += 1 if np.ndim(a) == 2 else len(a)
        return svd(a, *args, **kwargs)

    def counted_dense_svd(a):
        rows["n"] += 1
        return dense_svd(a)

    dyn.linearise(x)  # the first point asked about chooses the coordinate partition (a decomposition of its own)
    monkeypatch.setattr(np.linalg, "svd", counted_svd)
    monkeypatch.setattr(_dense, "svd", counted_dense_svd)
    dyn.linearise_near(x, _stencil(model, x, 6e-6))
    assert rows["n"] == 1
    rows["n"] = 0
    dyn.linearise_near(x, _stencil(model, x, 0.3, seed=2))
    assert rows["n"] >= 5
