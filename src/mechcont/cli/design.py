"""``mechcont design``: where the downlock force is positive, the F = 0 boundary, folds and margins."""

from __future__ import annotations

import click

from ..errors import InputError
from ._app import cli
from ._parse import assignments, named_as, names, renamed
from ._parse import bounds as parse_bounds
from ._run import load_at
from .downlock import model_and_condition, warn


@cli.command("design")
@click.argument("model")
@click.option("--vary", "x_name", default=None, metavar="NAME",
              help="Design parameter continued (default: the first --bounds name).")
@click.option("--across", "y_name", default=None, metavar="NAME",
              help="Second design parameter, in levels (default: the other --bounds name).")
# their spellings before --x/--y meant the plot's axes (continue): kept for scripts
@click.option("--x", "old_x", default=None, hidden=True)
@click.option("--y", "old_y", default=None, hidden=True)
@click.option("--bounds", "bounds_", multiple=True, required=True, metavar="NAME=LO:HI",
              help="Ranges of both design parameters (finite).")
@click.option("--levels", default=11, show_default=True, type=int, help="Number of levels of the second parameter.")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="Set a parameter (SI units, or the units the file declares; angles in rad).")
@click.option("--hold", "holds", multiple=True, metavar="NAME=VALUE",
              help="Downlock condition: a state held at a value (default: the model's).")
@click.option("--condition", default=None, metavar="NAME",
              help="Downlock condition: a condition declared under [conditions], held at its target.")
@click.option("--force", default=None, metavar="NAME", help="The downlock force (default: the model's, F).")
@click.option("--max-steps", type=int, default=2000, show_default=True, help="Most continuation steps each way.")
@click.option("--out", default=None, metavar="FILE", help="Write the table as .csv or .md.")
@click.option("--plot", default=None, metavar="FILE", help="Region plot (.png, .svg, .pdf).")
@click.option("--sensitivity", "sens_text", default=None, metavar="NAMES",
              help="Comma-separated parameters: per level, exact derivatives of the force at the design --vary value "
                   "and of the lock and fold margins (SI units).")
def design_command(model: str, x_name: str | None, y_name: str | None, old_x: str | None, old_y: str | None,
                   bounds_: tuple[str, ...], levels: int, sets: tuple[str, ...], holds: tuple[str, ...],
                   condition: str | None, force: str | None, max_steps: int, out: str | None, plot: str | None,
                   sens_text: str | None) -> None:
    """Where MODEL's downlock force is positive over (--vary, --across), the margin to the folds, as a table and a plot.

    The lock margin is signed: positive when the design locks unaided (by that much of --vary
    before it stops), negative when it does not. Runs that stop short of their bounds are
    named on stderr. --sensitivity NAMES adds, per level, the exact derivatives (implicit-function
    theorem) of the force at the design --vary value, of the lock margin and of the margin to the fold
    with respect to each name.
    """
    from ._run import mechanism_only

    mechanism_only(model, "design")
    import numpy as np

    from .._io import check_output_path
    from ..analysis.design import design_region
    from ..outputs.plotting import FIGURE_SUFFIXES
    from ..outputs.tables import RECORD_SUFFIXES, markdown_table, write_records

    out_path = check_output_path(out, "--out", RECORD_SUFFIXES)
    plot_path = check_output_path(plot, "--plot", FIGURE_SUFFIXES)
    if levels < 2 or levels > 200:
        raise InputError("--levels", f"must be between 2 and 200, got {levels}")
    if max_steps < 1:
        raise InputError("--max-steps", f"must be a positive integer, got {max_steps}")
    x_name, x_option = renamed(x_name, old_x, "--vary", "--x")
    y_name, y_option = renamed(y_name, old_y, "--across", "--y")
    values = assignments(sets, "set")
    bnds = parse_bounds(bounds_)
    rest = [n for n in bnds if n not in (x_name, y_name)]  # --vary/--across default to the --bounds names, in order
    x_name = x_name or (rest.pop(0) if rest else None)
    y_name = y_name or (rest.pop(0) if rest else None)
    if x_name is None or y_name is None:
        raise InputError("--bounds", "give the ranges of two design parameters, e.g. --bounds l_sp1=LO:HI --bounds LU=LO:HI")
    for n in (x_name, y_name):
        if n not in bnds or not all(np.isfinite(bnds[n])):
            raise InputError("--bounds", f"give a finite range for {n}, e.g. {n}=LO:HI")
    if x_name == y_name:
        raise InputError(y_option, f"must differ from {x_option}")
    system, h, f = model_and_condition(load_at(model, values), holds, force, condition)
    for n in (*values, x_name, y_name):
        system.variable(n)
    from ..analysis.design_sensitivity import check_design_parameters, design_sensitivity

    with named_as({"params": "--sensitivity"}):
        sens_params = check_design_parameters(system, names(sens_text, "sensitivity"), h, f)
    from .._progress import Progress

    with Progress("design", total=levels + 2, unit="runs") as bar:
        region = design_region(system, x_name, y_name, x_bounds=bnds[x_name],
                               y_levels=np.linspace(*bnds[y_name], levels), values=values,
                               hold=assignments(holds, "hold") or None, force=f, condition=condition,
                               max_steps=max_steps, progress=bar.update if bar.enabled else None)
    records = region.table()
    if sens_params:
        sens = design_sensitivity(system, region, sens_params, values, hold=h, force=f)
        for rec, derivatives in zip(records, sens.rows):
            rec.update({k: "none" if v is None else v for k, v in derivatives.items()})
        warn(sens.notes)
    click.echo(markdown_table(records))
    warn(region.warnings)
    if region.folds is not None:
        for p in region.folds.cusps:
            click.echo(f"cusp: {y_name} = {p[y_name]:.6g}, {x_name} = {p[x_name]:.6g}, "
                       f"{f} = {p[f]:.6g} {system.variable(f).unit}".rstrip())
    if out_path is not None:
        write_records(records, out_path)
        click.echo(f"wrote {out_path}")
    if plot_path is not None:
        from ..outputs.design_plots import design_figure
        from ..outputs.plotting import save_figure

        fig = design_figure(region, force_name=f, title=f"{system.name}: where the gear locks unaided ({f} > 0)")
        save_figure(fig, plot_path, dpi=120)
        click.echo(f"wrote {plot_path}")
