"""The figures of the paper's nose-gear section (:mod:`mechcont.paper.nose_gear`): Figs. 7–11 and the design
region, each drawn from the section's results (:class:`~mechcont.paper.nose_gear.NoseGearResults`)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from ._nose_gear_settings import FIG7_RATE, L_SP1_RANGE, LU_RANGE, MISRIG

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    from ..continuation import Branch
    from ..dynamics import SweepResult
    from .nose_gear import NoseGearResults

__all__ = ["_plot_all"]

T = TypeVar("T")


def _done(value: T | None, what: str) -> T:
    """``value``, a result :func:`~.nose_gear.run` computed (its field ``what``); RuntimeError when it was not run."""
    if value is None:
        raise RuntimeError(f"the nose-gear results have no {what}: run() computes it")
    return value


def _save(fig: Figure, path: Path) -> None:
    from ..outputs.plotting import save_figure

    save_figure(fig, path)


def _oc_curve(branch_or_sweep: Branch | SweepResult, dense: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """(F, overcentre angle in deg) along a branch (smooth, with per-sample stability) or a sweep."""
    from ..continuation import Branch
    from ..models.nose_gear import overcentre_angle
    from ..outputs.plotting import curve

    if not dense or not isinstance(branch_or_sweep, Branch):  # a sweep's samples are drawn as they are
        return branch_or_sweep["F"], np.degrees(overcentre_angle(branch_or_sweep["theta4"], branch_or_sweep["theta5"]))
    F, t4, t5, _ = curve(branch_or_sweep, "F", "theta4", "theta5")
    return F, np.degrees(overcentre_angle(np.radians(t4), np.radians(t5)))


def _line(ax: Axes, branch: Branch, x: str, y: str, *args: str, **kw: Any) -> list[Line2D]:
    """``y`` against ``x`` along ``branch`` as a smooth curve through the continuation's points."""
    from ..outputs.plotting import curve

    xs, ys, _ = curve(branch, x, y)
    return ax.plot(xs, ys, *args, **kw)


def _unit(res: NoseGearResults, name: str) -> str:
    return _done(res.system, "system").variable(name).unit


def _lab(res: NoseGearResults, name: str, what: str = "") -> str:
    """An axis label: ``what`` then the name with its display unit."""
    from ..outputs.plotting import axis_label

    return f"{what} {axis_label(name, _unit(res, name))}".strip()


def _plot_all(res: NoseGearResults, out_dir: Path) -> list[Path]:
    """Figs. 7-11 of the paper and the design map, each a PNG in ``out_dir``; their paths."""
    return [f(res, out_dir) for f in (_plot_fig7, _plot_fig8, _plot_fig9, _plot_fig10, _plot_fig11, _plot_design)]


