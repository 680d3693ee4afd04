"""Figures of families of periodic orbits: amplitude diagrams, phase portraits, the animation of one period.

The amplitude diagram draws, against the continuation parameter, the largest and the smallest value
of one state over each orbit (stable orbits solid, unstable dashed), with the labelled orbits
(``LPC``, ``PD``, ``NS``, ``UZ``) marked, over the equilibrium branch the family was born on when it
is given. Values are in SI units (angles in degrees, as in every diagram of mechcont).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..units import display
from .plotting import axis_label, label_point, legend_below, new_figure, plot_branch

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..continuation import Branch, CycleBranch
    from ..equations import Dynamics, Model

__all__ = ["plot_amplitude", "amplitude_figure", "phase_portrait", "animate_cycle"]

_MARKERS = {"LPC": ("o", "tab:red"), "PD": ("s", "tab:purple"), "NS": ("D", "tab:green"), "UZ": ("^", "tab:orange"),
            "HB": ("*", "tab:blue"), "EP": ("x", "0.4")}
#: What each marker means, in the legend.
_MEANING = {"LPC": "LPC: fold of the cycles", "PD": "PD: period doubling", "NS": "NS: torus (Neimark-Sacker)",
            "UZ": "UZ: orbit at a requested value", "HB": "HB: Hopf point (amplitude 0)",
            "EP": "EP: end of the computed family"}


def _shown(values: np.ndarray | Sequence[float], unit: str) -> np.ndarray:
    """``values`` (SI) as drawn: an angle (``rad``) in degrees."""
    return display(np.asarray(values, float), unit)[0] if unit == "rad" else np.asarray(values, float)


def _state(cycles: CycleBranch, state: str | None) -> int:
    """The index of ``state`` among the cycles' states (the first for None); :class:`InputError` naming them."""
    if state is None:
        return 0
    if state not in cycles.state_names:
        raise InputError("state", f"'{state}' is not a state of the cycles; states: {', '.join(cycles.state_names)}")
    return cycles.state_names.index(state)


def plot_amplitude(cycles: CycleBranch, state: str | None = None, ax: Axes | None = None, *, branch: Branch | None = None,
                   color: str = "tab:blue") -> Axes:
    """Draw the max and min of ``state`` (default: the first) over each orbit of ``cycles`` (a
    :class:`~mechcont.continuation.CycleBranch`) against its parameter, stable solid and unstable dashed,
    labelled orbits marked (each kind named in the legend); ``branch``: the equilibrium
    :class:`~mechcont.continuation.Branch` drawn beneath, stable solid and unstable dashed by its dynamic
    stability where it has the column ``n_unstable_dynamic`` (``continue --dynamic``,
    :func:`~mechcont.analysis.with_dynamic_stability`: a cycle is born where the equilibria lose *dynamic*
    stability, which the static judgement of a mechanism does not see), else as it has it. No legend: the caller
    adds it (:func:`~mechcont.outputs.plotting.legend_below`, below the axes, where it hides nothing). Returns
    the axes."""
    if ax is None:
        _, ax = new_figure()
    k = _state(cycles, state)
    name, unit = cycles.state_names[k], cycles.state_units[k]
    if branch is not None:
        if "n_unstable_dynamic" in branch.names:
            branch = branch.replace(n_unstable=branch.column("n_unstable_dynamic").astype(int))
        plot_branch(branch, cycles.vary, name, ax=ax, color="k", label="equilibria", lw=1.2, endpoints=False,
                    stability_legend=True)
    p = _shown(cycles.p, cycles.vary_unit)
    # the interval between rows i and i + 1 is drawn in the style of the orbit it reaches
    states = cycles.stable[1:] if len(p) > 1 else cycles.stable
    drawn: set[bool] = set()
    for ys in (cycles.maximum[:, k], cycles.minimum[:, k]):
        y = _shown(ys, unit)
        start = 0
        for i in range(1, len(states) + 1):
            if i == len(states) or states[i] != states[start]:
                st = bool(states[start])
                lab = None if st in drawn else ("cycles, stable" if st else "cycles, unstable")
                drawn.add(st)
                ax.plot(p[start:i + 1], y[start:i + 1], "-" if st else "--", color=color, lw=1.6, label=lab)
                start = i
    ymax, ymin = _shown(cycles.maximum[:, k], unit), _shown(cycles.minimum[:, k], unit)
    box = (float(p.min()), float(p.max()), float(ymin.min()), float(ymax.max()))
    named: set[str] = set()
    for pname, i in cycles.point_names():
        lab = cycles.labels[i]
        marker, mc = _MARKERS.get(lab, ("*", "tab:blue"))
        meaning = None if lab in named else _MEANING.get(lab, lab)
        named.add(lab)
        for y, name_it in ((ymax[i], meaning), (ymin[i], None)):
            ax.plot([p[i]], [y], marker, color=mc, ms=6, mew=1.5, mfc="none" if lab != "EP" else mc, label=name_it)
        if lab not in ("EP", "HB"):
            label_point(ax, float(p[i]), float(ymax[i]), pname + ("?" if i in cycles.approximate else ""), box, color=mc)
    ax.set_xlabel(axis_label(cycles.vary, cycles.vary_unit))
    ax.set_ylabel(axis_label(name, unit) + ": max and min over the orbit")
    ax.grid(True, alpha=0.3)
    return ax


