"""The paper's speed claim, measured: downlock force against LU by sweeps and by continuation.

The downlock force of the symmetric overcentre is its lower fold in F (the push that snaps
the locked mechanism through), here at the 20 values of the unstrained spring length LU
``numpy.linspace(0.1, 1.4, 20)`` m, obtained

(a) the traditional way: per LU value, one time simulation (Udwadia–Kalaba model, RK45 =
    Dormand–Prince at Matlab ODE45's default tolerances rtol = 1e-3, atol = 1e-6) ramping
    F down from 20 N at a constant rate until the lock-link angle theta1 passes 0 (the
    mechanism snapped through); the jump load is the F at which the snap motion started
    (|dtheta1/dt| crossed the jump threshold). The engineer does not know the fold in
    advance, so every sweep starts from the same locked state at F = 20 N. The start
    equilibria are computed from the closed form, outside the timing (in the sweeps' favour).
(b) by continuation: one equilibrium branch in F at LU = 0.4 m to find the lower fold,
    one two-parameter fold continuation in (F, LU) over 0.1-1.4 m, and at each of the 20
    LU values the fold located exactly (``locate_fold``, Newton on the fold system with LU
    held, started from the nearest fold-curve point) — so both methods give values at the
    same 20 LU, with no interpolation.

Both are compared with the closed form ``symmetric_folds``. A sweep's error is the delay
of a slow passage through a saddle-node, ~ rate^(2/3), always past the fold. The rate an
engineer would use is the fastest that gets the whole curve within ``USABLE_ERROR`` (1 N,
0.7 % of the largest downlock force); ``comparison_table`` measures it.

``cases()`` serves ``benchmarks/run.py`` (20 repetitions per case): the sweep case there is
the usable rate on every 4th LU value (5 of the 20, which spread over the same range), to
keep the benchmark run short; the full 20-value set is in the table printed by
``python benchmarks/bench_dynamics.py`` (median CPU times: sweeps of 3 runs, continuation of 20).
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
SWEEP_RTOL, SWEEP_ATOL = 1e-3, 1e-6  # ODE45's defaults: tighter ones cost 2x and change the jump loads < 0.02 N
USABLE_ERROR = 1.0  # N: accuracy needed of a downlock-force curve (0.7 % of the largest, 136 N at LU = 0.1 m)
USABLE_RATE = 0.25  # N/s: the fastest of RATES that meets USABLE_ERROR (checked by comparison_table)
RATES = (4.0, 1.0, 0.5, 0.25)


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
    """Jump load (N) of one down-sweep of F per start (one per LU value), at ``rate`` N/s.

    ``nan`` where a sweep ends without a snap-through (none does over 20 -> -160 N).
    """
    out = []
    for x0 in starts:
        r = sweep(system, x0, {"F": (F_START, F_STOP, rate)}, watch="theta1", through=0.0, stop_on_jump=True,
                  max_step=math.inf, rtol=SWEEP_RTOL, atol=SWEEP_ATOL)
        if not r.jumps:
            out.append(math.nan)
            continue
        # F when the snap motion started (the rate threshold was crossed), not at theta1 = 0
        out.append(float(np.interp(r.jumps[0].t_start, r.t, r["F"])))
    return np.array(out)


def downlock_by_continuation(system) -> np.ndarray:
    """Lower-fold force (N) at each LU: branch at LU = 0.4 m, fold curve in (F, LU), exact fold per LU."""
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


def sidestay_freefall(until: float = 0.05):
    """The dual-sidestay gear's freefall (63 coordinates, both lock stops, the retraction actuator as a damper,
    aft attachment 5e7 N/m) released at gear up, simulated for ``until`` s: a callable for the timing (the
    model and its retracted pose made before)."""
    from mechcont.paper import freefall_sidestay as fs

    model = fs.freefall_gear()
    x = fs.retracted(model)
    return lambda: fs.sidestay_freefall(model, x, until=until)


def cases():
    """Benchmark cases for benchmarks/run.py."""
    sw_system, starts = sweep_setup()
    ct_system = build_overcentre(c=C)
    ct_system.compile()
    subset = starts[::4]
    return [
        (f"downlock_5of20LU_sweeps_{USABLE_RATE:g}N_per_s", lambda: downlock_by_sweeps(sw_system, subset, USABLE_RATE),
         20),
        ("downlock_20LU_fold_continuation", lambda: downlock_by_continuation(ct_system), 20),
        ("dual_sidestay_freefall_0.05s_simulated", sidestay_freefall(0.05), 5),
    ]


def _median_time(fn, repeats: int) -> tuple[float, object]:
    """Median CPU time of ``repeats`` calls after a warm-up (CPU, not wall-clock: other jobs on
    the machine do not inflate it), and the last result."""
    fn()  # warm-up
    times, value = [], None
    for _ in range(repeats):
        t0 = time.process_time()
        value = fn()
        times.append(time.process_time() - t0)
    return statistics.median(times), value


def comparison_table(rates=RATES, sweep_repeats: int = 3, continuation_repeats: int = 20) -> str:
    """Markdown tables: time and accuracy of each method against the closed form, the ratio, per-LU values."""
    ref = reference()
    sw_system, starts = sweep_setup()
    ct_system = build_overcentre(c=C)
    t_ct, f_ct = _median_time(lambda: downlock_by_continuation(ct_system), continuation_repeats)
    err_ct = float(np.max(np.abs(f_ct - ref)))
    rows = ["| method (20 LU values, 0.1-1.4 m) | median CPU time (s) | max error vs closed form (N) | "
            "all past the fold | time / continuation |", "|---|---|---|---|---|"]
    by_rate = {}
    for rate in rates:
        t_sw, f_sw = _median_time(lambda rate=rate: downlock_by_sweeps(sw_system, starts, rate), sweep_repeats)
        by_rate[rate] = (t_sw, f_sw)
        err = np.abs(f_sw - ref)
        rows.append(f"| sweeps, F ramped at {rate:g} N/s | {t_sw:.3g} | {np.max(err):.3g} | "
                    f"{'yes' if np.all(f_sw < ref) else 'NO'} | "
                    f"{t_sw / t_ct:.0f} |")
    rows.append(f"| two-parameter fold continuation + fold at each LU | {t_ct:.3g} | {err_ct:.1g} | "
                "(exact) | 1 |")
    usable = [r for r in rates if np.max(np.abs(by_rate[r][1] - ref)) <= USABLE_ERROR]
    lines = [f"Downlock force of the overcentre (c = {C:g} N s/m) at 20 LU values; sweeps: RK45 rtol "
             f"{SWEEP_RTOL:g}, atol {SWEEP_ATOL:g}, median of {sweep_repeats}; continuation: median of "
             f"{continuation_repeats}.", "", *rows, ""]
    if usable:
        rate = max(usable)
        t_sw, f_sw = by_rate[rate]
        lines += [f"Fastest sweep rate within {USABLE_ERROR:g} N everywhere: {rate:g} N/s, "
                  f"{t_sw:.2f} s against {1e3 * t_ct:.1f} ms for continuation: continuation is "
                  f"{t_sw / t_ct:.0f} times faster, and exact (error {err_ct:.1g} N against "
                  f"{np.max(np.abs(f_sw - ref)):.2f} N).", "",
                  "| LU (m) | closed form (N) | continuation (N) | sweep (N) | sweep error (N) |", "|---|---|---|---|---|"]
        lines += [f"| {lu:.4f} | {fr:.4f} | {fc:.4f} | {fs:.3f} | {fs - fr:+.3f} |"
                  for lu, fr, fc, fs in zip(LUS, ref, f_ct, f_sw)]
    else:
        lines.append(f"No sweep rate tried meets {USABLE_ERROR:g} N everywhere.")
    return "\n".join(lines)


if __name__ == "__main__":
    print(comparison_table(), file=sys.stdout)
