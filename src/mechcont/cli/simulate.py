"""``mechcont simulate``: a plain time simulation from rest, with the stops as unilateral constraints."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from ..equations import velocity_coordinate
from ..errors import InputError
from ._app import cli
from ._parse import Integrator, assignments, check_integration, integrator, integrator_options, named_as
from ._run import QUIET_HELP, quiet_stdout

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from ..dynamics import SimulationResult
    from ..equations import Model


def _start(system: Model, starts: tuple[str, ...],
           coords: tuple[str, ...]) -> tuple[npt.NDArray[np.float64], dict[str, float]]:
    """The assembled start vector: ``--start`` coordinates or conditions held."""
    from ..dynamics import assemble

    start = assignments(starts, "start")
    for n in start:
        if n not in system.names:
            raise InputError("--start", f"{n} is not a variable of {system.name}; give a coordinate or a condition: "
                                        + ", ".join(_holdable(system, coords)))
    try:
        return assemble(system, start, hold=list(start)), start
    except InputError as exc:
        raise InputError("--start", str(exc).split(": ", 1)[-1]) from None


def echo_balance(result: SimulationResult) -> None:
    """Print the history's energy balance in one line; warn (one line, stderr) when its residual
    exceeds what the integrator's tolerance explains (:attr:`~mechcont.dynamics.EnergyBalance.bound`). A history
    without the audit (a mechanism with element states: a tyre's deflection) says so instead."""
    if not result.energy:
        click.echo("# no energy balance: the element states (a tyre's deflection) store and dissipate energy the "
                   "audit does not count")
        return
    b = result.balance
    unit = result.energy_unit
    click.echo(f"# {b.describe(unit)}")
    if not b.closes and not result.integrator_failure:  # a failed run's own line says why it stopped
        click.echo(f"warning: the energy balance does not close: residual {b.worst:.3g} {unit} exceeds the "
                   f"{b.bound:.3g} {unit} "
                   "the integrator's tolerances explain; tighten --rtol, or the model's forces and masses disagree",
                   err=True)


def _holdable(system: Model, coords: tuple[str, ...]) -> list[str]:
    """The names ``--start`` accepts: coordinates and conditions."""
    return [*coords, *(r[5:] for r in system.equation_names if r.startswith("cond_"))]


@cli.command("simulate")
@click.argument("model")
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
              help="Override a parameter (SI units, or the units the file declares; angles in rad).")
@click.option("--start", "starts", multiple=True, metavar="NAME=VALUE",
              help="Starting coordinate or condition, held while the mechanism is assembled (e.g. theta1=1.2); "
                   "the simulation starts at rest there.")
@click.option("--until", "until", type=float, required=True, metavar="SECONDS", help="Simulated time (s).")
@click.option("--stops", "use_stops", is_flag=True,
              help="Simulate the description's stops: impacts (restitution e), contact with its reaction, release.")
@click.option("--watch", default=None, help="Column plotted against time (default: the first --start, else the "
                                            "first coordinate).")
@click.option("--damping", default=0.0, show_default=True, help="Mass-proportional damping (1/s).")
@integrator_options
@click.option("--step-budget", default=1_000_000, show_default=True, type=int, metavar="STEPS",
              help="Most integrator steps a run may take, projected from its recent step size before it gets there "
                   "(a stiff mechanism on an explicit --method ends early with a message naming the stiff element).")