def amplitude_figure(cycles: CycleBranch, state: str | None = None, *, branch: Branch | None = None,
                     title: str | None = None) -> Figure:
    """A new figure of :func:`plot_amplitude`, titled ``title``."""
    fig, ax = new_figure()
    plot_amplitude(cycles, state, ax=ax, branch=branch)
    if title:
        ax.set_title(title)
    legend_below(fig, ncols=2)
    return fig


def phase_portrait(cycles: CycleBranch, rows: Sequence[int] | None = None, states: tuple[str, str] | None = None,
                   ax: Axes | None = None) -> Axes:
    """Draw the orbits of ``rows`` (default: up to 8 spread along the family, labelled ones first) in the plane of
    two ``states`` (default: the first two), each closed over one period; stable solid, unstable dashed."""
    if ax is None:
        _, ax = new_figure()
    if len(cycles.state_names) < 2 and states is None:
        raise InputError("states", "a phase portrait needs two states; this system has one")
    a, b = (cycles.state_names[0], cycles.state_names[1]) if states is None else states
    ka, kb = _state(cycles, a), _state(cycles, b)
    if rows is None:
        labelled = [i for _, i in cycles.point_names() if cycles.labels[i] not in ("HB",)]
        spread = list(np.unique(np.linspace(1 if len(cycles) > 1 else 0, len(cycles) - 1, 8).astype(int)))
        rows = sorted(set(labelled + spread))[:12]
    import matplotlib as mpl

    cmap = mpl.colormaps["viridis"]
    for n, i in enumerate(rows):
        _, Z = cycles.orbit(int(i), 200)
        ax.plot(_shown(Z[:, ka], cycles.state_units[ka]), _shown(Z[:, kb], cycles.state_units[kb]),
                "-" if cycles.stable[i] else "--", color=cmap(n / max(len(rows) - 1, 1)), lw=1.2,
                label=f"{cycles.vary} = {cycles.p[i]:.4g}, T = {cycles.period[i]:.4g} s")
    ax.set_xlabel(axis_label(a, cycles.state_units[ka]))
    ax.set_ylabel(axis_label(b, cycles.state_units[kb]))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=7)
    return ax


def animate_cycle(system: Model, dynamics: Dynamics, cycles: CycleBranch, row: int, path: str | os.PathLike, *,
                  frames: int = 48, fps: float | None = None, **kwargs: Any) -> int:
    """Animate one period of the orbit of ``row`` of ``cycles`` on the model's drawing (``system`` with a
    scene; ``dynamics`` its :class:`~mechcont.equations.Dynamics`, whose ``full_vector`` gives each frame's
    variables): ``frames`` instants equally spaced in time. Writes ``path`` (.gif, .mp4, .html) through
    :func:`~mechcont.outputs.animation.animate` (``kwargs`` passed on); returns the number of frames."""
    from .animation import animate

    if not 0 <= row < len(cycles):
        raise InputError("row", f"row {row} out of range; the family has {len(cycles)} orbits (0..{len(cycles) - 1})")
    _, rows = cycles.full_vectors(dynamics, row, frames)
    vary = cycles.vary if cycles.vary in system.names else None
    return animate(system, rows[:-1], path, fps=fps, vary=vary, **kwargs)
