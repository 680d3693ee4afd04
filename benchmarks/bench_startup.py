"""Start-up of whole CLI processes with a warm disk cache, as ratios to a bare ``import numpy, scipy.linalg``.

A command should start like a compiled tool: with a warm cache every model loads its structure
and compiled code from disk and nothing heavy it does not use is imported. Each command runs as
a fresh process, in rounds that run every case once, interleaved with the bare-import baseline
(so a change in the machine's load falls on all cases alike); the table gives each case's
median over the rounds divided by the baseline's median in the same rounds.

``--before SRC`` also times the same commands with ``PYTHONPATH=SRC`` (another copy of mechcont's
``src``, e.g. ``git archive <commit> src | tar -x -C /tmp/before``), each source tree with its
own warm cache, in the same rounds: the before/after figures of a change.

Rounds: at least 5 (``--rounds``); ``MECHCONT_BENCH_STARTUP=0`` skips this part in
``benchmarks/run.py``. Run alone: ``python benchmarks/bench_startup.py [--rounds N] [--before SRC]``.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_process import BASELINE, _command, _run  # noqa: E402 - the same process runner

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
#: (name, CLI arguments, target ratio with a warm cache)
COMMANDS = [
    ("continue overcentre", ["continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
                             "--bounds", "theta1=-1.2:1.2"], 1.5),
    ("models", ["models"], 1.5),
    ("downlock nose_gear", ["downlock", "nose_gear", "--vary", "l_sp1", "--bounds", "l_sp1=-0.175:0.175"], 2.0),
    ("check dual_sidestay.toml", ["check", str(EXAMPLES / "dual_sidestay.toml")], 3.0),
]
_BARE = "bare import numpy, scipy.linalg"


def cases():
    """No in-process cases: this module is a whole-process report (see :func:`report`)."""
    return []


def measure(rounds: int, sources: dict[str, str | None], k: str = "", progress=None) -> dict[tuple[str, str], float]:
    """Median seconds of every (command, source) over ``rounds`` interleaved rounds, and of the baseline.

    ``sources`` maps a label to a ``PYTHONPATH`` (None: this interpreter's own ``mechcont``).
    Each source gets its own cache directory, filled by one run of every command first.
    """
    chosen = [c for c in COMMANDS if k in c[0]]
    base_env = {**os.environ, "MPLBACKEND": "Agg"}
    base_env.pop("MECHCONT_NO_CACHE", None)
    tmp = Path(tempfile.mkdtemp(prefix="mechcont-bench-startup-"))
    envs = {}
    for label, src in sources.items():
        env = {**base_env, "MECHCONT_CACHE_DIR": str(tmp / label)}
        if src is not None:
            env["PYTHONPATH"] = src
        envs[label] = env
    times: dict[tuple[str, str], list[float]] = {(_BARE, "-"): []}
    try:
        for env in envs.values():  # fill the caches (and the interpreter's bytecode caches)
            for _, args, _ in chosen:
                _run(_command(args, tmp), env)
        _run(BASELINE, base_env)
        for r in range(rounds):
            times[(_BARE, "-")].append(_run(BASELINE, base_env))
            for name, args, _ in chosen:
                for label, env in envs.items():
                    times.setdefault((name, label), []).append(_run(_command(args, tmp), env))
            if progress:
                progress(r + 1, rounds)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return {key: statistics.median(ts) for key, ts in times.items()}


def table(medians: dict[tuple[str, str], float], rounds: int) -> str:
    """The markdown table of :func:`measure`'s medians: seconds, ratio to the baseline, target."""
    base = medians[(_BARE, "-")]
    targets = {name: target for name, _, target in COMMANDS}
    w = max(len(name) for name, _ in medians)
    lines = [f"whole process, warm cache, median of {rounds} interleaved rounds, ratio to the bare import",
             f"| {'command':<{w}} | source | median (s) | ratio | target |",
             f"|{'-' * (w + 2)}|--------|------------|-------|--------|"]
    for (name, label), med in medians.items():
        ratio = med / base
        goal = "" if name not in targets else f"<= {targets[name]:g}x {'ok' if ratio <= targets[name] else 'MISSED'}"
        lines.append(f"| {name:<{w}} | {label:<6} | {med:>10.3f} | {ratio:>4.2f}x | {goal} |")
    return "\n".join(lines)


def report(min_repeats: int = 5, k: str = "") -> str:
    """The start-up table for ``benchmarks/run.py`` (5 rounds: each takes a few seconds; ``min_repeats`` is
    for the in-process cases)."""
    if os.environ.get("MECHCONT_BENCH_STARTUP", "1").strip().lower() in ("0", "no", "off", "false"):
        return ""
    if k and not any(k in c[0] for c in COMMANDS):
        return ""
    rounds = 5
    medians = measure(rounds, {"this": None}, k,
                      progress=lambda i, n: print(f"  start-up round {i}/{n}", file=sys.stderr))
    return table(medians, rounds)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=7, help="interleaved rounds (at least 5)")
    ap.add_argument("--before", default=None, metavar="SRC", help="also time mechcont from this src folder")
    ap.add_argument("-k", default="", help="only commands whose name contains this")
    args = ap.parse_args(argv)
    if args.rounds < 5:
        ap.error("--rounds must be at least 5")
    sources: dict[str, str | None] = {"after": None}
    if args.before is not None:
        sources = {"before": str(Path(args.before).resolve()), **sources}
    medians = measure(args.rounds, sources, args.k,
                      progress=lambda i, n: print(f"  round {i}/{n}", file=sys.stderr))
    print(table(medians, args.rounds))


if __name__ == "__main__":
    main()
