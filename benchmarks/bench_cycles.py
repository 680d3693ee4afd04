"""The periodic orbits of AUTO-07p's demo ``ab`` in mechcont alone, in CPU time: the ``bench_auto`` family without AUTO.

The family from the first Hopf point to D = 0.3 (NTST = 50, NCOL = 4; :mod:`_auto_ab`), called in this process
with the model built and one warm-up call before timing. ``python benchmarks/bench_cycles.py [--repeats N]
[--profile]`` prints the median and the minimum CPU time (``time.process_time``, the figure that holds on a shared
machine) per family and per orbit, the orbits' count, the fold of cycles (D, period) and the period at D = 0.3; with
``--profile``, the 25 most expensive functions of one call (cProfile, cumulative). AUTO-07p took 111 ms of its
``Total Time`` for its 150 orbits of this family on the development machine (idle; ``bench_auto.py`` measures both).
Also a case of ``benchmarks/run.py`` (wall time there).
"""

from __future__ import annotations

import argparse
import gc
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
import _auto_ab  # noqa: E402


def cases():
    _, family = _auto_ab.mechcont_family()
    return [("ab: periodic orbits from HB1 to D = 0.3", family, 5)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=9, help="timed calls (median reported)")
    ap.add_argument("--profile", action="store_true", help="also print a cProfile of one call")
    args = ap.parse_args(argv)
    _, family = _auto_ab.mechcont_family()
    fam = family()  # warm-up: compiled code, caches
    times = []
    gc.collect()
    gc.disable()
    try:
        for _ in range(args.repeats):
            t0 = time.process_time()
            family()
            times.append(time.process_time() - t0)
    finally:
        gc.enable()
    med, n = statistics.median(times), len(fam)
    lpc = [(float(fam.p[i]), float(fam.period[i])) for _, i in fam.point_names() if fam.labels[i] == "LPC"]
    print("| family | orbits | CPU median (ms) | CPU min (ms) | per orbit (ms) | LPC (D, period s) | period at D = 0.3 (s) |")
    print("|---|---|---|---|---|---|---|")
    print(f"| ab, HB1 to D = 0.3 | {n} | {med * 1e3:.1f} | {min(times) * 1e3:.1f} | {med / n * 1e3:.2f} | "
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
