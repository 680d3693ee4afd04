"""``mechcont sweep``: a quasi-static sweep (time simulation with slowly ramped loads)."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

import click

from ..errors import InputError
from ..units import display
from ._app import cli
from ._parse import assignments, check_integration, integrator, integrator_options, named_item, number
from ._run import QUIET_HELP, quiet_stdout

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from ..continuation import Branch
    from ..dynamics import JumpGap, SweepResult
    from ..equations import Model


def _ramps(items: Iterable[str]) -> list[tuple[str, float, float, float]]:
    """``["F=60:-90:2"]`` -> ``[("F", 60.0, -90.0, 2.0)]``."""
    out = []
    for item in items:
        name, spec = named_item(item, "--ramp", "NAME=FROM:TO:RATE")
        parts = spec.split(":")
        if len(parts) != 3:
            raise InputError("--ramp", f"'{item}' is not NAME=FROM:TO:RATE")
        a, b, r = (number(p.strip(), f"--ramp {name}") for p in parts)
        out.append((name, a, b, r))
    if not out:
        raise InputError("--ramp", "give at least one NAME=FROM:TO:RATE")
    return out


def _shown(system: Model, name: str, value: float) -> tuple[float, str]:
    """A value and its unit as printed: angles in degrees."""
    return display(value, system.variable(name).unit)


def _read_branch(path: str, system: Model, parameter: str) -> Branch:
    """The --branch table: a branch of this model continued in the ramped ``parameter``."""
    from ..continuation import Branch
    from ..continuation.branch_rows import refuse_cycles_table

    branch = Branch.read_csv(path, model=system.name)
    refuse_cycles_table(branch.names, path, "--branch")
    missing = [n for n in system.names if n not in branch.names]
    if missing:
        raise InputError("--branch", f"'{path}' lacks the column(s) {', '.join(missing[:5])} of model '{system.name}'")
    if branch.vary and branch.vary != parameter:
        raise InputError("--branch", f"'{path}' is a branch in {branch.vary}, but the sweep ramps {parameter}; "
                                     f"continue in {parameter} (mechcont continue ... --vary {parameter})")
    return branch


def _other_values(branch: Branch, system: Model, ramped: Iterable[str]) -> list[str]:
    """The parameters (not ramped) whose value on the --branch differs from the sweep's, in the equations:
    ``["l0 = 0.6 m (sweep 0.5 m)"]`` (:func:`mechcont.dynamics.held_branch_differences`)."""
    from ..dynamics import held_branch_differences

    out = []
    for n, on_branch, here in held_branch_differences(system, branch, ramped):
        a, b = _shown(system, n, on_branch), _shown(system, n, here)
        out.append(f"{n} = {a[0]:.6g} {a[1]} (sweep {b[0]:.6g} {b[1]})".replace(" )", ")"))
    return out


def _start_on_stops(system: Model, x0: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """With --stops the sweep starts from the equilibrium nearest the assembled start with a consistent set of
    stops in contact (:func:`mechcont.analysis.equilibrium_on_stops`), so the simulation starts where the
    stops allow; one line naming --start when there is none."""
    from ..analysis import equilibrium_on_stops
    from ..errors import ConvergenceError

    try:
        x, _ = equilibrium_on_stops(system, x0, values={n: x0[system.index(n)] for n in system.parameter_names},
                                    stable=True)
    except (ConvergenceError, InputError) as exc:
        raise InputError("--start", f"no equilibrium with a consistent set of stops in contact near the start: {exc}; "
                                    "give another --start, or --no-equilibrium to start at rest there") from None
    return x


def _gaps(result: SweepResult, branch: Branch | None) -> tuple[list[str], str]:
    """Per jump: "; 4.8 N past LP2 (F = -75.58 N)", the gap to the fold it follows, and the same for the runaway
    ("" when there is none); empty without a branch."""
    if branch is None:
        return [], ""
    from ..dynamics import branch_jump_gaps, branch_runaway_gap

    name = result.ramps[0].name
    unit = branch.units.get(name, "")

    def text(fold: str, g: JumpGap) -> str:
        where = "past" if g.past else "BEFORE (not a fold of this sweep?)"
        return f"; {abs(g.gap):.4g} {unit} {where} {fold} ({name} = {g.fold_value:.6g} {unit})".replace("  ", " ")

    run = branch_runaway_gap(result, branch)
    return [text(fold, g) for fold, g in branch_jump_gaps(result, branch)], "" if run is None else text(*run)


def _no_fold_note(system: Model, result: SweepResult, branch: Branch) -> str:
    """The line said when the --branch has no fold in the ramped parameter: no jump is expected, and when some were
    found, their plausible causes (the sweep beyond the branch's range of the parameter named first)."""
    name = result.ramps[0].name
    text = f"the branch has no fold in {name}: no jump is expected"
    moves = result.jumps + ([result.runaway] if result.runaway is not None else [])
    if not moves:
        return text
    text += (f", yet {len(result.jumps)} jump(s){' and a runaway' if result.runaway is not None else ''} were found: ")
    values = branch.column(name)
    lo, hi = float(values.min()), float(values.max())
    beyond = [j.value for j in moves if not lo <= j.value <= hi]
    if beyond:
        unit = f" {system.variable(name).unit}".rstrip()
        return text + (f"the branch covers {name} = {lo:.6g} to {hi:.6g}{unit} only and the sweep jumped at "
                       f"{', '.join(f'{v:.6g}' for v in beyond)}{unit}: continue the branch over the sweep's range "
                       "(--bounds) to see its fold")
    return text + ("plausible causes: the sweep runs on another branch than this one (continued from another "
                   "--start), a stop moved it (an impact or a release, with --stops), or the ramp is too fast to "
                   "follow the branch (a lower rate)")


def _print_stop_loads(system: Model, result: SweepResult) -> None:
    """One line per stop event of a sweep with stops: time, kind, stop and the ramped load there."""
    name = result.ramps[0].name
    unit = system.variable(name).unit
    if not result.stop_events:
        click.echo("no stop event")
    for ev in result.stop_events:
        load = float(result[name][ev.row])
        click.echo(f"{ev.describe()}  at {name} = {load:.6g} {unit}".rstrip())
    for kind in ("contact", "release"):
        loads = result.stop_loads(kind)
        if loads:
            click.echo(f"{kind} loads: " + ", ".join(f"{v:.6g}" for v in loads) + f" {unit}".rstrip())


@cli.command("sweep")
@click.argument("model")
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
              help="Override a parameter (SI units, or the units the file declares; angles in rad).")
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
@integrator_options
@click.option("--out", default=None, metavar="FILE.csv", help="Write the time history as CSV.")
@click.option("--plot", default=None, metavar="FILE.png", help="Plot WATCH against the ramped parameter.")
@click.option("--branch", "branch_csv", default=None, metavar="BRANCH.csv",
              help="A continuation branch in the ramped parameter (mechcont continue --out): drawn under the sweep, "
                   "and each jump (and a runaway) is paired with the fold it follows (the gap printed).")
