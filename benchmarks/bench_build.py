"""Build cost against size: planar chains of N bars pinned to the ground at both ends.

A chain of N bars has 3N coordinates, 2(N+1) pin constraints (so 5N+2 unknowns: the
coordinates and the reactions) and N-2 degrees of freedom; the first N-2 bar angles are
held for the first assembly. Every build here is *cold*: the disk cache is disabled
(``MECHCONT_NO_CACHE=1``) unless a case says "cached".

A build is the time until the system and its mechanics are usable: generation of the
equations (``Mechanism.build``) plus every compilation (``EquationSystem.compile`` and the
mechanics' compiled functions). "compile" below is the time spent inside the compile
methods (exact differentiation in SymEngine and code generation); "symbolic" is the rest
(description, kinematics, loads, equilibrium rows in SymPy, the first assembly).

Targets (issue "Compile once, start fast"): 86 unknowns (16 bars) <= 2 s, 166 unknowns
(32 bars) <= 10 s, the nose gear description <= 0.5 s, growth exponent (log-log slope of
build time against unknowns) <= 2.

``python benchmarks/bench_build.py [N ...]`` prints the table and the fitted exponent
(default N = 4 8 16 32); ``python benchmarks/bench_build.py --models [SRC]`` the cold and cached
start of the shipped models as a fresh process builds them through the disk cache (:data:`MODELS`;
``SRC``: another checkout's ``src`` to compare with); ``cases()`` serves ``benchmarks/run.py``.
"""

from __future__ import annotations

import atexit
import contextlib
import math
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Iterable

import numpy as np


def chain_toml(n_bars: int) -> str:
    """Description text of a chain of ``n_bars`` unit bars from ground A = (0, 0) to ground B.

    Nominal shape: a half-circle arch (bar i at angle pi/2 - pi (i - 1/2) / N), so B lies on
    the x axis at ``sum sin(pi (i - 1/2) / N)``; the first N-2 angles are held at it. Gravity,
    one spring from above to the middle bar, and a moment on the first bar load it.
    """
    if n_bars < 3:
        raise ValueError("a chain pinned at both ends needs at least 3 bars")
    angles = [math.pi / 2 - math.pi * (i + 0.5) / n_bars for i in range(n_bars)]
    span = sum(math.cos(a) for a in angles)
    mid = n_bars // 2 + 1
    out = [
        "[mechanism]",
        f'name = "chain{n_bars}"',
        f'description = "chain of {n_bars} bars pinned at both ends"',
        f"dof = {n_bars - 2}",
        "",
        "[parameters]",
        'L = { value = 1.0, unit = "m" }',
        'm = { value = 1.0, unit = "kg" }',
        'g = { value = 9.81, unit = "m/s^2" }',
        'k = { value = 100.0, unit = "N/m" }',
        'L0 = { value = 0.5, unit = "m" }',
        'T = { value = 0.0, unit = "N m" }',
        f'span = {{ value = {span!r}, unit = "m" }}',
        "",
        "[ground]",
        "A = [0, 0]",
        'B = ["span", 0]',
        f"S = [{span / 2!r}, {n_bars / 2!r}]",
        "",
    ]
    for i, a in enumerate(angles, start=1):
        out += [f"[bodies.b{i}]", 'length = "L"', 'mass = "m"', f"initial = {{ theta = {a!r} }}", ""]
    joints = [("ground.A", "b1.a")] + [(f"b{i}.b", f"b{i + 1}.a") for i in range(1, n_bars)]
    joints.append((f"b{n_bars}.b", "ground.B"))
    for i, (a, b) in enumerate(joints):
        out += [f"[joints.J{i}]", 'type = "revolute"', f'a = "{a}"', f'b = "{b}"', ""]
    out += ["[springs.s]", 'a = "ground.S"', f'b = "b{mid}.origin"', 'k = "k"', 'free_length = "L0"', "",
            "[gravity]", 'g = "g"', "",
            "[loads.T]", 'type = "moment"', 'body = "b1"', 'magnitude = "T"', "",
            "[assembly]",
            "hold = { " + ", ".join(f"theta_b{i + 1} = {angles[i]!r}" for i in range(n_bars - 2)) + " }", ""]
    return "\n".join(out)


