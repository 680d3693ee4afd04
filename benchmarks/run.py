"""Run every benchmark in this folder and print a table of median timings.

Each ``benchmarks/bench_*.py`` module defines ``cases()`` returning a list of
``(name, function, repeats)``: ``function()`` runs one repetition (its set-up is done
inside ``cases()``, before timing). A module may also define ``report(min_repeats, k)`` returning a table of its own (printed
after the main table): ``bench_process.py`` times whole CLI processes that way.
Usage: ``python benchmarks/run.py [-k SUBSTRING]``.
"""

from __future__ import annotations

import argparse
import gc
import importlib.util
import statistics
import sys
import time
from pathlib import Path


def _load(path: Path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-k", default="", help="only cases whose name contains this")
    ap.add_argument("--min-repeats", type=int, default=20)
    args = ap.parse_args(argv)
    here = Path(__file__).parent
    sys.path.insert(0, str(here))
    rows = []
    reports = []
    for path in sorted(here.glob("bench_*.py")):
        mod = _load(path)
        if hasattr(mod, "report"):
            reports.append(mod.report)
        for name, fn, repeats in mod.cases():
            if args.k not in name:
                continue
            n = max(repeats, args.min_repeats)
            fn()  # warm-up (compilation caches)
            times = []
            gc.collect()
            gc.disable()  # as timeit does: a collection triggered by earlier cases is not this case's cost
            try:
                for _ in range(n):
                    t0 = time.perf_counter()
                    fn()
                    times.append(time.perf_counter() - t0)
            finally:
                gc.enable()
            rows.append((path.stem[6:], name, n, statistics.median(times), min(times)))
            print(f"  {name}: {statistics.median(times) * 1e3:.2f} ms", file=sys.stderr)
    w = max((len(r[1]) for r in rows), default=4)
    print(f"| {'group':<12} | {'case':<{w}} | runs | median (ms) | min (ms) |")
    print(f"|{'-' * 14}|{'-' * (w + 2)}|------|-------------|----------|")
    for group, name, n, med, mn in rows:
        print(f"| {group:<12} | {name:<{w}} | {n:>4} | {med * 1e3:>11.3f} | {mn * 1e3:>8.3f} |")
    for report in reports:
        table = report(args.min_repeats, args.k)
        if table:
            print()
            print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
