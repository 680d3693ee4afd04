"""Compiled code: sparse outputs, pickling, the disk cache, batched evaluation.

Every comparison of results here is bit for bit (``np.array_equal`` or the bytes), except
where two different compiled layouts of the same derivatives are compared.
"""

import hashlib
import importlib.util
import json
import os
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import symengine as se
import sympy as sp
from derivative_checks import check_derivatives

from mechcont.equations import EquationSystem, Variable, _cache, _codegen
from mechcont.mechanism import load, parse_description
from mechcont.models import build_overcentre

ROOT = Path(__file__).resolve().parents[1]


def _bench_build():
    spec = importlib.util.spec_from_file_location("bench_build", ROOT / "benchmarks" / "bench_build.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _chain(n_bars):
    return parse_description(_bench_build().chain_toml(n_bars), f"chain{n_bars}.toml").build()


def _point(system, seed=0):
    rng = np.random.default_rng(seed)
    return system.defaults() + 0.01 * rng.standard_normal(len(system.names))


def _fingerprint(system, x):
    """Every compiled quantity at ``x`` as hex bytes (for bit-for-bit comparison across processes)."""
    v = np.linspace(-1.0, 1.0, len(x))
    r, J = system.residual_and_jacobian(x)
    m = system.mechanics
    st = m.stability(x)
    qd = np.linspace(0.5, -0.5, len(m.coordinates))
    arrays = [r, J, system.jacobian_derivative(x, v), st.eigenvalues, np.array([st.n_unstable], float),
              m.phi(x), m.phi_q(x), m.tangent_stiffness(x), m.mass(x), m.gamma(x, qd), m.damping_matrix(x, qd)]
    return [a.tobytes().hex() for a in arrays]


# -- sparse code generation -------------------------------------------------------------
def test_derivative_entries_only_nonzero_in_row_major_order():
    x, y, z = se.symbols("x y z")
    entries = _codegen.derivative_entries([x * y, z**2 + 0 * x, se.Integer(3)], [z, y, x])
    assert [ij for ij, _ in entries] == [(0, 1), (0, 2), (1, 0)]
    assert [str(d) for _, d in entries] == ["x", "y", "2*z"]


def test_smooth_expressions_and_the_ones_that_need_the_exact_rules():
    x, y = se.symbols("x y")
    assert _codegen.is_smooth(se.sin(x) * se.sqrt(x**2 + y**2) + se.atan2(y, x) + se.log(x) / 3)
    for e in (se.Abs(x), se.sign(x) * y, se.Max(x, y), se.Min(x, 2 * y) + x):
        assert not _codegen.is_smooth(e)
    # the exact rules still apply where they are needed: |u|' = sign(u) u', Max picks the argument
    (_, dabs), = _codegen.derivative_entries([se.Abs(x**2 - y)], [x])
    assert dabs.subs({x: 2.0, y: 1.0}) == 4.0 and dabs.subs({x: 0.5, y: 1.0}) == -1.0
    (_, dmax), = _codegen.derivative_entries([se.Max(x, 2 * x)], [x])
    assert float(dmax.subs({x: 1.0})) == 2.0 and float(dmax.subs({x: -1.0})) == 1.0


@pytest.mark.parametrize("dense_max", [0, 10**9])
def test_compile_sparse_matches_the_dense_array_in_both_layouts(monkeypatch, dense_max):
    monkeypatch.setattr(_codegen, "DENSE_MAX", dense_max)
    monkeypatch.setenv("MECHCONT_NO_CACHE", "1")
    syms = sp.symbols("a b c", real=True)
    a, b, c = syms
    entries = [((0, 1, 2), a * b), ((1, 0, 0), sp.sin(c)), ((1, 2, 1), a + c**2)]
    f = _codegen.compile_sparse(syms, entries, (2, 3, 3))
    x = np.array([0.3, -1.2, 2.5])
    expected = np.zeros((2, 3, 3))
    expected[0, 1, 2], expected[1, 0, 0], expected[1, 2, 1] = x[0] * x[1], np.sin(x[2]), x[0] + x[2] ** 2
    assert f(x).shape == (2, 3, 3)
    assert np.allclose(f(x), expected, rtol=1e-15, atol=0)
    assert (f.idx is None) == (dense_max > 0)
    with pytest.raises(ValueError):
        f(np.zeros(2))


def test_a_variable_named_like_a_cse_temporary_is_not_confused_with_one():
    x0, x1 = sp.symbols("x0 x1", real=True)
    f = _codegen.compile_dense([x1, x0], [sp.sin(x0 + x1) * sp.cos(x0 + x1), x0 * sp.sin(x0 + x1)], cache=False)
    u, w = 0.4, 1.3  # x1 = u, x0 = w
    assert np.allclose(f(np.array([u, w])), [np.sin(u + w) * np.cos(u + w), w * np.sin(u + w)], rtol=1e-15)


@pytest.fixture(scope="module")
def chain12():
    return _chain(12)


def test_large_chain_scattered_layouts_have_exact_derivatives(chain12):
    """A 12-bar chain (62 equations): Jacobian, Hessians and statics beyond DENSE_MAX are scattered."""
    system = chain12
    system.compile(second_derivatives=True)
    assert system._code["res_jac"].idx is not None
    assert not system.mechanics._statics_layout.dense
    check_derivatives(system)


def test_dense_and_scattered_layouts_agree(monkeypatch):
    monkeypatch.setenv("MECHCONT_NO_CACHE", "1")
    dense = load("fourbar")
    dense.mechanics._compile()  # compiled on first use: before the limit changes
    dense.compile(second_derivatives=True)
    monkeypatch.setattr(_codegen, "DENSE_MAX", 0)
    scattered = load("fourbar")
    scattered.mechanics._compile()
    assert scattered.mechanics._statics_layout.dense is False and dense.mechanics._statics_layout.dense is True
    x = _point(dense)
    for a, b in [(dense.residual(x), scattered.residual(x)), (dense.jacobian(x), scattered.jacobian(x)),
                 (dense.mechanics.tangent_stiffness(x), scattered.mechanics.tangent_stiffness(x)),
                 (dense.mechanics.mass(x), scattered.mechanics.mass(x))]:
        assert np.allclose(a, b, rtol=1e-13, atol=1e-12)
    v = np.linspace(-1.0, 1.0, len(x))
    assert np.allclose(dense.jacobian_derivative(x, v), scattered.jacobian_derivative(x, v), rtol=1e-13, atol=1e-12)
    sd, ss = dense.mechanics.stability(x), scattered.mechanics.stability(x)
    assert sd.n_unstable == ss.n_unstable and np.allclose(sd.eigenvalues, ss.eigenvalues, rtol=1e-10)


@pytest.mark.parametrize("dense_max", [0, 10**9])
def test_column_view_equals_the_columns_of_the_whole_jacobian_bit_for_bit(monkeypatch, dense_max):
    """The continuation's restricted evaluation (EquationSystem.columns) gives the same bits, in the
    same memory layout as ``J[:, cols]`` (the layout decides the order of later sums), in both layouts."""
    monkeypatch.setenv("MECHCONT_NO_CACHE", "1")
    monkeypatch.setattr(_codegen, "DENSE_MAX", dense_max)
    system = load("fourbar")
    x = _point(system)
    cols = np.array([system.index(n) for n in reversed(system.state_names)] + [len(system.names) - 1])
    view = system.columns(cols)
    assert system.columns(list(cols)) is view  # one view per set of columns, kept with the code
    r, J = system.residual_and_jacobian(x)
    rv, Jv = view.residual_and_jacobian(x)
    assert np.array_equal(rv, r) and np.array_equal(Jv, J[:, cols]) and Jv.strides == J[:, cols].strides
    v = np.linspace(-1.0, 1.0, len(x))
    H = system.jacobian_derivative(x, v)[:, cols]
    Hv = view.jacobian_derivative(x, v)
    assert np.array_equal(Hv, H) and Hv.strides == H.strides
    assert np.array_equal(view.residual_and_jacobian(list(x))[1], Jv)  # any sequence of floats
    with pytest.raises(ValueError):
        view.residual_and_jacobian(x[:-1])
    with pytest.raises(ValueError):
        system.columns([0, 0])


def test_fold_system_blocks_are_the_column_views_bit_for_bit():
    """The fold system scatters d(G_s v)/dx straight into its Jacobian: the same bits as the view's
    jacobian_derivative with v on the states (and the view's Jacobian columns above it)."""
    from mechcont.continuation._fold_point import _FoldSystem

    system = load("fivebar")
    x0 = _point(system)
    states = list(system.state_names)[:len(system.equations)]  # a square lens with T1 free
    idx = np.array([system.index(n) for n in [*states, "T1"]])
    rng = np.random.default_rng(4)
    col = rng.uniform(0.5, 2.0, len(states))
    fs = _FoldSystem(system, x0, idx, np.arange(len(states)), col)
    n, nv = len(states), len(idx)
    for _ in range(5):
        U = np.concatenate([x0[idx] + 0.01 * rng.normal(size=nv), rng.normal(size=n)])
        res, out = fs.evaluate(U)
        x, vh = fs.full(U), U[nv:]
        vf = np.zeros(len(x))
        vf[idx[:n]] = col * vh
        r, J = fs.view.residual_and_jacobian(x)
        assert np.array_equal(out[:n, :nv], J) and np.array_equal(res[:n], r)
        assert np.array_equal(out[n:2 * n, :nv], fs.view.jacobian_derivative(x, vf))
        assert np.array_equal(res, fs.residual(U))


def test_gather_reads_entries_of_every_compiled_layout():
    a, b = sp.symbols("a b", real=True)
    dense = _codegen.compile_dense([a, b], [a * b, a - b, sp.sin(a)], cache=False)
    scattered = _codegen.compile_sparse([a, b], [((0, 2), a * b), ((1, 0), a + b)], (2, 3), cache=False)
    x = np.array([0.7, -1.3])
    for f in (dense, scattered):
        pos = [4, 0, 2, 2] if f is scattered else [2, 0, 1]
        assert np.array_equal(f.gather(pos)(x), f(x).reshape(-1)[pos])


def test_chain_build_compiles_only_nonzero_entries(chain12):
    """12 bars (62 equations, 69 variables): only the Jacobian's non-zero entries are compiled."""
    n_eq, n = len(chain12.equations), len(chain12.names)
    chain12.compile()  # (the module's fixture is shared: this test must not rely on an earlier one compiling it)
    f = chain12._code["res_jac"]
    assert f.idx is not None and f.n_out == n_eq + int(np.count_nonzero(np.abs(chain12.jacobian(_point(chain12))) > 0))
    assert f.n_out < (n_eq + n_eq * n) // 10


# -- pickling ---------------------------------------------------------------------------
@pytest.mark.parametrize("make", [build_overcentre, lambda: load("fourbar")], ids=["overcentre", "fourbar"])
def test_pickle_round_trip_is_bit_identical(make):
    system = make()
    x = _point(system)
    before = _fingerprint(system, x)
    copy = pickle.loads(pickle.dumps(system))
    assert _fingerprint(copy, x) == before
    assert copy.names == system.names and copy.equations == system.equations
    # a model's declared fields all travel (never silently half-there), the callables included
    # (the symbolic parts of a pickled model are unpickled on first use: read them on both)
    copy.symbols, system.symbols, system.equations  # noqa: B018 - read for their side effect
    assert type(copy) is type(system) and copy.unpickled_without == () and set(vars(copy)) == set(vars(system))
    assert copy.reaction_names == system.reaction_names  # plain data does travel
    assert [b.tobytes() for _, b in copy.scene(x).bars] == [b.tobytes() for _, b in system.scene(x).bars]
    if system.coordinates_of is not None:
        assert copy.coordinates_of(x) == system.coordinates_of(x) and copy.dropped_residual(x) == 0.0
        copy.check_values({})
    # the compiled-state export alone is enough for the numeric core
    core = EquationSystem.from_compiled_state(pickle.loads(pickle.dumps(system.compiled_state())))
    assert _fingerprint(core, x) == before
    # with_values copies still share the compiled code (a shallow copy, not the pickled state)
    other = copy.with_values({copy.parameter_names[0]: 1.25})
    assert other._code is copy._code and other.scene is copy.scene


def test_unpickled_in_a_fresh_process_compiles_nothing_and_is_bit_identical(tmp_path):
    system = load("fourbar")
    x = _point(system)
    (tmp_path / "system.pkl").write_bytes(pickle.dumps(system))
    np.save(tmp_path / "x.npy", x)
    code = f"""
import json, pickle, sys, numpy as np
sys.path.insert(0, {str(ROOT / 'tests')!r})
from test_compiled_code import _fingerprint
from mechcont.equations import _codegen
s = pickle.loads(open({str(tmp_path / 'system.pkl')!r}, 'rb').read())
print(json.dumps({{"fp": _fingerprint(s, np.load({str(tmp_path / 'x.npy')!r})), "compiled": _codegen.COUNTS["compiled"]}}))
"""
    out = _run(code, {"MECHCONT_NO_CACHE": "1", "PYTHONHASHSEED": "7"})
    assert out["compiled"] == 0
    assert out["fp"] == _fingerprint(system, x)


# -- disk cache -------------------------------------------------------------------------
def _run(code: str, env: dict) -> dict:
    full = {**os.environ, **env}
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=full, timeout=300, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


_BUILD = """
import json, sys, numpy as np
sys.path.insert(0, {tests!r})
from test_compiled_code import _fingerprint, _point
from mechcont.equations import _cache, _codegen
from mechcont.mechanism import load
from mechcont.models import build_overcentre
out = {{}}
for name, s in (("overcentre", build_overcentre()), ("fourbar", load("fourbar"))):
    x = _point(s)
    fp = _fingerprint(s, x)
    if s.coordinates_of is not None:
        s.scene(x); s.coordinates_of(x)
    out[name] = fp
print(json.dumps({{"fp": out, "compiled": _codegen.COUNTS["compiled"], "stats": _cache.STATS}}))
""".format(tests=str(ROOT / "tests"))


def test_second_process_starts_from_the_cache(tmp_path):
    env = {"MECHCONT_CACHE_DIR": str(tmp_path / "cache"), "MECHCONT_NO_CACHE": ""}
    first = _run(_BUILD, {**env, "PYTHONHASHSEED": "1"})
    assert first["compiled"] > 0 and first["stats"]["writes"] > 0
    second = _run(_BUILD, {**env, "PYTHONHASHSEED": "2"})
    assert second["compiled"] == 0 and second["stats"]["misses"] == 0
    assert second["fp"] == first["fp"]
    # and the same as without any cache
    fresh = _run(_BUILD, {"MECHCONT_NO_CACHE": "1"})
    assert fresh["fp"] == first["fp"] and fresh["stats"] == {"hits": 0, "misses": 0, "writes": 0}


_LATER = """
import json, sys, numpy as np
from mechcont.equations import _cache, _codegen
from mechcont.models import load_model
m = load_model("fourbar.toml")
before = {"second": "hess_values" in m._code, "statics": "_statics" in vars(m.mechanics),
          "compiled": _codegen.COUNTS["compiled"]}
x = m.defaults() + np.linspace(-0.01, 0.01, len(m.names))
qd = np.linspace(0.5, -0.5, len(m.mechanics.coordinates))
fp = [a.tobytes().hex() for a in (*m.residual_and_jacobian(x), m.jacobian_derivative(x, np.linspace(-1, 1, len(x))),
                                  m.mechanics.stability(x).eigenvalues, m.mechanics.mass(x), m.mechanics.gamma(x, qd))]
print(json.dumps({"before": before, "fp": fp, "compiled": _codegen.COUNTS["compiled"], "stats": _cache.STATS,
                  "sympy": "sympy" in sys.modules}))
"""


def test_a_stored_model_leaves_its_second_derivatives_to_first_use_and_a_later_process_loads_them(tmp_path):
    """A model built and kept in the disk cache has no second derivatives (nor mechanics groups) compiled
    until used: a build that never needs them never pays for them. Compiled on first use, they go to the
    cache under the key kept with the stored model, so a second process loads them (compiling nothing,
    importing no SymPy), bit-identical to a process without any cache."""
    env = {"MECHCONT_CACHE_DIR": str(tmp_path / "cache"), "MECHCONT_NO_CACHE": ""}
    first = _run(_LATER, env)
    assert first["before"]["second"] is False and first["before"]["statics"] is False
    assert first["compiled"] >= first["before"]["compiled"] + 2  # compiled on first use
    second = _run(_LATER, env)
    assert second["before"]["compiled"] == 0 and second["compiled"] == 0 and second["stats"]["misses"] == 0
    assert not second["sympy"] and second["fp"] == first["fp"]
    fresh = _run(_LATER, {"MECHCONT_NO_CACHE": "1"})
    assert fresh["fp"] == first["fp"] and fresh["before"]["second"] is False


def test_concurrent_processes_share_one_cache_safely(tmp_path):
    """Three processes compile the same models into one empty cache at once: all succeed, all agree."""
    env = {**os.environ, "MECHCONT_CACHE_DIR": str(tmp_path / "cache"), "MECHCONT_NO_CACHE": ""}
    procs = [subprocess.Popen([sys.executable, "-c", _BUILD], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True, env=env, cwd=ROOT) for _ in range(3)]
    outs = []
    for p in procs:
        stdout, stderr = p.communicate(timeout=300)
        assert p.returncode == 0, stderr
        outs.append(json.loads(stdout.strip().splitlines()[-1]))
    assert outs[0]["fp"] == outs[1]["fp"] == outs[2]["fp"]
    assert not list((tmp_path / "cache").rglob(".tmp-*"))
    again = _run(_BUILD, {"MECHCONT_CACHE_DIR": str(tmp_path / "cache"), "MECHCONT_NO_CACHE": ""})
    assert again["compiled"] == 0 and again["fp"] == outs[0]["fp"]


def _tiny(expr_extra=0):
    a, b = sp.symbols("a b", real=True)
    return EquationSystem("tiny", [Variable("a"), Variable("b", "parameter", 2.0)], [a**3 - b + expr_extra * a])


def test_cache_keys_follow_the_content(monkeypatch, tmp_path):
    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("MECHCONT_NO_CACHE", raising=False)
    base = _codegen.COUNTS["compiled"]
    _tiny().compile()
    assert _codegen.COUNTS["compiled"] == base + 1
    _tiny().compile()  # same equations: loaded
    assert _codegen.COUNTS["compiled"] == base + 1
    _tiny(1).compile()  # a changed equation: a new key, compiled
    assert _codegen.COUNTS["compiled"] == base + 2
    # floats that print alike but differ in the last bit are different content
    x = sp.Symbol("x", real=True)
    f1 = _codegen.compile_dense([x], [sp.Float(0.1 + 0.2) * x])
    f2 = _codegen.compile_dense([x], [sp.Float(0.3) * x])
    assert f1(np.array([1.0]))[0] == 0.1 + 0.2 and f2(np.array([1.0]))[0] == 0.3
    assert _cache.expr_text(se.sympify(sp.Float(0.1 + 0.2) * x)) != _cache.expr_text(se.sympify(sp.Float(0.3) * x))


def test_corrupt_or_foreign_entries_are_recompiled(monkeypatch, tmp_path):
    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("MECHCONT_NO_CACHE", raising=False)
    x = np.array([1.5, 2.0])
    expected = _tiny().residual_and_jacobian(x)
    files = sorted(tmp_path.rglob("*.pkl"))
    assert files and not list(tmp_path.rglob(".tmp-*"))
    assert (tmp_path / "cache").stat().st_mode & 0o077 == 0  # private to the user
    good = files[0].read_bytes()
    foreign = pickle.dumps(("another key", {"res_jac": None}))
    for bad in (b"", good[: len(good) // 2], good[:-1] + bytes([good[-1] ^ 1]), b"not a cache entry",
                _cache._MAGIC + hashlib.sha256(foreign).digest() + foreign):
        files[0].write_bytes(bad)
        before = _codegen.COUNTS["compiled"]
        r, J = _tiny().residual_and_jacobian(x)
        assert _codegen.COUNTS["compiled"] == before + 1
        assert np.array_equal(r, expected[0]) and np.array_equal(J, expected[1])
        assert files[0].read_bytes() != bad  # rewritten
    files[0].chmod(0)  # unreadable: a miss, and the failed rewrite is no error either
    try:
        assert np.array_equal(_tiny().residual(x), expected[0])
    finally:
        files[0].chmod(0o600)


def test_no_cache_and_unwritable_directories(monkeypatch, tmp_path):
    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(tmp_path / "c"))
    monkeypatch.setenv("MECHCONT_NO_CACHE", "1")
    assert _cache.cache_dir() is None
    _tiny().compile()
    assert not (tmp_path / "c").exists()
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(blocker / "below-a-file"))
    monkeypatch.setenv("MECHCONT_NO_CACHE", "0")
    assert np.array_equal(_tiny().residual(np.array([1.0, 2.0])), [-1.0])


