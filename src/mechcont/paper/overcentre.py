"""The paper's overcentre analyses by continuation: Figures 3b, 4a-c and 5a-c.

Every special point is compared with the closed form of the symmetric overcentre
(:mod:`mechcont.models.overcentre`), and the comparison goes into the summary.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..analysis import equilibrium_family
from ..continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium
from ..models import build_overcentre
from ..models.overcentre import symmetric_cusp, symmetric_folds
from ..outputs.plotting import new_figure, plot_branch, plot_surface, save_figure

__all__ = ["run", "compute"]

THETA_BOUNDS = (-1.25, 1.25)


def compute() -> dict:
    """All overcentre results: branches at LU = 0.4 and 2 m, the LU family, the fold curve."""
    system = build_overcentre()
    opts = ContinuationOptions(bounds={"theta1": THETA_BOUNDS})
    out = {"system": system}
    for LU in (0.4, 2.0):
        x0 = find_equilibrium(system, values={"LU": LU}, hold={"theta1": 0.3}, free=["F"])
        out[f"branch_{LU}"] = continuation(system, x0, "F", options=opts)
    x0 = find_equilibrium(system, values={"LU": 0.1}, hold={"theta1": 0.3}, free=["F"])
    out["family"] = equilibrium_family(system, x0, "F", "LU", np.linspace(0.1, 2.0, 14), options=opts,
                                       move_hold=["theta1"], move_free=["F"])
    lower = min(out["family"][0].special("LP"), key=lambda p: p["F"])
    out["folds"] = continue_folds(system, lower, "F", "LU", options=ContinuationOptions(bounds={"LU": (0.1, 2.0)}))
    return out


def _fold_check(branch, LU, p) -> list[str]:
    lines = []
    expected = symmetric_folds(p["L1"], p["m1"], p["m2"], p["g"], p["k"], LU)
    got = sorted(branch.special("LP"), key=lambda q: q["theta1"])
    for q, (th, F) in zip(got, expected):
        lines.append(f"| {LU:g} | LP | {np.degrees(q['theta1']):.6f} | {q['F']:.8f} | "
                     f"{abs(q['F'] - F) / abs(F):.1e} | {abs(q['theta1'] - th) / abs(th):.1e} |")
    return lines


def run(out_dir: Path, quiet: bool = True) -> list[str]:
    """Write Figures 3b, 4a-c, 5a-c (PNG) into ``out_dir``; return summary Markdown lines."""
    out_dir = Path(out_dir)
    r = compute()
    s = r["system"]
    p = s.as_dict(s.defaults())
    b04, b2, fam, folds = r["branch_0.4"], r["branch_2.0"], r["family"], r["folds"]

    fig, ax = new_figure()
    plot_branch(b04, "F", "theta1", ax=ax)
    ax.set_title("Fig. 3b: overcentre, LU = 0.4 m (solid stable, dashed unstable)")
    save_figure(fig, out_dir / "fig3b_overcentre_branch.png")

    fig, ax = new_figure(figsize=(7, 5.5), projection="3d")
    plot_surface(fam, "F", "LU", "theta1", folds=folds, ax=ax)
    ax.view_init(22, -125)
    ax.set_title("Fig. 4a: equilibria over (F, LU) and the fold curve")
    save_figure(fig, out_dir / "fig4a_overcentre_surface.png")

    for tag, b, LU in (("4b", b2, 2.0), ("4c", b04, 0.4)):
        fig, ax = new_figure()
        plot_branch(b, "F", "theta1", ax=ax)
        ax.set_title(f"Fig. {tag}: LU = {LU:g} m")
        save_figure(fig, out_dir / f"fig{tag}_overcentre_LU{LU:g}.png")

    fig, ax = new_figure(figsize=(6.5, 5), projection="3d")
    plot_branch(folds, "LU", "theta1", ax=ax, z="F")
    ax.set_title("Fig. 5a: fold curve in (LU, theta1, F)")
    save_figure(fig, out_dir / "fig5a_fold_curve.png")
    for tag, y in (("5b", "theta1"), ("5c", "F")):
        fig, ax = new_figure()
        plot_branch(folds, "LU", y, ax=ax)
        if y == "F":
            ax.axhline(0.0, color="0.5", lw=0.8)
        ax.set_title(f"Fig. {tag}: fold curve, {y} vs LU")
        save_figure(fig, out_dir / f"fig{tag}_fold_{y}.png")

    lines = ["## Overcentre mechanism (paper Section II, eq. 6)", "",
             f"Parameters (not published in the paper, chosen for its qualitative results): "
             f"L1 = L2 = {p['L1']:g} m, m1 = m2 = {p['m1']:g} kg, k = {p['k']:g} N/m, m = n = 0, g = {p['g']} m/s^2.",
             "", "| LU (m) | point | theta1 (deg) | F (N) | rel. error F vs closed form | rel. error theta1 |",
             "|---|---|---|---|---|---|"]
    lines += _fold_check(b04, 0.4, p)
    for b in fam:
        LU = b["LU"][0]
        if LU in (0.1,) or abs(LU - 1.2) < 0.1:
            lines += _fold_check(b, LU, p)
    (cp,) = folds.special("CP") or [None]
    LUc, thc, Fc = symmetric_cusp(p["L1"], p["m1"], p["m2"], p["g"], p["k"])
    lines += ["", f"- LU = 2 m: {len(b2.special('LP'))} folds, all {len(b2)} points stable: "
                  f"{bool(np.all(b2.stable))} (paper: single stable branch).",
              f"- LU = 0.4 m: {len(b04.special('LP'))} folds (hysteresis loop between "
              f"F = {min(q['F'] for q in b04.special('LP')):.3f} N and {max(q['F'] for q in b04.special('LP')):.3f} N)."]
    if cp is not None:
        lines.append(f"- Cusp (CP) on the fold curve at LU = {cp['LU']:.10f} m, F = {cp['F']:.8f} N, "
                     f"theta1 = {np.degrees(cp['theta1']):.2e} deg (closed form LU = {LUc:g} m, F = {Fc:g} N).")
    lower = folds["theta1"] > 0
    LU0 = float(np.interp(0.0, folds["F"][lower], folds["LU"][lower]))
    lines.append(f"- The lower fold crosses F = 0 at LU = {LU0:.4f} m: for LU above it the mechanism downlocks "
                 "with no applied force (paper: approximately 1.2 m).")
    lines.append("- Figures: fig3b, fig4a-c, fig5a-c (`*.png`).")
    return lines
