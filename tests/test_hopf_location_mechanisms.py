"""Hopf points of mechanisms located cheaply and their first Lyapunov coefficients accurately (issue 35's speed
criterion, "Hopf location as fast as LP location"): the caster wheel's l1 against its closed form (the physics in
tests/test_caster_tyre_truth.py) in three unit systems and frames, the directional derivatives of the critical
pair's sum against the eigenvalues of nearby linearisations (the shimmy gear: two allowed motions, where each
point's own singular vectors need not move smoothly), and the number of linearisations a location takes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from test_caster_tyre_truth import _truth

from mechcont.continuation import ContinuationOptions, SpecialPoint, continuation, find_equilibrium, locate_hopf
from mechcont.continuation._hopf_point import HopfTest
from mechcont.continuation._problem import EquilibriumProblem
from mechcont.equations import dynamics_of
from mechcont.models import load_model

DATA = Path(__file__).resolve().parent / "data"


def _branch(model, length: float):
    return continuation(model, find_equilibrium(model), "V", hopf=True,
                        options=ContinuationOptions(bounds={"V": (0.5 * length, 50 * length)}))


@pytest.mark.parametrize("name, length, mass", [("caster_tyre", 1.0, 1.0), ("caster_tyre_mm_g", 1e3, 1e3),
                                                ("caster_tyre_moved", 1.0, 1.0)])
def test_caster_lyapunov_coefficient_against_its_closed_form(name, length, mass):
    """l1 from differences of the rates alone: the second and third directional derivatives' errors (about
    eps^(2/3) and eps^(4/7) of the states' scales) leave l1 within 1e-9 (measured 2e-11 to 7e-10); the
    differences of differenced Jacobians before were off by 6e-6, 4e-4 and 2e-4, and moved by 1e-4 when the
    point moved by one ulp."""
    V, omega, l1 = _truth(length, mass)
    model = load_model(str(DATA / f"{name}.toml"))
    hb = _branch(model, length)["HB1"]
    assert hb["V"] == pytest.approx(V, rel=1e-12)
    for point in (hb, locate_hopf(model, hb, "V")):
        h = point.extra["hopf"]
        assert h.frequency == pytest.approx(omega, rel=1e-12)
        assert h.lyapunov == pytest.approx(l1, rel=1e-8)
    # the same point moved by an ulp in its parameters gives the same l1 to that accuracy
    x = np.array(hb.x) * (1 + 2 * np.finfo(float).eps)
    from mechcont.continuation._hopf_point import first_lyapunov

    assert first_lyapunov(dynamics_of(model), x, hb.extra["hopf"].frequency, model)[0] == pytest.approx(l1, rel=1e-8)


@pytest.fixture(scope="module")
def gear():
    from mechcont.paper import _shimmy_analysis as an
    from mechcont.paper.shimmy import gear_at

    model, x1 = gear_at(1.0)
    return model, an.equilibria(model, x1)


def _g(dyn, x):
    """lambda_1 + lambda_2 of the pair nearest to summing to zero, from the eigenvalues alone."""
    lam = dyn.linearise(x).eigenvalues()
    i, j = np.triu_indices(len(lam), 1)
    return float((lam[i] + lam[j])[np.argmin(np.abs(lam[i] + lam[j]))].real)


def test_directional_derivatives_of_the_pair_sum_against_the_eigenvalues_nearby(gear):
    """The shimmy gear (two allowed motions): dg along random directions of the branch's unknowns, from one
    batch of linearisations in x's projected basis, against central differences of g itself (eigenvalues do
    not depend on the basis), Richardson-extrapolated; agreement to 1e-6 of g's slope (differences of g: ~1e-8)."""
    model, branch = gear
    hb = branch["HB1"]
    dyn = dynamics_of(model)
    test = HopfTest(dyn, model)
    problem = EquilibriumProblem(model, hb.x, "V", list(hb.unknowns), stability=False)
    x = np.array(hb.x)
    dirs = np.random.default_rng(1).standard_normal((3, len(problem.idx))) * problem.scale
    got = test.derivatives(x, problem.idx, dirs, test.pair(x))
    row = test.gradient(x, problem.idx, test.pair(x))
    for d, value, g_row in zip(dirs, got, dirs @ row):
        def g_at(s, d=d):
            xs = x.copy()
            xs[problem.idx] += s * d
            return _g(dyn, xs)

        h = 1e-4
        central = [(g_at(k * h) - g_at(-k * h)) / (2 * k * h) for k in (1, 2)]
        truth = (4 * central[0] - central[1]) / 3
        assert value == pytest.approx(truth, rel=1e-6)
        assert g_row == pytest.approx(truth, rel=1e-6)