@click.option("--out", default=None, metavar="FILE.csv", help="Write the time history as CSV (a row at each event).")
@click.option("--plot", default=None, metavar="FILE.png", help="Plot WATCH against time, stop events marked.")
@click.option("--no-progress", is_flag=True, help="No progress bar (the results are printed).")
@click.option("--quiet", is_flag=True, help=QUIET_HELP)
def simulate_command(model: str, settings: tuple[str, ...], starts: tuple[str, ...], until: float, use_stops: bool,
                     watch: str | None, damping: float, method: str, rtol: float, atol: float, step_budget: int,
                     out: str | None, plot: str | None, no_progress: bool, quiet: bool) -> None:
    """Simulate MODEL in time from rest in the pose assembled with the --start values held.

    Example: mechcont simulate tests/data/bar_drop.toml --start theta_bar=0 --until 3 --stops
    --out history.csv --plot history.png

    The start is not an equilibrium: the mechanism moves from rest under its loads. With
    --stops every stop event (impact with its speed, contact, release) is printed with its
    time and the stop's name, and the CSV has a row at each (its label column says which).

    An ODE file ([system] table, docs/ode-format.md) is integrated from its initial states, the
    --start values replacing them; its CSV has t, the states and the parameters.
    """
    click.get_current_context().with_resource(quiet_stdout(quiet))
    from .._io import check_output_path
    from ..dynamics import check_duration, check_simulable
    from ..models import model_at
    from ..outputs.plotting import FIGURE_SUFFIXES

    out_path = check_output_path(out, "--out", (".csv",))
    plot_path = check_output_path(plot, "--plot", FIGURE_SUFFIXES)
    check_duration(until, "--until")
    solver = integrator(method, rtol, atol)
    system = model_at(model, assignments(settings, "set"))
    if system.ode is not None:
        return _simulate_ode(system, model, starts, until, watch, solver, step_budget, out_path, plot_path,
                             use_stops=use_stops, damping=damping, quiet=no_progress or quiet)
    coords = check_simulable(system, model).coordinates
    x0, start = _start(system, starts, coords)
    if watch is None:
        watch = next(iter(start), coords[0])
    elif watch not in system.names and velocity_coordinate(watch, coords) is None:
        raise InputError("--watch", f"{watch} is not a column of {system.name}; give a variable or <coordinate>_dot")
    stops = system.stops
    if use_stops and not stops:
        raise InputError("--stops", f"{system.name} declares no stops ([stops.NAME] in the description)")
    import numpy as np

    from .._progress import Progress
    from ..dynamics import simulate

    try:
        # overflow on the way to a stiff run's stop is reported by that stop's one line, not numpy's warnings
        with Progress("simulate", total=until, unit="s simulated", quiet=no_progress or quiet) as bar, \
                np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            result = simulate(system, x0, (0.0, until), damping=damping, stops=use_stops, **solver,
                              progress=bar.set if bar.enabled else None, max_steps=step_budget)
    except InputError as exc:  # named by the option that gave the value
        option = {"x0": "--start", "rtol": "--rtol", "damping": "--damping", "max_steps": "--step-budget"}.get(exc.field)
        if option is None and exc.field.startswith("R_"):
            option = "--set"
        if option is None:
            raise
        raise InputError(option, f"{exc.field}: {str(exc).split(': ', 1)[-1]}" if option == "--set"
                         else str(exc).split(": ", 1)[-1]) from None
    if stops and not use_stops:
        click.echo(f"warning: the stops ({', '.join(s.name for s in stops)}) are ignored; give --stops to simulate "
                   "them", err=True)
    click.echo(f"# {system.name}: {result.t[-1]:.6g} s simulated from rest, {len(result)} rows, {result.nfev} evaluations; "
               f"max constraint drift {result.constraint_drift:.2e}")
    if not result.success:
        click.echo(f"# warning: {result.message}")
    echo_balance(result)
    from ..dynamics import UNRESOLVED

    unresolved = result.motion_warning.startswith(UNRESOLVED)
    if result.motion_warning and not unresolved:
        click.echo(f"warning: {result.motion_warning}", err=True)
    units = {s.name: system.variable(s.condition).unit for s in stops}
    for ev in result.stop_events:
        click.echo(ev.describe(units.get(ev.stop, "")))
    if use_stops and not result.stop_events:
        click.echo("no stop event")
    if out_path is not None:
        from ..outputs.tables import event_labels

        labels = event_labels(result, units) if use_stops else None
        result.to_csv(out_path, labels=labels)
        click.echo(f"wrote {out_path}")
    if plot_path is not None:
        from ..outputs.history_plots import history_figure
        from ..outputs.plotting import save_figure

        save_figure(history_figure(result, watch, title=f"{system.name}: {watch} from rest"), plot_path)
        click.echo(f"wrote {plot_path}")
    check_integration(result, method, [str(p) for p in (out_path, plot_path) if p is not None])
    if unresolved:  # the history is written; the mechanism itself is bad input
        raise InputError("redundant", result.motion_warning)


def _simulate_ode(system: Model, model: str, starts: tuple[str, ...], until: float, watch: str | None,
                  solver: Integrator, step_budget: int, out_path: Path | None, plot_path: Path | None, *,
                  use_stops: bool, damping: float, quiet: bool) -> None:
    """``simulate`` of an ODE file: du/dt = f(u, p) from the file's initial states (``--start`` replacing them)."""
    from .._progress import Progress
    from ..dynamics import ode_start, simulate_ode

    for given, option in ((use_stops, "--stops"), (damping != 0.0, "--damping")):
        if given:
            raise InputError(option, f"is a mechanism option; {model} is an ODE system")
    assert system.ode is not None  # the caller's branch: an ODE file
    x0 = ode_start(system, assignments(starts, "start"))
    states = system.ode.states
    watch = watch or next(iter(assignments(starts, "start")), states[0])
    if watch not in states:
        raise InputError("--watch", f"{watch} is not a state of {system.name}; valid: {', '.join(states)}")
    with named_as({"max_steps": "--step-budget", "x0": "--start"}), \
            Progress("simulate", total=until, unit="s simulated", quiet=quiet) as bar:
        result = simulate_ode(system, x0, (0.0, until), **solver, max_steps=step_budget,
                              progress=bar.set if bar.enabled else None)
    click.echo(f"# {system.name}: {result.t[-1]:.6g} s simulated from "
               + ", ".join(f"{n} = {x0[system.index(n)]:.6g}" for n in states)
               + f", {len(result)} rows, {result.nfev} evaluations")
    final = result.states[-1]
    click.echo("# at the end: " + ", ".join(f"{n} = {v:.10g}" for n, v in zip(states, final)))
    if out_path is not None:
        result.to_csv(out_path)
        click.echo(f"wrote {out_path}")
    if plot_path is not None:
        from ..outputs.history_plots import history_figure
        from ..outputs.plotting import save_figure

        save_figure(history_figure(result, watch, title=f"{system.name}: {watch}"), plot_path)
        click.echo(f"wrote {plot_path}")
    check_integration(result, solver["method"], [str(p) for p in (out_path, plot_path) if p is not None])
