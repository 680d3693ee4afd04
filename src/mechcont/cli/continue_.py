"""``mechcont continue``: a branch of equilibria in one parameter."""

from __future__ import annotations

import click

from ._app import cli
from ._run import check_outputs, common_options, continuation_options, run_continuation, solve_start, write_branch


@cli.command("continue")
@click.argument("model")
@common_options
@click.option("--vary", required=True, metavar="NAME", help="Continuation parameter (any variable).")
@click.option("--out", default=None, help="Branch table: .csv or .json.")
@click.option("--plot", default=None, help="Figure: .png, .svg or .pdf.")
@click.option("--x", "xname", default=None, help="Plot x axis (default: the --vary name).")
@click.option("--y", "yname", default=None, help="Plot y axis (default: the --start state).")
def continue_command(model, sets, starts, holds, frees, bnds, ds, dsmax, max_steps, quiet, vary, out, plot, xname, yname):
    """Continue equilibria of MODEL in --vary, both directions, within --bounds.

    Example: mechcont continue overcentre --set LU=0.4 --start theta1=0.3 --vary F
    --bounds theta1=-1.2:1.2 --out branch.csv --plot branch.png
    """
    from ..continuation import continuation
    from ..models import load_model
    from ._parse import assignments

    check_outputs(out, plot)
    options = continuation_options(bnds, ds, dsmax, max_steps)
    system = load_model(model)
    x0 = solve_start(system, sets, starts, vary, frees, holds)
    branch = run_continuation(continuation, system, x0, vary, hold=holds, free=frees, options=options, quiet=quiet)
    first_state = next(iter(assignments(starts, "start")), None) or branch.unknowns[0]
    write_branch(branch, out, plot, xname or vary, yname or first_state, quiet)
    if not quiet and system.mechanics is not None and len(branch.values):
        from ..analysis.redundancy import redundancy_along

        report = redundancy_along(system, branch)
        if report.dropped or report.changes or report.states[0].indeterminate:
            click.echo("redundant constraints along the branch:")
            names = [""] * len(branch.values)
            for p, name in zip(branch.special_points, branch.point_names()):
                names[p.index] = name
            for line in report.lines(names):
                click.echo(f"  {line}")
