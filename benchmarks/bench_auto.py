"""mechcont against AUTO-07p on the same problem: the paper's overcentre (eq. 6) at LU = 0.4 m.

Optional: runs only when ``AUTO_DIR`` names a built AUTO-07p (``$AUTO_DIR/bin/auto`` and
``$AUTO_DIR/lib/*.o``); without it, prints one line saying how to get AUTO and exits 0.
Run: ``AUTO_DIR=/path/to/auto-07p python benchmarks/bench_auto.py [--repeats N] [--cycles-only]``.

The overcentre is written as an AUTO algebraic problem (IPS = 0, six unknowns
``x1, y1, theta1, x2, y2, theta2``, PAR(1) the force, PAR(2) = LU; the equations below are
eq. 6 typed again in Fortran, Jacobian by AUTO's finite differences, JAC = 0) and started
from the point mechcont's ``find_equilibrium`` gives at theta1 = 0.3 rad. AUTO variants (see
``VARIANTS``): PAR(1) = F in newtons; PAR(1) = F/127 (F rescaled by k = 127 N/m so that its
arclength weight is near the states'); and the rescaled one without AUTO's per-iteration
diagnostics file (IID = 0). Work measured, in both programs:

* branch: the equilibrium branch in F, both directions from the start, to F = -200 and 200 N
  (AUTO: two runs, ``DS`` and ``-DS``, ended by ``UZSTOP``);
* fold curve: from the fold at F = -75.58 N, continued in (F, LU), both ways, to LU = 0.1 m
  (through the cusp at LU = 1.5 m).

Before timing anything, the folds AUTO locates (``LP``) and the fold-curve ends (``UZ``) are
checked against mechcont's to 1e-6 relative, so both solve the same problem.

Timings, each the median of ``--repeats`` interleaved rounds measured in this run:

* in-process: AUTO's own ``Total Time`` (wall clock around each run, including its reading of
  the constants and writing of the b/s/d files) against ``continuation()`` / ``continue_folds()``
  called in this process (model built before timing); per branch and per computed point;
* whole process: ``auto branch.auto`` / ``auto folds.auto`` (AUTO's Python CLUI, the
  equations compiled before timing) against ``mechcont continue overcentre ... --bounds
  F=-200:200`` / ``mechcont folds ...`` (compiled-code cache warm);
* periodic orbits: the family of AUTO's demo ``ab`` from its first Hopf point to D = 0.3
  (NTST = 50, NCOL = 4; :mod:`_auto_ab`), in rounds of their own: AUTO's run (its ``Total Time``, wall, and the
  CPU time of its program) against :func:`mechcont.continuation.cycles_from_hopf` in this process (wall and CPU
  time) at two settings, each checked against AUTO's results first: mechcont's defaults (Newton to 1e-10) and
  AUTO's demo's tolerance (Newton to 1e-7, as its EPSL = EPSU); with the Newton iterations of each program
  (AUTO's counted in its diagnostics file). CPU time is the fairer figure on a shared machine (a program waiting
  for a core counts in the wall time). ``--cycles-only``: this alone.

AUTO runs with ``OMP_NUM_THREADS=1`` and, for its Python CLUI, the interpreter running this
script (first on ``PATH`` as ``python``), so both programs start the same Python and NumPy.
"""

from __future__ import annotations

import argparse
import gc
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
import _auto_ab  # noqa: E402
from _bytecode import compile_sources  # noqa: E402

HOW_TO_GET = ("bench_auto: AUTO_DIR is not set to a built AUTO-07p; get it from https://github.com/auto-07p/auto-07p "
              "(./configure && make, needs gfortran), then AUTO_DIR=/path/to/auto-07p python benchmarks/bench_auto.py")

LU = 0.4
THETA1 = 0.3
F_BOUND = 200.0
LU_BOUNDS = (0.1, 2.0)
REL_TOL = 1e-6

#: (name, F = FSCALE * PAR(1), DSMAX of the branch, DSMAX of the fold curve, IID). With F in newtons, of
#: DSMAX = 0.5, 1, 2, 5, 10, 20 only 2 locates both folds: at the others AUTO's secant search for the
#: fold at -75.6 N (fold function near +-0.9 on both sides: the tangent turns from F to the states
#: within a tiny arclength) runs out of its ITMX = 8 iterations and reports no LP (ITMX = 20 gives
#: LPs off by 1e-4). With F/127 every DSMAX from 0.005 to 1 locates both; 1 gives point counts
#: nearest mechcont's. IID = 2 (AUTO's default) writes every Newton iteration to the d-file; IID = 0
#: writes none (the b- and s-files as before): mechcont writes no file in-process.
VARIANTS = [("F in N", 1.0, 2.0, 2.0, 2), ("F/127", 127.0, 1.0, 1.0, 2), ("F/127, IID=0", 127.0, 1.0, 1.0, 0)]


