"""Figures of the freefall section: the lock links against their stop over time, for the nose gear at each
airspeed and for the dual-sidestay gear's two lock-link pairs in each run of its table.

A freefall's finding is whether the lock links come to rest *on* their stop, so the figures plot what the stop
decides: the lock links' angle from the stop (deg; 0 on the stop, negative short of it), over the whole run of
every simulation (the time axis covers each run to its end), with a second panel that enlarges the last degrees
before the stop, where a run that fails to lock hovers short of it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.typing import ColorType

    from ..dynamics import SimulationResult
    from ..dynamics.freefall import FreefallResult

__all__ = ["nose_gear_figure", "sidestay_figure"]

#: Colour of a run that does not lock; the locked runs take the ``viridis`` scale in table order.
_FAILED = "tab:red"


def _colours(n: int) -> list[ColorType]:
    from matplotlib import colormaps

    return [colormaps["viridis"](v) for v in np.linspace(0.0, 0.85, max(n, 1))]


def _gap_deg(history: SimulationResult, condition: str, limit: float, sine: bool = False) -> np.ndarray:
    """The lock links' angle from their stop (deg, < 0 short of it) along ``history``: ``condition`` (rad, or the
    sine of the angle with ``sine``) less the stop's ``limit`` (same kind)."""
    v = np.asarray(history[condition], float)
    if sine:
        return np.degrees(np.arcsin(np.clip(v, -1.0, 1.0)) - math.asin(limit))
    return np.degrees(v - limit)


def _panels(title: str, zoom: float, share: bool = True) -> tuple[Figure, Axes, Axes]:
    """A figure with the whole fall above and the last ``zoom`` degrees before the stop below (the same time
    axis with ``share``; else the lower panel's own, to enlarge the strikes)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.2, 6.4), layout="constrained")
    whole, near = fig.subplots(2, 1, sharex=share, height_ratios=(1.0, 1.2))
    for ax in (whole, near):
        ax.axhline(0.0, color="k", lw=1.0, ls=":", label="_stop")
        ax.grid(True, alpha=0.3)
    whole.set_ylabel("lock links from their stop\n(deg; 0 on it, < 0 short of it)")
    near.set_ylabel("the same, enlarged (deg)")
    near.set_ylim(-zoom, 0.15 * zoom)
    for ax in (near,) if share else (whole, near):
        ax.set_xlabel("time since the uplock release (s)")
    fig.suptitle(title)
    return fig, whole, near


def nose_gear_figure(runs: Sequence[tuple[float, FreefallResult]], over: float, path: Path) -> None:
    """The nose gear's freefall runs ``[(U m/s, FreefallResult)]``: the lock links' overcentre angle from their
    stop (``over`` rad past aligned) against time, each run to its end; the runs that do not lock in red. Saved
    to ``path``."""
    from ..outputs.plotting import save_figure

    fig, whole, near = _panels("Nose gear freefall: do the lock links come to rest on their stop?", 1.0)
    colours = iter(_colours(sum(1 for _, r in runs if r.locked)))
    for U, r in runs:
        h = r.history
        gap = _gap_deg(h, "overcentre", over)
        if r.locked:
            colour, lw = next(colours), 1.4
            what = f"locked at {r.time_to_lock:.2f} s"
        else:
            tail = gap[h.t >= h.t[-1] - 0.5]
            colour, lw = _FAILED, 2.2
            what = f"{r.outcome}: {-tail.max():.2f} to {-tail.min():.2f} deg short of the stop at the end"
        label = f"U = {U:g} m/s, {what}"
        whole.plot(h.t, gap, label=label, color=colour, lw=lw)
        near.plot(h.t, gap, label=label, color=colour, lw=lw)
    whole.set_xlim(0.0, max(float(r.history.t[-1]) for _, r in runs))
    near.legend(loc="upper center", bbox_to_anchor=(0.5, -0.28), ncols=2, fontsize=8, frameon=False)
    save_figure(fig, path)


def sidestay_figure(runs: Sequence[tuple[float, float, FreefallResult]], stops: dict[str, tuple[str, float]], path: Path) -> None:
    """The dual-sidestay gear's freefall runs ``[(k_att N/m, stretch, FreefallResult)]``: each lock-link pair's
    angle from its stop (``stops``: ``{pair: (condition, limit)}``, conditions and limits sines of the angle past
    aligned) against time, each run to its end; forward pair solid, aft dashed. Saved to ``path``."""
    from ..outputs.plotting import save_figure

    fig, whole, near = _panels("Dual-sidestay gear freefall: both lock-link pairs onto their stops", 0.5, share=False)
    styles = {pair: ls for pair, ls in zip(stops, ("-", "--"))}
    colours = _colours(len(runs))
    first = min(e.time for _, _, r in runs for e in r.history.stop_events if e.kind == "impact") \
        if any(r.history.stop_events for _, _, r in runs) else 0.0
    for (k, stretch, r), colour in zip(runs, colours):
        h = r.history
        for pair, (condition, limit) in stops.items():
            gap = _gap_deg(h, condition, limit, sine=True)
            label = f"{pair}, k_att = {k:.0e} N/m, stretch {stretch:g} ({r.outcome})"
            whole.plot(h.t, gap, styles[pair], color=colour, lw=1.3, label=label)
            near.plot(h.t, gap, styles[pair], color=colour, lw=1.3, label=label)
    end = max(float(r.history.t[-1]) for _, _, r in runs)
    whole.set_xlim(0.0, end)
    # the strikes and the settling on the stops: from just before the first strike to past the last lock
    last = max((r.time_to_lock for _, _, r in runs if r.time_to_lock is not None), default=end)
    near.set_xlim(max(0.0, first - 0.005), min(end, last + 0.25 * (last - first) + 0.005))
    near.legend(loc="upper center", bbox_to_anchor=(0.5, -0.28), ncols=2, fontsize=7.5, frameon=False)
    save_figure(fig, path)