def _plot_fig7(res: NoseGearResults, out_dir: Path) -> Path:
    """Fig. 7: the continuation (black) over the slow time simulation (light grey), as in the paper."""
    from matplotlib.figure import Figure

    from ..outputs.plotting import interval_states
    fig = Figure(figsize=(5.8, 4.2), layout="constrained")
    ax = fig.add_subplot()
    if res.fig7_sweep is not None:
        ax.plot(*_oc_curve(res.fig7_sweep, dense=False), color="0.75", lw=4,
                label=f"time simulation (F ramped at {FIG7_RATE:g} N/s)")
    b = _done(res.fig7_branch, "fig7_branch")
    F, oc = _oc_curve(b)
    states = np.repeat(interval_states(b), (len(F) - 1) // max(len(b) - 1, 1))
    for state, style, word in ((0, "-", "stable"), (1, "--", "unstable")):
        if np.any(states == state):
            mask = np.append(states == state, states[-1] == state)
            ax.plot(np.where(mask, F, np.nan), np.where(mask, oc, np.nan), "k" + style, label=f"continuation ({word})")
    ax.axhline(180.0, color="0.5", lw=0.6)
    ax.set_xlabel("applied force F (N)")
    ax.set_ylabel("overcentre angle (deg)")
    ax.set_title("Fig. 7: no spring, no airflow")
    ax.legend(fontsize=8, loc="upper left")
    path = out_dir / "nose_gear_fig7.png"
    _save(fig, path)
    return path


def _plot_fig8(res: NoseGearResults, out_dir: Path) -> Path:
    """Fig. 8: the change of the downlock force with the airspeed, aligned and mis-rigged."""
    from matplotlib.figure import Figure

    from ..outputs.plotting import curve
    fig = Figure(figsize=(5.8, 4.2), layout="constrained")
    ax = fig.add_subplot()
    for br, text in ((_done(res.fig8_aligned, "fig8_aligned"), "aligned at theta4 = 0 (default rig)"),
                     (_done(res.fig8_misrigged, "fig8_misrigged"), f"lug {abs(MISRIG) * 1e3:.1f} mm short of aligned")):
        U, Fb, _ = curve(br, "U", "F")
        ax.plot(U, Fb - br["F"][np.argmin(br["U"])], label=text)
    ax.set_xlabel(_lab(res, "U", "airspeed"))
    ax.set_ylabel("change of downlock force F (N)")
    ax.set_title("Fig. 8: effect of airflow")
    ax.legend(fontsize=8)
    path = out_dir / "nose_gear_fig8.png"
    _save(fig, path)
    return path


def _plot_fig9(res: NoseGearResults, out_dir: Path) -> Path:
    """Fig. 9: the downlock force against the spring length and stiffness."""
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    from ..outputs.plotting import curve
    fig = Figure(figsize=(9, 3.8), layout="constrained")
    axs = fig.subplots(1, 2)
    _line(axs[0], _done(res.fig9_LU, "fig9_LU"), "LU", "F", "k-")
    axs[0].set_xlabel(_lab(res, "LU", "unstrained spring length"))
    kk = _done(res.fig9_k, "fig9_k")
    kx, kF, _ = curve(kk, "k", "F")
    axs[1].plot(kx / 1e3, kF, "k-")
    axs[1].set_xlabel("spring stiffness k (kN/m)")
    for a in axs:
        a.set_ylabel("downlock force F (N)")
        a.axhline(0, color="0.6", lw=0.6)
        a.xaxis.set_major_locator(MaxNLocator(5))
    fig.suptitle("Fig. 9: spring properties")
    path = out_dir / "nose_gear_fig9.png"
    _save(fig, path)
    return path


def _plot_fig10(res: NoseGearResults, out_dir: Path) -> Path:
    """Fig. 10: the downlock force against the spring attachment, its extremum marked."""
    from matplotlib.figure import Figure

    from ..outputs.plotting import label_point
    fig = Figure(figsize=(5.8, 4.2), layout="constrained")
    ax = fig.add_subplot()
    fig10 = _done(res.fig10, "fig10")
    _line(ax, fig10, "l_sp1", "F", "k-")
    box = (*L_SP1_RANGE, float(fig10["F"].min()), float(fig10["F"].max()))
    for p in _done(res.fig11_force_branch, "fig11_force_branch").special("LP"):
        ax.plot(p["l_sp1"], p["F"], "o", color="darkorange")
        label_point(ax, p["l_sp1"], p["F"], f"extremum {p['F']:.1f} N", box, color="darkorange")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.set_xlabel("spring attachment l_sp1 (m, + towards the knee)")
    ax.set_ylabel("downlock force F (N)")
    ax.set_title("Fig. 10: spring attachment (LU = 1.3 m)")
    path = out_dir / "nose_gear_fig10.png"
    _save(fig, path)
    return path


def _plot_fig11(res: NoseGearResults, out_dir: Path) -> Path:
    """Fig. 11: the surface of equilibria, the LU = 1.3 m curve and the fold locus, in 3-D and three projections."""
    from matplotlib.figure import Figure

    from ..outputs.plotting import curve
    fig = Figure(figsize=(10, 8), layout="constrained")
    ax3 = fig.add_subplot(2, 2, 1, projection="3d")
    LU_, Fm = [], []
    grid = np.linspace(*L_SP1_RANGE, 60)
    for br in res.fig11_surface:
        xs, Fs, _ = curve(br, "l_sp1", "F")
        o = np.argsort(xs)
        Fm.append(np.interp(grid, xs[o], Fs[o]))
        LU_.append(br["LU"][0])
    G, Y = np.meshgrid(grid, LU_)
    ax3.computed_zorder = False
    # every grid cell its own quadrilateral: with the default strides (50 rows and columns of a 60-column grid) the
    # edge faces had more vertices than the others, and Matplotlib pads such ragged faces with uninitialised
    # memory, whose projection overflowed (a RuntimeWarning on some runs)
    ax3.plot_surface(G, Y, np.array(Fm), color="0.8", alpha=0.6, linewidth=0, zorder=1, rstride=1, cstride=1)
    hi = _done(res.fig10, "fig10")
    fc = res.fig11_fold_curve
    hx, hy, hz, _ = curve(hi, "l_sp1", "LU", "F")
    ax3.plot(hx, hy, hz, "k-", lw=2, zorder=3)
    if fc is not None:
        fx, fy, fz, _ = curve(fc, "l_sp1", "LU", "F")
        ax3.plot(fx, fy, fz, color="0.3", lw=2.5, zorder=4)
    ax3.set_xlabel(_lab(res, "l_sp1"))
    ax3.set_ylabel(_lab(res, "LU"))
    ax3.set_zlabel(_lab(res, "F"))
    ax3.set_title("(a) surface of equilibria, LU = 1.3 m curve, fold locus", fontsize=10)
    projections = [("l_sp1", "F", "(b) F vs l_sp1"), ("LU", "F", "(c) F vs LU"), ("l_sp1", "LU", "(d) LU vs l_sp1")]
    for k, (xn, yn, title) in enumerate(projections):
        _plot_fig11_projection(fig.add_subplot(2, 2, k + 2), res, xn, yn, title, hi, fc)
    entries: dict[str, object] = {}   # one legend for the panels, below them: in a panel it hid the surface's curves
    for ax in fig.axes[1:]:
        for handle, text in zip(*ax.get_legend_handles_labels()):
            entries.setdefault(text, handle)
    fig.legend(handles=list(entries.values()), labels=list(entries), loc="outside lower center", ncols=len(entries),
               fontsize=9, frameon=False)
    fig.suptitle("Fig. 11: limit points of F with respect to l_sp1, continued in LU")
    path = out_dir / "nose_gear_fig11.png"
    _save(fig, path)
    return path


def _plot_fig11_projection(ax: Axes, res: NoseGearResults, xn: str, yn: str, title: str, hi: Branch,
                           fc: Branch | None) -> None:
    """One projection of Fig. 11 (``yn`` against ``xn``): the LU = 1.3 m curve ``hi``, the fold locus
    ``fc`` with its cusp and, in the (l_sp1, F) plane, the surface's curves."""
    from ..outputs.plotting import label_point

    if (xn, yn) == ("l_sp1", "F"):
        for j, br in enumerate(res.fig11_surface):
            _line(ax, br, "l_sp1", "F", color="0.82", lw=0.8,
                  label=f"LU = {LU_RANGE[0]:g}..{LU_RANGE[1]:g} m (surface)" if j == 0 else None)
    _line(ax, hi, xn, yn, "k-", lw=2, label="LU = 1.3 m")
    xs_all, ys_all = [hi[xn]], [hi[yn]]
    if fc is not None:
        _line(ax, fc, xn, yn, color="0.3", lw=2.5, label="fold locus")
        xs_all.append(fc[xn])
        ys_all.append(fc[yn])
    if (xn, yn) == ("l_sp1", "F"):
        xs_all += [br["l_sp1"] for br in res.fig11_surface]
        ys_all += [br["F"] for br in res.fig11_surface]
    xa, ya = np.concatenate(xs_all), np.concatenate(ys_all)
    box = (float(xa.min()), float(xa.max()), float(ya.min()), float(ya.max()))
    if fc is not None:
        for p in fc.special("CP"):
            ax.plot(p[xn], p[yn], "o", color="tab:green")
            if (xn, yn) == ("LU", "F"):  # at the top-left corner, where both fold branches leave to the right
                ax.set_ylim(None, box[3] + 0.12 * (box[3] - box[2]))
                ax.annotate("CP (cusp)", (p[xn], p[yn]), textcoords="offset points", xytext=(8, 4),
                            fontsize=8, color="tab:green")
            else:
                label_point(ax, p[xn], p[yn], "CP (cusp)", box, color="tab:green")
    ax.set_xlabel(_lab(res, xn))
    ax.set_ylabel(_lab(res, yn))
    ax.set_title(title, fontsize=10)


def _plot_design(res: NoseGearResults, out_dir: Path) -> Path:
    """The design map: where the gear locks unaided (F > 0)."""
    path = out_dir / "nose_gear_design.png"
    _save(design_map_figure(res), path)
    return path


def design_map_figure(res: NoseGearResults) -> Figure:
    """The nose gear's design map of the results ``res`` (:func:`~mechcont.paper.nose_gear.compute`): where the
    gear locks unaided (F > 0). Returns the figure."""
    from matplotlib.figure import Figure

    from ..outputs.plotting import plot_design_region

    fig = Figure(figsize=(6.8, 4.6), layout="constrained")
    ax = fig.add_subplot()
    plot_design_region(_done(res.region, "region"), ax)
    ax.set_title("Design: where the gear locks unaided (F > 0)")
    return fig