def test_default_cache_directory(monkeypatch, tmp_path):
    monkeypatch.delenv("MECHCONT_NO_CACHE", raising=False)
    monkeypatch.delenv("MECHCONT_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert _cache.cache_dir() == tmp_path / "mechcont"
    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(tmp_path / "mine"))
    assert _cache.cache_dir() == tmp_path / "mine"


def test_the_test_suite_never_uses_the_users_cache():
    assert Path(os.environ["MECHCONT_CACHE_DIR"]).resolve() != (Path.home() / ".cache" / "mechcont").resolve()


# -- batched evaluation -----------------------------------------------------------------
def test_batch_equals_the_loop_bit_for_bit():
    system = load("nose_gear")
    rng = np.random.default_rng(3)
    X = system.defaults() + 0.01 * rng.standard_normal((200, len(system.names)))
    R, J = system.residual_and_jacobian_batch(X)
    assert R.shape == (200, len(system.equations)) and J.shape == (200, len(system.equations), len(system.names))
    for i in range(len(X)):
        r, j = system.residual_and_jacobian(X[i])
        assert np.array_equal(R[i], r) and np.array_equal(J[i], j)
    assert np.array_equal(system.residual_batch(X[:3]), R[:3])
    assert system.residual_batch(X[:0]).shape == (0, len(system.equations))
    with pytest.raises(ValueError):
        system.residual_batch(X[0])