@contextlib.contextmanager
def _compile_timer(acc: list[float]):
    """Add the time spent inside the compile methods to ``acc[0]`` (outermost calls only)."""
    from mechcont.equations import EquationSystem, MechanicalModel

    patched = []
    depth = [0]

    def wrap(cls, name):
        orig = cls.__dict__[name]

        def timed(*args, **kwargs):
            depth[0] += 1
            t0 = time.perf_counter()
            try:
                return orig(*args, **kwargs)
            finally:
                depth[0] -= 1
                if depth[0] == 0:
                    acc[0] += time.perf_counter() - t0

        setattr(cls, name, timed)
        patched.append((cls, name, orig))

    for cls in (EquationSystem, MechanicalModel):
        for name in ("compile", "_compile_group"):
            if name in cls.__dict__:
                wrap(cls, name)
    try:
        yield
    finally:
        for cls, name, orig in patched:
            setattr(cls, name, orig)


def _ready(system, everything: bool = True):
    """Compile what a continuation with stability needs; with ``everything``, also the second
    derivatives (folds, cusps) and the dynamic model (time simulation)."""
    system.compile()
    x = system.defaults()
    system.residual_and_jacobian(x)
    m = system.mechanics
    if m is not None:
        m.stability(x)
    if everything:
        system.jacobian_derivative(x, np.ones(len(x)))
        if m is not None:
            m.mass(x)
            m.gamma(x, np.zeros(len(m.coordinates)))
            m.damping_matrix(x)
    return system


def build_chain(n_bars: int, everything: bool = True):
    """Parse, generate and compile a chain; the system, compiled (see :func:`_ready`)."""
    from mechcont.mechanism import parse_description

    return _ready(parse_description(chain_toml(n_bars), f"chain{n_bars}.toml").build(), everything)


def timed_build(fn) -> tuple[float, float, object]:
    """(total s, compile s, result) of ``fn()``."""
    acc = [0.0]
    with _compile_timer(acc):
        t0 = time.perf_counter()
        out = fn()
        total = time.perf_counter() - t0
    return total, acc[0], out


def timed_stages(make) -> tuple[float, float, float, float, object]:
    """Cold build of ``make()`` (a built, uncompiled system) in stages:
    (ready s, everything s, compile s of everything, second derivatives s, system)."""
    acc = [0.0]
    with _compile_timer(acc):
        t0 = time.perf_counter()
        system = _ready(make(), everything=False)
        ready = time.perf_counter() - t0
        t1 = time.perf_counter()
        system.jacobian_derivative(system.defaults(), np.ones(len(system.names)))
        hess = time.perf_counter() - t1
        _ready(system, everything=True)
        total = time.perf_counter() - t0
    return ready, total, acc[0], hess, system


