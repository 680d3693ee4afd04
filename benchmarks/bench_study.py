"""Studies: batched nose-gear downlock solves against the single-point path, and a 10,000-sample
tolerance study serially and on a local Dask cluster (``python benchmarks/bench_study.py``).

``cases()`` (the benchmark table) times the kernels; running this file measures the whole
study three ways (median of 5 runs each, the cluster started inside every run), checks that
they agree and prints a table with the throughput per core.
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time

#: The issue's study: 10,000 nose-gear downlock solves over a two-parameter tolerance distribution.
N = 10_000


def tolerance_spec(n: int = N):
    """Rigging tolerances of the nose gear: spring free length and spring attachment (m)."""
    from mechcont.analysis.study import Distribution, StudySpec

    return StudySpec("nose_gear", "mc", (("LU", Distribution("normal", (1.3, 0.01))),
                                         ("l_sp1", Distribution("truncnormal", (0.1, 0.005, 0.09, 0.11)))),
                     n=n, seed=1)


def _rows(system, spec):
    import numpy as np

    X = np.tile(system.vector({"theta4": 0.0}, base=system.downlock.pose), (spec.size, 1))
    S = spec.samples()
    for j, n in enumerate(spec.names):
        X[:, system.index(n)] = S[:, j]
    return X, S


def cases():
    from mechcont.analysis import downlock_point
    from mechcont.continuation import choose_unknowns
    from mechcont.continuation._batch import newton_batch
    from mechcont.models import load_model

    system = load_model("nose_gear")
    spec = tolerance_spec(2000)
    X, S = _rows(system, spec)
    unknowns = choose_unknowns(system, hold=["theta4"], free=["F"])

    def single():
        for i in range(50):
            downlock_point(system, dict(zip(spec.names, S[i])))

    return [
        ("2000 downlock solves, batched (newton_batch)", lambda: newton_batch(system, X, unknowns), 20),
        ("50 downlock solves, one at a time (downlock_point)", single, 20),
    ]


def _median_run(spec, scheduler, repeats=5):
    from mechcont.analysis.study import run_study

    times, frame = [], None
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as d:
            t0 = time.perf_counter()
            r = run_study(spec, os.path.join(d, "s"), scheduler=scheduler)
            times.append(time.perf_counter() - t0)
            frame = r.frame()
    return statistics.median(times), min(times), frame


def main() -> int:
    import numpy as np

    from mechcont.analysis import downlock_point
    from mechcont.analysis.study import ModelSource, failure_probability, load_study_model

    spec = tolerance_spec()
    load_study_model(ModelSource.of("nose_gear"))  # the model is compiled (or read from the cache) once, not timed
    cores = os.cpu_count() or 1
    serial, serial_min, a = _median_run(spec, None)
    cluster, cluster_min, b = _median_run(spec, "local")
    system = load_study_model(ModelSource.of("nose_gear"))
    t0 = time.perf_counter()
    worst = 0.0
    for i in range(0, N, 100):  # the single-point path on every 100th sample
        x = downlock_point(system, {"LU": a["LU"][i], "l_sp1": a["l_sp1"][i]})
        worst = max(worst, abs(x[system.index("F")] - a["downlock_force"][i]) / max(1.0, abs(x[system.index("F")])))
    single = (time.perf_counter() - t0) / (N // 100)
    same = a.equals(b)
    print(f"{N} nose-gear downlock solves, LU ~ N(1.3 m, 0.01 m), l_sp1 ~ truncated N(0.1 m, 5 mm, 90..110 mm); "
          f"{cores} cores")
    print("| path | median (s) | min (s) | solves/s | solves/s per core |")
    print("|---|---|---|---|---|")
    print(f"| serial study, batched (one process) | {serial:.2f} | {serial_min:.2f} | {N / serial:,.0f} | "
          f"{N / serial:,.0f} |")
    print(f"| local cluster of {cores} worker processes, start included | {cluster:.2f} | {cluster_min:.2f} | "
          f"{N / cluster:,.0f} | {N / cluster / cores:,.0f} |")
    print(f"| single-point downlock_point (one at a time, 100 samples) | {single * N:.1f} (est.) | | {1 / single:,.0f} | "
          f"{1 / single:,.0f} |")
    print(f"serial and cluster results identical: {same}; batched vs single-point largest relative difference of the "
          f"force: {worst:.1e}")
    print(failure_probability(a).line())
    return 0 if same and worst < 1e-10 and np.isfinite(worst) else 1


if __name__ == "__main__":
    sys.exit(main())
