"""Figures of time simulations: quasi-static sweeps drawn over continuation branches."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .plotting import legend_below, new_figure, plot_branch

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..continuation import Branch
    from ..dynamics import SweepResult

__all__ = ["plot_sweep", "sweep_figure"]


def plot_sweep(result: SweepResult, ax: Axes | None = None, *, color: str = "k", label: str | None = "time simulation",
               arrows: bool = True, degrees: bool | None = None) -> Axes:
    """Draw a sweep as (ramped parameter, watched coordinate) curves, jumps as arrows.

    Intended over continuation branches (grey) as in the paper's Figures 3 and 4. Axes are
    labelled with their units; an angle (unit ``rad``) is shown in degrees, as
    :func:`mechcont.outputs.plotting.plot_branch` shows it (``degrees`` forces either way).

    A runaway (:attr:`~mechcont.dynamics.SweepResult.runaway`: the mechanism ran away past its last fold and had
    not settled when the sweep ended) is drawn like a jump, dashed, from where it started to where the sweep
    ended, its start marked by an open circle with the legend entry ``runaway`` (with ``arrows``).
    Returns the matplotlib axes.
    """
    if ax is None:
        _, ax = new_figure()
    sim = result.simulation
    unit = sim.unit(result.watch) if hasattr(sim, "unit") else ""
    if degrees is None:
        degrees = unit == "rad"
    k = 180.0 / np.pi if degrees else 1.0
    for i in range(len(result.ramps)):
        p, w = result.curve(i)
        ax.plot(p, k * w, color=color, lw=1.0, label=label if i == 0 else None)
    if arrows:
        for j in result.jumps:
            b, a = j.before[result.watch], j.after[result.watch]
            ax.annotate("", xy=(j.value, k * a), xytext=(j.value, k * b),
                        arrowprops=dict(arrowstyle="->", color=color, lw=0.8))
        if (run := result.runaway) is not None:
            b, a = run.before[result.watch], run.after[result.watch]
            ax.annotate("", xy=(run.value, k * a), xytext=(run.value, k * b), gid="runaway",
                        arrowprops=dict(arrowstyle="->", color=color, lw=0.8, linestyle="--"))
            ax.plot([run.value], [k * b], marker="o", mfc="none", mec=color, ls="none", label="runaway")
    name = result.ramps[0].name
    xunit = sim.unit(name) if hasattr(sim, "unit") else ""
    ax.set_xlabel(f"{name} ({xunit})" if xunit else name)  # drawn as stored (SI)
    ax.set_ylabel(f"{result.watch} (deg)" if degrees else f"{result.watch} ({unit})" if unit else result.watch)
    return ax


def sweep_figure(result: SweepResult, *, title: str, branch: Branch | None = None, degrees: bool | None = None) -> Figure:
    """A sweep (:class:`~mechcont.dynamics.SweepResult`) as a figure, over ``branch`` when given.

    The continuation branch is drawn wide and grey (stable solid, unstable dashed, with a
    legend entry for each), the time simulation in black with its jumps as arrows and its runaway (if
    any) as a dashed arrow from a circle (:func:`plot_sweep`); angles in degrees. Returns the figure.
    """
    fig, ax = new_figure(figsize=(6.4, 4.8))
    if branch is not None:
        plot_branch(branch, result.ramps[0].name, result.watch, ax=ax, color="0.65", lw=3.0, label="continuation",
                    stability_legend=True, endpoints=False)
    plot_sweep(result, ax, degrees=degrees)
    ax.set_title(title, fontsize=10)
    legend_below(fig)   # in the axes it lay over the branch
    return fig