@contextlib.contextmanager
def _env(**values):
    old = {k: os.environ.get(k) for k in values}
    os.environ.update(values)
    try:
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def cases():
    from mechcont.mechanism import load_description

    nose = load_description("nose_gear")
    cache = tempfile.mkdtemp(prefix="mechcont-bench-cache-")
    atexit.register(shutil.rmtree, cache, ignore_errors=True)

    def cold(fn):
        def run():
            with _env(MECHCONT_NO_CACHE="1"):
                return fn()
        return run

    def cached(fn):
        def run():
            with _env(MECHCONT_CACHE_DIR=cache, MECHCONT_NO_CACHE="0"):
                return fn()
        return run

    # batched evaluation: 1000 points near the nose gear's defaults, one call vs a loop
    gear = _ready(nose.build(), everything=False)
    X = gear.defaults() + 0.01 * np.random.default_rng(0).standard_normal((1000, len(gear.names)))

    def loop():
        for x in X:
            gear.residual_and_jacobian(x)

    return [
        ("build chain 4 bars (22 unknowns, cold, all compiled)", cold(lambda: build_chain(4)), 3),
        ("build chain 8 bars (42 unknowns, cold, all compiled)", cold(lambda: build_chain(8)), 3),
        ("build nose_gear description (cold, ready)", cold(lambda: _ready(nose.build(), everything=False)), 3),
        ("build nose_gear description (cold, all compiled)", cold(lambda: _ready(nose.build())), 3),
        ("build nose_gear description (cached, all compiled)", cached(lambda: _ready(nose.build())), 3),
        ("build chain 8 bars (42 unknowns, cached, all compiled)", cached(lambda: build_chain(8)), 3),
        ("nose_gear residual+Jacobian at 1000 points, loop", loop, 20),
        ("nose_gear residual+Jacobian at 1000 points, batch", lambda: gear.residual_and_jacobian_batch(X), 20),
    ]


#: The models ``--models`` builds: what users and the test suite build through the disk cache.
MODELS = ("examples/dual_sidestay.toml", "examples/shimmy.toml", "nose_gear", "fourbar.toml")

_MODEL_SCRIPT = r"""
import json, sys, time
import numpy as np
from mechcont.models import load_model

def clocks():
    return time.process_time(), time.perf_counter()

c0, w0 = clocks()
m = load_model(sys.argv[1])
c1, w1 = clocks()
x = m.defaults()
m.residual_and_jacobian(x)
if m.mechanics is not None:
    m.mechanics.stability(x)
c2, w2 = clocks()
v = np.linspace(-1.0, 1.0, len(x))
m.jacobian_derivative(x, v)
c3, w3 = clocks()
X = x + 1e-3 * np.random.default_rng(0).standard_normal((200, len(x)))
t = time.process_time()
for y in X:
    m.residual_and_jacobian(y)
rj = (time.process_time() - t) / len(X)
t = time.process_time()
for y in X:
    m.jacobian_derivative(y, v)
jd = (time.process_time() - t) / len(X)
print(json.dumps({"n": len(m.names), "build": [c1 - c0, w1 - w0], "ready": [c2 - c0, w2 - w0],
                  "second": [c3 - c2, w3 - w2], "res_jac_us": rj * 1e6, "jac_deriv_us": jd * 1e6}))
"""


def model_builds(models: Iterable[str] = MODELS, src: str | None = None) -> list[tuple[str, dict, dict]]:
    """Cold and cached start of each model as a fresh process runs it (``load_model`` through a fresh disk cache,
    then the same in a second process): per model ``(name, cold, cached)``, each a dict of CPU and wall
    seconds (``build``: ``load_model``; ``ready``: also the first residual, Jacobian and stability;
    ``second``: the first second derivatives after that, what a fold needs) and the per-call CPU cost of
    the residual and Jacobian and of the second derivatives (microseconds). ``src``: the package source
    to run (another checkout's ``src``, to compare), default this one's."""
    import json
    import subprocess

    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    src = src or os.path.join(root, "src")
    out = []
    for name in models:
        path = os.path.join(root, name) if name.startswith("examples/") else name
        with tempfile.TemporaryDirectory(prefix="mechcont-bench-cache-") as cache:
            env = {**os.environ, "PYTHONPATH": src, "MECHCONT_CACHE_DIR": cache, "MECHCONT_NO_CACHE": "",
                   "OPENBLAS_NUM_THREADS": "1"}
            runs = [json.loads(subprocess.run([sys.executable, "-c", _MODEL_SCRIPT, path], env=env, check=True,
                                              capture_output=True, text=True).stdout.strip().splitlines()[-1])
                    for _ in range(2)]
        out.append((name, runs[0], runs[1]))
    return out


