"""Figures of a retraction: actuator load and length against the driving angle, lock-up maps."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Protocol

import numpy as np

from .plotting import legend_below, new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..analysis.retraction import ActuatorLoads
    from ..analysis.stops import StopRun
    from ..continuation import Branch

#: A sequence of numbers (SI) as the figures take them: an array or a list.
_Values = np.ndarray | Sequence[float]


class _PairTensions(Protocol):
    """A downlock of the two sidestays: each lock-link pair's tension ``{side: N}`` (the paper's ``DownlockLoads``)."""

    @property
    def tension(self) -> Mapping[str, float]: ...

__all__ = ["plot_actuator_loads", "plot_lock_up", "plot_rigging", "plot_downlock", "plot_fold_curve"]


def plot_actuator_loads(loads: ActuatorLoads, title: str = "retraction actuator") -> Figure:
    """Two panels against the retraction angle (deg): actuator load (kN, + tension) and length (m).

    ``loads`` is an :class:`~mechcont.analysis.retraction.ActuatorLoads`; returns the figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.5, 6.0), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    deg = np.degrees(loads.s)
    ax1.plot(deg, loads.tension / 1e3, color="#6a3d9a", label="actuator load")
    ax1.axhline(0.0, color="0.6", linewidth=0.8)
    ax1.set_ylabel("actuator load (kN, + tension)")
    ax1.set_title(f"{title}: efficiency {loads.efficiency:.3f}, peak {loads.peak / 1e3:.1f} kN")
    ax2.plot(deg, loads.length, color="#1f77b4", label="actuator length")
    ax2.set_ylabel("actuator length (m)")
    ax2.set_xlabel("retraction angle theta (deg)")
    for ax in (ax1, ax2):
        ax.grid(True, linewidth=0.3, alpha=0.5)
    return fig


def plot_lock_up(plane_angles: _Values, lock_angles: _Values, retracted: float, current: float | None = None) -> Figure:
    """Retraction angle (deg) at which the gear locks up against the aft sidestay plane angle (deg).

    ``lock_angles`` holds ``nan`` where the gear retracts fully (to ``retracted``, rad), drawn
    on the dashed full-retraction line; ``current`` marks the default plane angle (rad).
    """
    fig, ax = new_figure((6.5, 4.5))
    phi = np.degrees(np.asarray(plane_angles, float))
    lock = np.degrees(np.asarray(lock_angles, float))
    full = np.isnan(lock)
    ax.plot(phi, lock, "o-", color="#d62728", label="locks up (first fold LP)")   # nan breaks the line
    ax.plot(phi[full], np.full(full.sum(), math.degrees(retracted)), "s", color="#2ca02c", label="retracts fully")
    ax.axhline(math.degrees(retracted), color="0.5", linestyle="--", linewidth=0.8)
    if current is not None:
        ax.axvline(math.degrees(current), color="0.3", linestyle=":", linewidth=1.0, label="default plane angle")
    ax.set_xlabel("aft sidestay plane angle phi_aft (deg)")
    ax.set_ylabel("retraction angle at lock-up (deg)")
    ax.grid(True, linewidth=0.3, alpha=0.5)
    legend_below(fig)
    return fig


