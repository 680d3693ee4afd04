"""The paper's dynamic-model comparison (Fig. 3a) and the gap between each jump and its fold.

* Fig. 3a: the overcentre at LU = 0.4 m, F slowly decreased then increased in a time
  simulation: a hysteresis loop. As in the paper (its Matlab model and ADAMS), the loop comes
  from two dynamic models: mechcont's Udwadia–Kalaba model and, when Exudyn is installed,
  an independent Exudyn multibody model. Beside it, close-ups of both jumps on the
  continuation branch (shared with :mod:`mechcont.paper.overcentre`): each jump comes just
  after its fold.
* The gap between the jump load and the fold load for sweeps 4, 16 and 64 times slower:
  it shrinks like rate^(2/3), the slow-passage law of a saddle-node.

Run times go to ``timings`` (the caller prints them), never into the summary, which is
the same on every run.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..dynamics import gap_versus_rate, jump_gaps
from ..models.overcentre import symmetric_folds
from ..outputs.sweep_plots import plot_sweep
from ._timing import timed
from .overcentre import F_RANGE, F_START, RATE, C, branch, hysteresis, sweep_duration, system

if TYPE_CHECKING:
    from ..continuation import Branch
    from ..dynamics import JumpGap, SweepResult

__all__ = ["run"]

L, M1, M2, G, K = 1.5, 1.0, 1.0, 9.81, 127.0
RATES = (4.0, 1.0, 0.25, 0.0625)  # N/s: the gap-versus-rate study
RATE_START = -65.0  # N: the study starts at rest on the upper branch, 10.6 N above the lower fold


def _crossings(F: np.ndarray, theta1: np.ndarray) -> list[float]:
    """Loads F (N) where theta1 passes 0 (linear between samples): the snap-throughs."""
    i = np.flatnonzero(np.sign(theta1[:-1]) != np.sign(theta1[1:]))
    return [float(F[k] + (F[k + 1] - F[k]) * theta1[k] / (theta1[k] - theta1[k + 1])) for k in i]


def _exudyn_loop(r04: SweepResult) -> tuple[np.ndarray, np.ndarray, float] | None:
    """The same sweep in Exudyn (h = 10 ms, trapezoidal): (F, theta1, run time s), or None if not installed."""
    from ..dynamics import exudyn_available, exudyn_overcentre

    if not exudyn_available():
        return None
    params = dict(L1=L, L2=L, m1=M1, m2=M2, g=G, k=K, LU=0.4, m=0.0, n=0.0, c=C)
    t_rec, F_rec = r04.t, r04["F"]  # piecewise-linear ramp; its kinks are samples of the record
    t0 = time.perf_counter()
    t, th = exudyn_overcentre(params, float(r04["theta1"][0]), lambda tt: float(np.interp(tt, t_rec, F_rec)),
                              float(t_rec[-1]), 0.01)
    return np.interp(t, t_rec, F_rec), th, time.perf_counter() - t0


def _fig3(r04: SweepResult, b04: Branch, exu: tuple[np.ndarray, np.ndarray, float] | None,
          gaps: Sequence[JumpGap], path: Path) -> None:
    """(a) the two dynamic models alone, as the paper's Fig. 3a; (b, c) each jump on the branch."""
    from matplotlib.figure import Figure

    from ..outputs.plotting import plot_branch, save_figure

    fig = Figure(figsize=(11.0, 4.6), layout="constrained")
    grid = fig.add_gridspec(2, 2, width_ratios=(1.5, 1.0))
    ax = fig.add_subplot(grid[:, 0])
    if exu is not None:
        ax.plot(exu[0], np.degrees(exu[1]), color="0.65", lw=3.5, label="Exudyn multibody model")
    plot_sweep(r04, ax, degrees=True, label="Udwadia–Kalaba model (mechcont)")
    ax.set_xlabel("F (N)")
    ax.set_xlim(F_RANGE[0] - 5, F_RANGE[1] + 5)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.11), ncols=2, frameon=False)  # off the curves
    ax.set_title(f"(a) Fig. 3a: two dynamic models, F from {F_START:g} N down to {F_RANGE[0]:g} N and up to "
                 f"{F_RANGE[1]:g} N at {RATE:g} N/s", fontsize=9)
    folds = {round(p["F"], 9): n for n, p in zip(b04.point_names(), b04.special_points) if p.label == "LP"}
    for k, g in enumerate(gaps):
        axz = fig.add_subplot(grid[k, 1])
        plot_branch(b04, "F", "theta1", ax=axz, color="0.7", lw=3.0, special=False,
                    label="continuation" if k == 0 else None, stability_legend=k == 0)
        plot_sweep(r04, axz, degrees=True, label="time simulation" if k == 0 else None)
        p = next(q for q in b04.special("LP") if abs(q["F"] - g.fold_value) < 1e-6)
        lo, hi = sorted((g.fold_value - 8.0 * g.direction, g.jump_value + 3.0 * g.direction))
        axz.set_xlim(lo, hi)
        th = np.degrees(p["theta1"])
        axz.set_ylim(th - 45, th + 45)
        axz.plot(g.fold_value, th, "o", color="0.3", ms=6, zorder=6)
        name = folds.get(round(g.fold_value, 9), "LP")
        # beside the fold, on the side away from the sweep's path (below-left going down, above-right going up)
        axz.annotate(f"{name}: F = {g.fold_value:.2f} N", (g.fold_value, th), textcoords="offset points",
                     xytext=(-8, -10) if g.direction < 0 else (8, 8), ha="right" if g.direction < 0 else "left",
                     va="top" if g.direction < 0 else "bottom", fontsize=8, color="0.3")
        axz.axvline(g.jump_value, color="k", lw=0.6, ls=":")
        axz.annotate(f"jump at {g.jump_value:.2f} N\n({abs(g.gap):.2f} N past {name})", (g.jump_value, th - 30),
                     textcoords="offset points", xytext=(-6 if g.direction > 0 else 6, 0),
                     ha="right" if g.direction > 0 else "left", va="center", fontsize=8)
        axz.set_xlabel("F (N)")
        axz.set_title(f"({'bc'[k]}) F {'decreasing' if g.direction < 0 else 'increasing'}: the jump "
                      f"after {name}", fontsize=9)
        if k == 0:
            axz.legend(fontsize=7, loc="lower right" if g.direction < 0 else "upper left")
    save_figure(fig, path)


