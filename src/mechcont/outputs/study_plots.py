"""Figures of a study's results (:mod:`mechcont.analysis.study`).

* a grid over two parameters: the downlock force as a filled contour map (blue where the
  gear locks unaided), the ``F = 0`` line, and the fold curve of ``F`` in the first
  parameter (where dF/dx = 0 on the grid: the extrema of the force, the design map's folds);
* a grid over one parameter: the force against it, with ``F = 0``;
* sampled tolerances (Monte Carlo, Latin hypercube): the histogram of the downlock force
  with ``F = 0`` and the probability of not locking unaided with its 95 % interval, beside
  the sensitivity ranking (standardised regression coefficients).

Angles are shown in degrees, every other value in its SI unit (named on the axes).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .._status import Status
from ..units import display_scale
from .plotting import axis_label

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.typing import LineStyleType

__all__ = ["plot_study", "plot_response_surface", "plot_force_histogram", "plot_sensitivity"]


def _axis(df: pd.DataFrame, name: str) -> tuple[float, str]:
    """Display factor and axis label of the column ``name`` (degrees for radians)."""
    unit = df.attrs.get("units", {}).get(name, "")
    return display_scale(unit), axis_label(name, unit)


def plot_response_surface(df: pd.DataFrame, ax: Axes, column: str = "downlock_force") -> Axes:
    """Contour map of ``column`` over a 2-D grid study, the 0 line and the fold curve (dF/dx = 0)."""
    from ..analysis.study import grid_values, study_spec_of

    spec = study_spec_of(df)
    (xn, xa), (yn, ya) = spec.parameters
    fx, lx = _axis(df, xn)
    fy, ly = _axis(df, yn)
    Z = grid_values(df, column)  # axis 0: x, axis 1: y
    x, y = xa.values() * fx, ya.values() * fy
    lim = np.nanmax(np.abs(Z)) if np.isfinite(Z).any() else 1.0
    cs = ax.contourf(x, y, Z.T, levels=21, cmap="RdBu", vmin=-lim, vmax=lim)
    ax.figure.colorbar(cs, ax=ax, label=_axis(df, column)[1])
    handles: list[tuple[str, LineStyleType, str]] = []  # (colour, line style, legend text)
    if np.nanmin(Z) < 0 < np.nanmax(Z):
        ax.contour(x, y, Z.T, levels=[0.0], colors="k", linewidths=2)
        handles.append(("k", "-", f"{column} = 0: locks unaided on the blue side"))
    if xa.n >= 3:
        dZ = np.gradient(Z, xa.values(), axis=0)
        if np.nanmin(dZ) < 0 < np.nanmax(dZ):
            ax.contour(x, y, dZ.T, levels=[0.0], colors="tab:red", linewidths=1.5, linestyles="--")
            handles.append(("tab:red", "--", f"folds: extrema of the force in {xn}"))
    from matplotlib.lines import Line2D

    if handles:
        ax.legend([Line2D([], [], color=c, linestyle=s, lw=2) for c, s, _ in handles], [t for *_, t in handles],
                  loc="best", fontsize=8)
    ax.set_xlabel(lx)
    ax.set_ylabel(ly)
    return ax


def plot_force_histogram(df: pd.DataFrame, ax: Axes, column: str = "downlock_force") -> Axes:
    """Histogram of ``column`` over the converged samples, ``F = 0`` marked, P(not locking) in the title."""
    from ..analysis.study import failure_probability

    ok = (df["status"] == Status.CONVERGED).to_numpy()
    F = df[column].to_numpy()[ok]
    bins = max(10, min(80, int(np.sqrt(len(F)))))
    edges = np.histogram_bin_edges(F, bins).tolist()   # one set of bins for both sides
    ax.hist(F[F > 0], bins=edges, color="tab:blue", label="locks unaided (F > 0)")
    ax.hist(F[F <= 0], bins=edges, color="tab:red", label="does not (F <= 0)")
    ax.axvline(0.0, color="k", lw=1.5)
    fp = failure_probability(df)
    ax.set_title(f"P(not locking unaided) = {fp.probability:.3g}\n95 % interval [{fp.low:.3g}, {fp.high:.3g}], "
                 f"{fp.samples} samples", fontsize=9)
    ax.set_xlabel(_axis(df, column)[1])
    ax.set_ylabel("samples (count)")
    ax.legend(fontsize=8)
    return ax


def plot_sensitivity(df: pd.DataFrame, ax: Axes, column: str = "downlock_force") -> Axes:
    """Horizontal bars of the standardised regression coefficients, largest on top."""
    from ..analysis.study import sensitivity, study_spec_of

    ranking, r2 = sensitivity(df, list(study_spec_of(df).names), column)
    names = [s.name for s in ranking][::-1]
    src = [s.src for s in ranking][::-1]
    ax.barh(names, src, color=["tab:red" if v < 0 else "tab:blue" for v in src])
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_xlim(-1.05, 1.05)
    ax.set_xlabel(f"standardised regression coefficient on {column} (1)")
    ax.set_ylabel("toleranced parameter (name)")
    ax.set_title(f"sensitivity (linear fit R² = {r2:.3f})", fontsize=9)
    return ax


def plot_study(df: pd.DataFrame, path: str | os.PathLike[str], dpi: int = 120) -> Path:
    """The study's figure (see the module docstring), written atomically to ``path`` (.png/.svg/.pdf)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..analysis.study import study_spec_of
    from .plotting import save_figure

    spec = study_spec_of(df)
    if spec.sampling == "grid" and len(spec.parameters) == 2:
        fig, ax = plt.subplots(figsize=(7, 5))
        plot_response_surface(df, ax)
        ax.set_title(f"{spec.model}: downlock force over the design grid", fontsize=10)
    elif spec.sampling == "grid" and len(spec.parameters) == 1:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        name = spec.names[0]
        f, label = _axis(df, name)
        ok = df["status"] == Status.CONVERGED
        ax.plot(df.loc[ok, name] * f, df.loc[ok, "downlock_force"], "k.-")
        ax.axhline(0.0, color="tab:red", lw=1)
        ax.set_xlabel(label)
        ax.set_ylabel(_axis(df, "downlock_force")[1])
        ax.set_title(f"{spec.model}: downlock force (locks unaided above the red line)", fontsize=10)
    elif spec.sampling != "grid":
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5), width_ratios=(1.4, 1))
        plot_force_histogram(df, a1)
        plot_sensitivity(df, a2)
        fig.suptitle(f"{spec.model}: {spec.size} samples ({spec.sampling})", fontsize=10)
    else:
        from ..errors import InputError

        raise InputError("--plot", f"a grid over {len(spec.parameters)} parameters has no figure; use one or two --grid")
    fig.tight_layout()
    out = save_figure(fig, path, dpi=dpi)
    plt.close(fig)
    return out
