"""Where the time of mechcont's overcentre branch goes, per point (cProfile).

The branch of ``benchmarks/bench_auto.py`` (LU = 0.4 m, from theta1 = 0.3 rad, in F to
+-200 N, 83 points) run ``--runs`` times under cProfile. Prints the share of each part of a
step and the top functions by own time. Per-point figures are the shares applied to
the branch's unprofiled median time, because cProfile's own cost per call inflates
Python-heavy parts.
Run: ``python benchmarks/profile_overcentre.py [--runs N]``.
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import statistics
import sys
import time


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=100)
    args = ap.parse_args(argv)
    from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
    from mechcont.models import build_overcentre

    s = build_overcentre(LU=0.4)
    x0 = find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])
    opts = ContinuationOptions(bounds={"F": (-200.0, 200.0)})
    npts = len(continuation(s, x0, "F", options=opts).values)
    times = []
    for _ in range(30):
        t0 = time.perf_counter()
        continuation(s, x0, "F", options=opts)
        times.append(time.perf_counter() - t0)
    plain = statistics.median(times)
    prof = cProfile.Profile()
    prof.enable()
    for _ in range(args.runs):
        continuation(s, x0, "F", options=opts)
    prof.disable()
    stats = pstats.Stats(prof).stats  # type: ignore[attr-defined]

    def key(fname: str, func: str):
        (k,) = [k for k in stats if k[0].endswith(fname) and k[2] == func]
        return k

    def via(callee, caller) -> float:
        """Cumulative seconds of ``callee`` when called from ``caller``."""
        c = stats[callee][4].get(caller)
        return c[3] if c else 0.0

    total = stats[key("_api.py", "continuation")][3]
    step = key("_palc.py", "_step")
    values = [k for k in stats if k[0].endswith("_palc.py") and k[2] == "<listcomp>"]
    parts = {
        "corrector (Newton: model evaluations, bordered LU solves, convergence tests)": via(key("_palc.py", "correct"), step),
        "tangent (one bordered solve per point)": via(key("_palc.py", "tangent"), step),
        "event test functions at every point (LP, BP det, bounds)": sum(via(k, step) for k in values),
        "locating LP/EP within their steps, fold polish": via(key("_palc.py", "_events_in_step"), step),
        "point state (PointState, full vector)": via(key("_palc.py", "state"), step),
        "step control (_step's own code, accept/reject, tangent angle)": stats[step][2] + via(key("_palc.py", "accept"), step),
        "start of each direction (initial tangent by SVD)": sum(stats[k][3] for k in stats
                                                                if k[0].endswith("_palc.py") and k[2] == "__init__"),
        "stability (batched at the end)": stats[key("_problem.py", "stability_batch")][3],
    }
    parts["recording the branch, set-up (the rest)"] = total - sum(parts.values())
    per_point = plain / npts
    print(f"branch: {npts} points, {plain * 1e3:.2f} ms unprofiled (median of 30) = {per_point * 1e6:.1f} µs/point; "
          f"{args.runs} runs profiled")
    print("| part | share | µs/point |\n|---|---|---|")
    for name, t in parts.items():
        print(f"| {name} | {t / total:.1%} | {t / total * per_point * 1e6:.1f} |")
    print("\n| function (own time) | share | µs/point | calls/point |\n|---|---|---|---|")
    for (f, line, fn), (_, nc, tt, _, _) in sorted(stats.items(), key=lambda kv: -kv[1][2])[:10]:
        where = f.split("/src/")[-1].split("site-packages/")[-1]
        print(f"| {where}:{line}({fn}) | {tt / total:.1%} | {tt / total * per_point * 1e6:.1f} | {nc / args.runs / npts:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
