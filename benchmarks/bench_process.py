"""Whole-process timings of CLI commands, as ratios to a bare ``import numpy, scipy.linalg``.

A user waits for the whole process: interpreter start, imports, loading the model (from the
disk cache of compiled code when it is warm) and the work. Each command is timed as a fresh
process, in rounds that run every case once (so a change in the machine's load falls on
all cases alike), and reported as its median over the rounds divided by the median of the
bare-import baseline measured in the same rounds.

* warm: ``MECHCONT_CACHE_DIR`` is a temporary directory filled by one run before timing;
* cold: every run gets a fresh, empty ``MECHCONT_CACHE_DIR`` (everything compiled again).

Files a command reads (the branch ``animate`` draws) are written once, before timing, by the
commands in ``PREPARE``.

Rounds: at least 20 (``--min-repeats`` of ``benchmarks/run.py``); ``MECHCONT_BENCH_PROCESS_REPEATS=N``
sets N for a quick look (the table says how many were run). ``MECHCONT_BENCH_PROCESS=0``
skips this part. Run alone: ``python benchmarks/bench_process.py``.
"""

from __future__ import annotations

import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from _bytecode import compile_sources  # noqa: E402

#: (name, CLI arguments, target ratio with a warm cache or None)
COMMANDS = [
    ("continue overcentre (bounded branch)",
     ["continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
      "--bounds", "theta1=-1.2:1.2"], 4.0),
    ("models", ["models"], 4.0),
    # issue 19: at most 2x the bare import with a warm cache (as in bench_startup.py)
    ("downlock nose_gear", ["downlock", "nose_gear", "--vary", "l_sp1", "--bounds", "l_sp1=-0.175:0.175"], 2.0),
    # issue 19: at most about 5 s with a warm cache (the bare import takes about 0.7 s)
    ("animate overcentre branch (54 frames, GIF)",
     ["animate", "overcentre", "--branch", "{tmp}/overcentre-branch.csv", "--out", "{tmp}/overcentre.gif"], 7.0),
]
#: Files the commands read, written once before timing: CLI arguments ("{tmp}": the run's temporary folder).
PREPARE = [
    ["continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--bounds", "theta1=-1.2:1.2",
     "--out", "{tmp}/overcentre-branch.csv"],
]
BASELINE = [sys.executable, "-c", "import numpy, scipy.linalg"]


def cases():
    """No in-process cases: this module is a whole-process report (see :func:`report`)."""
    return []


def _command(args: list[str], tmp: Path) -> list[str]:
    return [sys.executable, "-c", "import sys; from mechcont.cli import main; main(sys.argv[1:])",
            *(a.replace("{tmp}", str(tmp)) for a in args)]


def _run(argv: list[str], env: dict[str, str]) -> float:
    """Seconds from start to exit of one process (its output discarded; a failure is an error)."""
    t0 = time.perf_counter()
    proc = subprocess.run(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    dt = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(argv[3:])} failed ({proc.returncode}): {proc.stderr.decode()[-500:]}")
    return dt


def measure(repeats: int, k: str = "", progress=None) -> list[tuple[str, str, float, float | None]]:
    """Median seconds per (command, cache) over ``repeats`` interleaved rounds.

    Returns rows ``(name, cache, median seconds, target ratio)``, the baseline first with
    cache ``-``.
    """
    env = {**os.environ, "MPLBACKEND": "Agg"}
    env.pop("MECHCONT_NO_CACHE", None)
    chosen = [c for c in COMMANDS if k in c[0]]
    tmp = Path(tempfile.mkdtemp(prefix="mechcont-bench-process-"))
    try:
        warm_env = {**env, "MECHCONT_CACHE_DIR": str(tmp / "warm")}
        for args in PREPARE:
            _run(_command(args, tmp), warm_env)
        compile_sources()  # bytecode, as on a machine that writes it (see _bytecode.py)
        for _, args, _ in chosen:  # fill the warm cache
            _run(_command(args, tmp), warm_env)
        _run(BASELINE, env)
        times: dict[tuple[str, str], list[float]] = {("bare import numpy, scipy.linalg", "-"): []}
        for r in range(repeats):
            times[("bare import numpy, scipy.linalg", "-")].append(_run(BASELINE, env))
            for name, args, _ in chosen:
                times.setdefault((name, "warm"), []).append(_run(_command(args, tmp), warm_env))
                cold = tmp / f"cold-{r}"
                times.setdefault((name, "cold"), []).append(
                    _run(_command(args, tmp), {**env, "MECHCONT_CACHE_DIR": str(cold)}))
                shutil.rmtree(cold, ignore_errors=True)
            if progress:
                progress(r + 1, repeats)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    targets = {name: target for name, _, target in chosen}
    return [(name, cache, statistics.median(ts), targets.get(name) if cache == "warm" else None)
            for (name, cache), ts in times.items()]


def report(min_repeats: int = 20, k: str = "") -> str:
    """The whole-process table (markdown) with ratios to the bare import in the same run."""
    if os.environ.get("MECHCONT_BENCH_PROCESS", "1").strip().lower() in ("0", "no", "off", "false"):
        return ""
    repeats = int(os.environ.get("MECHCONT_BENCH_PROCESS_REPEATS", min_repeats))
    if repeats < 1:
        raise ValueError(f"MECHCONT_BENCH_PROCESS_REPEATS must be at least 1, got {repeats}")
    if k and not any(k in c[0] for c in COMMANDS):
        return ""
    rows = measure(repeats, k, progress=lambda i, n: print(f"  whole-process round {i}/{n}", file=sys.stderr))
    base = rows[0][2]
    w = max(len(r[0]) for r in rows)
    lines = [f"whole process, median of {repeats} rounds, ratio to the bare import in the same rounds",
             f"| {'command':<{w}} | cache | median (s) | ratio | target (warm) |",
             f"|{'-' * (w + 2)}|-------|------------|-------|---------------|"]
    for name, cache, med, target in rows:
        ratio = med / base
        goal = "" if target is None else f"<= {target:g}x {'ok' if ratio <= target else 'MISSED'}"
        lines.append(f"| {name:<{w}} | {cache:<5} | {med:>10.3f} | {ratio:>4.1f}x | {goal:<13} |")
    return "\n".join(lines)


if __name__ == "__main__":
    print(report(int(sys.argv[1]) if len(sys.argv) > 1 else 20))
