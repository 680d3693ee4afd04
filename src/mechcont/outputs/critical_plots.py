"""The critical airspeed of a freefall drawn against damping (a figure; the numbers are
:func:`mechcont.dynamics.freefall.critical_airspeed`'s)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["critical_figure"]


def critical_figure(dampings: Sequence[float], brackets: Sequence, quasi_static: float | Sequence[float], *,
                    damping_label: str = "damping", airspeed_label: str = "critical airspeed (m/s)", title: str = "") -> Figure:
    """Dynamic critical airspeed against damping, with the quasi-static prediction as a line.

    ``brackets``: per damping a :class:`CriticalAirspeed` or a pair ``(locked, failed)`` (values run): each
    drawn as its locking end with a bar to the failing end; ``quasi_static``: one value (a horizontal line) or
    one per damping (a scanned parameter the statics depend on: a line through them). Returns a Matplotlib figure (save it with
    :func:`mechcont.outputs.plotting.save_figure`)."""
    import matplotlib.pyplot as plt

    from ..dynamics.freefall import CriticalAirspeed

    pairs = np.array([(b.locked, b.failed) if isinstance(b, CriticalAirspeed) else tuple(b) for b in brackets],
                     float).reshape(-1, 2)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(dampings, pairs[:, 0], "o-", label="dynamic: largest run that locked (bisection on time simulations)")
    ax.vlines(dampings, pairs.min(axis=1), pairs.max(axis=1), color="C0", lw=3, alpha=0.4,
              label="bracket to the run that did not lock")
    qs = np.atleast_1d(np.asarray(quasi_static, dtype=float))
    if len(qs) > 1 and not np.allclose(qs, qs[0], rtol=1e-9, atol=0.0):
        ax.plot(dampings, qs, "k--", label="quasi-static (fold of the stall branch)")
    else:
        ax.axhline(float(qs[0]), color="k", ls="--", label="quasi-static (fold of the stall branch)")
    ax.set_xlabel(damping_label)
    ax.set_ylabel(airspeed_label)
    if all(d > 0 for d in dampings) and max(dampings) / min(dampings) > 20:
        ax.set_xscale("log")
    ax.legend()
    ax.set_title(title)
    fig.tight_layout()
    return fig
