"""Bifurcation diagrams: branches with stability, special points, surfaces and fold curves.

Stable parts are drawn solid, unstable parts dashed (fold curves, whose stability is
not evaluated, solid); special points are marked and labelled as in the branch
(``LP1``, ``CP1``...). Angles (unit ``rad``) are shown in degrees. Matplotlib is imported
lazily and only through :class:`matplotlib.figure.Figure`, so everything runs headless.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .._io import atomic_write
from ..errors import InputError

__all__ = ["plot_branch", "plot_surface", "new_figure", "save_figure", "axis_values", "FIGURE_SUFFIXES"]

FIGURE_SUFFIXES = (".png", ".svg", ".pdf")
_MARKERS = {"LP": ("o", "tab:red"), "BP": ("s", "tab:purple"), "CP": ("D", "tab:green"),
            "EP": ("x", "0.4"), "UZ": ("^", "tab:orange")}
_ANGLE_HINTS = ("theta", "psi", "alpha", "angle")


def _is_angle(branch, name: str) -> bool:
    units = getattr(branch, "units", None) or {}
    if name in units:
        return units[name] == "rad"
    return name.startswith(_ANGLE_HINTS)


def axis_values(branch, name: str) -> tuple[np.ndarray, str]:
    """Values of ``name`` along ``branch`` for display (degrees for angles) and an axis label."""
    v = branch.column(name)
    units = getattr(branch, "units", None) or {}
    if _is_angle(branch, name):
        return np.degrees(v), f"{name} (deg)"
    unit = units.get(name, "")
    return v, f"{name} ({unit})" if unit else name


def new_figure(figsize=(6.0, 4.5), projection: str | None = None):
    """A headless figure and one axes (``projection="3d"`` for surfaces)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    ax = fig.add_subplot(projection=projection) if projection else fig.add_subplot()
    return fig, ax


def _runs(mask: np.ndarray):
    """Index ranges [i, j] (inclusive, overlapping by one point) where ``mask`` is constant."""
    if len(mask) == 0:
        return
    start = 0
    for i in range(1, len(mask)):
        if mask[i] != mask[start]:
            yield start, i, mask[start]
            start = i
    yield start, len(mask) - 1, mask[start]


def plot_branch(branch, x: str, y: str, ax=None, *, color="k", label: str | None = None,
                special: bool = True, z: str | None = None, lw: float = 1.6):
    """Draw ``y`` against ``x`` (and ``z`` on 3-D axes) along a branch.

    Parameters
    ----------
    branch:
        A :class:`~mechcont.continuation.Branch`.
    x, y, z:
        Variable names for the axes (any column). Angles are shown in degrees.
    ax:
        Matplotlib axes; a new figure is made when ``None``.
    special:
        Mark and label special points (``LP1``, ``CP1``, ...; end points are only marked).

    Returns
    -------
    matplotlib.axes.Axes
    """
    if ax is None:
        _, ax = new_figure(projection="3d" if z else None)
    xs, xl = axis_values(branch, x)
    ys, yl = axis_values(branch, y)
    zs, zl = axis_values(branch, z) if z else (None, None)
    stab = branch.n_unstable
    state = np.where(stab < 0, 2, np.where(stab == 0, 0, 1))
    styles = {0: "-", 1: "--", 2: "-"}  # fold curves (stability not evaluated) solid
    first = True
    for i, j, st in _runs(state):
        sl = slice(i, j + 1)
        args = (xs[sl], ys[sl]) if z is None else (xs[sl], ys[sl], zs[sl])
        ax.plot(*args, styles[int(st)], color=color, lw=lw, label=label if first else None)
        first = False
    if special:
        counts: dict[str, int] = {}
        for p in branch.special_points:
            counts[p.label] = counts.get(p.label, 0) + 1
            marker, mc = _MARKERS.get(p.label, ("*", "tab:blue"))
            pos = (xs[p.index], ys[p.index]) if z is None else (xs[p.index], ys[p.index], zs[p.index])
            ax.plot(*[[c] for c in pos], marker, color=mc, ms=6, mew=1.5, mfc="none" if p.label != "EP" else mc)
            if p.label != "EP":
                name = f"{p.label}{counts[p.label]}"
                if z is None:
                    ax.annotate(name, (xs[p.index], ys[p.index]), textcoords="offset points", xytext=(5, 5),
                                fontsize=8, color=mc)
                else:
                    ax.text(*pos, f" {name}", fontsize=8, color=mc)
    ax.set_xlabel(xl)
    ax.set_ylabel(yl)
    if z:
        ax.set_zlabel(zl)
    ax.grid(True, alpha=0.3)
    return ax


def plot_surface(branches: Sequence, x: str, y: str, z: str, folds=None, ax=None, *, highlight=None):
    """A surface of equilibria from a family of branches, with the fold curve on it.

    ``branches`` are one-parameter branches computed at successive values of a second
    parameter; each is drawn as a thin line and the family as a translucent surface
    (members resampled by normalised arclength, so each should span the same range).
    ``folds`` (a fold-curve branch) is drawn thick in dark grey; ``highlight`` (one
    branch) in colour. Returns the 3-D axes.
    """
    if ax is None:
        _, ax = new_figure(figsize=(7, 5.5), projection="3d")
    grid = []
    for b in branches:
        xs, xl = axis_values(b, x)
        ys, yl = axis_values(b, y)
        zs, zl = axis_values(b, z)
        ax.plot(xs, ys, zs, color="0.55", lw=0.6)
        # resample by normalised arclength so neighbouring members form a mesh even where
        # the surface folds over the (x, y) plane
        t = (b.s - b.s[0]) / max(b.s[-1] - b.s[0], 1e-300)
        u = np.linspace(0.0, 1.0, 80)
        grid.append([np.interp(u, t, xs), np.interp(u, t, ys), np.interp(u, t, zs)])
    if len(grid) >= 2:
        G = np.array(grid)  # (members, 3, samples)
        ax.plot_surface(G[:, 0], G[:, 1], G[:, 2], color="0.75", alpha=0.35, linewidth=0, shade=True)
    if folds is not None:
        plot_branch(folds, x, y, ax=ax, z=z, color="0.15", lw=2.5)
    if highlight is not None:
        plot_branch(highlight, x, y, ax=ax, z=z, color="tab:blue", lw=2.0, special=False)
    if branches:
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.set_zlabel(zl)
    return ax


def save_figure(fig, path: str | os.PathLike, dpi: int = 150) -> Path:
    """Save ``fig`` as PNG, SVG or PDF (by suffix) through a temporary file; returns the path."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FIGURE_SUFFIXES:
        raise InputError(str(path), f"unknown figure type '{suffix}'; use one of {', '.join(FIGURE_SUFFIXES)}")
    return atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format=suffix[1:]))