def test_locating_a_hopf_point_linearises_a_few_times_per_newton_iteration(gear):
    """From the branch row before HB1: the bordered Newton step needs g's slope along two directions only, in one
    batch of five linearisations with the point's own; the whole row took two per unknown and iteration, one
    at a time (about 300 here)."""
    model, branch = gear
    hb = branch["HB1"]
    counts = {"rows": 0, "batches": 0, "single": 0}
    base = dynamics_of(model)

    class Counted(type(base)):  # type: ignore[misc]
        def linearise(self, x):
            counts["rows"] += 1
            counts["single"] += 1
            return super().linearise(x)

        def linearise_near(self, x, X, descriptor=None):
            counts["rows"] += len(X)
            counts["batches"] += 1
            return super().linearise_near(x, X, descriptor)

    dyn = Counted(model)
    start = SpecialPoint("HB", 0, branch.values[hb.index - 1].copy(), hb.names, unknowns=hb.unknowns, vary="V")
    point = locate_hopf(model, start, "V", dynamics=dyn)
    assert point["V"] == pytest.approx(hb["V"], rel=1e-13)
    # one batch per Newton iteration (the point and two directions both ways), one linearisation to confirm
    assert 1 <= counts["batches"] <= 10 and counts["single"] <= 2
    assert counts["rows"] <= 5 * counts["batches"] + counts["single"]


def test_l1_takes_the_pairs_linearisation_turned_into_the_rates_coordinates(gear):
    """l1 at a located Hopf point uses the critical pair's exact linearisation, turned from its allowed motions
    (eta, eta', ds) into the rates' state z by the basis the dynamics linearised with, instead of differencing
    the rates' Jacobian and solving two eigenvalue problems again. Against that differenced Jacobian (central
    differences, about eps^(2/3) ~ 4e-11 of each column: measured 1.6e-11 on this gear of two allowed motions,
    1.4e-10 on the closed four-bar), within 1e-8; its eigenvectors exact to rounding and normalised as the
    formula asks; a point never linearised has no basis (no stale one), and l1 from either way agrees within
    its own differencing error (1e-8)."""
    from mechcont.continuation._hopf_point import first_lyapunov
    from mechcont.continuation._lyapunov import critical_vectors

    model, branch = gear
    x = np.array(branch["HB1"].x)
    dyn = dynamics_of(model)
    pair = HopfTest(dyn, model).pair(x)
    A, q, p = critical_vectors(dyn, x, pair)
    J = dyn.rates_jacobian(dyn.state_at(x), x)
    assert np.all(np.max(np.abs(A - J), axis=0) <= 1e-8 * np.max(np.abs(J), axis=0))
    scale = np.linalg.norm(A, 2)
    assert np.linalg.norm(A @ q - 1j * pair.omega * q) <= 1e-13 * scale
    assert np.linalg.norm(A.T @ p + 1j * pair.omega * p) <= 1e-13 * scale * np.linalg.norm(p)
    assert np.linalg.norm(q) == pytest.approx(1.0, abs=1e-15) and np.vdot(p, q) == pytest.approx(1.0, abs=1e-14)
    moved = x * (1 + 4 * np.finfo(float).eps)
    assert dyn.linearisation_basis(moved) is None
    l1_pair = first_lyapunov(dyn, x, pair.omega, model, pair)[0]
    l1_rates = first_lyapunov(dyn, x, pair.omega, model)[0]
    assert l1_pair == pytest.approx(l1_rates, rel=1e-8)