_FORTRAN = """\
! The overcentre of Knowles et al. (2010), eq. 6, as an AUTO algebraic problem.
! U = (x1, y1, theta1, x2, y2, theta2); F = {fscale} * PAR(1), PAR(2) = LU, PAR(3:10) = L1, L2, m1, m2, g, k, m, n.
SUBROUTINE FUNC(NDIM, U, ICP, PAR, IJAC, F, DFDU, DFDP)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, ICP(*), IJAC
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(OUT) :: F(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: DFDU(NDIM, NDIM), DFDP(NDIM, *)
  DOUBLE PRECISION X1, Y1, T1, X2, Y2, T2, FORCE, LU, L1, L2, M1, M2, G, K, M, N, DX, DY, L, FSX, FSY
  X1 = U(1); Y1 = U(2); T1 = U(3); X2 = U(4); Y2 = U(5); T2 = U(6)
  FORCE = {fscale} * PAR(1); LU = PAR(2)
  L1 = PAR(3); L2 = PAR(4); M1 = PAR(5); M2 = PAR(6); G = PAR(7); K = PAR(8); M = PAR(9); N = PAR(10)
  ! spring from the point of bar 1 at m beyond its centre to the point of bar 2 at n beyond its centre
  DX = X2 + N * COS(T2) - X1 - M * COS(T1)
  DY = Y2 + N * SIN(T2) - Y1 - M * SIN(T1)
  L = SQRT(DX * DX + DY * DY)
  FSX = K * (LU - L) * DX / L
  FSY = K * (LU - L) * DY / L
  F(1) = X1 - L1 / 2 * COS(T1)
  F(2) = Y1 - L1 / 2 * SIN(T1)
  F(3) = X2 + L2 / 2 * COS(T2) - (X1 + L1 / 2 * COS(T1))
  F(4) = Y2 + L2 / 2 * SIN(T2) - (Y1 + L1 / 2 * SIN(T1))
  F(5) = Y2 - L2 / 2 * SIN(T2)
  F(6) = FSX * ((0.5D0 - M / L1) * TAN(T1) - (0.5D0 - N / L2) * TAN(T2)) + FSY * (M / L1 - N / L2) &
       + (M1 * G + M2 * G) / 2 - FORCE
END SUBROUTINE FUNC

SUBROUTINE STPNT(NDIM, U, PAR, T)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(INOUT) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(IN) :: T
{start}
END SUBROUTINE STPNT

SUBROUTINE BCND
END SUBROUTINE BCND
SUBROUTINE ICND
END SUBROUTINE ICND
SUBROUTINE FOPT
END SUBROUTINE FOPT
SUBROUTINE PVLS
END SUBROUTINE PVLS
"""

_CONSTANTS = """\
NDIM=6, IPS=0, IRS=0, ILP=1
ICP=[1]
NTST=1, NCOL=1, IAD=0, ISP=1, ISW=1, IPLT=0, NBC=0, NINT=0
NMX=5000, NPR=5000, MXBF=0, IID={iid}, ITMX=8, ITNW=8, NWTN=3, JAC=0
EPSL=1e-10, EPSU=1e-10, EPSS=1e-10
DS={ds}, DSMIN=1e-9, DSMAX={dsmax}, IADS=1
NPAR=10, THL={{}}, THU={{}}
UZSTOP={{1: [{flo!r}, {fhi!r}]}}
"""

_BRANCH = """\
b = run(e='oc', c='oc') + run(e='oc', c='oc', DS='-')
for p in b('LP'):
    print('RESULT LP', repr(float(p['PAR(1)'])), repr(float(p['U(3)'][0])))
"""

_FOLDS = _BRANCH + """\
lp = [p for p in b('LP') if p['U(3)'][0] > 0][0]
for ds in (0.01, -0.01):
    f = run(lp, ICP=[1, 2], ISW=2, DS=ds, DSMAX={dsmax}, UZSTOP={{2: [{lulo!r}, {luhi!r}]}})
    for p in f('UZ'):
        print('RESULT UZ', repr(float(p['PAR(1)'])), repr(float(p['PAR(2)'])))
"""

