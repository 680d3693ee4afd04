"""The shimmy section's figures and its summary paragraph, from the computed numbers (:mod:`._shimmy_analysis`)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..continuation import Branch, CycleBranch, SpecialPoint
    from ._shimmy_analysis import CycleSimulation

__all__ = ["chart_figure", "amplitude_diagram", "finding", "limit_on_curve"]

_NAMES = {"c_psi": "shimmy damper rate", "e": "caster length"}


def limit_on_curve(curve: Branch, parameter: str, speed: float) -> float:
    """The value of ``parameter`` (SI) where the Hopf ``curve`` meets ``speed`` (m/s), interpolated between its
    two points around it (NaN when the curve does not reach that speed)."""
    V, p = curve.column("V"), curve.column(parameter)
    for i in range(len(V) - 1):
        if (V[i] - speed) * (V[i + 1] - speed) <= 0 and V[i] != V[i + 1]:
            return float(p[i] + (speed - V[i]) * (p[i + 1] - p[i]) / (V[i + 1] - V[i]))
    return math.nan


def chart_figure(curves: dict, grids: dict, design: dict, path: Path) -> None:
    """The two stability charts side by side: each Hopf curve (hatched into the stable side, the words
    ``stable`` and ``unstable`` in the middle of each side's largest empty area), the coarse brute-force check
    (dots: green stable, red shimmy), the example's design point; one legend below both panels, where it hides
    nothing."""
    from matplotlib.figure import Figure

    from ..outputs.plotting import legend_below, save_figure
    from ..outputs.stability_chart import label_stable_sides, plot_stability_chart

    fig = Figure(figsize=(6.0 * len(curves), 5.2), layout="constrained")
    axes = fig.subplots(1, len(curves), squeeze=False)[0]
    for ax, (param, curve) in zip(axes, curves.items()):
        speeds, values, re = grids[param]
        vv, pp = np.meshgrid(speeds, values)
        stable = re < 0
        ax.plot(vv[stable], pp[stable], ".", color="tab:green", ms=3, label="eigenvalues: stable")
        ax.plot(vv[~stable], pp[~stable], ".", color="tab:red", ms=3, label="eigenvalues: shimmy")
        # drawn before the chart, so that the side words keep clear of it
        ax.plot([design["V"]], [design[param]], "*", color="k", ms=10, zorder=5, label="HB1 of the example")
        plot_stability_chart(ax, [curve], "V", param)
        ax.set_title(f"speed x {_NAMES[param]}")
    legend_below(fig, axes, ncols=4)
    for ax, (param, curve) in zip(axes, curves.items()):
        label_stable_sides(ax, [curve], "V", param)
    save_figure(fig, path)   # (not cropped: a crop re-runs the constrained layout in the smaller page)


def amplitude_diagram(branch: Branch, hopf_speed: float, cycles: CycleBranch, sims: Sequence[CycleSimulation],
                      path: Path) -> None:
    """Torsion amplitude (deg) against speed: the straight running (0, stable solid, shimmying dashed), the onset
    at the Hopf point (labelled with its speed), the cycles (stable solid, unstable dashed), the simulations' end
    amplitudes (markers); the legend below the axes, where it hides nothing."""
    from ..outputs.cycle_plots import plot_amplitude
    from ..outputs.plotting import label_point, legend_below, new_figure, save_figure
    from ._shimmy_analysis import TORSION

    fig, ax = new_figure(figsize=(6.5, 5.0))
    V = branch.column("V")
    ax.plot(V[V <= hopf_speed], 0 * V[V <= hopf_speed], "-", color="k", lw=1.4, label="straight running, stable")
    ax.plot(V[V >= hopf_speed], 0 * V[V >= hopf_speed], "--", color="k", lw=1.4, label="straight running, shimmy")
    plot_amplitude(cycles, TORSION, ax=ax)
    for s in sims:
        ax.plot([s.speed], [math.degrees(s.amplitude)], "o", mfc="none", color="tab:red", ms=9,
                label="time simulation (end)" if s is sims[0] else None)
    top = float(np.max(np.abs(np.degrees(cycles.maximum[:, cycles.state_names.index(TORSION)]))))
    label_point(ax, hopf_speed, 0.0, f"shimmy onset (HB1)\nV = {hopf_speed:.2f} m/s", (V.min(), V.max(), -top, top),
                color="tab:blue", fontsize=9, background=True)
    ax.set_xlabel("speed V (m/s)")
    ax.set_ylabel("torsion angle about the strut (deg),\nmax and min over the cycle")
    legend_below(fig, ncols=2)
    save_figure(fig, path)   # (not cropped: a crop re-runs the constrained layout in the smaller page)


def _stable_above(grid: tuple[np.ndarray, np.ndarray, np.ndarray], limit: float) -> bool:
    """Whether every point of the brute-force ``grid`` (speeds, values, leading real parts) whose value
    exceeds ``limit`` is stable: the side of the Hopf curve a design limit claims."""
    _, values, re = grid
    return bool(np.all(re[values > limit] < 0))


def finding(hopf: SpecialPoint, curves: dict, grids: dict, cycles: CycleBranch, sims: Sequence[CycleSimulation],
            top_speed: float, design: dict) -> list[str]:
    """The summary's paragraph and its numbers (Markdown lines), every figure computed; a design limit
    (damper rate, caster) is stated only where the brute-force ``grids`` confirm the stable side."""
    from ._shimmy_analysis import TORSION

    h = hopf.extra["hopf"]
    c_need = limit_on_curve(curves["c_psi"], "c_psi", top_speed)
    e_need = limit_on_curve(curves["e"], "e", top_speed)
    c_need = c_need if math.isfinite(c_need) and _stable_above(grids["c_psi"], c_need) else math.nan
    e_need = e_need if math.isfinite(e_need) and _stable_above(grids["e"], e_need) else math.nan
    k = cycles.state_names.index(TORSION)
    stable = [i for i in range(len(cycles.p)) if cycles.stable[i]]
    kind = "supercritical" if h.lyapunov < 0 else "subcritical"
    grows = max(math.degrees(cycles.maximum[i, k]) for i in stable) if stable else math.nan
    folds = [float(cycles.p[i]) for i, lab in enumerate(cycles.labels) if lab == "LPC"]
    onset = (f"The onset is {kind} (first Lyapunov coefficient {h.lyapunov:.3g}): "
             + ("the cycles born there are stable and grow from zero with the speed, so shimmy starts gently and stops "
                "again when the aircraft slows below the Hopf speed"
                + (" (no fold of the cycles up to the end of the range: no hysteresis)" if not folds else
                   f" (but the cycles fold at V = {', '.join(f'{v:.2f}' for v in folds)} m/s: a jump there)")
                + f"; the saturating tyre bounds them, at most {grows:.1f} deg of torsion up to {top_speed:g} m/s."
                if h.lyapunov < 0 else
                "the cycles born there are unstable, so the gear can jump to a large cycle below the Hopf speed and "
                "keeps shimmying when slowed back through it (hysteresis)."))
    lines = [f"With the example's damper rate c_psi = {design['c_psi']:g} N m s/rad and caster e = {design['e']:g} m, "
             f"straight running loses stability at V = {design['V']:.3f} m/s (Hopf point HB1, shimmy frequency "
             f"{h.frequency / (2 * math.pi):.1f} Hz). {onset} "
             + (f"A shimmy damper of at least {c_need:.1f} N m s/rad keeps the gear shimmy-free up to {top_speed:g} m/s "
                "(the Hopf curve in speed and damper rate)" if math.isfinite(c_need) else
                f"No single damper rate bound from the chart keeps it shimmy-free to {top_speed:g} m/s")
             + (f"; at the example's damper rate, a caster of at least {e_need:.3f} m does too." if math.isfinite(e_need)
                else "."),
             "",
             "The gear's parameters are representative of the nose gear of Thota, Krauskopf & Lowenberg (2009), "
             "recalled, not checked against that paper's Table 1: the numbers illustrate the method, they are not "
             "that study's.", ""]
    for s in sims:
        row = int(np.argmin(np.abs(cycles.p - s.speed)))
        lines.append(f"- V = {s.speed:g} m/s: a time simulation from a {math.degrees(s.disturbance):.2f} deg "
                     f"disturbance ends ({s.until:g} s) on a cycle of {math.degrees(s.amplitude):.3f} deg and "
                     f"{1e3 * s.period:.4f} ms (transient still to decay about "
                     f"{math.degrees(s.remaining):.3f} deg); the continued cycle: "
                     f"{math.degrees(cycles.maximum[row, k]):.3f} deg and {1e3 * cycles.period[row]:.4f} ms, "
                     f"largest Floquet multiplier {abs(cycles.multipliers[row][0]):.4f}.")
    return lines
