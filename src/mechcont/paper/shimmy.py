"""Nose-gear shimmy (after Thota, Krauskopf & Lowenberg 2009): the model and what needs no Hopf point.

The gear is ``examples/shimmy.toml`` (top view: torsion about the strut with a shimmy damper, the
strut's lateral bending as a sprung lateral slider, a caster and a saturating stretched-string tyre;
its parameters ``V`` (m/s), ``e`` (m) and ``c_psi`` (N m s/rad) are the design study's). This module
gives (the gear and its eigenvalues in :mod:`._shimmy_gear`, which the section's computations import)

* :func:`shimmy_mechanism`, :func:`gear_at`: the description, and the gear running straight at a
  speed (the equilibrium: the tyre at its steady state, no deflection);
* :func:`leading_eigenvalue`: the eigenvalue of the linearised dynamics with the largest real part
  at that equilibrium (1/s; shimmy when positive, its imaginary part the shimmy frequency);
* :func:`onset_speed`: the lowest speed in a range where the straight running loses stability, by
  bisection on the leading real part: an independent check of a Hopf point found by continuation
  (one linearisation per step: slow beside a Hopf curve, fine for a few points);
* :func:`stability_grid`: the leading real part over a grid of speed and one parameter, the
  brute-force chart to compare the Hopf curves with.

* :func:`run`: the ``mechcont paper`` shimmy section (in the default run; ``--only shimmy`` alone): the
  equilibrium branch in speed with its Hopf point, the Hopf curves over (speed, damper rate) and
  (speed, caster) with a brute-force check, the limit cycles against speed with their Floquet
  stability, two time simulations landing on them, the figures and the summary paragraph
  (computations in :mod:`._shimmy_analysis`, figures and words in :mod:`._shimmy_figures`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._shimmy_gear import (
    DAMPER_RATES,
    EXAMPLE,
    SPEEDS,
    gear_at,
    leading_eigenvalue,
    onset_speed,
    shimmy_mechanism,
    stability_grid,
)

__all__ = ["EXAMPLE", "SPEEDS", "DAMPER_RATES", "shimmy_mechanism", "gear_at", "leading_eigenvalue", "onset_speed",
           "stability_grid", "run"]

#: Points per axis of the coarse brute-force grid drawn under each stability chart (a check, not the chart).
CHECK_GRID = 10


def run(out_dir: Path, quiet: bool = True, timings: dict | None = None) -> list[str]:
    """Write the shimmy figures into ``out_dir``; return the summary's Markdown lines (run times into ``timings``)."""
    from . import _shimmy_analysis as an
    from . import _shimmy_figures as fg
    from ._timing import timed

    timings = {} if timings is None else timings
    out_dir = Path(out_dir)
    mech = shimmy_mechanism()
    with timed(timings, "shimmy: equilibria in speed, Hopf point"):
        model, x = gear_at(SPEEDS[0], mech)
        branch = an.equilibria(model, x)
        hopf = next(p for p in branch.special_points if p.label == "HB")
    design = {n: float(hopf[n]) for n in ("V", "c_psi", "e")}
    curves, grids, checks = {}, {}, {}
    for param in an.CHART:
        with timed(timings, f"shimmy: Hopf curve in speed and {param}"):
            curves[param] = an.hopf_curve(model, hopf, param)
        with timed(timings, f"shimmy: check of the {param} chart ({CHECK_GRID}^2 eigenvalue grid, curve points)"):
            speeds = np.linspace(SPEEDS[0], SPEEDS[1], CHECK_GRID)
            values = np.linspace(*an.CHART[param], CHECK_GRID)
            grids[param] = (speeds, values, stability_grid(speeds, param, values, mech))
            checks[param] = an.curve_check(model, curves[param], param, mech)
    with timed(timings, "shimmy: limit cycles from HB1"):
        cycles = an.shimmy_cycles(model, hopf)
    with timed(timings, "shimmy: time simulations onto the cycles"):
        sims = [an.simulate_onto(v, mech) for v in an.SIM_SPEEDS]
    fg.chart_figure(curves, grids, design, out_dir / "shimmy_stability_chart.png")
    fg.amplitude_diagram(branch, design["V"], cycles, sims, out_dir / "shimmy_amplitude.png")
    onset = onset_speed(mech)
    lines = ["## Nose-gear shimmy (after Thota, Krauskopf & Lowenberg 2009)", "",
             *fg.finding(hopf, curves, grids, cycles, sims, SPEEDS[1], design),
             f"- Checks: HB1 at {design['V']:.6f} m/s, by bisection of the leading eigenvalue "
             f"{onset:.6f} m/s; along the Hopf curves the leading eigenvalue's |Re|/|Im| computed afresh is at most "
             + ", ".join(f"{checks[p]:.1e} ({p})" for p in an.CHART) + ".",
             "",
             "![shimmy stability charts: Hopf curves hatched into the stable side, over a coarse eigenvalue grid]"
             "(shimmy_stability_chart.png)", "",
             "![torsion amplitude of the shimmy cycles against speed](shimmy_amplitude.png)", ""]
    return lines
