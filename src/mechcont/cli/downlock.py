"""``mechcont downlock``: the downlock force as a function of any design parameter."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import click

from .._io import check_output_path
from ..errors import InputError
from ..outputs.tables import summary_rows
from ..units import display
from ._app import cli
from ._parse import assignments, freed_parameters, named_as, names
from ._parse import bounds as parse_bounds
from ._run import load_at

if TYPE_CHECKING:
    from ..continuation import Branch
    from ..equations import Model


def model_and_condition(system: Model, holds: Iterable[str], force: str | None,
                        condition: str | None = None) -> tuple[Model, dict[str, float], str]:
    """``system`` and its downlock condition (``--hold``/``--condition``/``--force`` or the model's own)."""
    from ..analysis.downlock import downlock_condition

    hold = assignments(holds, "hold") or None
    try:
        h, f = downlock_condition(system, hold, force, condition=condition)
    except InputError as exc:
        if exc.field == "condition":  # name the option the user typed
            raise InputError("--condition", str(exc)[len(exc.field) + 2:]) from None
        raise
    return system, h, f


def _or_none(value: float) -> str:
    """A force for the table (12 wide), ``none`` where there is no fold (nan)."""
    return f"{value:12.6g}" if value == value else f"{'none':>12}"


def warn(lines: Iterable[str]) -> None:
    """Each line on stderr as ``warning: ...`` (runs that stopped short: where and why)."""
    for line in lines:
        click.echo(f"warning: {line}", err=True)


@cli.command("downlock")
@click.argument("model")
@click.option("--vary", required=True, metavar="NAME", help="Design parameter to continue in (e.g. U, k, LU, l_sp1).")
@click.option("--bounds", "bounds_", multiple=True, metavar="NAME=LO:HI",
              help="Range of a variable; required for --vary.")
@click.option("--free", "frees", multiple=True, metavar="NAME", help="A further parameter solved for.")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="Set a parameter (SI units, or the units the file declares; angles in rad).")
@click.option("--hold", "holds", multiple=True, metavar="NAME=VALUE",
              help="Downlock condition: held lock-link state (default: the model's, theta4=0 for nose_gear).")
@click.option("--condition", default=None, metavar="NAME",
              help="Downlock condition: a condition declared under [conditions], held at its target.")
@click.option("--force", default=None, metavar="NAME", help="The downlock force solved for (default: the model's, F).")
@click.option("--max-steps", type=int, default=None, help="Most continuation steps each way (default 2000).")
@click.option("--out", default=None, metavar="FILE", help="Write the branch as .csv or .json.")
@click.option("--plot", default=None, metavar="FILE", help="Plot the downlock force (.png, .svg, .pdf).")
@click.option("--sensitivity", "sens_text", default=None, metavar="NAMES",
              help="Comma-separated parameters: exact d<FORCE>_d<NAME> columns per point (SI units).")
@click.option("--release-span", "span", type=float, default=None, metavar="N",
              help="A lock on stops: how far each release run pushes the --force, in its scales [50].")
def downlock_command(model: str, vary: str, bounds_: tuple[str, ...], frees: tuple[str, ...], sets: tuple[str, ...],
                     holds: tuple[str, ...], condition: str | None, force: str | None, max_steps: int | None,
                     out: str | None, plot: str | None, sens_text: str | None, span: float | None) -> None:
    """Downlock force of MODEL (built-in name or description .toml) as a function of --vary.

    The lock links are held aligned (e.g. theta4 = 0, overcentre angle 180 deg, or the
    description's [mechanism] downlock condition), the force is solved for, and the --vary
    parameter is continued within its --bounds. A positive force means the gear locks with
    no help. Also printed: the unlock folds of the downlocked point at the start value
    (released, continued in the force), written per point as unlock_<FORCE> columns.
    Runs that stop short of their bounds are named on stderr.

    On a description with [stops] and no --hold/--condition, the locked state is the one resting
    on its stops (the --force at its value): printed is the stop's reaction (the lock's preload)
    along --vary and, per point, the unlock load: the force increased until the stop releases
    (SR) and the fold that follows, smooth (LP) or not (NSF: the release is the snap).
    """
    from ._run import mechanism_only

    mechanism_only(model, "downlock")
    import numpy as np

    from ..analysis.downlock import downlock_table
    from ..continuation import check_max_steps
    from ..outputs.plotting import FIGURE_SUFFIXES
    from ..outputs.tables import BRANCH_SUFFIXES

    out_path = check_output_path(out, "--out", BRANCH_SUFFIXES)
    plot_path = check_output_path(plot, "--plot", FIGURE_SUFFIXES)
    values = assignments(sets, "set")
    bnds = parse_bounds(bounds_)
    sens_params = names(sens_text, "sensitivity")
    check_max_steps(max_steps, "--max-steps")
    system = load_at(model, values)  # loaded once: the analyses never modify it
    stops = system.stops
    if stops and not holds and condition is None:
        if sens_params:
            raise InputError("--sensitivity", "is not available for a lock resting on its stops; give the lock's "
                                              "--hold or --condition to differentiate the held downlock force")
        return _on_stops(system, vary, bnds, frees, values, force, max_steps, out_path, plot_path, span)
    if span is not None:
        raise InputError("--release-span", "is for a lock resting on its stops; leave out --hold/--condition")
    system, h, f = model_and_condition(system, holds, force, condition)
    if stops:
        click.echo(f"note: the stops of {system.name} ({', '.join(s.name for s in stops)}) are ignored here: the lock is "
                   "held at the condition given; leave out --hold/--condition to take the locked state on its stops")
    for n in values:
        system.variable(n)
    from ..analysis.unlock import RELEASE_FORCE_SPAN, RELEASE_STATE_SPAN

    with named_as({"params": "--sensitivity", "sensitivity": "--sensitivity"}):
        result = downlock_table(system, vary, bnds, sensitivity=sens_params, free=freed_parameters(system, frees),
                                values=values, hold=h, force=f, max_steps=max_steps)
    branch = result.branch
    if sens_params:
        for p in sens_params:
            col = f"d{f}_d{p}"
            click.echo(f"  {col} ({branch.units[col]}) from {branch[col].min():.6g} to {branch[col].max():.6g}")
    (xs, unit_x), Fs = display(branch[vary], system.variable(vary).unit), branch[f]
    held = ", ".join(f"{k}={v:g}" for k, v in h.items())
    unlock_col = f"unlock_{f}" if f"unlock_{f}" in branch.names else None
    unit_f = system.variable(f).unit
    click.echo(f"downlock force {f} ({unit_f}) vs {vary} ({unit_x}), {held} held: "
               f"{len(branch)} points, {f} from {Fs.min():.6g} to {Fs.max():.6g} {unit_f}; status {branch.status}"
               .replace(" ;", ";"))
    for i in summary_rows(len(branch)):
        extra = f"   unlock {_or_none(branch[unlock_col][i])}" if unlock_col else ""
        click.echo(f"  {vary} = {xs[i]:12.6g}   {f} = {Fs[i]:12.6g}{extra}   {branch.stability_labels()[i]} "
                   f"{branch.labels[i]}")
    if unlock_col and not np.isfinite(branch[unlock_col]).all():
        click.echo(f"  unlock none: the release run from that point met no fold increasing {f} before its bounds "
                   f"({f} moved by {RELEASE_FORCE_SPAN:g} of its scales, or the released state by "
                   f"{RELEASE_STATE_SPAN:g}): the locked state is not bounded there")
    start = values.get(vary, system.variable(vary).value)
    assert result.unlock is not None  # downlock() finds the start's unlock folds by default
    click.echo(f"at {vary} = {start:g}: {result.unlock.summary(held, unit_f)}")
    for note in result.unlock.notes:
        click.echo(f"  {note}")
    warn(result.warnings)
    _write(branch, out_path, plot_path, vary, f, held, f"{system.name}: downlock force vs {vary}")


