"""The compiled condensation of parameters (``_ccondense``) against the NumPy/LAPACK one and the whole dense system.

Both paths factor the same collocation Jacobian; they differ in the order of their eliminations (the compiled
one pivots the reduced system within its block structure, LAPACK over whole columns), so they agree to
rounding amplified by the system's condition number, and each is checked against ``numpy.linalg.solve`` of the
whole Jacobian assembled from the same blocks.
"""

import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from mechcont.continuation import _kernel, cycles_from_hopf
from mechcont.continuation._collocation import Mesh
from mechcont.continuation._condensation import Border, CondensedLU
from mechcont.continuation._cycle_system import CycleSystem, RateFunction, phase_reference
from mechcont.equations import dynamics_of, ode_model

needs_kernel = pytest.mark.skipif(_kernel._cc is None, reason="the compiled condensation was not built (no C compiler)")
EPS = np.finfo(float).eps


def both(monkeypatch, run):
    """``run()`` with the compiled condensation, then with NumPy's."""
    monkeypatch.delenv("MECHCONT_PURE_PYTHON", raising=False)
    assert _kernel.condensation() is not None
    compiled = run()
    monkeypatch.setenv("MECHCONT_PURE_PYTHON", "1")
    assert _kernel.condensation() is None
    python = run()
    monkeypatch.delenv("MECHCONT_PURE_PYTHON")
    return compiled, python


def random_blocks(ntst, ncol, n, seed):
    """Collocation-shaped blocks whose transfer matrices range over four decades (so that the reduced
    system's pivots come from the identity, the transfer blocks and the periodicity rows in turn)."""
    rng = np.random.default_rng(seed)
    mn = ncol * n
    S = rng.standard_normal((ntst, mn, mn)) + 3 * np.eye(mn)
    L = rng.standard_normal((ntst, mn, n)) * 10.0 ** rng.uniform(-2, 2, (ntst, 1, 1))
    aT, ap = rng.standard_normal((ntst, mn)), rng.standard_normal((ntst, mn))
    mesh = Mesh(ntst, ncol)
    phase = rng.standard_normal(mesh.n_nodes * n)
    closing = rng.standard_normal(mesh.n_nodes * n + 2)
    return mesh, S, L, aT, ap, phase, closing, rng


def whole(mesh, S, L, aT, ap, phase, closing, n):
    """The whole Jacobian (dense) from the blocks: collocation rows, periodicity, phase, closing."""
    ntst, m = mesh.ntst, mesh.ncol
    mn, size = m * n, mesh.n_nodes * n + 2
    J = np.zeros((size, size))
    for j in range(ntst):
        rows = slice(j * mn, (j + 1) * mn)
        J[rows, j * mn:j * mn + n] = L[j]
        J[rows, j * mn + n:(j + 1) * mn + n] = S[j]
        J[rows, -2], J[rows, -1] = aT[j], ap[j]
    per = ntst * mn + np.arange(n)
    J[per, np.arange(n)] = -1.0
    J[per, ntst * mn + np.arange(n)] = 1.0
    J[-2, :-2], J[-1] = phase, closing
    return J


@needs_kernel
@pytest.mark.parametrize("ntst,ncol,n,seed", [(7, 2, 2, 0), (12, 4, 3, 1), (5, 7, 1, 2), (50, 4, 2, 3), (3, 3, 4, 4)])
def test_random_blocks_solve_as_the_whole_system(monkeypatch, ntst, ncol, n, seed):
    mesh, S, L, aT, ap, phase, closing, rng = random_blocks(ntst, ncol, n, seed)
    J = whole(mesh, S, L, aT, ap, phase, closing, n)
    b = rng.standard_normal(J.shape[0])
    nc = ntst * ncol * n

    def run():
        border = Border(phase, closing, mesh, n)
        lu = CondensedLU(S.copy(), L.copy(), aT, ap, border, mesh, n, rhs=b[:nc].reshape(ntst, ncol * n))
        return lu.solve(b, lu.w), lu.solve(b), lu.solve(np.r_[np.zeros(nc), b[nc:]]), lu.transfer(), lu.multipliers()

    compiled, python = both(monkeypatch, run)
    truth = np.linalg.solve(J, b)
    truth0 = np.linalg.solve(J, np.r_[np.zeros(nc), b[nc:]])
    # a backward-stable solve errs by a small multiple of eps * cond(J) relative to the solution
    bound = 100 * EPS * np.linalg.cond(J)
    for got in (compiled, python):
        for x, ref in ((got[0], truth), (got[1], truth), (got[2], truth0)):
            assert np.max(np.abs(x - ref)) <= bound * np.max(np.abs(ref))
    # the transfer matrices are the same small solves in either path: agreement to rounding of each block
    scale = np.max(np.abs(python[3]))
    assert np.max(np.abs(compiled[3] - python[3])) <= 1e-12 * scale
    np.testing.assert_allclose(compiled[4], python[4], rtol=0, atol=1e-12 * np.max(np.abs(python[4])))


