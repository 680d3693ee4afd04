"""Second derivatives compiled as several functions (equations._chunks): the values of the one function to
rounding, exact against finite differences, through every caller (direct, column views, batches, pickles,
the compiled corrector's C entry point), and kept apart from unsplit ones in the disk cache."""

import pickle

import numpy as np
import pytest
from derivative_checks import check_derivatives

from mechcont.continuation import ContinuationOptions, _kernel, continuation, continue_folds, find_equilibrium
from mechcont.equations import _codegen, _compiled
from mechcont.equations._chunks import ChunkedKernel, distinct
from mechcont.mechanism import load
from mechcont.models import build_overcentre, overcentre

#: Each second derivative is the same expression either way; only SymEngine's common sub-expressions differ
#: (shared within a chunk only), which regroups sums of at most a few hundred rounded products: a change of
#: a few hundred ulps of the largest term at most, far below 1e-12 of the largest entry (measured: 6e-14
#: on the dual-sidestay gear). A wrong scatter or a shifted chunk changes entries by O(1).
RTOL = 1e-12


def _point(system, seed=0):
    rng = np.random.default_rng(seed)
    return system.defaults() + 0.01 * rng.standard_normal(len(system.names))


def _close(a, b):
    scale = max(1.0, float(np.abs(b).max(initial=0.0)))
    assert np.abs(a - b).max(initial=0.0) <= RTOL * scale


@pytest.fixture()
def pair(monkeypatch):
    """The five-bar's second derivatives as one function and as chunks of 7 entries (no disk cache)."""
    monkeypatch.setenv("MECHCONT_NO_CACHE", "1")
    whole = load("fivebar").compile(second_derivatives=True)
    monkeypatch.setattr(_compiled, "SECOND_DERIVATIVES_CHUNK", 7)
    split = load("fivebar").compile(second_derivatives=True)
    return whole, split