@click.option("--stops", "use_stops", is_flag=True,
              help="Simulate the description's stops (impacts, contact with its reaction, release) and print the "
                   "ramped load at each contact and release.")
@click.option("--no-progress", is_flag=True, help="No progress bar (the results are printed).")
@click.option("--quiet", is_flag=True, help=QUIET_HELP)
def sweep_command(model: str, settings: tuple[str, ...], starts: tuple[str, ...], ramps: tuple[str, ...], watch: str,
                  damping: float, settle: float, equilibrium: bool, through: float | None, method: str, rtol: float,
                  atol: float, out: str | None, plot: str | None, branch_csv: str | None, use_stops: bool,
                  no_progress: bool, quiet: bool) -> None:
    """Ramp loads of MODEL slowly in a time simulation and report where WATCH jumps.

    Example: mechcont sweep overcentre --set LU=0.4 --set c=50 --start theta1=1.2
    --ramp F=-65:-90:0.5 --ramp F=-90:110:2 --watch theta1

    With --branch (the same model continued in the ramped parameter) the plot shows the
    branch under the sweep, stable solid and unstable dashed, and each jump (and a runaway,
    where the mechanism ran away past its last fold and had not settled when the sweep ended)
    is printed with its gap to the fold it follows: the time simulation's delay past the fold.
    """
    click.get_current_context().with_resource(quiet_stdout(quiet))
    from ._run import mechanism_only

    mechanism_only(model, "sweep")
    from .._io import check_output_path
    from ..dynamics import check_simulable, parse_ramps, sweep, sweep_start
    from ..models import model_at
    from ..outputs.plotting import FIGURE_SUFFIXES

    out_path = check_output_path(out, "--out", (".csv",))
    plot_path = check_output_path(plot, "--plot", FIGURE_SUFFIXES)
    solver = integrator(method, rtol, atol)
    segs = parse_ramps(_ramps(ramps))
    system = model_at(model, assignments(settings, "set"))
    branch = _read_branch(branch_csv, system, segs[0].name) if branch_csv is not None else None
    start = assignments(starts, "start")
    mechanics = check_simulable(system, model)
    if use_stops and not system.stops:
        raise InputError("--stops", f"{system.name} declares no stops ([stops.NAME] in the description)")
    x0 = sweep_start(system, start, segs, equilibrium=equilibrium and not use_stops, start_field="--start")
    if use_stops and equilibrium:
        x0 = _start_on_stops(system, x0)
    total = settle + sum(r.duration for r in segs)
    from .._progress import Progress

    try:
        with Progress("sweep", total=total, unit="s simulated", quiet=no_progress or quiet) as bar:
            result = sweep(system, x0, segs, watch=watch, damping=damping, settle=settle, through=through, **solver,
                           progress=bar.set if bar.enabled else None, stops=use_stops)
    except InputError as exc:  # the start is the --start pose (with --stops, its equilibrium on the stops)
        if exc.field != "x0":
            raise
        raise InputError("--start", str(exc)[len(exc.field) + 2:]) from None
    if not mechanics.stability(x0).stable:  # said after sweep(), which reports bad input first
        a = _shown(system, watch, x0[system.index(watch)])
        click.echo(f"warning: the sweep starts at an unstable equilibrium ({watch} = {a[0]:.6g} {a[1]}".rstrip()
                   + "): it leaves it at once; give a --start nearer a stable one", err=True)
    if branch is not None and (differ := _other_values(branch, system, {r.name for r in segs})):
        click.echo(f"warning: '{branch_csv}' was continued at other parameter values: {', '.join(differ)}; "
                   "its folds are not this sweep's (continue with the same --set)", err=True)
    sim = result.simulation
    click.echo(f"# {system.name}: {len(segs)} segment(s), {total:g} s simulated, {len(sim)} samples, "
               f"{sim.nfev} evaluations; max constraint drift {sim.constraint_drift:.2e}")
    if not sim.success:
        click.echo(f"# warning: {sim.message}")
    if not result.jumps and result.runaway is None:
        click.echo(f"no jump of {watch} detected")
    gaps, runaway_gap = _gaps(result, branch)
    if use_stops:
        _print_stop_loads(system, result)
    for i, j in enumerate(result.jumps, 1):
        word = "increasing" if j.direction > 0 else "decreasing"
        a, b = _shown(system, watch, j.before[watch]), _shown(system, watch, j.after[watch])
        click.echo(f"jump {i}: {j.parameter} = {j.value:.6g} {system.variable(j.parameter).unit} ({word}, segment "
                   f"{j.segment + 1}) at t = {j.time:.4g} s; {watch} {a[0]:.6g} -> {b[0]:.6g} {a[1]}".rstrip()
                   + (gaps[i - 1] if gaps else ""))
    if (run := result.runaway) is not None:
        a, b = _shown(system, watch, run.before[watch]), _shown(system, watch, run.after[watch])
        click.echo(f"runaway: {watch} left the equilibrium at {run.parameter} = {run.value:.6g} "
                   f"{system.variable(run.parameter).unit} ({'increasing' if run.direction > 0 else 'decreasing'}, "
                   f"segment {run.segment + 1}) at t = {run.time:.4g} s and had not settled when the sweep ended; "
                   f"{watch} {a[0]:.6g} -> {b[0]:.6g} {a[1]}".rstrip() + runaway_gap)
    if branch is not None and not branch.special("LP"):
        click.echo(_no_fold_note(system, result, branch))
    if out_path is not None:
        result.to_csv(out_path)
        click.echo(f"wrote {out_path}")
    if plot_path is not None:
        from ..outputs.plotting import save_figure
        from ..outputs.sweep_plots import sweep_figure

        title = (f"{system.name}: {watch} against {segs[0].name}, time simulation"
                 + (" on the continuation branch" if branch is not None else ""))
        fig = sweep_figure(result, title=title, branch=branch, degrees=system.variable(watch).unit == "rad")
        save_figure(fig, plot_path)
        click.echo(f"wrote {plot_path}")
    check_integration(sim, method, [str(p) for p in (out_path, plot_path) if p is not None])
