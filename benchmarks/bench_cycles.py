"""The periodic orbits of AUTO-07p's demo ``ab`` in mechcont alone, in CPU time: the ``bench_auto`` family without AUTO.

The family from the first Hopf point to D = 0.3 (NTST = 50, NCOL = 4; :mod:`_auto_ab`), called in this process
with the model built and one warm-up call before timing. ``python benchmarks/bench_cycles.py [--repeats N]
[--profile]`` prints the median and the minimum CPU time (``time.process_time``, the figure that holds on a shared
machine) per family and per orbit, the orbits' count, the fold of cycles (D, period) and the period at D = 0.3; with
``--profile``, the 25 most expensive functions of one call (cProfile, cumulative); with ``--both``, the compiled
condensation (``_ccondense``) and NumPy's (``MECHCONT_PURE_PYTHON=1``) in alternate calls of this process, each
with its own row (the fairest comparison on a shared machine, whose load moves between processes). AUTO-07p's own time for its
150 orbits of this family is measured beside mechcont's by ``bench_auto.py --cycles-only`` (docs/benchmarks.md).
Also a case of ``benchmarks/run.py`` (wall time there).
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
import _auto_ab  # noqa: E402


def cases():
    _, family = _auto_ab.mechcont_family()
    return [("ab: periodic orbits from HB1 to D = 0.3", family, 5)]


@contextlib.contextmanager
def _mode(mode: str):
    """``MECHCONT_PURE_PYTHON`` set for ``"numpy"``, unset for ``"compiled"``, left as it is for ``""``."""
    old = os.environ.get("MECHCONT_PURE_PYTHON")
    if mode == "numpy":
        os.environ["MECHCONT_PURE_PYTHON"] = "1"
    elif mode == "compiled":
        os.environ.pop("MECHCONT_PURE_PYTHON", None)
    try:
        yield
    finally:
        if old is None:
            os.environ.pop("MECHCONT_PURE_PYTHON", None)
        else:
            os.environ["MECHCONT_PURE_PYTHON"] = old


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=9, help="timed calls (median reported)")
    ap.add_argument("--profile", action="store_true", help="also print a cProfile of one call")
    ap.add_argument("--both", action="store_true",
                    help="alternate the compiled and the NumPy condensation (MECHCONT_PURE_PYTHON) call by call")
    args = ap.parse_args(argv)
    _, family = _auto_ab.mechcont_family()
    pure = os.environ.get("MECHCONT_PURE_PYTHON", "") not in ("", "0")
    modes = ["compiled", "numpy"] if args.both else ["numpy" if pure else ""]
    fams, times = {}, {mode: [] for mode in modes}
    for mode in modes:
        with _mode(mode):
            fams[mode] = family()  # warm-up: compiled code, caches
    gc.collect()
    gc.disable()
    try:
        for _ in range(args.repeats):
            for mode in modes:
                with _mode(mode):
                    t0 = time.process_time()
                    family()
                    times[mode].append(time.process_time() - t0)
    finally:
        gc.enable()
    print("| family | orbits | CPU median (ms) | CPU min (ms) | per orbit (ms) | LPC (D, period s) | period at D = 0.3 (s) |")
    print("|---|---|---|---|---|---|---|")
    for mode in modes:
        fam, ts = fams[mode], times[mode]
        med, n = statistics.median(ts), len(fam)
        lpc = [(float(fam.p[i]), float(fam.period[i])) for _, i in fam.point_names() if fam.labels[i] == "LPC"]
        name = "ab, HB1 to D = 0.3" + (f" ({mode})" if mode else "")
        print(f"| {name} | {n} | {med * 1e3:.1f} | {min(ts) * 1e3:.1f} | {med / n * 1e3:.2f} | "
              f"{', '.join(f'({d:.10f}, {T:.9f})' for d, T in lpc)} | {float(fam.period[-1]):.9f} |")
    if args.profile:
        import cProfile
        import pstats

        prof = cProfile.Profile()
        prof.enable()
        family()
        prof.disable()
        pstats.Stats(prof).sort_stats("cumulative").print_stats(25)
    return 0


if __name__ == "__main__":
    sys.exit(main())
