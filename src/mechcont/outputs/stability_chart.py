"""The stability chart: Hopf curves (and fold curves) in a two-parameter plane, with the stable side marked.

A Hopf curve (``mechcont folds --point BRANCH.csv:HB1 --along P2``) is the boundary where the
equilibrium's critical eigenvalue pair crosses the imaginary axis. Where no other eigenvalue is unstable
(column ``n_unstable_other`` = 0) crossing it changes the equilibrium's stability: short hatch marks on
the curve point into the stable side (columns ``stable_<p>``, the direction into which the pair turns
stable), the engineer's way of drawing a stability boundary, with the words ``stable`` and
``unstable`` on either side, each in the middle of its side's largest empty area
(:func:`label_stable_sides`, once the figure is laid out; the legend goes below the axes, where it
hides nothing). Past a Bogdanov–Takens point (``BT``) the curve goes on as neutral saddles
(no boundary: dotted); ``GH`` marks where the cycles born at the curve change from stable to unstable.
Fold curves (``LP``), given too, are drawn dashed.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from .plotting import axis_values, label_point, legend_below, new_figure

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.text import Text

    from ..continuation import Branch

__all__ = ["stability_chart", "plot_stability_chart", "label_stable_sides"]

_POINT_STYLE = {"BT": ("s", "tab:purple"), "GH": ("D", "tab:green"), "CP": ("D", "tab:olive"), "EP": ("x", "0.4")}
#: Hatch length as a fraction of the axes.
_HATCH = 0.025


def plot_stability_chart(ax: Axes, hopf_curves: Sequence[Branch], x: str, y: str, folds: Sequence[Branch] = ()) -> None:
    """Draw ``hopf_curves`` (branches from :func:`~mechcont.continuation.continue_hopf`) and ``folds``
    (from :func:`~mechcont.continuation.continue_folds`) on ``ax`` with ``x``, ``y`` the two parameters;
    axes labelled with their units (angles in degrees). No legend and no side words: the caller adds the legend
    (:func:`~mechcont.outputs.plotting.legend_below`), then :func:`label_stable_sides` on the laid-out figure."""
    xlabel = ylabel = ""
    spans = []
    for b in [*hopf_curves, *folds]:
        xs, xlabel = axis_values(b, x)
        ys, ylabel = axis_values(b, y)
        spans.append((np.nanmin(xs), np.nanmax(xs), np.nanmin(ys), np.nanmax(ys)))
    if not spans:
        return
    box = (min(s[0] for s in spans), max(s[1] for s in spans), min(s[2] for s in spans), max(s[3] for s in spans))
    wx, wy = (box[1] - box[0]) or 1.0, (box[3] - box[2]) or 1.0
    for k, b in enumerate(folds):
        xs, ys = axis_values(b, x)[0], axis_values(b, y)[0]
        ax.plot(xs, ys, "--", color="0.35", lw=1.2, label="fold (LP) curve" if k == 0 else None)
    for k, b in enumerate(hopf_curves):
        xs, ys = axis_values(b, x)[0], axis_values(b, y)[0]
        omega = b.column("omega") if "omega" in b.names else np.ones(len(b))
        hopf = np.isfinite(omega)
        ax.plot(np.where(hopf, xs, np.nan), ys, "-", color="tab:blue", lw=1.8,
                label="Hopf (HB) curve" if k == 0 else None)
        if not hopf.all():
            ax.plot(np.where(hopf, np.nan, xs), ys, ":", color="tab:blue", lw=1.2,
                    label="neutral saddle" if k == 0 else None)
        _hatch(ax, b, x, y, xs, ys, hopf, (wx, wy))
        for name, p in zip(b.point_names(), b.special_points):
            style = _POINT_STYLE.get(p.label)
            if style is None:
                continue
            i = p.index
            ax.plot(xs[i], ys[i], style[0], color=style[1], ms=6, mfc="none" if p.label == "EP" else style[1])
            if p.label != "EP":
                label_point(ax, xs[i], ys[i], name, box, color=style[1])
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)


def _stable_directions(b: Branch, x: str, y: str, hopf: np.ndarray,
                       spans: tuple[float, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """``(ux, uy, ok)``: the unit direction into the stable side at each point of Hopf curve ``b`` (per span of
    the drawn box, ``spans`` in data units) and where it is a stability boundary (``None`` without the columns)."""
    cx, cy = f"stable_{x}", f"stable_{y}"
    if cx not in b.names or cy not in b.names:
        return None
    others = b.column("n_unstable_other") if "n_unstable_other" in b.names else np.zeros(len(b))
    dx, dy = b.column(cx) * spans[0], b.column(cy) * spans[1]  # per axes fraction: d/d(x / span)
    norm = np.hypot(dx, dy)
    ok = hopf & (others == 0) & np.isfinite(norm) & (norm > 0)
    return dx / np.where(norm > 0, norm, 1.0), dy / np.where(norm > 0, norm, 1.0), ok


def label_stable_sides(ax: Axes, hopf_curves: Sequence[Branch], x: str, y: str) -> list[Text]:
    """Write ``stable`` and ``unstable`` on the two sides of the Hopf ``hopf_curves`` drawn on ``ax`` by
    :func:`plot_stability_chart` (call it once the figure has its legend and layout): each in the middle of its
    side's largest empty area (:func:`~mechcont.outputs._regions.label_sides`). Returns the texts written."""
    from ._regions import label_sides

    points, normals, valid = [], [], []
    for b in hopf_curves:
        xs, ys = axis_values(b, x)[0], axis_values(b, y)[0]
        omega = b.column("omega") if "omega" in b.names else np.ones(len(b))
        # the direction is in parameter units per span; (xs, ys) may be shown in degrees: scale it alike
        sx = (np.nanmax(xs) - np.nanmin(xs)) or 1.0
        sy = (np.nanmax(ys) - np.nanmin(ys)) or 1.0
        dirs = _stable_directions(b, x, y, np.isfinite(omega), (sx, sy))
        if dirs is None:
            continue
        points.append(np.column_stack([xs, ys]))
        normals.append(np.column_stack([dirs[0] * sx, dirs[1] * sy]))
        valid.append(dirs[2])
    if not points:
        return []
    return label_sides(ax, np.vstack(points), np.vstack(normals), np.concatenate(valid),
                       (("stable", "tab:green"), ("unstable", "tab:red")))