_MECHCONT_ARGS = ["--set", f"LU={LU}", "--start", f"theta1={THETA1}", "--vary", "F"]
MECHCONT_CONTINUE = ["continue", "overcentre", *_MECHCONT_ARGS, "--bounds", f"F={-F_BOUND:g}:{F_BOUND:g}"]
MECHCONT_FOLDS = ["folds", "overcentre", *_MECHCONT_ARGS, "--along", "LU", "--bounds", f"LU={LU_BOUNDS[0]:g}:{LU_BOUNDS[1]:g}",
                  "--bounds", f"F={-F_BOUND:g}:{F_BOUND:g}"]


def _fortran_start(x0: dict[str, float], fscale: float) -> str:
    """STPNT's body: mechcont's start point and the model's parameter values as Fortran literals."""
    d = lambda v: f"{float(v)!r}".replace("e", "D") + ("" if "e" in f"{float(v)!r}" else "D0")  # noqa: E731
    par = [x0["F"] / fscale, x0["LU"], x0["L1"], x0["L2"], x0["m1"], x0["m2"], x0["g"], x0["k"], x0["m"], x0["n"]]
    u = [x0[n] for n in ("x1", "y1", "theta1", "x2", "y2", "theta2")]
    lines = [f"  PAR({i + 1}) = {d(v)}" for i, v in enumerate(par)] + [f"  U({i + 1}) = {d(v)}" for i, v in enumerate(u)]
    return "\n".join(lines)


def write_problem(folder: Path, x0: dict[str, float], fscale: float, dsmax: float, fold_dsmax: float, iid: int = 2) -> None:
    """Write the AUTO problem (``oc.f90``, ``c.oc``) and the scripts ``branch.auto``, ``folds.auto``."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "oc.f90").write_text(_FORTRAN.format(fscale=f"{fscale!r}D0", start=_fortran_start(x0, fscale)))
    (folder / "c.oc").write_text(_CONSTANTS.format(ds=0.01 * min(dsmax, 1.0), dsmax=dsmax, iid=iid, flo=-F_BOUND / fscale,
                                                   fhi=F_BOUND / fscale))
    (folder / "branch.auto").write_text(_BRANCH)
    (folder / "empty.auto").write_text("")
    (folder / "folds.auto").write_text(_FOLDS.format(dsmax=fold_dsmax, lulo=LU_BOUNDS[0], luhi=LU_BOUNDS[1]))


def parse_auto_output(out: str) -> tuple[list[float], list[int], list[list[str]]]:
    """What an ``auto`` process printed: AUTO's ``Total Time`` of each run (s), the points each
    run computed (the PT column of the last row it prints) and the scripts' ``RESULT`` lines
    split into words (without ``RESULT``)."""
    times = [float(t) for t in re.findall(r"Total Time\s+(\S+)", out)]
    points = []
    for chunk in out.split("Total Time")[:-1]:
        # a periodic run prints an unstable orbit's point number negative
        rows = re.findall(r"^\s+-?\d+\s+(-?\d+)\s+[A-Z]{2}\s+\d+\s", chunk, flags=re.M)
        points.append(abs(int(rows[-1])))
    results = [line.split()[1:] for line in out.splitlines() if line.startswith("RESULT")]
    return times, points, results


class AutoRun:
    """One ``auto SCRIPT`` process: its wall time (s) and what it printed (see :func:`parse_auto_output`)."""

    def __init__(self, auto_dir: Path, folder: Path, script: str, env: dict[str, str]):
        t0 = time.perf_counter()
        proc = subprocess.run([str(auto_dir / "bin" / "auto"), script], cwd=folder, env=env, capture_output=True, text=True)
        self.wall = time.perf_counter() - t0
        if proc.returncode != 0 or "Traceback" in proc.stdout + proc.stderr or "AUTO Runtime Error" in proc.stdout:
            raise RuntimeError(f"auto {script} failed ({proc.returncode}): {(proc.stdout + proc.stderr)[-800:]}")
        self.run_times, self.run_points, self.results = parse_auto_output(proc.stdout)

    def values(self, kind: str, fscale: float) -> list[tuple[float, float]]:
        """``(F [N], second)`` of each printed point of ``kind`` (``LP``: second theta1; ``UZ``: LU)."""
        return [(float(a) * fscale, float(b)) for k, a, b in self.results if k == kind]


def cases():
    """No cases for ``benchmarks/run.py``: this comparison runs alone (it needs ``AUTO_DIR``)."""
    return []


def _mechcont_cli(args: list[str]) -> list[str]:
    return [sys.executable, "-c", "import sys; from mechcont.cli import main; main(sys.argv[1:])", *args]


def _timed(argv: list[str], env: dict[str, str]) -> float:
    t0 = time.perf_counter()
    proc = subprocess.run(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    dt = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(argv[-12:])} failed ({proc.returncode}): {proc.stderr.decode()[-500:]}")
    return dt


def _agree(what: str, ours: list[float], theirs: list[float]) -> bool:
    ours, theirs = sorted(ours), sorted(theirs)
    ok = len(ours) == len(theirs) and all(abs(a - b) <= REL_TOL * max(abs(a), 1.0) for a, b in zip(ours, theirs))
    print(f"  {what}: mechcont {', '.join(f'{v:.10g}' for v in ours)} | AUTO {', '.join(f'{v:.10g}' for v in theirs)}"
          f"  {'agree' if ok else 'DISAGREE'}")
    return ok


def mechcont_problem():
    """The model, its start, and the functions timed in-process: (branch, fold curve)."""
    from mechcont.continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium
    from mechcont.models import build_overcentre

    s = build_overcentre(LU=LU)
    x0 = find_equilibrium(s, hold={"theta1": THETA1}, free=["F"])
    opts = ContinuationOptions(bounds={"F": (-F_BOUND, F_BOUND)})
    fopts = ContinuationOptions(bounds={"LU": LU_BOUNDS})

    def branch():
        return continuation(s, x0, "F", options=opts)

    def fold_curve(b=None):
        b = b if b is not None else branch()
        lp = [p for p in b.special("LP") if p["theta1"] > 0][0]
        return continue_folds(s, lp, "F", "LU", options=fopts)

    return s, x0, branch, fold_curve


def _median_in_process(fn, repeats: int) -> float:
    """Median seconds of ``repeats`` calls of ``fn`` after one warm-up, garbage collection off
    while timing (as in ``benchmarks/run.py``)."""
    fn()
    times = []
    gc.collect()
    gc.disable()
    try:
        for _ in range(repeats):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
    finally:
        gc.enable()
    return statistics.median(times)


def _auto_env(tmp: Path, auto_dir: Path) -> dict[str, str]:
    """The environment of AUTO's runs: its ``python`` this interpreter (a symlink in ``tmp/bin``), one thread."""
    (tmp / "bin").mkdir()
    (tmp / "bin" / "python").symlink_to(sys.executable)
    return {**os.environ, "AUTO_DIR": str(auto_dir), "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg",
            "PATH": f"{tmp / 'bin'}{os.pathsep}{os.environ.get('PATH', '')}"}


