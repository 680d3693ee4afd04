"""``mechcont folds``: locate a fold in one parameter and continue it in a second."""

from __future__ import annotations

from dataclasses import replace

import click

from ..errors import InputError
from ._app import cli
from ._parse import assignments, renamed
from ._run import (
    check_outputs,
    common_options,
    continuation_options,
    held_states,
    load_at,
    run_continuation,
    solve_start,
    write_branch,
)


@cli.command("folds")
@click.argument("model")
@common_options
@click.option("--vary", required=True, metavar="P1", help="Continuation parameter: the fold is a turning point in it.")
@click.option("--along", "second", default=None, metavar="P2",
              help="Second parameter, continued along the fold curve (required).")
@click.option("--solve-for", "old_frees", multiple=True, hidden=True)  # the old spelling of --free here
@click.option("--fold", "which", default=1, show_default=True,
              help="Which fold of the first branch: N for LPN, numbered along the branch as `continue` prints them.")
@click.option("--out", default=None, help="Fold-curve table: .csv or .json.")
@click.option("--plot", default=None, help="Figure: .png, .svg or .pdf (P1 against P2).")
def folds_command(model, sets, starts, holds, frees, bnds, ds, dsmax, max_steps, quiet, vary, second, old_frees, which,
                  out, plot):
    """Locate fold number --fold of the branch in --vary, then continue it in --along.

    --free names a parameter solved for on the branch, as in `continue`. Scripts written before
    --along gave P2 as --free P2 (and the solved-for parameters as --solve-for): one --free
    without --along (and without --hold, or with --solve-for) is still read that way, with a note.

    Example: mechcont folds overcentre --set LU=0.4 --start theta1=0.3 --vary F --along LU
    --bounds LU=0.1:2 --out folds.csv
    """
    from ..continuation import continuation, continue_folds
    from ..outputs.tables import branch_value, special_table

    check_outputs(out, plot)
    holds, starts = held_states(holds, starts)
    old_spelling = second is None and len(frees) == 1 and (bool(old_frees) or not holds)
    if old_spelling:  # folds --vary P1 --free P2, as written before --along
        second, frees = frees[0], ()
    if second is None:
        raise InputError("--along", "give the second parameter, continued along the fold curve (e.g. --along LU)")
    frees, _ = renamed(tuple(frees), tuple(old_frees), "--free", "--solve-for")
    options = continuation_options(bnds, ds, dsmax, max_steps)
    system = load_at(model, assignments(sets, "set"))
    system.index(second)
    x0 = solve_start(system, sets, starts, vary, frees, holds)
    first = run_continuation(continuation, system, x0, vary, hold=holds, free=frees, quiet=quiet,
                             options=replace(options, bounds={k: v for k, v in options.bounds.items() if k != second}))
    if old_spelling:  # said once the input is known good, so that an error stays one line
        click.echo(f"note: folds --free {second} is now --along {second} (--free names a parameter solved for, "
                   "as in continue)", err=True)
    lps = first.special("LP")
    if not lps:
        raise InputError("--vary", f"the branch in {vary} has no fold within the bounds; change --set or --bounds")
    folds = [(n, p) for n, p in zip(first.point_names(), first.special_points) if p.label == "LP"]
    listed = ", ".join(f"{n} at {vary} = {branch_value(first, vary, p[vary]):.6g}" for n, p in folds)
    if not 1 <= which <= len(lps):
        raise InputError("--fold", f"the branch has {len(lps)} fold(s) ({listed}); choose 1..{len(lps)}")
    if not quiet:  # the folds of the first branch, numbered as `continue` numbers them: what --fold picks from
        click.echo(special_table(first, [vary, *[n for n in assignments(starts, "start") if n != vary]]))
        if first.message:  # e.g. a runaway at max_steps, with the bounds to add
            click.echo(f"ends of the branch in {vary}: {first.message}")
        click.echo(f"continuing {folds[which - 1][0]} (--fold {which}) in {second}\n")
    curve = run_continuation(continue_folds, system, lps[which - 1], vary, second, options=options, quiet=quiet,
                             label="fold curve")
    shown = [n for n in assignments(starts, "start") if n != vary]
    write_branch(curve, out, plot, second, vary, quiet, extra=shown)