@needs_kernel
def test_singular_block_and_singular_reduced_system_raise_in_both_paths(monkeypatch):
    mesh, S, L, aT, ap, phase, closing, _ = random_blocks(6, 3, 2, 5)
    n = 2
    S_bad = S.copy()
    S_bad[4, :, 2] = 0.0  # a zero column in interval 4's block

    def singular_block():
        with pytest.raises(np.linalg.LinAlgError, match="(?i)singular"):
            CondensedLU(S_bad.copy(), L, aT, ap, Border(phase, closing, mesh, n), mesh, n)
        return True

    def singular_reduced():
        # phase and closing rows both zero: the reduced system has two zero rows
        with pytest.raises(np.linalg.LinAlgError, match="(?i)singular"):
            CondensedLU(S.copy(), L, aT, ap, Border(0 * phase, 0 * closing, mesh, n), mesh, n)
        return True

    assert both(monkeypatch, singular_block) == (True, True)
    assert both(monkeypatch, singular_reduced) == (True, True)


def _ab():
    sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
    try:
        import _auto_ab
    finally:
        sys.path.pop(0)
    return _auto_ab.mechcont_family()


def _stuart_landau():
    x, y, mu, om = sp.symbols("x y mu omega", real=True)
    r2 = x**2 + y**2
    return ode_model("sl", {"x": 0.0, "y": 0.0}, {"mu": 0.0, "omega": 2.0},
                     {"x": mu * x - om * y - x * r2, "y": om * x + mu * y - y * r2})


def _newton_step(model, vary, fam, i, rng):
    """The Newton correction at a perturbed orbit ``i`` of ``fam``, and the multipliers and transfer matrices of
    its factors."""
    mesh, u = fam.orbits[i]
    system = CycleSystem(RateFunction(model, dynamics_of(model), vary, fam.x_base), mesh, np.ones(u.shape[1]), 1.0)
    X = system.pack(u, float(fam.period[i]), float(fam.p[i]))
    X = X * (1 + 1e-3 * rng.standard_normal(X.size))
    closing = system.row(rng.standard_normal(system.size))
    res, lu = system.factored(X, phase_reference(system, X), closing, float(closing @ X) + 1e-3)
    return lu.solve(-res, lu.w), lu.multipliers(), lu.transfer()


