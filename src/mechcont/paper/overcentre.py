"""The paper's overcentre analyses: Figures 3b, 4a-c and 5a-c.

* Fig. 3b: the continuation branch at LU = 0.4 m over the whole force range of the time
  simulations (F = -90..110 N): both stable branches, the unstable branch between them and
  the two folds, with the paper's example load F = 20 N, where two stable equilibria coexist.
* Fig. 4a: the surface of equilibria over (F, LU), stable and unstable sheets in two
  colours, the fold curve on it, and the two quasi-static time simulations (LU = 2 m and
  0.4 m) as black curves, as in the paper.
* Fig. 4b, c: each time simulation (black) on its continuation branch (grey).
* Fig. 5a-c: the fold curve (two-parameter continuation) and its projections.

Every special point is compared with the closed form of the symmetric overcentre
(:mod:`mechcont.models.overcentre`), and the comparison goes into the summary. The
branches and sweeps at LU = 0.4 and 2 m are shared with :mod:`mechcont.paper.dynamics`
(:func:`branch`, :func:`hysteresis`), so every figure numbers the folds alike.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from ..analysis import equilibrium_family
from ..continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium
from ..models import build_overcentre
from ..models.overcentre import symmetric_cusp, symmetric_folds
from ..outputs.plotting import curve, label_point, legend_below, new_figure, plot_branch, plot_surface, save_figure

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..continuation import Branch
    from ..dynamics import SweepResult
    from ..equations import Model

__all__ = ["run", "compute", "branch", "hysteresis", "system", "F_RANGE", "F_EXAMPLE", "RATE", "C"]

F_RANGE = (-90.0, 110.0)  # N: the range of the time simulations; every branch spans it
F_EXAMPLE = 20.0  # N: the paper's example load (Fig. 4b,c text)
RATE = 1.0  # N/s: ramp rate of the quasi-static time simulations
C = 50.0  # N s/m: damper along the spring (time simulations only; no effect on equilibria)
F_START = 60.0  # N: the sweeps start at rest on the upper branch here, then go down and up
THETA_LIMIT = 1.5  # rad: beyond +-86 deg the force needed grows without bound
LU_LEVELS = np.round(np.linspace(0.4, 2.0, 33), 10)  # m: members of the Fig. 4a surface
_GUESS = {0.4: 1.35, 2.0: 0.5}  # rad: theta1 near the upper equilibrium at F_START


@functools.cache
def system(LU: float) -> Model:
    """The overcentre at ``LU`` (m) with the damper ``C`` (used by the time simulations only)."""
    return build_overcentre(LU=LU, c=C)


@functools.cache
def _start(LU: float) -> np.ndarray:
    th = _GUESS.get(LU, 1.0)
    return find_equilibrium(system(LU), values={"F": F_START}, guess={"theta1": th, "theta2": np.pi - th})


def _options(**bounds: tuple[float, float]) -> ContinuationOptions:
    return ContinuationOptions(bounds={"F": F_RANGE, "theta1": (-THETA_LIMIT, THETA_LIMIT), **bounds}, max_steps=2000)


@functools.cache
def branch(LU: float) -> Branch:
    """The continuation branch at ``LU`` over :data:`F_RANGE`, from the upper equilibrium at 60 N."""
    return continuation(system(LU), _start(LU), "F", options=_options())


_SWEEPS: dict[float, SweepResult] = {}


def hysteresis(LU: float, progress: Callable[[float], None] | None = None) -> SweepResult:
    """The quasi-static time simulation at ``LU``: F from 60 N down to -90 N, then up to 110 N, at 1 N/s.

    Computed once per process (``progress(t)`` gets the simulated time, s, while it runs).
    """
    from ..dynamics import sweep

    if LU not in _SWEEPS:
        _SWEEPS[LU] = sweep(system(LU), _start(LU), {"F": [(F_START, F_RANGE[0], RATE),
                                                           (F_RANGE[0], F_RANGE[1], RATE)]},
                            watch="theta1", progress=progress)
    return _SWEEPS[LU]


def sweep_duration() -> float:
    """Seconds simulated by :func:`hysteresis` (for progress bars)."""
    return (abs(F_START - F_RANGE[0]) + abs(F_RANGE[1] - F_RANGE[0])) / RATE


def compute(progress: Callable[[float], None] | None = None) -> dict[str, Any]:
    """All overcentre results: branches and sweeps at LU = 0.4 and 2 m, the LU family, fold curves.

    ``progress(t)`` receives the seconds simulated so far by both time simulations.
    """
    out: dict[str, Any] = {"system": system(0.4)}
    for k, LU in enumerate((0.4, 2.0)):
        out[f"branch_{LU}"] = branch(LU)
        out[f"sweep_{LU}"] = hysteresis(LU, None if progress is None else _after(progress, k * sweep_duration()))
    lp = branch(0.4).special("LP")[0]
    base = build_overcentre()
    x0 = find_equilibrium(base, values={"LU": LU_LEVELS[0], "F": F_START}, guess={"theta1": 1.35, "theta2": 1.79})
    out["family"] = equilibrium_family(base, x0, "F", "LU", list(LU_LEVELS), options=_options())  # moved at F = 60 N
    # the fold curve over the whole LU range (Fig. 5), and within the surface's ranges (Fig. 4a)
    out["folds"] = continue_folds(system(0.4), lp, "F", "LU", options=ContinuationOptions(bounds={"LU": (0.1, 2.0)}))
    out["folds_4a"] = continue_folds(system(0.4), lp, "F", "LU", options=ContinuationOptions(
        bounds={"LU": (LU_LEVELS[0], LU_LEVELS[-1]), "F": F_RANGE}))
    return out


def _after(progress: Callable[[float], None], done: float) -> Callable[[float], None]:
    """``progress`` told the seconds simulated by this sweep after the ``done`` seconds (s) of those before."""
    return lambda t: progress(done + t)


# -- figures ----------------------------------------------------------------------------------
def _equilibria_at(b: Branch, F: float) -> list[tuple[float, bool]]:
    """``(theta1 in deg, stable)`` of every equilibrium of branch ``b`` at load ``F`` (N)."""
    Fd, th, sd = curve(b, "F", "theta1")
    s = np.asarray(b.s)
    out = []
    for k in np.flatnonzero(np.sign(Fd[:-1] - F) * np.sign(Fd[1:] - F) < 0):
        w = (F - Fd[k]) / (Fd[k + 1] - Fd[k])
        i = int(np.clip(np.searchsorted(s, sd[k], side="right") - 1, 0, len(s) - 2))
        out.append((float(th[k] + w * (th[k + 1] - th[k])), bool(b.n_unstable[i] == 0 and b.n_unstable[i + 1] == 0)))
    return out


def _fig3b(b: Branch, path: Path) -> None:
    fig, ax = new_figure(figsize=(6.4, 4.8))
    plot_branch(b, "F", "theta1", ax=ax, stability_legend=True, label="continuation", endpoints=False)
    ax.axvline(F_EXAMPLE, color="0.55", lw=0.8, ls=":")
    eq = _equilibria_at(b, F_EXAMPLE)
    for th, st in eq:
        ax.plot(F_EXAMPLE, th, "o", color="k", mfc="k" if st else "white", ms=6, zorder=5)
    n_st = sum(st for _, st in eq)
    ax.plot([], [], "o", color="k", mfc="k", label=f"equilibria at F = {F_EXAMPLE:g} N: stable")
    ax.plot([], [], "o", color="k", mfc="white", label=f"equilibrium at F = {F_EXAMPLE:g} N: unstable")
    ax.annotate(f"F = {F_EXAMPLE:g} N: {n_st} stable equilibria,\nan unstable one between", (F_EXAMPLE, 0.0),
                textcoords="offset points", xytext=(8, 0), fontsize=8, va="center", color="0.3")
    ax.set_xlim(F_RANGE[0] - 5, F_RANGE[1] + 5)
    ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 0.1))
    ax.set_title("Fig. 3b: continuation, LU = 0.4 m (solid stable, dashed unstable)", fontsize=10)
    save_figure(fig, path)


def _sweep_on_branch(ax: Axes, b: Branch, sw: SweepResult, title: str) -> None:
    from ..outputs.sweep_plots import plot_sweep

    plot_branch(b, "F", "theta1", ax=ax, color="0.7", lw=3.5, label="continuation", stability_legend=True,
                special=False)
    for name, p in zip(b.point_names(), b.special_points):
        if p.label == "LP":
            F, th = p["F"], np.degrees(p["theta1"])
            ax.plot(F, th, "o", color="0.3", ms=7, zorder=6)
            label_point(ax, F, th, f"{name} (F = {F:.1f} N)", (*F_RANGE, -85.0, 85.0), color="0.3")
    plot_sweep(sw, ax, degrees=True, label=f"time simulation, F ramped at {RATE:g} N/s")
    ax.set_xlabel("F (N)")
    ax.set_xlim(F_RANGE[0] - 5, F_RANGE[1] + 5)
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="upper left" if not b.special("LP") else "lower left",
              bbox_to_anchor=None if not b.special("LP") else (0.12, 0.2))


def _fig4a(r: dict[str, Any], path: Path) -> None:
    save_figure(fig4a_figure(r), path, tight=True)   # a 3-D axes leaves its box's lower part empty at this view


def fig4a_figure(r: dict[str, Any]) -> Figure:
    """Fig. 4a of :func:`compute`'s results ``r``: the sheets of equilibria over (F, LU), the fold curve and the two
    time simulations (save it with ``tight=True``). Returns the figure."""
    fig, ax = new_figure(figsize=(7.6, 6.0), projection="3d")
    plot_surface(r["family"], "F", "LU", "theta1", folds=r["folds_4a"], ax=ax)
    # one style per simulation, one legend entry each
    sims: tuple[tuple[float, str, Literal["-", "--"]], ...] = ((0.4, "#1f77b4", "--"), (2.0, "#6a3d9a", "-"))
    for LU, colour, style in sims:
        sw = r[f"sweep_{LU}"]
        ax.plot(sw["F"], np.full(len(sw.t), LU), np.degrees(sw["theta1"]), color=colour, linestyle=style, lw=1.6)
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from ..outputs.plotting import SHEET_COLOURS

    ax.legend(handles=[Patch(color=SHEET_COLOURS[0], label="stable equilibria"),
                       Patch(color=SHEET_COLOURS[1], label="unstable equilibria"),
                       Line2D([], [], color="0.15", lw=2.5, label="fold curve (CP: cusp)"),
                       *(Line2D([], [], color=c, linestyle=ls, lw=1.6, label=f"time simulation, LU = {LU:g} m")
                         for LU, c, ls in sims)],
              fontsize=9, loc="upper left")
    ax.view_init(elev=18, azim=-40)  # the pleat between the folds and the cusp in view
    ax.set_box_aspect(None, zoom=0.92)
    ax.set_title("Fig. 4a: equilibria over (F, LU), fold curve and two time simulations", fontsize=10)
    return fig


def sweep_figure(r: dict[str, Any], LU: float) -> Figure:
    """Fig. 4b (``LU`` = 2 m) or 4c (0.4 m) of :func:`compute`'s results ``r``: the time simulation on the
    continuation branch. Returns the figure."""
    tag = "4b" if LU == 2.0 else "4c"
    fig, ax = new_figure(figsize=(6.4, 4.8))
    _sweep_on_branch(ax, r[f"branch_{LU}"], r[f"sweep_{LU}"], f"Fig. {tag}: LU = {LU:g} m, time simulation (black) "
                                                              "on the continuation branch (grey)")
    return fig


def _fig5(folds: Branch, out_dir: Path) -> None:
    fig, ax = new_figure(figsize=(6.5, 5), projection="3d")
    plot_branch(folds, "LU", "theta1", ax=ax, z="F")
    LU, th, F, _ = curve(folds, "LU", "theta1", "F")
    (f0, _), (_, t1) = ax.get_zlim(), ax.get_ylim()
    ax.plot(LU, th, np.full_like(LU, f0), color="0.6", lw=1.0, ls="--",  # shadows: Fig. 5b on the floor,
            label="its projections: Fig. 5b on the floor, 5c on the back wall")
    ax.plot(LU, np.full_like(LU, t1), F, color="0.6", lw=1.0, ls="--")  # Fig. 5c on the back wall
    ax.set_zlim(f0, None)
    ax.set_ylim(None, t1)
    ax.view_init(elev=20, azim=-120)
    ax.set_title("Fig. 5a: fold curve in (LU, theta1, F)", fontsize=10)
    _name_markers(ax)
    legend_below(fig, ncols=1)
    save_figure(fig, out_dir / "fig5a_fold_curve.png")
    for tag, y in (("5b", "theta1"), ("5c", "F")):
        fig, ax = new_figure()
        plot_branch(folds, "LU", y, ax=ax)
        if y == "F":
            ax.axhline(0.0, color="0.5", lw=0.8)
            LU0 = _downlock_length(folds)
            ax.plot(LU0, 0.0, "o", color="k", ms=5)
            ax.annotate(f"F = 0 at LU = {LU0:.3f} m:\nabove it the mechanism\ndownlocks with no force", (LU0, 0.0),
                        xytext=(0.97, 0.25), textcoords="axes fraction", ha="right", va="center", fontsize=8,
                        arrowprops=dict(arrowstyle="->", color="0.3", lw=0.8))
        ax.set_title(f"Fig. {tag}: fold curve, {y} vs LU", fontsize=10)
        _name_markers(ax)
        legend_below(fig)
        save_figure(fig, out_dir / f"fig{tag}_fold_{y}.png")


def _name_markers(ax: Axes) -> None:
    """Name the fold curve and the markers :func:`plot_branch` put on it (first of each kind) for the legend."""
    names = {"x": "EP: end of the computation (the bound LU = 0.1 m)", "D": "CP: cusp, the folds meet",
             "o": "F = 0 on the lower fold"}
    curve_named = False
    for line in ax.get_lines():
        marker = line.get_marker()
        if marker in names and line.get_linestyle() in ("None", ""):
            line.set_label(names.pop(marker))
        elif not curve_named and marker in ("None", "") and line.get_color() != "0.6":
            line.set_label("fold curve")
            curve_named = True


def _downlock_length(folds: Branch) -> float:
    """LU (m) where the lower fold (theta1 > 0) of the fold curve crosses F = 0 (on its drawn spline)."""
    F, LU, th, _ = curve(folds, "F", "LU", "theta1")
    k = np.flatnonzero((th[:-1] > 0) & (th[1:] > 0) & (np.sign(F[:-1]) != np.sign(F[1:])))[0]
    return float(LU[k] + (LU[k + 1] - LU[k]) * F[k] / (F[k] - F[k + 1]))


def _downlock_length_exact(p: dict[str, float]) -> float:
    """The same from the closed form of the symmetric mechanism."""
    from scipy.optimize import brentq

    def lower(LU: float) -> float:
        return symmetric_folds(p["L1"], p["m1"], p["m2"], p["g"], p["k"], LU)[1][1]

    return float(brentq(lower, 0.5, 1.49, xtol=1e-12))


# -- summary ----------------------------------------------------------------------------------
def _fold_check(b: Branch, LU: float, p: dict[str, float]) -> list[str]:
    lines = []
    expected = symmetric_folds(p["L1"], p["m1"], p["m2"], p["g"], p["k"], LU)
    got = sorted(((q, n) for q, n in zip(b.special_points, b.point_names()) if q.label == "LP"),
                 key=lambda qn: qn[0]["theta1"])
    for (q, name), (th, F) in zip(got, expected):
        lines.append(f"| {LU:g} | {name} | {np.degrees(q['theta1']):.6f} | {q['F']:.8f} | "
                     f"{abs(q['F'] - F) / abs(F):.1e} | {abs(q['theta1'] - th) / abs(th):.1e} |")
    return lines


def run(out_dir: Path, quiet: bool = True, timings: dict | None = None) -> list[str]:
    """Write Figures 3b, 4a-c, 5a-c (PNG) into ``out_dir``; return summary Markdown lines."""
    import time

    from .._progress import Progress

    out_dir = Path(out_dir)
    t0 = time.perf_counter()
    with Progress("[overcentre] time simulations", total=2 * sweep_duration(), unit="s simulated",
                  quiet=quiet) as bar:
        r = compute(progress=bar.set if bar.enabled else None)
    if timings is not None:
        timings["overcentre: continuation and time simulations"] = time.perf_counter() - t0
    p = r["system"].as_dict(r["system"].defaults())
    b04, b2, fam, folds = r["branch_0.4"], r["branch_2.0"], r["family"], r["folds"]

    _fig3b(b04, out_dir / "fig3b_overcentre_branch.png")
    _fig4a(r, out_dir / "fig4a_overcentre_surface.png")
    for tag, LU in (("4b", 2.0), ("4c", 0.4)):
        save_figure(sweep_figure(r, LU), out_dir / f"fig{tag}_overcentre_LU{LU:g}.png")
    _fig5(folds, out_dir)

    eq2 = _equilibria_at(b2, F_EXAMPLE)
    eq04 = _equilibria_at(b04, F_EXAMPLE)
    lines = ["## Overcentre mechanism (paper Section II, eq. 6; Figs. 3b, 4, 5)", "",
             f"Parameters (not published in the paper, chosen for its qualitative results): "
             f"L1 = L2 = {p['L1']:g} m, m1 = m2 = {p['m1']:g} kg, k = {p['k']:g} N/m, m = n = 0 m, "
             f"g = {p['g']} m/s^2. Branches are continued in the applied force F over {F_RANGE[0]:g}..{F_RANGE[1]:g} N "
             "(the range of the time simulations), starting from the upper equilibrium at F = 60 N; folds are "
             "numbered LP1, LP2 along each branch from its end at F = -90 N, in every figure and table.", "",
             "Folds against the closed form of the symmetric mechanism (relative errors: |computed - exact| / |exact|, "
             "dimensionless):", "",
             "| LU (m) | fold | theta1 (deg) | F (N) | rel. error of F | rel. error of theta1 |",
             "|---|---|---|---|---|---|"]
    lines += _fold_check(b04, 0.4, p)
    for b in fam:
        LU = float(b["LU"][0])
        if any(abs(LU - v) < 1e-9 for v in (0.8, 1.2, 1.45)):
            lines += _fold_check(b, LU, p)
    (cp,) = folds.special("CP") or [None]
    LUc, thc, Fc = symmetric_cusp(p["L1"], p["m1"], p["m2"], p["g"], p["k"])
    n2 = len(b2)
    lines += ["", f"- LU = 2 m (Fig. 4b): {len(b2.special('LP'))} folds; "
                  + (f"all {n2} computed points are stable" if np.all(b2.stable) else
                     f"{int(np.sum(~b2.stable))} of {n2} computed points are unstable")
              + f" (paper: a single stable branch). At F = {F_EXAMPLE:g} N the one equilibrium is theta1 = "
              + ", ".join(f"{th:.1f} deg" for th, _ in eq2) + ".",
              f"- LU = 0.4 m (Figs. 3b, 4c): {len(b04.special('LP'))} folds, "
              + ", ".join(f"{n} at F = {q['F']:.3f} N (theta1 = {np.degrees(q['theta1']):.2f} deg)"
                          for n, q in zip(b04.point_names(), b04.special_points) if q.label == "LP")
              + f": between them the mechanism is bistable. At F = {F_EXAMPLE:g} N the equilibria are theta1 = "
              + ", ".join(f"{th:.1f} deg ({'stable' if st else 'unstable'})" for th, st in eq04) + "."]
    if cp is not None:
        lines.append(f"- Cusp (CP) on the fold curve at LU = {cp['LU']:.10f} m, F = {cp['F']:.8f} N, "
                     f"theta1 = {np.degrees(cp['theta1']):.2e} deg (closed form LU = {LUc:g} m, F = {Fc:g} N, "
                     f"theta1 = {np.degrees(thc):g} deg): for LU above it there is no fold and no hysteresis.")
    LU0 = _downlock_length(folds)
    LU0_exact = _downlock_length_exact(p)
    lines.append(f"- The lower fold crosses F = 0 at LU = {LU0:.4f} m (closed form {LU0_exact:.4f} m): for LU above it "
                 "the mechanism downlocks with no applied force (paper: approximately 1.2 m).")
    lines += ["", "![Fig. 3b](fig3b_overcentre_branch.png)", "", "![Fig. 4a](fig4a_overcentre_surface.png)", "",
              "![Fig. 4b](fig4b_overcentre_LU2.png) ![Fig. 4c](fig4c_overcentre_LU0.4.png)", "",
              "Figures 5a-c: the fold curve in (LU, theta1, F) and its projections; it is computed from LU = 0.1 m "
              "(its end, EP) to the cusp CP1.", "",
              "![Fig. 5a](fig5a_fold_curve.png)", "",
              "![Fig. 5b](fig5b_fold_theta1.png) ![Fig. 5c](fig5c_fold_F.png)", ""]
    return lines
