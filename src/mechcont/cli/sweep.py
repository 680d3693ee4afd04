"""``mechcont sweep``: a quasi-static sweep (time simulation with slowly ramped loads)."""

from __future__ import annotations

import sys

import click

from ..errors import InputError
from ._app import cli
from ._parse import assignments, number


def _ramps(items) -> list[tuple[str, float, float, float]]:
    """``["F=60:-90:2"]`` -> ``[("F", 60.0, -90.0, 2.0)]``."""
    out = []
    for item in items:
        name, sep, spec = item.partition("=")
        name = name.strip()
        parts = spec.split(":")
        if not sep or not name or len(parts) != 3:
            raise InputError("--ramp", f"'{item}' is not NAME=FROM:TO:RATE")
        a, b, r = (number(p.strip(), f"--ramp {name}") for p in parts)
        out.append((name, a, b, r))
    if not out:
        raise InputError("--ramp", "give at least one NAME=FROM:TO:RATE")
    return out


@cli.command("sweep")
@click.argument("model")
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE", help="Override a parameter (SI units).")
@click.option("--start", "starts", multiple=True, metavar="NAME=VALUE",
              help="Starting coordinate, held while the mechanism is assembled (e.g. theta1=1.2).")
@click.option("--ramp", "ramps", multiple=True, metavar="NAME=FROM:TO:RATE",
              help="A sweep segment: NAME from FROM to TO at RATE units/s (repeat for more, in order).")
@click.option("--watch", required=True, help="Coordinate whose jumps are detected (e.g. theta1).")
@click.option("--damping", default=0.0, show_default=True, help="Mass-proportional damping (1/s).")
@click.option("--settle", default=0.0, show_default=True, help="Seconds at the initial loads before ramping.")
@click.option("--equilibrium/--no-equilibrium", default=True, show_default=True,
              help="Start from the equilibrium nearest the start configuration (Newton), else as assembled.")
@click.option("--through", type=float, default=None, help="Time jumps where WATCH passes this value.")
@click.option("--rtol", default=1e-6, show_default=True, help="Integrator relative tolerance.")
@click.option("--out", default=None, metavar="FILE.csv", help="Write the time history as CSV.")
@click.option("--plot", default=None, metavar="FILE.png", help="Plot WATCH against the ramped parameter.")
@click.option("--quiet", is_flag=True, help="No progress bar.")
def sweep_command(model, settings, starts, ramps, watch, damping, settle, equilibrium, through, rtol, out, plot,
                  quiet):
    """Ramp loads of MODEL slowly in a time simulation and report where WATCH jumps.

    Example: mechcont sweep overcentre --set LU=0.4 --set c=50 --start theta1=1.2
    --ramp F=-65:-90:0.5 --ramp F=-90:110:2 --watch theta1
    """
    from .._io import check_output_path
    from ..dynamics import assemble, parse_ramps, sweep
    from ..models import load_model
    from ..outputs.plotting import FIGURE_SUFFIXES

    out_path = check_output_path(out, "--out", (".csv",))
    plot_path = check_output_path(plot, "--plot", FIGURE_SUFFIXES)
    segs = parse_ramps(_ramps(ramps))
    system = load_model(model, **assignments(settings, "set"))
    start = assignments(starts, "start")
    values = dict(start)
    for r in segs:  # each ramped parameter begins at its first segment's start value
        values.setdefault(r.name, r.start)
    if system.mechanics is None:
        raise InputError("model", f"'{model}' has no mechanics (masses, forces): it cannot be simulated")
    try:
        x0 = assemble(system, values, hold=[n for n in start if n in system.names])
    except InputError as exc:
        if exc.field != "x0":
            raise
        raise InputError("--start", str(exc).split(": ", 1)[1]) from None
    if equilibrium:
        from ..continuation import find_equilibrium

        x0 = find_equilibrium(system, values={n: x0[system.index(n)] for n in system.parameter_names}, guess=x0)
    total = settle + sum(r.duration for r in segs)
    if quiet or not sys.stderr.isatty():
        result = sweep(system, x0, segs, watch=watch, damping=damping, settle=settle, through=through, rtol=rtol)
    else:
        with click.progressbar(length=1000, label="sweep", file=sys.stderr) as bar:
            state = {"done": 0}

            def progress(t):
                k = min(1000, int(1000 * t / total))
                if k > state["done"]:
                    bar.update(k - state["done"])
                    state["done"] = k

            result = sweep(system, x0, segs, watch=watch, damping=damping, settle=settle, through=through,
                           rtol=rtol, progress=progress)
    sim = result.simulation
    click.echo(f"# {system.name}: {len(segs)} segment(s), {total:g} s simulated, {len(sim)} samples, "
               f"{sim.nfev} evaluations; max constraint drift {sim.constraint_drift:.2e}")
    if not sim.success:
        click.echo(f"# warning: {sim.message}")
    if not result.jumps:
        click.echo(f"no jump of {watch} detected")
    for i, j in enumerate(result.jumps, 1):
        word = "increasing" if j.direction > 0 else "decreasing"
        click.echo(f"jump {i}: {j.parameter} = {j.value:.6g} ({word}, segment {j.segment + 1}) at t = {j.time:.4g} s; "
                   f"{watch} {j.before[watch]:.6g} -> {j.after[watch]:.6g}")
    if out_path is not None:
        result.to_csv(out_path)
        click.echo(f"wrote {out_path}")
    if plot_path is not None:
        from ..dynamics import plot_sweep
        from ..outputs.plotting import new_figure, save_figure

        fig, ax = new_figure()
        plot_sweep(result, ax, degrees=system.variable(watch).unit == "rad")
        save_figure(fig, plot_path)
        click.echo(f"wrote {plot_path}")
