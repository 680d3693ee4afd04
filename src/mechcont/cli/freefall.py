"""``mechcont freefall``: release at rest from the uplock, simulate with the stops until locked, at rest short
of locking, or still moving at --until; the critical airspeed bracketed by runs, beside its quasi-static predictor."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from ..equations import units_of
from ..errors import InputError
from ._app import cli
from ._parse import (
    MAX_SCAN,
    assignments,
    check_count,
    check_integration,
    integrator,
    integrator_options,
    named_item,
    number,
    renamed,
    span,
)

if TYPE_CHECKING:
    from ..equations import Model

#: A freefall's lock: a stop, several stops, or a condition's (name, value).
LockSpec = str | list[str] | tuple[str, float]


def _range(text: str | None, option: str) -> tuple[str, float, float] | None:
    """``"U=20:80"`` -> ``("U", 20.0, 80.0)`` (:func:`mechcont.cli._parse.span`, both ends finite)."""
    return None if text is None else span(text, option)


def _scan(text: str | None) -> tuple[str, list[float]] | None:
    """``"c=1,10,100"`` -> ``("c", [1.0, 10.0, 100.0])``."""
    if text is None:
        return None
    name, vals = named_item(text, "--scan", "NAME=V1,V2,...")
    items = [v.strip() for v in vals.split(",") if v.strip()]
    if not items:
        raise InputError("--scan", f"'{text}' is not NAME=V1,V2,...")
    return name, [number(v, f"--scan {name}") for v in items]


def _lock(system: Model, lock: tuple[str, ...], lock_condition: str | None) -> LockSpec:
    """The lock of :func:`~mechcont.dynamics.freefall.freefall` from the two options (exactly one; --lock repeatable)."""
    if bool(lock) == (lock_condition is not None):
        raise InputError("--lock", "give exactly one of --lock STOP (repeatable) and --lock-condition NAME=VALUE")
    if lock:
        from ..dynamics.freefall import find_lock_stops

        try:
            find_lock_stops(system, list(lock))
        except InputError as exc:
            raise _option_error(exc) from None
        return lock[0] if len(lock) == 1 else list(lock)
    assert lock_condition is not None
    ((name, value),) = assignments([lock_condition], "lock-condition").items()
    if name not in system.names or system.variable(name).kind != "state":
        raise InputError("--lock-condition", f"{name} is not a coordinate or condition of {system.name}")
    return name, value


def _option_error(exc: InputError, start_option: str = "--start") -> InputError:
    """An error from the library, named by the option that gave the value (``start_option``: the spelling of
    ``--start`` given)."""
    option = {"x0": start_option, "rtol": "--rtol", "damping": "--damping", "lock": "--lock", "critical": "--critical",
              "tol": "--tol", "until": "--until", "held_by": "--held-by",
              "rest_speed": "--rest-speed", "max_steps": "--step-budget"}.get(exc.field)
    return exc if option is None else InputError(option, str(exc).split(": ", 1)[-1])


@cli.command("freefall")
@click.argument("model")
@click.option("--start", "starts", multiple=True, metavar="NAME=VALUE",
              help="The retracted pose: coordinate or condition held while assembling (the uplock); released at rest.")
@click.option("--from", "old_starts", multiple=True, hidden=True)  # its old spelling: --start names the start everywhere
@click.option("--held-by", default=None, metavar="PARAM",
              help="The retracted pose is the static equilibrium with the --start values held by PARAM (e.g. the "
                   "retraction actuator's force) solved for, then released; without it compliant joints deflect as "
                   "held by a reaction conjugate to each --start value.")
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
              help="Override a parameter (SI units, or the units the file declares; angles in rad).")
@click.option("--lock", multiple=True, metavar="STOP",
              help="A lock stop (repeatable): locked when every one is in contact and at rest.")
@click.option("--lock-condition", default=None, metavar="NAME=VALUE",
              help="Locked when this coordinate or condition reaches VALUE (instead of --lock).")
@click.option("--until", type=float, required=True, metavar="SECONDS", help="Longest simulated time (s).")
@click.option("--critical", default=None, metavar="V=LO:HI",
              help="Find the critical value of parameter V (an airspeed) in [LO, HI] by bisection on runs.")
@click.option("--tol", type=float, default=None, help="Bisection tolerance (units of V; default (HI-LO)/1000).")
@click.option("--scan", default=None, metavar="NAME=V1,V2,...",
              help="With --critical: the critical value at each value of parameter NAME (e.g. a damper's c).")
@click.option("--max-scan", type=click.IntRange(1, 100_000), default=MAX_SCAN, show_default=True,
              help="Most --scan values (each repeats the --critical bisection).")
@click.option("--damping", default=0.0, show_default=True, help="Mass-proportional damping (1/s).")
@integrator_options
@click.option("--step-budget", default=1_000_000, show_default=True, type=int, metavar="STEPS",
              help="Most integrator steps a run may take, projected from its recent step size before it gets there "
                   "(a stiff mechanism on an explicit --method ends early with a message naming the stiff element).")
@click.option("--rest-speed", default=1e-4, show_default=True,
              help="Coordinate speed (rad/s, m/s) below which a run that has not locked is at rest.")
@click.option("--out", default=None, metavar="FILE.csv",
              help="The time history (one run), or the critical values (with --critical).")
@click.option("--plot", default=None, metavar="FILE.png",
              help="The lock quantity against time (one run), or the critical value against the --scan parameter "
                   "with the quasi-static line.")
@click.option("--no-progress", is_flag=True, help="No progress bar for --critical's runs (the results are printed).")
def freefall_command(model: str, starts: tuple[str, ...], old_starts: tuple[str, ...], held_by: str | None,
                     settings: tuple[str, ...], lock: tuple[str, ...], lock_condition: str | None, until: float,
                     critical: str | None, tol: float | None, scan: str | None, max_scan: int, damping: float,
                     method: str, rtol: float, atol: float, step_budget: int, rest_speed: float, out: str | None,
                     plot: str | None, no_progress: bool) -> None:
    """Release MODEL at rest from the retracted pose and simulate it with its stops until it locks.

    Example: mechcont freefall examples/freefall_leg.toml --start angle=3.0 --lock downlock
    --until 10 --set U=40

    Simulates until it locks (the run ends there) or reaches --until. Prints the outcome (locked;
    at rest short of locking; still moving at --until, e.g. it struck the lock and left it), the
    time to lock, the impact speed at the lock, the peak damper tensions and stop reactions. With
    --critical V=LO:HI it bisects for the value of V where the outcome changes and prints the
    bracket by its two ends, each a run made (the one nearest the change that locked, the one that
    did not), and beside it the quasi-static prediction: the fold of the equilibria the gear could
    hang in on its way; their difference is significant only when it exceeds the bracket's width.
    """
    from ._run import mechanism_only

    mechanism_only(model, "freefall")
    from .._io import check_output_path
    from ..dynamics import check_duration, check_simulable
    from ..models import model_at
    from ..outputs.plotting import FIGURE_SUFFIXES

    out_path = check_output_path(out, "--out", (".csv",))
    plot_path = check_output_path(plot, "--plot", FIGURE_SUFFIXES)
    check_duration(until, "--until")
    solver = integrator(method, rtol, atol)
    starts, start_option = renamed(starts, old_starts, "--start", "--from")
    start = assignments(starts, start_option[2:])
    if not start:
        raise InputError("--start", "give the retracted pose, e.g. --start angle=1.2 (a coordinate or condition)")
    rng, scanned = _range(critical, "--critical"), _scan(scan)
    check_count(len(scanned[1]) if scanned else 0, "--scan", max_scan, "--max-scan")
    if scanned is not None and rng is None:
        raise InputError("--scan", "needs --critical V=LO:HI (the scan repeats the bisection)")
    if plot_path is not None and rng is not None and scanned is None:
        raise InputError("--plot", "with --critical the figure is against a --scan parameter: give --scan NAME=V1,...")
    system = model_at(model, assignments(settings, "set"))
    check_simulable(system, model)
    for n in start:
        if n not in system.names or system.variable(n).kind != "state":
            raise InputError(start_option, f"{n} is not a coordinate or condition of {system.name}")
    for n in [*([rng[0]] if rng else []), *([scanned[0]] if scanned else [])]:
        if n not in system.names or system.variable(n).kind != "parameter":
            raise InputError("--critical" if rng and n == rng[0] else "--scan",
                             f"{n} is not a parameter of {system.name}; valid: {', '.join(system.parameter_names)}")
    if rng and scanned and scanned[0] == rng[0]:
        raise InputError("--scan", f"{rng[0]} is the parameter --critical bisects; scan another one")
    if scanned is not None:  # each value checked as --set checks it, the model at it taken by with_values
        from ..equations import check_values_at

        for v in scanned[1]:
            check_values_at(system, {scanned[0]: v}, "--scan")
    lock_spec = _lock(system, lock, lock_condition)
    # a run ends when it has locked (every lock stop in contact, at rest), as a lock condition ends it
    options = {"damping": damping, **solver, "rest_speed": rest_speed, "held_by": held_by, "end_at_lock": True,
               "max_steps": step_budget}
    import numpy as np

    try:  # overflow on the way to a stiff run's stop is told by that stop's one line, not numpy's warnings
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            if rng is None:
                _one(system, start, lock_spec, until, options, out_path, plot_path)
            else:
                _critical(system, start, lock_spec, until, options, rng, tol, scanned, out_path, plot_path,
                          quiet=no_progress)
    except InputError as exc:
        raise _option_error(exc, start_option) from None


def _one(system: Model, start: dict[str, float], lock: LockSpec, until: float, options: dict[str, Any],
         out_path: Path | None, plot_path: Path | None) -> None:
    from ..dynamics.freefall import freefall
    from .simulate import echo_balance

    run = freefall(system, start, lock=lock, until=until, **options)
    h = run.history
    name = lock if isinstance(lock, str) else lock[0]
    stop = next((s for s in system.stops if s.name == name), None)
    watch = stop.condition if stop is not None else name
    units = {s.reaction: system.variable(s.reaction).unit for s in system.stops}
    units = {**{s.name: units[s.reaction] for s in system.stops},
             **{f"{s.name}_rate": f"{system.variable(s.condition).unit or '1'}/s" for s in system.stops},
             "lock_rate": f"{system.variable(watch).unit or '1'}/s", "damper": units_of(system).label("N")}
    click.echo(f"# {system.name}: released at rest from {', '.join(f'{k} = {v:g}' for k, v in start.items())}; "
               f"{h.t[-1]:.6g} s simulated, {len(h)} rows")
    if not h.success:
        click.echo(f"# warning: {h.message}")
    echo_balance(h)
    many = len(h.coordinates) > 6  # where a large mechanism hangs: its declared conditions, not 63 coordinates
    for line in run.describe(units, show=[c for c in system.conditions if c in h.names] if many else ()):
        click.echo(line)
    if out_path is not None:
        from ..outputs.tables import event_labels

        h.to_csv(out_path, labels=event_labels(h, {s.name: system.variable(s.condition).unit for s in system.stops})
                 if h.stop_events else None)
        click.echo(f"wrote {out_path}")
    if plot_path is not None:
        from ..outputs.history_plots import history_figure
        from ..outputs.plotting import save_figure

        save_figure(history_figure(h, watch, title=f"{system.name}: freefall, {run.outcome}"), plot_path)
        click.echo(f"wrote {plot_path}")
    check_integration(h, options["method"], [str(p) for p in (out_path, plot_path) if p is not None])


def _critical(system: Model, start: dict[str, float], lock: LockSpec, until: float, options: dict[str, Any],
              rng: tuple[str, float, float], tol: float | None, scanned: tuple[str, list[float]] | None,
              out_path: Path | None, plot_path: Path | None, *, quiet: bool = False) -> None:
    from .._progress import Progress
    from ..dynamics.freefall import bisection_runs, critical_scan

    vary, low, high = rng
    tol = (high - low) / 1000.0 if tol is None else tol
    total = bisection_runs(low, high, tol) * (len(scanned[1]) if scanned else 1)
    with Progress(f"freefall --critical {vary}", total=total, unit="runs", quiet=quiet) as bar:
        scan = critical_scan(system, start, vary, low, high, lock=lock, until=until, tol=tol, scan=scanned,
                             progress=bar.update if bar.enabled else None, **options)
    for line in scan.describe():
        click.echo(line)
    if out_path is not None:
        from ..outputs.tables import write_rows

        write_rows(out_path, scan.header(), scan.rows())
        click.echo(f"wrote {out_path}")
    if plot_path is not None:
        from ..outputs.critical_plots import critical_figure
        from ..outputs.plotting import save_figure

        name, unit = scan.scan, scan.unit
        assert name is not None  # the figure is against the --scan parameter (checked above)
        fig = critical_figure(list(scan.values), list(scan.brackets), list(scan.quasi_static_values),
                              damping_label=f"{name} ({system.variable(name).unit})".replace(" ()", ""),
                              airspeed_label=f"critical {vary} ({unit})".replace(" ()", ""),
                              title=f"{system.name}: freefall critical {vary} (runs of {until:g} s)")
        save_figure(fig, plot_path)
        click.echo(f"wrote {plot_path}")