def _write(branch: Branch, out_path: Path | None, plot_path: Path | None, vary: str, force: str, held: str,
           title: str) -> None:
    """The branch's table (``--out``) and figure of the force against ``vary`` (``--plot``), each when asked."""
    from ..outputs.tables import write_branch_table

    if out_path is not None:
        write_branch_table(branch, out_path)
        click.echo(f"wrote {out_path}")
    if plot_path is not None:
        from ..outputs.design_plots import downlock_figure
        from ..outputs.plotting import save_figure

        save_figure(downlock_figure(branch, vary, force, held=held, title=title), plot_path, dpi=120)
        click.echo(f"wrote {plot_path}")


def _on_stops(system: Model, vary: str, bnds: Mapping[str, tuple[float, float]], frees: Sequence[str],
              values: Mapping[str, float], force: str | None, max_steps: int | None, out_path: Path | None,
              plot_path: Path | None, span: float | None = None) -> None:
    """``downlock`` on a description with stops: the lock rests on them (:mod:`mechcont.analysis.stop_lock`);
    ``span``: how far each release run pushes the force (its scales; default the library's)."""
    import math

    from ..analysis.stop_lock import downlock_on_stops_table
    from ..analysis.unlock import RELEASE_FORCE_SPAN

    if span is None:
        span = RELEASE_FORCE_SPAN
    elif not (math.isfinite(span) and 0 < span <= 1e6):
        raise InputError("--release-span", f"must be a number of the force's scales in (0, 1e6], not {span:g}")

    for n in values:
        system.variable(n)
    result, unlock = downlock_on_stops_table(system, vary, bnds, force=force, free=freed_parameters(system, frees),
                                             values=values, max_steps=max_steps, span=span)
    f = result.force
    branch = result.branch
    reactions = [s.reaction for s in system.stops if s.name in result.lock_stops]
    xs, unit_x = display(branch[vary], system.variable(vary).unit)
    unit_f = system.variable(f).unit
    on = ", ".join(result.lock_stops)
    spans = "; ".join(f"{r} from {branch[r].min():.6g} to {branch[r].max():.6g} {system.variable(r).unit}"
                      for r in reactions)
    click.echo(f"lock resting on stop {on} (the locked state; its reaction is the preload) vs {vary} ({unit_x}), "
               f"{f} = {branch[f][0]:g} {unit_f}: {len(branch)} points, {spans}; status {branch.status}")
    for i in summary_rows(len(branch)):
        held = "   ".join(f"{r} = {branch[r][i]:12.6g}" for r in reactions)
        click.echo(f"  {vary} = {xs[i]:12.6g}   {held}   unlock {_or_none(unlock[i])}   "
                   f"{branch.stability_labels()[i]} {branch.labels[i]}")
    start = values.get(vary, system.variable(vary).value)
    found = result.unlock
    if found is not None:
        click.echo(f"at {vary} = {start:g}: {found.summary(f'resting on stop {on}', unit_f)}")
        for note in found.notes:
            click.echo(f"  {note}".replace("a larger span searches further", "a larger --release-span searches further"))
    warn(result.warnings)
    _write(branch, out_path, plot_path, vary, f, f"resting on stop {on}", f"{system.name}: lock on stop {on} vs {vary}")
