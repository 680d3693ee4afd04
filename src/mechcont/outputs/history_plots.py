"""A time history drawn against time, with its stop events marked."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..units import display
from .plotting import axis_label, new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..dynamics import OdeHistory, SimulationResult

__all__ = ["history_figure"]

_EVENT_STYLE = {"impact": ("v", "tab:red"), "contact": ("o", "tab:green"), "release": ("^", "tab:blue")}


def history_figure(result: SimulationResult | OdeHistory, watch: str, *, title: str | None = None) -> Figure:
    """A figure of column ``watch`` of a :class:`~mechcont.dynamics.SimulationResult` (or an ODE's
    :class:`~mechcont.dynamics.OdeHistory`) against time (s);
    angles (rad) shown in degrees; each stop event marked (impact, contact, release)."""
    unit = result.unit(watch)
    y, shown = display(np.asarray(result[watch], dtype=float), unit)
    fig, ax = new_figure(figsize=(7.0, 4.0))
    ax.plot(result.t, y, color="k", lw=1.2)
    seen = set()
    for ev in result.stop_events:
        marker, color = _EVENT_STYLE.get(ev.kind, ("x", "0.4"))
        ax.plot([ev.time], [y[ev.row]], marker=marker, color=color, ls="none",
                label=None if ev.kind in seen else ev.kind)
        seen.add(ev.kind)
    ax.set_xlabel(axis_label("t", "s"))
    ax.set_ylabel(axis_label(watch, shown))
    if seen:
        ax.legend(title="stop events")
    if title:
        ax.set_title(title)
    return fig