def _hatch(ax: Axes, b: Branch, x: str, y: str, xs: np.ndarray, ys: np.ndarray, hopf: np.ndarray,
           spans: tuple[float, float]) -> None:
    """Hatch marks into the stable side where crossing the curve changes stability."""
    dirs = _stable_directions(b, x, y, hopf, spans)
    if dirs is None:
        return
    ux, uy, ok = dirs
    idx = np.flatnonzero(ok)
    if len(idx) == 0:
        return
    # evenly along the drawn curve (in axes fractions), not per computed point: steps crowd where the curve bends
    run = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(xs) / spans[0], np.diff(ys) / spans[1]))])
    targets = np.arange(0.0, run[idx[-1]] + 1e-12, 1.5 * _HATCH)
    marks = idx[np.unique(np.clip(np.searchsorted(run[idx], targets), 0, len(idx) - 1))]
    for i in marks:
        ax.plot([xs[i], xs[i] + _HATCH * ux[i] * spans[0]], [ys[i], ys[i] + _HATCH * uy[i] * spans[1]],
                "-", color="tab:blue", lw=0.8)


def stability_chart(hopf_curves: Sequence[Branch], x: str, y: str, folds: Sequence[Branch] = (), *,
                    title: str | None = None) -> Figure:
    """A new figure of the stability chart (:func:`plot_stability_chart`) titled ``title``."""
    fig, ax = new_figure()
    plot_stability_chart(ax, hopf_curves, x, y, folds)
    if title:
        ax.set_title(title)
    legend_below(fig, ncols=3)
    label_stable_sides(ax, hopf_curves, x, y)
    return fig