def print_model_builds(src: str | None = None) -> None:
    """The table of :func:`model_builds` (CPU seconds, wall in brackets: the machine may be shared)."""
    print("| model | unknowns | cold build (s) | cold ready (s) | first 2nd derivs (s) | cached ready (s) "
          "| cached 2nd derivs (s) | res+Jac per call (us) | 2nd derivs per call (us) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, cold, warm in model_builds(src=src):
        def f(d: dict, k: str) -> str:
            return f"{d[k][0]:.2f} ({d[k][1]:.2f})"
        print(f"| {name} | {cold['n']} | {f(cold, 'build')} | {f(cold, 'ready')} | {f(cold, 'second')} | "
              f"{f(warm, 'ready')} | {f(warm, 'second')} | {cold['res_jac_us']:.1f} | {cold['jac_deriv_us']:.1f} |",
              flush=True)


def main(argv: list[str]) -> int:
    if argv[:1] == ["--models"]:
        print_model_builds(argv[1] if len(argv) > 1 else None)
        return 0
    sizes = [int(a) for a in argv] or [4, 8, 16, 32]
    from mechcont.mechanism import load_description, parse_description

    print("ready: built, residual + Jacobian and stability compiled (what a continuation needs before its "
          "first fold);\nall: also the second derivatives (folds, cusps) and the dynamic model; symbolic/compile "
          "split all;\ncached: all, in a process whose disk cache holds this model.\n")
    rows = []
    print("| bars | unknowns | variables | ready (s) | all (s) | symbolic (s) | compile (s) | 2nd derivs (s) | cached (s) |")
    print("|-----:|---------:|----------:|----------:|--------:|-------------:|------------:|---------------:|-----------:|")
    with tempfile.TemporaryDirectory(prefix="mechcont-bench-cache-") as cache:
        for n_bars in sizes:
            mech = parse_description(chain_toml(n_bars), f"chain{n_bars}.toml")
            with _env(MECHCONT_NO_CACHE="1"):
                ready, total, comp, hess, system = timed_stages(mech.build)
            with _env(MECHCONT_CACHE_DIR=cache, MECHCONT_NO_CACHE="0"):
                _ready(mech.build())  # fills the cache
                warm, _, _ = timed_build(lambda m=mech: _ready(m.build()))
            n = len(system.equations)
            rows.append((n, ready, total))
            print(f"| {n_bars:>4} | {n:>8} | {len(system.names):>9} | {ready:>9.3f} | {total:>7.3f} | "
                  f"{total - comp:>12.3f} | {comp:>11.3f} | {hess:>14.3f} | {warm:>10.3f} |", flush=True)
        nose = load_description("nose_gear")
        with _env(MECHCONT_NO_CACHE="1"):
            ready, total, comp, hess, system = timed_stages(nose.build)
        with _env(MECHCONT_CACHE_DIR=cache, MECHCONT_NO_CACHE="0"):
            _ready(nose.build())
            warm, _, _ = timed_build(lambda: _ready(nose.build()))
        print(f"\nnose_gear description ({len(system.equations)} unknowns): ready {ready:.3f} s, all {total:.3f} s "
              f"(symbolic {total - comp:.3f} s, compile {comp:.3f} s, of which second derivatives {hess:.3f} s); "
              f"cached {warm:.3f} s")
    if len(rows) >= 2:
        n = np.log([r[0] for r in rows])
        for label, col in (("ready", 1), ("all", 2)):
            t = np.log([r[col] for r in rows])
            slope = np.polyfit(n, t, 1)[0]
            last = (t[-1] - t[-2]) / (n[-1] - n[-2])
            print(f"growth exponent of '{label}' (log-log slope against unknowns): {slope:.2f} over all sizes, "
                  f"{last:.2f} between the two largest")
    return 0


if __name__ == "__main__":
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "src"))
    sys.exit(main(sys.argv[1:]))
