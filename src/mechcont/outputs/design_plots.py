"""Figures of the landing-gear workflows: the downlock force along a design parameter, and the
design map of where a gear locks unaided. Headless (:class:`matplotlib.figure.Figure`)."""

from __future__ import annotations

import numpy as np

from ..units import display
from .plotting import axis_label, curve, new_figure, plot_design_region

__all__ = ["downlock_figure", "design_figure"]


def downlock_figure(branch, vary: str, force: str, *, held: str, title: str):
    """The downlock force ``force`` (N) against ``vary`` along a downlock ``branch``.

    The continuation's points are joined smoothly (:func:`~.plotting.curve`; angles in
    degrees); when the branch has an ``unlock_<force>`` column (the unlock fold of each
    downlocked point) it is drawn dashed beside it, with a legend. ``held`` names the
    downlock condition in the legend (``"theta4=0"``). Returns the figure.
    """
    fig, ax = new_figure(figsize=(5.5, 4))
    unit = (getattr(branch, "units", None) or {}).get(vary, "")
    cx, cF, _ = curve(branch, vary, force)
    ax.plot(cx, cF, "k-", label=f"downlock force ({held})")
    unlock_col = f"unlock_{force}"
    if unlock_col in branch.names:
        xs = branch[vary]
        ax.plot(display(np.asarray(xs, dtype=float), unit)[0], branch[unlock_col], "--", color="tab:red",
                label=f"unlock fold ({force} increasing)")
        ax.legend(loc="best", fontsize=8)
        ax.set_ylabel(f"{force} (N)")
    else:
        ax.set_ylabel(f"downlock force {force} (N)")
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_xlabel(axis_label(vary, unit))
    ax.set_title(title)
    return fig


def design_figure(region, *, force_name: str = "F", title: str):
    """The design map of a :class:`~mechcont.analysis.design.DesignRegion` (see
    :func:`~.plotting.plot_design_region`: force contours, the F = 0 boundary, folds, the
    design point with its force and signed lock margin). Returns the figure."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.5, 4.5))
    ax = fig.add_subplot()
    plot_design_region(region, ax, force_name=force_name)
    ax.set_title(title)
    return fig