def _gap_figure(rates: Sequence[float], g: np.ndarray, path: Path) -> None:
    from ..outputs.plotting import new_figure, save_figure

    fig, ax = new_figure()
    ax.loglog(rates, g, "ko-", label="time simulations")
    ax.loglog(rates, g[0] * (np.array(rates) / rates[0]) ** (2 / 3), "--", color="0.5",
              label="rate^(2/3) (slow passage through a fold)")
    ax.set_xticks(rates, [f"{r:g}" for r in rates])
    ax.set_xticks([], minor=True)
    ticks = [t for t in (0.5, 1, 2, 5, 10, 20, 50) if g.min() / 1.5 <= t <= g.max() * 1.5]
    ax.set_yticks(ticks, [f"{t:g}" for t in ticks])
    ax.set_yticks([], minor=True)
    ax.set_xlabel("sweep rate dF/dt (N/s)")
    ax.set_ylabel("|jump F - fold F| (N)")
    ax.legend(fontsize=8)
    ax.set_title("Jump past the lower fold against sweep rate", fontsize=10)
    save_figure(fig, path)


def run(out_dir: Path, quiet: bool = True, timings: dict | None = None) -> list[str]:
    """Write the dynamic-comparison figures into ``out_dir``; return summary Markdown lines."""
    timings = {} if timings is None else timings
    out_dir = Path(out_dir)
    loop, gaps, names = _loop_part(out_dir, quiet, timings)
    return ["## Time simulation against continuation (paper Fig. 3a; each jump against its fold)", "", *loop,
            *_no_fold_part(quiet, timings), *_rate_part(out_dir, quiet, timings, gaps, names)]