def test_batch_of_a_scattered_jacobian(chain12):
    system = chain12
    X = np.stack([_point(system, seed) for seed in range(4)])
    R, J = system.residual_and_jacobian_batch(X)
    for i in range(4):
        assert np.array_equal(J[i], system.jacobian(X[i])) and np.array_equal(R[i], system.residual(X[i]))


def test_cli_no_cache_flag_leaves_the_cache_untouched(tmp_path):
    cache = tmp_path / "cache"
    env = {**os.environ, "MECHCONT_CACHE_DIR": str(cache), "MECHCONT_NO_CACHE": ""}
    args = [str(Path(sys.executable).with_name("mechcont")), "--no-cache", "continue", "overcentre", "--start", "theta1=0.3",
            "--vary", "F", "--bounds", "theta1=-1:1", "--quiet"]
    r = subprocess.run(args, env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert not cache.exists() or not any(p.is_file() for p in cache.rglob("*"))
    r = subprocess.run([a for a in args if a != "--no-cache"], env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert any(p.is_file() for p in cache.rglob("*"))  # without the flag the same run writes the cache


def test_a_long_float_constant_is_smooth_and_differentiates_alike():
    # a description's 17-digit constants become SymEngine RealMPFR numbers: smooth, so their rows skip
    # the search for unevaluated derivatives (which made the dual-sidestay second derivatives 4x slower)
    import symengine as se
    import sympy as sp

    from mechcont.equations._codegen import derivative_entries, is_smooth, to_engine

    x, y = sp.symbols("x y", real=True)
    e = to_engine(sp.Float("0.29157727625195257", 17) * sp.sqrt(x ** 2 + y ** 2) * sp.sin(x * y))
    assert any(type(n).__name__ == "RealMPFR" for n in se.sympify(e).atoms(se.Number))
    assert is_smooth(e)
    args = [se.Symbol("x"), se.Symbol("y")]
    fast, checked = derivative_entries([e], args, True), derivative_entries([e], args, False)
    assert [ij for ij, _ in fast] == [ij for ij, _ in checked]
    assert all(se.expand(a - b) == 0 for (_, a), (_, b) in zip(fast, checked))
