"""Bifurcation diagrams: branches with stability, special points, surfaces and fold curves.

Stable parts are drawn solid, unstable parts dashed (fold curves, whose stability is
not evaluated, solid); special points are marked and labelled as in the branch
(``LP1``, ``CP1``...). Angles (unit ``rad``) are shown in degrees. Matplotlib is imported
lazily and only through :class:`matplotlib.figure.Figure`, so everything runs headless.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, overload

import numpy as np

from .._io import atomic_write
from ..errors import InputError
from ..units import display, display_unit

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.legend import Legend
    from matplotlib.transforms import Bbox
    from matplotlib.typing import ColorType
    from mpl_toolkits.mplot3d import Axes3D

    from ..analysis.design import DesignRegion
    from ..continuation import Branch

__all__ = ["plot_branch", "branch_figure", "plot_surface", "new_figure", "save_figure", "interval_states",
           "axis_values", "axis_label", "curve", "label_point", "nice_levels", "signed_levels",
           "plot_design_region", "legend_below", "FIGURE_SUFFIXES"]

FIGURE_SUFFIXES = (".png", ".svg", ".pdf")
_MARKERS = {"LP": ("o", "tab:red"), "BP": ("s", "tab:purple"), "CP": ("D", "tab:green"),
            "EP": ("x", "0.4"), "UZ": ("^", "tab:orange"), "HB": ("*", "tab:blue"), "BT": ("s", "tab:purple"),
            "GH": ("D", "tab:green")}
_ANGLE_HINTS = ("theta", "psi", "alpha", "angle")
#: Samples per continuation step of a drawn curve (a cubic through the computed points).
PER_STEP = 8


def _is_angle(branch: Branch, name: str) -> bool:
    units: dict[str, str] = getattr(branch, "units", None) or {}
    if name in units:
        return units[name] == "rad"
    return name.startswith(_ANGLE_HINTS)


def axis_label(name: str, unit: str) -> str:
    """``"F (N)"``; an angle (``rad``) is labelled in degrees, ``"theta1 (deg)"``; a quantity without a unit (an
    ODE file's state or parameter written without one) is labelled dimensionless, ``"u1 (1)"``."""
    return f"{name} ({display_unit(unit) or '1'})"


def axis_values(branch: Branch, name: str) -> tuple[np.ndarray, str]:
    """Values of ``name`` along ``branch`` for display (degrees for angles) and an axis label."""
    v = branch.column(name)
    units = getattr(branch, "units", None) or {}
    if _is_angle(branch, name):
        return display(np.asarray(v, dtype=float), "rad")[0], axis_label(name, "rad")
    return v, axis_label(name, units.get(name, ""))


def _dense_s(s: np.ndarray, per_step: int) -> np.ndarray:
    """``per_step`` samples in every interval of ``s``, the computed points among them."""
    t = np.linspace(0.0, 1.0, per_step, endpoint=False)
    inner = (s[:-1, None] + np.diff(s)[:, None] * t[None, :]).ravel()
    return np.append(inner, s[-1])


def curve(branch: Branch, *names: str, per_step: int = PER_STEP) -> tuple[np.ndarray, ...]:
    """Columns ``names`` of ``branch`` as smooth curves for drawing (display units: angles in degrees).

    The continuation's own points are kept and joined by a cubic spline in the branch's
    arclength ``s`` (``per_step`` samples per step), so a branch computed with long steps
    is drawn as the smooth curve it is, never as a coarse polyline. Returns one array per
    name, then the arclength of each sample.
    """
    cols = np.column_stack([axis_values(branch, n)[0] for n in names]) if names else np.zeros((len(branch), 0))
    s = np.asarray(branch.s, float)
    if len(s) < 3 or per_step < 2 or not np.all(np.diff(s) > 0):
        return (*cols.T, s)
    from scipy.interpolate import CubicSpline

    sd = _dense_s(s, per_step)
    dense = CubicSpline(s, cols, axis=0)(sd)
    dense[::per_step] = cols  # the computed points exactly
    return (*dense.T, sd)


def interval_states(branch: Branch) -> np.ndarray:
    """Stability per interval between rows: 0 stable, 1 unstable, 2 not evaluated.

    Where the two ends differ the change is at a special point (a fold): the interval takes
    the state of its other end, so a fold row (neutral, either count) never decides.
    """
    nu = np.asarray(branch.n_unstable)
    st = np.where(nu < 0, 2, np.where(nu == 0, 0, 1))
    labels = list(getattr(branch, "labels", [""] * len(st)))
    out = np.empty(max(len(st) - 1, 0), dtype=int)
    for i in range(len(out)):
        a, b = st[i], st[i + 1]
        out[i] = a if a == b else (b if labels[i] else a)
    return out


def label_point(ax: Axes, x: float, y: float, text: str, box: tuple[float, float, float, float], color: ColorType = "k",
                fontsize: float = 8, background: bool = False) -> None:
    """Write ``text`` beside the point (x, y) on the side facing the middle of ``box``
    (``xmin, xmax, ymin, ymax`` of what is drawn), so that it stays inside the axes;
    ``background`` puts it on a white box (over contours or lines)."""
    xmin, xmax, ymin, ymax = box
    fx = (x - xmin) / (xmax - xmin) if xmax > xmin else 0.5
    fy = (y - ymin) / (ymax - ymin) if ymax > ymin else 0.5
    dx, ha = (-6, "right") if fx > 0.75 else (6, "left")
    dy, va = (-6, "top") if fy > 0.8 else (6, "bottom")
    ax.annotate(text, (x, y), textcoords="offset points", xytext=(dx, dy), ha=ha, va=va, fontsize=fontsize,
                color=color, bbox=dict(boxstyle="round,pad=0.2", facecolor="white", edgecolor="none", alpha=0.8)
                if background else None)


@overload
def new_figure(figsize: tuple[float, float] = ..., projection: None = None) -> tuple[Figure, Axes]: ...
@overload
def new_figure(figsize: tuple[float, float] = ..., *, projection: Literal["3d"]) -> tuple[Figure, Axes3D]: ...
@overload
def new_figure(figsize: tuple[float, float] = ..., projection: str | None = None) -> tuple[Figure, Axes]: ...
def new_figure(figsize: tuple[float, float] = (6.0, 4.5), projection: str | None = None) -> tuple[Figure, Axes]:
    """A headless figure and one axes (``projection="3d"`` for surfaces)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    ax = fig.add_subplot(projection=projection) if projection else fig.add_subplot()
    return fig, ax


def _interval_runs(states: np.ndarray) -> Iterator[tuple[int, int, int]]:
    """``(i, j, state)``: rows i..j joined by intervals of one state (consecutive runs share a row)."""
    if len(states) == 0:
        yield 0, 0, 2
        return
    start = 0
    for k in range(1, len(states) + 1):
        if k == len(states) or states[k] != states[start]:
            yield start, k, states[start]
            start = k


_STATE_WORDS = {0: "stable", 1: "unstable", 2: None}


def plot_branch(branch: Branch, x: str, y: str, ax: Axes | None = None, *, color: ColorType = "k",
                label: str | None = None, special: bool = True, z: str | None = None, lw: float = 1.6,
                stability_legend: bool = False, endpoints: bool = True) -> Axes:
    """Draw ``y`` against ``x`` (and ``z`` on 3-D axes) along a branch.

    Parameters
    ----------
    branch:
        A :class:`~mechcont.continuation.Branch`.
    x, y, z:
        Variable names for the axes (any column). Angles are shown in degrees.
    ax:
        Matplotlib axes; a new figure is made when ``None``.
    label:
        Legend entry of the branch (on its first drawn piece).
    special:
        Mark and label special points (``LP1``, ``CP1``, ...: :meth:`Branch.point_names`,
        the numbering of every output; end points are only marked).
    stability_legend:
        One legend entry per style actually drawn: ``"<label>, stable"`` (solid) and
        ``"<label>, unstable"`` (dashed).
    endpoints:
        Mark the end points (``EP``).

    The curve is the continuation's points joined by a cubic in arclength
    (:func:`curve`); stable parts solid, unstable dashed, fold curves (stability not
    evaluated) solid.

    Returns
    -------
    matplotlib.axes.Axes
    """
    if ax is None:
        _, ax = new_figure(projection="3d" if z else None)
    names = (x, y, z) if z else (x, y)
    *cols, sd = curve(branch, *names)
    _, xl = axis_values(branch, x)
    _, yl = axis_values(branch, y)
    zl = axis_values(branch, z)[1] if z else None
    states = interval_states(branch)
    s = np.asarray(branch.s, float)
    styles = {0: "-", 1: "--", 2: "-"}  # fold curves (stability not evaluated) solid
    seen: set[int] = set()
    first = True
    dense = len(sd) != len(s)
    per = (len(sd) - 1) // max(len(s) - 1, 1) if dense else 1
    for i, j, st in _interval_runs(states):
        a, b = i * per, j * per + 1  # rows i..j
        seg = [c[a:b] for c in cols]
        st = int(st)
        if stability_legend and st in (0, 1) and st not in seen:
            lab = f"{label}, {_STATE_WORDS[st]}" if label else _STATE_WORDS[st]
        elif not stability_legend and first:
            lab = label
        else:
            lab = None
        seen.add(st)
        ax.plot(*seg, styles[st], color=color, lw=lw, label=lab)
        first = False
    if special:
        xs, ys = axis_values(branch, x)[0], axis_values(branch, y)[0]
        zs = axis_values(branch, z)[0] if z else None
        box = (float(np.min(cols[0])), float(np.max(cols[0])), float(np.min(cols[1])), float(np.max(cols[1])))
        for name, p in zip(branch.point_names(), branch.special_points):
            if p.label == "EP" and not endpoints:
                continue
            marker, mc = _MARKERS.get(p.label, ("*", "tab:blue"))
            pos = (xs[p.index], ys[p.index]) if zs is None else (xs[p.index], ys[p.index], zs[p.index])
            ax.plot(*[[c] for c in pos], marker, color=mc, ms=6, mew=1.5, mfc="none" if p.label != "EP" else mc)
            if p.label != "EP":
                text = name if p.located else name + "?"
                if z is None:
                    label_point(ax, pos[0], pos[1], text, box, color=mc)
                else:
                    ax3: Axes3D = ax   # with z, 3-D axes
                    ax3.text(*pos, f" {text}", fontsize=8, color=mc)
    ax.set_xlabel(xl)
    ax.set_ylabel(yl)
    if z:
        axz: Axes3D = ax   # with z, 3-D axes
        axz.set_zlabel(zl)
    ax.grid(True, alpha=0.3)
    return ax


#: Face colours of a surface of equilibria: stable sheets grey, unstable sheets light red.
SHEET_COLOURS = {0: (0.72, 0.72, 0.72), 1: (0.93, 0.55, 0.50), 2: (0.72, 0.72, 0.72)}


def branch_figure(branch: Branch, x: str, y: str, *, title: str | None = None) -> Figure:
    """A new figure of ``y`` against ``x`` along ``branch`` (:func:`plot_branch`), titled ``title``."""
    fig, ax = new_figure()
    plot_branch(branch, x, y, ax=ax)
    if title:
        ax.set_title(title)
    return fig


def _sheet_samples(b: Branch, names: Sequence[str], samples: int) -> tuple[np.ndarray, np.ndarray]:
    """Member ``b`` resampled at ``samples`` points of its normalised arclength: (3, samples) values
    (display units) and the stability state (0/1/2) of each sample."""
    *cols, sd = curve(b, *names)
    t = (sd - sd[0]) / max(sd[-1] - sd[0], 1e-300)
    u = np.linspace(0.0, 1.0, samples)
    vals = np.array([np.interp(u, t, c) for c in cols])
    s = np.asarray(b.s, float)
    ts = (s - s[0]) / max(s[-1] - s[0], 1e-300)
    states = interval_states(b)
    k = np.clip(np.searchsorted(ts, u, side="right") - 1, 0, max(len(states) - 1, 0))
    return vals, (states[k] if len(states) else np.full(samples, 2))


def plot_surface(branches: Sequence[Branch], x: str, y: str, z: str, folds: Branch | None = None,
                 ax: Axes3D | None = None, *, highlight: Branch | None = None, stability: bool = True,
                 samples: int = 240, alpha: float = 0.8, member_lines: bool = False) -> Axes3D:
    """A surface of equilibria from a family of branches, with the fold curve on it.

    ``branches`` are one-parameter branches computed at successive values of a second
    parameter, each spanning the same range (e.g. the same bounds on the continuation
    parameter); the family is drawn as a surface (members resampled by normalised
    arclength), stable sheets grey and unstable sheets light red when ``stability``
    (:data:`SHEET_COLOURS`). ``folds`` (a fold-curve branch) is drawn thick in dark grey;
    ``highlight`` (one branch) in colour; ``member_lines`` draws every member thinly.
    Returns the 3-D axes.
    """
    if ax is None:
        _, ax = new_figure(figsize=(7, 5.5), projection="3d")
    grid, states = [], []
    for b in branches:
        vals, st = _sheet_samples(b, (x, y, z), samples)
        grid.append(vals)
        states.append(st)
        if member_lines:
            ax.plot(*vals, color="0.55", lw=0.5)
    if len(grid) >= 2:
        G = np.array(grid)  # (members, 3, samples)
        # a face is unstable when at least two of its four corners are
        U = (np.array(states) == 1).astype(int) if stability else np.zeros((len(grid), samples), int)
        face = (U[:-1, :-1] + U[1:, :-1] + U[:-1, 1:] + U[1:, 1:]) >= 2
        rgba = np.empty((*U.shape, 4))
        rgba[...] = (*SHEET_COLOURS[0], alpha)
        rgba[:-1, :-1][face] = (*SHEET_COLOURS[1], alpha)
        ax.computed_zorder = False  # curves are drawn over the surface, in the order given
        ax.plot_surface(G[:, 0], G[:, 1], G[:, 2], facecolors=rgba, linewidth=0, edgecolor="none", shade=False,
                        rstride=1, cstride=1, antialiased=True, zorder=1)
    if folds is not None:
        plot_branch(folds, x, y, ax=ax, z=z, color="0.1", lw=2.5)
    if highlight is not None:
        plot_branch(highlight, x, y, ax=ax, z=z, color="tab:blue", lw=2.0, special=False)
    if branches:
        ax.set_xlabel(axis_values(branches[0], x)[1])
        ax.set_ylabel(axis_values(branches[0], y)[1])
        ax.set_zlabel(axis_values(branches[0], z)[1])
    return ax


def nice_levels(limit: float, n: int = 10, per_tick: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Contour levels symmetric about 0 on round numbers covering ``[-limit, limit]``, and the
    (fewer) round ticks to label them: ``per_tick`` levels per tick, e.g. levels every 100 N, ticks
    every 200 N."""
    from matplotlib.ticker import MaxNLocator

    limit = float(limit) if np.isfinite(limit) and limit > 0 else 1.0
    ticks = MaxNLocator(nbins=n // 2, steps=[1, 2, 2.5, 5, 10], symmetric=True).tick_values(-limit, limit)
    half = (ticks[1] - ticks[0]) / per_tick
    top = half * np.ceil(limit / half - 1e-9)
    levels = np.arange(-top, top + half / 2, half)
    return levels, ticks[(ticks >= -top - 1e-9) & (ticks <= top + 1e-9)]


def signed_levels(limit: float, finest: float = float("nan")) -> np.ndarray:
    """Contour levels 0, +-a, +-b, ... on the 1-2-5 series from ``finest`` (rounded down to it; between
    ``limit``/200 and ``limit``/10, ``limit``/50 when not finite) to the first value >= ``limit``: narrow
    bands near 0, where a design is decided, wide ones far from it."""
    limit = float(limit) if np.isfinite(limit) and limit > 0 else 1.0
    finest = float(np.clip(finest, limit / 200, limit / 10)) if np.isfinite(finest) and finest > 0 else limit / 50
    e = int(np.floor(np.log10(finest)))
    series = [m * 10.0**k for k in range(e, e + 12) for m in (1, 2, 5)]
    series = [v for v in series if v >= max(v2 for v2 in series if v2 <= finest * (1 + 1e-12))]
    top = next(k for k, v in enumerate(series) if v >= limit * (1 - 1e-12))
    pos = np.array(series[:top + 1])
    return np.concatenate([-pos[::-1], [0.0], pos])


def plot_design_region(region: DesignRegion, ax: Axes, *, force_name: str = "F") -> None:
    """Draw a :class:`~mechcont.analysis.design.DesignRegion` on a matplotlib axis.

    Filled contours of the downlock force (N, blue where it is positive: locks unaided) on
    :func:`signed_levels` (the finest band half the design point's force), the continued
    F = 0 boundary (black), the fold locus with its cusps (orange) and the design point (star;
    its force and its signed lock margin along x in the legend, clear of the curves). Curves are
    the continuation's points joined smoothly (:func:`curve`).
    """
    from matplotlib.colors import BoundaryNorm

    X, Y = np.meshgrid(region.x, region.y)
    lim = np.nanmax(np.abs(region.force))
    xn, yn = region.x_name, region.y_name
    row = min(region.rows, key=lambda r: abs(r.level - region.design[1])) if region.rows else None
    if row is not None and abs(row.level - region.design[1]) > 1e-9 * max(1.0, abs(row.level)):
        row = None
    levels = signed_levels(lim, np.nan if row is None else abs(row.force_at_design) / 2)
    # blue: F > 0, the gear locks unaided; red: it needs help; each band its own shade (finer ones near F = 0)
    norm = BoundaryNorm(levels, 256)
    cs = ax.contourf(X, Y, region.force, levels=levels, cmap="RdBu", norm=norm)  # 0 is a level
    ax.contour(X, Y, region.force, levels=levels, colors="0.4", linewidths=0.3, alpha=0.6)
    unit = region.units[2] or "N"
    ax.figure.colorbar(cs, ax=ax, ticks=levels, label=f"downlock force {force_name} ({unit}); > 0: locks unaided")
    box = (float(region.x[0]), float(region.x[-1]), float(region.y[0]), float(region.y[-1]))
    if region.boundary is not None:
        bx, by, _ = curve(region.boundary, xn, yn)
        ax.plot(bx, by, "k-", lw=2, label=f"{force_name} = 0 (continued)")
    if region.folds is not None and region.folds.curve is not None:
        cx, cy, _ = curve(region.folds.curve, xn, yn)
        ax.plot(cx, cy, color="darkorange", lw=2, label=f"folds: extrema of {force_name} in {xn}")
        for p in region.folds.cusps:
            ax.plot(p[xn], p[yn], "o", color="darkorange", ms=7)
            label_point(ax, p[xn], p[yn], "CP", box, color="k")
    # the design point's values go in the legend, which finds a place off the curves (a label box beside the
    # star covered the F = 0 boundary)
    design = "design point"
    if row is not None:
        ux = region.units[0]
        design += f": {force_name} = {row.force_at_design:.3g} {unit}"
        if np.isfinite(row.lock_margin):
            design += f"\nlock margin {row.lock_margin:+.3g} {ux} along {xn}".rstrip()
    ax.plot(*region.design, "k*", ms=12, label=design)
    ax.set_xlim(region.x[0], region.x[-1])
    ax.set_ylim(region.y[0], region.y[-1])
    ax.set_xlabel(f"{xn} ({region.units[0]})" if region.units[0] else xn)  # values as stored (SI)
    ax.set_ylabel(f"{yn} ({region.units[1]})" if region.units[1] else yn)
    ax.legend(loc="best", fontsize=9)


def legend_below(fig: Figure, axes: Iterable[Axes] | None = None, *, ncols: int = 2, fontsize: float = 8) -> Legend:
    """One legend for ``axes`` (default: every axes of ``fig``; one entry per label) below them, outside every
    panel, where it hides no curve (``fig`` with the constrained layout, which makes room for it). Returns it."""
    entries: dict[str, object] = {}
    for ax in fig.axes if axes is None else axes:
        for handle, text in zip(*ax.get_legend_handles_labels()):
            entries.setdefault(text, handle)
        legend = ax.get_legend()
        if legend is not None:
            legend.remove()
    return fig.legend(handles=list(entries.values()), labels=list(entries), loc="outside lower center",
                      ncols=min(ncols, max(len(entries), 1)), fontsize=fontsize, frameon=False)


def save_figure(fig: Figure, path: str | os.PathLike[str], dpi: int = 150, *, tight: bool = False) -> Path:
    """Save ``fig`` as PNG, SVG or PDF (by suffix) through a temporary file; returns the path. ``tight`` crops the
    page to what is drawn (with a small margin)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FIGURE_SUFFIXES:
        raise InputError(str(path), f"unknown figure type '{suffix}'; use one of {', '.join(FIGURE_SUFFIXES)}")
    crop: dict[str, Any] = {"bbox_inches": _drawn_box(fig), "pad_inches": 0.0} if tight else {}
    return atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format=suffix[1:], **crop))


def _drawn_box(fig: Figure, pad: float = 0.1) -> Bbox:
    """The box (in) around what ``fig`` draws, ``pad`` in wider: a 2-D axes' tight box, a 3-D axes' axes (panes,
    ticks, labels), title and legend, not its whole square box, whose corners a perspective view leaves empty."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.transforms import Bbox

    canvas = fig.canvas if hasattr(fig.canvas, "get_renderer") else FigureCanvasAgg(fig)
    renderer = canvas.get_renderer()
    fig.draw_without_rendering()
    boxes = []
    for ax in fig.axes:
        parts: list[Artist | None] = [ax]
        if ax.name == "3d":
            ax3: Axes3D = ax
            parts = [ax3.xaxis, ax3.yaxis, ax3.zaxis, ax3.title, ax3.get_legend()]
        boxes += [p.get_tightbbox(renderer) for p in parts if p is not None]
    boxes += [t.get_window_extent(renderer) for t in fig.texts if t.get_text()]
    box = Bbox.union([b for b in boxes if b is not None and b.width > 0])
    return box.transformed(fig.dpi_scale_trans.inverted()).padded(pad)