def _loop_part(out_dir: Path, quiet: bool, timings: dict) -> tuple[list[str], list, dict[float, str]]:
    """The hysteresis loop at LU = 0.4 m against its branch (Fig. 3a, the jumps' table, Exudyn's snap-throughs):
    ``(lines, jump gaps, {fold F: its name})``."""
    from .._progress import Progress

    lines: list[str] = []
    with (timed(timings, "dynamics: time simulation at LU = 0.4 m (or reused)"),
          Progress("[dynamics] time simulation", total=sweep_duration(), unit="s simulated", quiet=quiet) as bar):
        r04 = hysteresis(0.4, bar.set if bar.enabled else None)
    with timed(timings, "dynamics: continuation branch at LU = 0.4 m (or reused)"):
        b04 = branch(0.4)
    (_, F_up), (_, F_low) = symmetric_folds(L, M1, M2, G, K, 0.4)
    lp = [p["F"] for p in b04.special("LP")]
    names = {round(p["F"], 9): n for n, p in zip(b04.point_names(), b04.special_points) if p.label == "LP"}
    exu = _exudyn_loop(r04)
    if exu is not None:
        timings["dynamics: Exudyn time simulation"] = exu[2]
    gaps = jump_gaps(r04, lp)
    _fig3(r04, b04, exu, gaps, out_dir / "dynamics_fig3_sweep_vs_continuation.png")
    thr = [t for t in r04.threshold if np.isfinite(t)]
    duration = sum(r.duration for r in r04.ramps)
    lines += [f"Overcentre, LU = 0.4 m, damper c = {C:g} N s/m along the spring, F ramped {F_START:g} -> "
              f"{F_RANGE[0]:g} -> {F_RANGE[1]:g} N at {RATE:g} N/s ({duration:.0f} s simulated; largest constraint "
              f"drift {r04.simulation.constraint_drift:.1e} m). A jump's load is the value of F when the angular "
              f"speed |d theta1/dt| first exceeds 10 times the segment's mean speed (range of theta1 over the duration "
              f"of the segment: " + ", ".join(f"{math.degrees(t):.1f} deg/s" for t in thr) + " here); the gap is the "
              "jump load minus the fold load (N), and a jump must come after its fold.", "",
              "| jump | F at jump (N) | fold | fold F, continuation (N) | fold F, closed form (N) | gap (N) | "
              "past the fold |",
              "|---|---|---|---|---|---|---|"]
    for i, g in enumerate(gaps, 1):
        closed = F_low if g.direction < 0 else F_up
        lines.append(f"| {i} ({'F decreasing' if g.direction < 0 else 'F increasing'}) | {g.jump_value:.3f} | "
                     f"{names.get(round(g.fold_value, 9), 'LP')} | {g.fold_value:.4f} | {closed:.4f} | "
                     f"{g.gap:+.3f} | {'yes' if g.past else 'NO'} |")
    uk = _crossings(r04["F"], r04["theta1"])
    if exu is None:
        lines += ["", "Exudyn is not installed (pip install exudyn): the independent dynamic model is left out."]
    else:
        ex = _crossings(exu[0], exu[1])
        lines += ["", "The same sweep in Exudyn (independent multibody code, 10 ms trapezoidal steps) snaps through "
                  "theta1 = 0 at F = "
                  + ", ".join(f"{b:.3f} N (Udwadia–Kalaba: {a:.3f} N)" for a, b in zip(uk, ex))
                  + (f"; {len(ex)} against {len(uk)} snap-throughs." if len(ex) != len(uk) else ".")
                  + " These snap-through loads are later than the jump loads of the table because theta1 passes 0 "
                    "halfway through the jump, which starts when its speed crosses the threshold."]
    lines += ["", "![Fig. 3a and the jumps at the folds](dynamics_fig3_sweep_vs_continuation.png)", ""]
    return lines, gaps, names