def plot_rigging(offsets: _Values, aft_angles: _Values, fwd_angle: float, misfit: _Values) -> Figure:
    """Rigid downlock against rigging error: the aft lock links' misfit (mm) at the forward links' alignment
    and the alignment angles (deg) against the aft attachment offset (mm)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.5, 6.0), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    off = 1e3 * np.asarray(offsets, float)
    ax1.plot(off, 1e3 * np.asarray(misfit, float), "o-", color="#d62728", label="aft links at fwd alignment")
    ax1.axhline(0.0, color="0.6", linewidth=0.8)
    ax1.set_ylabel("aft lock-link misfit (mm, + stretch)")
    ax1.legend(fontsize=8, loc="best")
    ax2.plot(off, np.degrees(aft_angles), "o-", color="#17becf", label="aft links aligned")
    ax2.axhline(math.degrees(fwd_angle), color="#8c564b", linestyle="--", label="fwd links aligned")
    ax2.set_ylabel("retraction angle at alignment (deg)")
    ax2.set_xlabel("aft airframe attachment offset along the stay (mm)")
    ax2.legend(fontsize=8, loc="best")
    for ax in (ax1, ax2):
        ax.grid(True, linewidth=0.3, alpha=0.5)
    return fig


def plot_downlock(offsets: _Values, compliant: Sequence[_PairTensions], rigid: Sequence[_PairTensions], stiffness: float,
                  side_load: float) -> Figure:
    """Lock-link tension (kN) of each pair against the aft attachment offset (mm), compliant (lines) and rigid
    (markers) sidestays; ``compliant``/``rigid`` are lists of ``DownlockLoads``."""
    fig, ax = new_figure((6.5, 4.5))
    off = 1e3 * np.asarray(offsets, float)
    for side, colour in (("fwd", "#8c564b"), ("aft", "#17becf")):
        ax.plot(off, [r.tension[side] / 1e3 for r in compliant], "-", color=colour,
                label=f"{side}, stay stiffness {stiffness:.1e} N/m")
        ax.plot(off, [r.tension[side] / 1e3 for r in rigid], "o", color=colour, markerfacecolor="none",
                label=f"{side}, rigid")
    ax.set_xlabel("aft airframe attachment offset along the stay (mm)")
    ax.set_ylabel("lock-link tension (kN)")
    ax.set_title(f"downlock loads, {side_load / 1e3:.0f} kN side load + gravity", fontsize=10)
    ax.grid(True, linewidth=0.3, alpha=0.5)
    legend_below(fig)
    return fig


def plot_fold_curve(lengths: _Values, angles: _Values, retracted: float, nominal: float, plane_angle: float) -> Figure:
    """Two-parameter fold curve: the lock-up angle (deg) against the aft first lock-link length (m), with the
    gear-up angle and the nominal length marked."""
    fig, ax = new_figure((6.5, 4.5))
    ax.plot(lengths, np.degrees(angles), "-", color="#d62728", label="lock-up fold (LP) curve")
    ax.axhline(math.degrees(retracted), color="0.5", linestyle="--", linewidth=0.8, label="gear up")
    ax.axvline(nominal, color="0.3", linestyle=":", linewidth=1.0, label="nominal length")
    ax.set_xlabel("aft lock link K-J length aft_L4 (m)")
    ax.set_ylabel("retraction angle at lock-up (deg)")
    ax.set_title(f"aft sidestay plane angle {math.degrees(plane_angle):.1f} deg", fontsize=10)
    ax.grid(True, linewidth=0.3, alpha=0.5)
    ax.legend(fontsize=8, loc="best")
    return fig


def plot_unlock_with_stops(runs: Mapping[str, StopRun], fold_curve: Branch | None = None,
                           labels: Mapping[str, str] | None = None) -> Figure:
    """Unlock with overcentre stops: (left) each unlock force (N) against its lock links' angle from
    aligned (deg, + overcentre), releases (SR) and unlock folds (LP) marked; (right) the unlock fold of
    both pairs together against the lock-spring stretch, cusps (CP) marked. ``runs`` maps the force name
    to its :class:`~mechcont.analysis.StopRun`; ``labels`` names each curve."""
    fig, ax = new_figure((11.5, 4.5) if fold_curve is not None else (6.5, 4.5))
    if fold_curve is not None:
        ax.remove()
        axes = fig.subplots(1, 2)
        ax = axes[0]
    colors = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
    marks = {"SR": ("s", "SR: a pair leaves its stop (open square)"), "LP": ("o", "LP: the links snap through (dot)")}
    named: set[str] = set()
    for (force, run), c in zip(runs.items(), colors):
        b = run.branch
        F = b.values[:, b.names.index(force)]
        side = "aft" if force == "F_aft" else "fwd"
        psi = np.degrees(np.arcsin(np.clip(b.values[:, b.names.index(f"{side}_lock")], -1, 1)))
        ax.plot(psi, F, "-", color=c, label=(labels or {}).get(force, force) + f" ({side} links' angle)")
        for p in b.special_points:   # named once in the legend (labels beside them ran into each other)
            if p.label in marks:
                marker, what = marks[p.label]
                ax.plot(np.degrees(np.arcsin(p[f"{side}_lock"])), p[force], marker, color=c, markersize=5,
                        markerfacecolor="white" if p.label == "SR" else c, label=None if p.label in named else what)
                named.add(p.label)
    ax.axvline(0.0, color="0.5", linestyle=":", linewidth=0.8)
    ax.set_xlabel("lock links' angle from aligned (deg, + overcentre)")
    ax.set_ylabel("unlock force (N)")
    ax.set_title("unlock with overcentre stops", fontsize=10)
    ax.grid(True, linewidth=0.3, alpha=0.5)
    if fold_curve is not None:
        ax = axes[1]
        b = fold_curve
        ax.plot(b.values[:, b.names.index("stretch")], b.values[:, b.names.index("F_lock")], "-", color="#2ca02c",
                label="folds (LP) of the unlock branch, both pairs")
        for p in b.special_points:
            if p.label == "CP":
                ax.plot(p["stretch"], p["F_lock"], "k*", markersize=9, label="cusp (CP)")
        ax.set_xlabel("lock-spring stretch, free over installed length (1)")
        ax.set_ylabel("unlock force, both pairs (N)")
        ax.set_title("two-parameter fold curve", fontsize=10)
        ax.grid(True, linewidth=0.3, alpha=0.5)
    legend_below(fig)
    return fig