class _CycleTimes:
    """The periodic orbits of ``ab`` in both programs, checked, then timed in alternated rounds: each round AUTO's
    periodic run (its ``Total Time``, wall, and its program's CPU time), then one call of mechcont's family at each of
    :data:`_auto_ab.SETTINGS` (wall and CPU time, garbage collection off, after a warm-up call)."""

    def __init__(self, auto_dir: Path, folder: Path, env: dict[str, str]) -> None:
        self.auto_dir, self.folder, self.env = auto_dir, folder, env
        _auto_ab.write_problem(folder)
        self.families = {name: _auto_ab.mechcont_family(tol)[1] for name, tol in _auto_ab.SETTINGS.items()}
        for fn in self.families.values():
            fn()  # warm-up: compiled code, caches
        counted = {name: _auto_ab.mechcont_iterations(fn) for name, fn in self.families.items()}
        self.results = {name: c[0] for name, c in counted.items()}
        self.iterations = {name: c[1:] for name, c in counted.items()}
        self.check = AutoRun(auto_dir, folder, "cycles.auto", env)  # also compiles ab.exe
        self.auto_iterations = _auto_ab.auto_iterations((folder / "fort.9").read_text())
        self.auto_wall: list[float] = []
        self.auto_cpu: list[float] = []
        self.wall: dict[str, list[float]] = {name: [] for name in self.families}
        self.cpu: dict[str, list[float]] = {name: [] for name in self.families}

    def agree(self) -> bool:
        """Every setting's family agrees with AUTO's (:func:`_auto_ab.agree`), the lines printed."""
        return all([_auto_ab.agree(self.check.results, fam, print, name) for name, fam in self.results.items()])

    def round(self) -> None:
        """One round: AUTO's run, then mechcont's family at each setting."""
        r = AutoRun(self.auto_dir, self.folder, "cycles.auto", self.env)
        self.auto_wall.append(r.run_times[1])
        self.auto_cpu.append(_auto_ab.auto_cpu(r.results))
        for name, fn in self.families.items():
            gc.collect()
            gc.disable()
            try:
                t0, c0 = time.perf_counter(), time.process_time()
                fn()
                self.wall[name].append(time.perf_counter() - t0)
                self.cpu[name].append(time.process_time() - c0)
            finally:
                gc.enable()

    def report(self) -> None:
        """The table: medians of the rounds, per family and per orbit, mechcont against AUTO in wall and CPU time."""
        med = statistics.median
        aw, ac, an = med(self.auto_wall), med(self.auto_cpu), self.check.run_points[1]
        print(f"\nPeriodic orbits of ab (HB1 to D = 0.3, NTST = {_auto_ab.NTST}, NCOL = {_auto_ab.NCOL}), median of "
              f"{len(self.auto_wall)} alternated rounds. Wall: AUTO's Total Time, mechcont's call. CPU: AUTO's program "
              "(its process), mechcont's call (this process)")
        print("| program, settings | orbits | Newton iterations (per orbit) | wall (ms) | CPU (ms) | CPU per orbit (ms) "
              "| vs AUTO per family: wall, CPU |")
        print("|---|---|---|---|---|---|---|")
        it, _ = self.auto_iterations
        print(f"| AUTO, its demo's EPSL = EPSU = 1e-7, Jacobian by differences | {an} | {it} ({it / an:.1f}) | "
              f"{aw * 1e3:.1f} | {ac * 1e3:.1f} | {ac / an * 1e3:.2f} | |")
        for name, fam in self.results.items():
            w, c = med(self.wall[name]), med(self.cpu[name])
            it, _ = self.iterations[name]
            print(f"| {name} | {len(fam)} | {it} ({it / len(fam):.1f}) | {w * 1e3:.1f} | {c * 1e3:.1f} | "
                  f"{c / len(fam) * 1e3:.2f} | {w / aw:.2f}×, {c / ac:.2f}× |")