@needs_kernel
@pytest.mark.parametrize("case", ["ab", "stuart_landau"])
def test_families_and_newton_steps_agree_in_both_paths(monkeypatch, case):
    if case == "ab":
        model, family = _ab()
        vary = "D"
    else:
        model, vary = _stuart_landau(), "mu"
        x0 = model.vector({"mu": 0.0})

        def family():
            from mechcont.continuation import ContinuationOptions

            return cycles_from_hopf(model, x0, "mu", ntst=20, ncol=4,
                                    options=ContinuationOptions(ds=0.02, dsmax=0.1, bounds={"mu": (-0.1, 1.0)}))

    fc, fp = both(monkeypatch, family)
    assert len(fc.p) == len(fp.p) > 10 and fc.labels == fp.labels
    np.testing.assert_allclose(fc.p, fp.p, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(fc.period, fp.period, rtol=1e-9)
    for mc, mp in zip(fc.multipliers, fp.multipliers):
        # where the non-trivial multiplier nears 1 (the fold of cycles) it and the trivial one form a near-double
        # eigenvalue of the monodromy matrix, which moves by the square root of a perturbation: sqrt(eps) there
        near_double = np.any(np.abs(mp - 1) < 1e-3)
        tol = 1e-7 if near_double else 1e-10
        np.testing.assert_allclose(mc, mp, rtol=0, atol=tol * max(1.0, np.max(np.abs(mp), initial=0.0)))
    for i in (1, len(fp.p) // 2, len(fp.p) - 1):
        (dc, mc, pc), (dp, mp, pp) = both(monkeypatch,
                                          lambda i=i: _newton_step(model, vary, fp, i, np.random.default_rng(i)))
        assert np.max(np.abs(dc - dp)) <= 1e-12 * np.max(np.abs(dp))
        assert np.max(np.abs(pc - pp)) <= 1e-12 * np.max(np.abs(pp))
        np.testing.assert_allclose(mc, mp, rtol=0, atol=1e-12 * np.max(np.abs(mp)))


@needs_kernel
@pytest.mark.parametrize("ntst,ncol,n", [(7, 2, 2), (5, 4, 3), (3, 7, 1)])
def test_collocation_blocks_are_the_sparse_jacobians_blocks(monkeypatch, ntst, ncol, n):
    # the blocks the condensation takes (compiled and NumPy) against CycleSystem.blocks, which the sparse Jacobian
    # (linearise) is built from: d(collocation at Gauss point k)/d(node i) per interval
    from mechcont.continuation._condensation import collocation_blocks

    rng = np.random.default_rng(ntst)
    model = _stuart_landau() if n == 2 else ode_model("lin", {f"z{i}": 0.0 for i in range(n)}, {"mu": 0.0},
                                                      {f"z{i}": sp.Symbol(f"z{i}", real=True) for i in range(n)})
    vary = "mu"
    system = CycleSystem(RateFunction(model, dynamics_of(model), vary, model.defaults()), Mesh(ntst, ncol),
                         np.ones(n), 1.0)
    Fz, T = rng.standard_normal((ntst, ncol, n, n)), 4.2
    (Sc, Lc), (Sp, Lp) = both(monkeypatch, lambda: collocation_blocks(system._D, system.mesh.Lc, Fz, T))
    ref = system.blocks(T, Fz)  # (ntst, ncol, ncol + 1, n, n)
    ref_S = ref[:, :, 1:].transpose(0, 1, 3, 2, 4).reshape(ntst, ncol * n, ncol * n)
    ref_L = ref[:, :, 0].reshape(ntst, ncol * n, n)
    for S, L in ((Sc, Lc), (Sp, Lp)):
        scale = np.max(np.abs(ref))
        assert np.max(np.abs(S - ref_S)) <= 4 * EPS * scale and np.max(np.abs(L - ref_L)) <= 4 * EPS * scale


@needs_kernel
@pytest.mark.parametrize("ntst,ncol,n", [(50, 4, 2), (7, 2, 3), (3, 7, 1)])
def test_mesh_rows_and_evaluation_agree_in_both_paths(monkeypatch, ntst, ncol, n):
    # the compiled Gram and phase rows (interval_rows) and evaluation between nodes (lagrange_values) against NumPy's,
    # on a non-uniform mesh, and the Gram row against the quadrature it stands for (the Gauss points' values)
    rng = np.random.default_rng(ntst + ncol)
    mesh = Mesh(ntst, ncol, np.sort(np.r_[0.0, rng.uniform(0, 1, ntst - 1), 1.0]))
    u, w = rng.standard_normal((mesh.n_nodes, n)), rng.standard_normal((mesh.n_nodes, n))
    t = np.r_[rng.uniform(-1.0, 2.0, 200), mesh.tau]
    compiled, python = both(monkeypatch, lambda: (mesh.gram_row(w), mesh.phase_row(w), mesh.evaluate(u, t)))
    for c, p in zip(compiled, python):
        assert np.max(np.abs(c - p)) <= 1e-13 * np.max(np.abs(p))
    uc, _ = mesh.at_collocation(u)
    wc, _ = mesh.at_collocation(w)
    quad = np.einsum("j,k,jkn,jkn->", mesh.h, mesh.g, uc, wc)
    assert compiled[0] @ u.ravel() == pytest.approx(quad, rel=1e-12, abs=1e-14)


@needs_kernel
def test_compiled_iteration_returns_the_newton_tests_norms():
    """The compiled iteration hands back the correction's largest |dX_i| and the corrected orbit's largest |X_i + dX_i|
    (the Newton loop's two tests) with the correction itself."""
    model, family = _ab()
    fam = family()
    i = len(fam.p) // 2
    mesh, u = fam.orbits[i]
    system = CycleSystem(RateFunction(model, dynamics_of(model), "D", fam.x_base), mesh, np.ones(u.shape[1]), 1.0)
    rng = np.random.default_rng(3)
    X = system.pack(u, float(fam.period[i]), float(fam.p[i])) * (1 + 1e-3 * rng.standard_normal(system.size))
    closing = system.row(rng.standard_normal(system.size))
    border = Border(phase_reference(system, X), closing, mesh, system.n)
    _, lu, dX, norms = system._factored_compiled(_kernel.condensation(), X, float(closing @ X) + 1e-3, border)
    assert norms[0] == pytest.approx(np.abs(dX).max(), rel=1e-15) and norms[0] > 0
    assert norms[1] == pytest.approx(np.abs(X + dX).max(), rel=1e-15)
    # the same correction as the NumPy path's solve from the same factors
    res, _ = system.factored(X, border.phase, closing, float(closing @ X) + 1e-3, border)
    np.testing.assert_allclose(dX, lu.solve(-res, lu.w), rtol=0, atol=1e-12 * np.abs(dX).max())
