"""Figures of the landing-gear workflows: the downlock force along a design parameter, and the
design map of where a gear locks unaided. Headless (:class:`matplotlib.figure.Figure`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..units import display
from .plotting import axis_label, curve, new_figure, plot_design_region

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..analysis.design import DesignRegion
    from ..analysis.optimize import OptimumMap
    from ..continuation import Branch

__all__ = ["downlock_figure", "design_figure", "optimum_figure"]


def downlock_figure(branch: Branch, vary: str, force: str, *, held: str, title: str) -> Figure:
    """The downlock force ``force`` (its unit, the branch's) against ``vary`` along a downlock ``branch``.

    The continuation's points are joined smoothly (:func:`~.plotting.curve`; angles in
    degrees); when the branch has an ``unlock_<force>`` column (the unlock fold of each
    downlocked point) it is drawn dashed beside it, with a legend. ``held`` names the
    downlock condition in the legend (``"theta4=0"``). Returns the figure.
    """
    fig, ax = new_figure(figsize=(5.5, 4))
    unit = (getattr(branch, "units", None) or {}).get(vary, "")
    funit = (getattr(branch, "units", None) or {}).get(force, "")
    cx, cF, _ = curve(branch, vary, force)
    ax.plot(cx, cF, "k-", label=f"downlock force ({held})")
    unlock_col = f"unlock_{force}"
    if unlock_col in branch.names:
        xs = branch[vary]
        ax.plot(display(np.asarray(xs, dtype=float), unit)[0], branch[unlock_col], "--", color="tab:red",
                label=f"unlock fold ({force} increasing)")
        ax.legend(loc="best", fontsize=8)
        ax.set_ylabel(axis_label(force, funit))
    else:
        ax.set_ylabel(axis_label(f"downlock force {force}", funit))
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_xlabel(axis_label(vary, unit))
    ax.set_title(title)
    return fig


def design_figure(region: DesignRegion, *, force_name: str = "F", title: str) -> Figure:
    """The design map of a :class:`~mechcont.analysis.design.DesignRegion` (see
    :func:`~.plotting.plot_design_region`: force contours, the F = 0 boundary, folds, the
    design point with its force and signed lock margin). Returns the figure."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.5, 4.5), layout="constrained")
    ax = fig.add_subplot()
    plot_design_region(region, ax, force_name=force_name)
    ax.set_title(title)
    return fig


def optimum_figure(omap: OptimumMap, *, force_name: str = "F", title: str, value_text: str = "") -> Figure:
    """An :class:`~mechcont.analysis.optimize.OptimumMap`: the design map (:func:`design_figure`'s), each active
    constraint's boundary dashed and the optimum as a filled diamond (``value_text`` beside its legend entry,
    e.g. ``"LU = 1.29 m"``). The view reaches a little beyond the design bounds, hatched there, so that a bound
    that is active (the optimum on it) is a line inside the frame with the optimum's marker whole; the legend
    sits below the map, off every curve. Returns the figure."""
    from matplotlib.patches import Rectangle

    fig = design_figure(omap.region, force_name=force_name, title=title)
    fig.set_size_inches(6.5, 5.6)   # room for the legend below
    ax = fig.axes[0]
    styles = ["--", ":", "-."]
    names = list(dict.fromkeys(w for w, _, _ in omap.boundaries))  # a constraint's pieces share its style and label
    for i, (what, xs, ys) in enumerate(omap.boundaries):
        first = all(w != what for w, _, _ in omap.boundaries[:i])
        ax.plot(xs, ys, styles[names.index(what) % len(styles)], color="magenta", lw=2.5,
                label=f"active: {what}" if first else None, zorder=4)
    ax.plot(*omap.optimum, "D", color="limegreen", mec="k", ms=9, zorder=5,
            label=f"optimum{': ' + value_text if value_text else ''}")
    (x0, x1), (y0, y1) = (omap.region.x[0], omap.region.x[-1]), (omap.region.y[0], omap.region.y[-1])
    px, py = _PAD * (x1 - x0), _PAD * (y1 - y0)
    bands = [(x0 - px, y0 - py, x1 - x0 + 2 * px, py), (x0 - px, y1, x1 - x0 + 2 * px, py),
             (x0 - px, y0, px, y1 - y0), (x1, y0, px, y1 - y0)]
    for k, (x, y, w, h) in enumerate(bands):
        ax.add_patch(Rectangle((x, y), w, h, facecolor="0.9", edgecolor="0.55", hatch="///", lw=0,
                               label="outside the design bounds" if k == 0 else None))
    ax.set_xlim(x0 - px, x1 + px)
    ax.set_ylim(y0 - py, y1 + py)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncols=2, fontsize=8, frameon=False)
    return fig


#: How far (fraction of each range) an optimum's map reaches beyond its design bounds.
_PAD = 0.04