def _cycles_only(auto_dir: Path, repeats: int) -> int:
    """``--cycles-only``: ab's periodic family, checked, then AUTO's run and mechcont's calls alternated ``repeats``
    times (:class:`_CycleTimes`)."""
    tmp = Path(tempfile.mkdtemp(prefix="mechcont-bench-auto-"))
    try:
        cycles = _CycleTimes(auto_dir, tmp / "ab", _auto_env(tmp, auto_dir))
        if not cycles.agree():
            print("AUTO and mechcont disagree: the comparison would not be of the same problem", file=sys.stderr)
            return 1
        for _ in range(repeats):
            cycles.round()
        cycles.report()
        return 0
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7, help="rounds (median reported; at least 5)")
    ap.add_argument("--cycles-only", action="store_true",
                    help="only the periodic orbits of ab: AUTO's run and mechcont's call alternated, nothing else")
    args = ap.parse_args(argv)
    auto_dir = Path(os.environ.get("AUTO_DIR", "")) if os.environ.get("AUTO_DIR") else None
    if auto_dir is None or not (auto_dir / "bin" / "auto").is_file() or not list((auto_dir / "lib").glob("*.o")):
        print(HOW_TO_GET)
        return 0
    repeats = max(args.repeats, 5)
    if args.cycles_only:
        return _cycles_only(auto_dir, repeats)
    s, x0vec, branch_fn, fold_fn = mechcont_problem()
    x0 = dict(zip(s.names, map(float, x0vec)))
    b = branch_fn()
    fc = fold_fn(b)
    our_lp = [p["F"] for p in b.special("LP")]
    our_ends = [p["F"] for p in fc.special("EP")]
    tmp = Path(tempfile.mkdtemp(prefix="mechcont-bench-auto-"))
    try:
        # $AUTO_DIR/bin/auto runs the first `python` on PATH: make it this interpreter (no shim in
        # between, the same start-up and NumPy as mechcont's processes)
        env = _auto_env(tmp, auto_dir)
        folders = {}
        ok = True
        print(f"Same problem? (folds of the branch in F at LU = {LU} m; fold-curve ends at LU = {LU_BOUNDS[0]} m; N)")
        for name, fscale, dsmax, fold_dsmax, iid in VARIANTS:
            folder = tmp / re.sub(r"\W", "_", name)
            write_problem(folder, x0, fscale, dsmax, fold_dsmax, iid)
            folders[name] = (folder, fscale)
            check = AutoRun(auto_dir, folder, "folds.auto", env)  # also compiles oc.exe (before any timing)
            ok &= _agree(f"AUTO {name}: LP (F)", our_lp, [f for f, _ in check.values("LP", fscale)])
            ok &= _agree(f"AUTO {name}: fold-curve ends (F)", our_ends, [f for f, _ in check.values("UZ", fscale)])
        cycles = _CycleTimes(auto_dir, tmp / "ab", env)
        ok &= cycles.agree()
        if not ok:
            print("AUTO and mechcont disagree: the comparison would not be of the same problem", file=sys.stderr)
            return 1
        menv = {**os.environ, "MPLBACKEND": "Agg", "MECHCONT_CACHE_DIR": str(tmp / "mechcont-cache")}
        menv.pop("MECHCONT_NO_CACHE", None)
        compile_sources(Path(auto_dir) / "python")  # both sides from bytecode, as on a machine that writes it
        for cmd in (MECHCONT_CONTINUE, MECHCONT_FOLDS):
            _timed(_mechcont_cli(cmd), menv)  # fill the warm cache
        rows: dict[str, list[float]] = {}
        auto_in: dict[str, list[float]] = {}
        auto_pts: dict[str, list[int]] = {}
        ours_in = {"branch": [], "fold curve": []}
        for _ in range(repeats):
            rows.setdefault("mechcont continue", []).append(_timed(_mechcont_cli(MECHCONT_CONTINUE), menv))
            rows.setdefault("mechcont folds", []).append(_timed(_mechcont_cli(MECHCONT_FOLDS), menv))
            rows.setdefault("auto empty.auto (AUTO's Python CLUI start-up)", []).append(
                AutoRun(auto_dir, next(iter(folders.values()))[0], "empty.auto", env).wall)
            for name, (folder, _) in folders.items():
                r = AutoRun(auto_dir, folder, "branch.auto", env)
                rows.setdefault(f"auto branch.auto ({name})", []).append(r.wall)
                auto_in.setdefault(f"branch {name}", []).append(sum(r.run_times))
                auto_pts[f"branch {name}"] = [sum(r.run_points)]
                r = AutoRun(auto_dir, folder, "folds.auto", env)
                rows.setdefault(f"auto folds.auto ({name})", []).append(r.wall)
                auto_in.setdefault(f"fold curve {name}", []).append(sum(r.run_times[2:]))
                auto_pts[f"fold curve {name}"] = [sum(r.run_points[2:])]
            ours_in["branch"].append(_median_in_process(branch_fn, 5))
            ours_in["fold curve"].append(_median_in_process(lambda: fold_fn(b), 5))
            cycles.round()
        med = {k: statistics.median(v) for k, v in rows.items()}
        print(f"\nIn-process, median of {repeats} rounds (mechcont: median of 5 calls per round; AUTO: its Total Time, "
              "both runs of a continuation summed)")
        print("| work | program | points | time (ms) | per point (µs) | mechcont / AUTO |")
        print("|---|---|---|---|---|---|")
        for work, ours in (("branch", b), ("fold curve", fc)):
            t_ours = statistics.median(ours_in[work])
            n_ours = len(ours.values)
            print(f"| {work} | mechcont | {n_ours} | {t_ours * 1e3:.2f} | {t_ours / n_ours * 1e6:.1f} | |")
            for name, *_ in VARIANTS:
                t = statistics.median(auto_in[f"{work} {name}"])
                n = auto_pts[f"{work} {name}"][0]
                print(f"| {work} | AUTO, {name} | {n} | {t * 1e3:.2f} | {t / n * 1e6:.1f} | "
                      f"{t_ours / t:.2f}× per {work}, {(t_ours / n_ours) / (t / n):.2f}× per point |")
        cycles.report()
        print(f"\nWhole process, median of {repeats} rounds (start to exit; mechcont cache warm, AUTO's oc.exe built)")
        print("| command | time (s) | mechcont / this |")
        print("|---|---|---|")
        for key, t in med.items():
            ours = med["mechcont folds" if "folds" in key else "mechcont continue"]
            shown = "" if key.startswith("mechcont") or "empty" in key else f"{ours / t:.2f}×"
            print(f"| {key} | {t:.3f} | {shown} |")
        return 0
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