def _no_fold_part(quiet: bool, timings: dict) -> list[str]:
    """LU = 2 m, no fold: how closely the time simulation follows the branch."""
    from .._progress import Progress

    with (timed(timings, "dynamics: time simulation at LU = 2 m (or reused)"),
          Progress("[dynamics] time simulation, LU = 2 m", total=sweep_duration(), unit="s simulated",
                   quiet=quiet) as bar):
        r2 = hysteresis(2.0, bar.set if bar.enabled else None)
    b2 = branch(2.0)
    order = np.argsort(b2["F"])
    lag = float(np.max(np.abs(r2["theta1"] - np.interp(r2["F"], b2["F"][order], b2["theta1"][order]))))
    return [f"LU = 2 m: {len(r2.jumps)} jumps; the sweep stays within {math.degrees(lag):.2f} deg of the "
            "continuation branch over the whole range (Fig. 4b, `fig4b_overcentre_LU2.png`).", ""]


def _rate_part(out_dir: Path, quiet: bool, timings: dict, gaps: list, names: dict[float, str]) -> list[str]:
    """The jump past the lower fold against the sweep rate (its figure and table), against the loop's ``gaps``."""
    from .._progress import Progress
    from ..continuation import find_equilibrium

    (_, F_low) = symmetric_folds(L, M1, M2, G, K, 0.4)[1]

    s04 = system(0.4)
    x_lock = find_equilibrium(s04, values={"F": RATE_START}, guess={"theta1": 1.1, "theta2": math.pi - 1.1})
    with (timed(timings, "dynamics: sweep-rate study"),
          Progress("[dynamics] sweep-rate study", total=len(RATES), unit="sweeps", quiet=quiet) as bar):
        study = []
        for rate in RATES:
            study += gap_versus_rate(s04, x_lock, "F", RATE_START, F_RANGE[0], (rate,), F_low, watch="theta1")
            bar.update()
    for r in study:
        timings[f"dynamics: sweep at {r.rate:g} N/s"] = r.seconds
    rate_gaps = np.array([abs(r.gap) for r in study])
    slope = float(np.polyfit(np.log(RATES), np.log(rate_gaps), 1)[0])
    _gap_figure(RATES, rate_gaps, out_dir / "dynamics_gap_vs_rate.png")
    lines = [f"Jump past the lower fold ({names.get(round(F_low, 9), 'LP')}, F = {F_low:.3f} N) for slower and "
              f"slower sweeps, each from rest on the upper branch at F = {RATE_START:g} N down to {F_RANGE[0]:g} N:", "",
              "| rate (N/s) | jump F (N) | gap (N) |", "|---|---|---|"]
    lines += [f"| {r.rate:g} | {r.jump_value:.3f} | {r.gap:+.3f} |" for r in study]
    one = next(r for r in study if r.rate == RATE)
    loop = next(x for x in gaps if x.direction < 0)
    lines += ["", f"Fitted gap ~ rate^{slope:.2f} (slow passage through a saddle-node predicts 2/3): the sweeps "
              "converge on the fold that continuation finds directly, and only in the limit of infinitely "
              "slow sweeps.", "",
              f"At the same rate of {RATE:g} N/s this study's jump ({one.jump_value:.3f} N) and the loop's "
              f"({loop.jump_value:.3f} N) differ by {abs(one.jump_value - loop.jump_value):.2f} N because the jump "
              "threshold scales with the segment: 10 times the mean speed of theta1 over the segment, and this "
              f"study's segment lasts {abs(F_RANGE[0] - RATE_START) / RATE:.0f} s against the loop's "
              f"{abs(F_START - F_RANGE[0]) / RATE:.0f} s, so its threshold is higher and the jump is timed later. "
              "The fold itself does not depend on the rate.", "",
              "![gap vs rate](dynamics_gap_vs_rate.png)", ""]
    return lines