def test_split_second_derivatives_equal_the_whole_to_rounding_and_finite_differences(pair):
    whole, split = pair
    fn_w, fn_s = whole._code["hess_values"], split._code["hess_values"]
    assert not isinstance(fn_w._fn, ChunkedKernel)
    assert isinstance(fn_s._fn, ChunkedKernel) and fn_s.n_out == fn_w.n_out
    # each distinct expression compiled once: d2G_i/dx_j dx_k and d2G_i/dx_k dx_j are one (symmetry)
    h = whole._code
    pairs = {(int(j), int(ik)) for j, ik in zip(h["hess_j"], h["hess_ik"])}
    n = len(whole.names)
    mirrored = sum((int(ik) % n, int(ik) // n * n + int(j)) in pairs for j, ik in zip(h["hess_j"], h["hess_ik"])
                   if int(j) != int(ik) % n)
    computed = fn_s._fn.bounds[-1]
    assert mirrored > 0 and computed <= fn_w.n_out - mirrored // 2
    assert len(fn_s._fn.kernels) == -(-computed // 7) > 2
    rng = np.random.default_rng(3)
    X = np.array([_point(whole, s) for s in range(4)])
    for x in X:
        v = rng.standard_normal(len(x))
        _close(fn_s(x), fn_w(x))
        _close(split.jacobian_derivative(x, v), whole.jacobian_derivative(x, v))
        cols = np.arange(0, len(x), 2)
        _close(split.columns(cols).jacobian_derivative(x, v), whole.jacobian_derivative(x, v)[:, cols])
    batch = fn_s.batch(X)
    assert all(np.array_equal(batch[i], fn_s(X[i])) for i in range(len(X)))  # the same machine code per row
    again = pickle.loads(pickle.dumps(fn_s))
    assert np.array_equal(again(X[0]), fn_s(X[0]))
    check_derivatives(split)


def test_distinct_keeps_each_expression_once_in_order_of_first_appearance():
    """The gather reproduces the list exactly (structural equality), and no two kept expressions are equal."""
    import symengine as se

    x, y = se.symbols("x y")
    exprs = [x * y, se.sin(x), y * x, 2 * x, se.sin(x), x + 1, 2 * x]
    unique, gather = distinct(exprs)
    assert unique == [x * y, se.sin(x), 2 * x, x + 1]
    assert gather.tolist() == [0, 1, 0, 2, 1, 3, 2]
    assert all(exprs[i] == unique[g] for i, g in enumerate(gather))


def test_the_c_entry_point_writes_every_chunk_in_place(pair):
    """What the compiled corrector calls (as_ctypes): each chunk's machine code on its slice of one array."""
    _, split = pair
    fn = split._code["hess_values"]
    x = _point(split, 5)
    callback, data = fn._fn.as_ctypes()
    out = np.full(fn.n_out, np.nan)
    callback(out.ctypes.data, x.ctypes.data, data.value)
    assert np.array_equal(out, fn(x))


def test_a_chunked_cache_entry_is_not_read_with_another_chunk_size(monkeypatch, tmp_path):
    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("MECHCONT_NO_CACHE", raising=False)
    monkeypatch.setattr(_compiled, "SECOND_DERIVATIVES_CHUNK", 7)
    load("fivebar").compile(second_derivatives=True)
    base = _codegen.COUNTS["compiled"]
    assert isinstance(load("fivebar").compile(second_derivatives=True)._code["hess_values"]._fn, ChunkedKernel)
    assert _codegen.COUNTS["compiled"] == base  # the same chunking: loaded
    monkeypatch.setattr(_compiled, "SECOND_DERIVATIVES_CHUNK", 10**6)
    whole = load("fivebar").compile(second_derivatives=True)
    assert not isinstance(whole._code["hess_values"]._fn, ChunkedKernel)
    assert _codegen.COUNTS["compiled"] == base + 1  # compiled again, as one function


@pytest.mark.skipif(not _kernel.AVAILABLE, reason="the compiled corrector was not built (no C compiler)")
def test_a_fold_curve_through_the_compiled_corrector_with_split_second_derivatives(monkeypatch):
    """The overcentre's fold curve to its cusp (as test_kernel's): the compiled corrector calls the chunks
    through their C entry point; the same curve as the Python corrector's and as the unsplit model's."""
    monkeypatch.setenv("MECHCONT_NO_CACHE", "1")
    monkeypatch.delenv("MECHCONT_PURE_PYTHON", raising=False)
    monkeypatch.setattr(overcentre, "_CACHE", {})  # this process's model, if any, may come from the disk cache

    def curve(pure: bool):
        s = build_overcentre(LU=0.1)
        x0 = find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])
        lp = min(continuation(s, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.4, 1.4)})).special("LP"),
                 key=lambda p: p["F"])
        if pure:
            monkeypatch.setenv("MECHCONT_PURE_PYTHON", "1")
        c = continue_folds(s, lp, "F", "LU", options=ContinuationOptions(bounds={"LU": (0.1, 2.0)}), direction=1,
                           stop_at_cusp=True)
        monkeypatch.delenv("MECHCONT_PURE_PYTHON", raising=False)
        return s, c

    _, whole = curve(False)
    monkeypatch.setattr(_compiled, "SECOND_DERIVATIVES_CHUNK", 3)
    monkeypatch.setattr(overcentre, "_CACHE", {})  # built again, as chunks
    s, split = curve(False)
    assert isinstance(s._code["hess_values"]._fn, ChunkedKernel)
    _, python = curve(True)
    for other in (whole, python):  # rounding apart (LU factors, regrouped sums): 1e-9 of each column's scale
        assert split.labels[-1] == other.labels[-1] == "CP" and split.values.shape == other.values.shape
        tol = 1e-9 * np.maximum(np.abs(other.values).max(axis=0), 1e-300)
        assert (np.abs(split.values - other.values) <= tol).all()
