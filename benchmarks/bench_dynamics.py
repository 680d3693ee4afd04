"""The paper's speed claim, measured: downlock force against LU by sweeps and by continuation.

The downlock force of the symmetric overcentre is its lower fold in F (the minimum push
that snaps the locked mechanism through), here at 20 values of the unstrained spring
length LU from 0.1 m to 1.4 m, obtained

(a) the traditional way: per LU value, one time simulation ramping F down from 20 N at a
    constant rate until the lock-link angle theta1 passes 0 (the mechanism snapped
    through); the jump load is the F at which the snap motion started;
(b) by continuation: one branch in F at LU = 0.4 m to find the fold, one two-parameter
    fold continuation in (F, LU), and a Newton polish of the fold at each LU value.

Both are compared with the closed form ``symmetric_folds``. ``cases()`` serves
``benchmarks/run.py``; ``python benchmarks/bench_dynamics.py`` prints the comparison table
(times are medians; sweeps use fewer repeats there because one set takes seconds).
"""

from __future__ import annotations

import math
import statistics
import sys
import time

import numpy as np

from mechcont.continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium, locate_fold
from mechcont.dynamics import assemble, sweep
from mechcont.models import build_overcentre
from mechcont.models.overcentre import symmetric_folds, symmetric_force

LUS = np.linspace(0.1, 1.4, 20)
L, M1, M2, G, K = 1.5, 1.0, 1.0, 9.81, 127.0
C = 10.0  # N s/m damper along the spring: light, the most accurate sweeps for their cost (stop at theta1 = 0)
F_START, F_STOP = 20.0, -160.0  # N: the locked mechanism at 20 N up; every downlock force lies above -160 N


def reference() -> np.ndarray:
    """Closed-form downlock (lower-fold) force at each LU (N)."""
    return np.array([symmetric_folds(L, M1, M2, G, K, lu)[1][1] for lu in LUS])


def _upper_equilibrium(system, lu: float, F: float) -> np.ndarray:
    th_fold = symmetric_folds(L, M1, M2, G, K, lu)[1][0]
    lo, hi = th_fold, math.pi / 2 - 1e-9
    for _ in range(200):  # bisection on the closed form: set-up only, not timed
        mid = 0.5 * (lo + hi)
        if symmetric_force(mid, L, M1, M2, G, K, lu) > F:
            hi = mid
        else:
            lo = mid
    th = 0.5 * (lo + hi)
    return assemble(system, {"LU": lu, "F": F, "c": C, "theta1": th, "theta2": math.pi - th}, hold=["theta1"])


def sweep_setup():
    """The model and one start (locked, at equilibrium under F_START) per LU value."""
    system = build_overcentre(c=C)
    return system, [_upper_equilibrium(system, lu, F_START) for lu in LUS]


def downlock_by_sweeps(system, starts, rate: float) -> np.ndarray:
    """Jump load (N) of one down-sweep of F per LU value, at ``rate`` N/s."""
    out = []
    for x0 in starts:
        r = sweep(system, x0, {"F": (F_START, F_STOP, rate)}, watch="theta1", through=0.0, stop_on_jump=True,
                  max_step=math.inf)
        if not r.jumps:
            out.append(math.nan)
            continue
        # F when the snap motion started (the rate threshold was crossed), not at theta1 = 0
        out.append(float(np.interp(r.jumps[0].t_start, r.t, r["F"])))
    return np.array(out)


def downlock_by_continuation(system) -> np.ndarray:
    """Lower-fold force (N) at each LU: branch at LU = 0.4 m, fold curve in (F, LU), Newton polish."""
    x0 = find_equilibrium(system, values={"LU": 0.4, "F": -60.0}, guess={"theta1": 1.0, "theta2": math.pi - 1.0})
    branch = continuation(system, x0, "F", direction=-1,
                          options=ContinuationOptions(bounds={"F": (-200.0, 200.0)}, max_steps=300, stability=False))
    lower = min(branch.special("LP"), key=lambda p: p["F"])
    curve = continue_folds(system, lower, vary="F", free="LU",
                           options=ContinuationOptions(bounds={"LU": (LUS[0] - 0.01, LUS[-1] + 0.01)}))
    i_lu, i_f = system.index("LU"), system.index("F")
    out = []
    for lu in LUS:
        guess = curve.values[np.argmin(np.abs(curve.values[:, i_lu] - lu))].copy()
        guess[i_lu] = lu
        x, _, _ = locate_fold(system, guess, "F")
        out.append(x[i_f])
    return np.array(out)


def cases():
    """Benchmark cases for benchmarks/run.py (a full 20-LU set per repetition)."""
    sw_system, starts = sweep_setup()
    ct_system = build_overcentre(c=C)
    ct_system.compile()
    return [
        ("downlock_20LU_sweeps_4N_per_s", lambda: downlock_by_sweeps(sw_system, starts, 4.0), 20),
        ("downlock_20LU_fold_continuation", lambda: downlock_by_continuation(ct_system), 20),
    ]


def _median_time(fn, repeats: int) -> tuple[float, object]:
    fn()  # warm-up
    times, value = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), value


def comparison_table(rates=(4.0, 1.0, 0.25), sweep_repeats: int = 3, continuation_repeats: int = 20) -> str:
    """Markdown table: time and accuracy of each method against the closed form, and the ratio."""
    ref = reference()
    sw_system, starts = sweep_setup()
    ct_system = build_overcentre(c=C)
    t_ct, f_ct = _median_time(lambda: downlock_by_continuation(ct_system), continuation_repeats)
    err_ct = float(np.max(np.abs(f_ct - ref)))
    rows = ["| method (20 LU values, 0.1-1.4 m) | median time (s) | max error vs closed form (N) | "
            "time / continuation |", "|---|---|---|---|"]
    for rate in rates:
        t_sw, f_sw = _median_time(lambda: downlock_by_sweeps(sw_system, starts, rate), sweep_repeats)
        err = float(np.max(np.abs(f_sw - ref)))
        side = "all past the fold" if np.all(f_sw < ref) else "NOT all past the fold"
        rows.append(f"| sweeps, F ramped at {rate:g} N/s ({side}) | {t_sw:.3g} | {err:.3g} | {t_sw / t_ct:.0f} |")
    rows.append(f"| two-parameter fold continuation | {t_ct:.3g} | {err_ct:.2g} | 1 |")
    return "\n".join(rows)


if __name__ == "__main__":
    print(comparison_table(), file=sys.stdout)
