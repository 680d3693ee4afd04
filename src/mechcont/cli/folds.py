"""``mechcont folds``: locate a fold in one parameter and continue it in a second."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import click

from ..errors import InputError
from ._app import cli
from ._parse import assignments, branch_row, named_as, renamed
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

if TYPE_CHECKING:
    from ..continuation import Branch, ContinuationOptions
    from ..equations import Model


@cli.command("folds")
@click.argument("model")
@common_options
@click.option("--vary", default=None, metavar="P1",
              help="Continuation parameter: the fold is a turning point in it (required without --point).")
@click.option("--along", "second", default=None, metavar="P2",
              help="Second parameter, continued along the fold curve (required).")
@click.option("--solve-for", "old_frees", multiple=True, hidden=True)  # the old spelling of --free here
@click.option("--fold", "which", default=1, show_default=True,
              help="Which fold of the first branch: N for LPN, numbered along the branch as `continue` prints them.")
@click.option("--out", default=None, help="Fold-curve table: .csv or .json.")
@click.option("--plot", default=None, help="Figure: .png, .svg or .pdf (P1 against P2; for a Hopf point the "
                                            "stability chart).")
@click.option("--point", default=None, metavar="BRANCH.csv:ROW",
              help="Start from this point of a branch table written by continue: a fold (LPn) or a Hopf point "
                   "(HBn, continued as a Hopf curve with BT and GH); its vary column gives P1.")
@click.option("--fold-curve", "fold_curves", multiple=True, metavar="CURVE.csv",
              help="With --point HBn and --plot: a fold curve table (written by folds) drawn on the stability chart.")
def folds_command(model: str, sets: tuple[str, ...], starts: tuple[str, ...], holds: tuple[str, ...],
                  frees: tuple[str, ...], bnds: tuple[str, ...], ds: float | None, dsmax: float | None,
                  max_steps: int | None, quiet: bool, vary: str | None, second: str | None,
                  old_frees: tuple[str, ...], which: int, out: str | None, plot: str | None, point: str | None,
                  fold_curves: tuple[str, ...]) -> None:
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
    if fold_curves and (point is None or not plot):
        raise InputError("--fold-curve", "is drawn on the stability chart: give it with --point BRANCH.csv:HBn and "
                                         "--plot")
    if point is not None:
        _from_point(system, point, vary, second, holds, frees, options, out, plot, quiet, fold_curves,
                    assignments(sets, "set"))
        return
    if vary is None:
        raise InputError("--vary", "give the parameter in which the fold is a turning point (e.g. --vary F), or "
                                   "--point BRANCH.csv:LP1")
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


def _from_point(system: Model, point: str, given_vary: str | None, second: str, holds: Sequence[str],
                frees: Sequence[str], options: ContinuationOptions, out: str | None, plot: str | None, quiet: bool,
                fold_curves: Sequence[str] = (), values: Mapping[str, float] | None = None) -> None:
    """``folds --point BRANCH.csv:ROW --along P2``: the fold curve of an ``LP`` row, the Hopf curve of an
    ``HB`` row (with its stability chart as the plot). ``values``: the --set parameters; where one differs from
    the row's, the point is first moved there (a fold followed as a fold, a Hopf point located from the row at
    those values), as ``cycles`` and ``sensitivity`` take a row to their --set values."""
    from ..continuation import continue_folds, continue_hopf, locate_hopf, move_point
    from ..continuation.branch_rows import read_branch_row

    csv_path, row = branch_row(point, "--point", "ROW (e.g. branch.csv:HB1)")
    with named_as({"point": "--point"}):
        found = read_branch_row(system, csv_path, row, hold=holds, free=frees)
    vary = found.vary
    if given_vary is not None and given_vary != vary:
        raise InputError("--vary", f"is {given_vary}, but '{csv_path}' was continued in {vary}; leave --vary out with "
                                   "--point")
    if vary == second:
        raise InputError("--along", f"is the branch's own parameter {vary}; choose a second parameter")
    p = found.point
    changed = {n: v for n, v in (values or {}).items() if system.variable(n).kind == "parameter" and n != vary
               and not math.isclose(p[n], v, rel_tol=1e-12, abs_tol=1e-300)}
    folds = [_fold_curve_table(path, system, vary, second) for path in fold_curves]
    if p.label == "LP":
        if folds:
            raise InputError("--fold-curve", "is drawn on a Hopf point's stability chart; this point is a fold")
        found.check(system, "LP")
        x = p.x
        if changed:
            with named_as({"set": "--set", "point": "--point"}):
                x = move_point(system, x, changed, solved=[*found.unknowns, vary], vary=vary, states=found.unknowns,
                               name=row).x
        curve = run_continuation(continue_folds, system, x, vary, second, hold=holds, free_extra=frees,
                                 options=options, quiet=quiet, label="fold curve")
        write_branch(curve, out, plot, second, vary, quiet)
        return
    if p.label != "HB":
        raise InputError("--point", f"'{row}' is labelled '{p.label or 'nothing'}'; give a fold (LPn) or a Hopf "
                                    "point (HBn)")
    found.check(system, "HB")
    with named_as({"point": "--point"}):
        hb = (locate_hopf(system, system.vector(changed, base=p.x), vary, hold=holds, free=frees) if changed
              else found.hopf(system, hold=holds, free=frees))
    curve = run_continuation(continue_hopf, system, hb, vary, second, options=options, quiet=quiet,
                             label="Hopf curve")
    _write_hopf_curve(curve, out, plot, second, vary, quiet, folds)


def _fold_curve_table(path: str, system: Model, p1: str, p2: str) -> Branch:
    """A fold-curve table for the stability chart: a branch table of ``system`` with both parameters."""
    from ..continuation import Branch, check_branch_table

    curve = Branch.read_csv(path, model=system.name)
    check_branch_table(curve, system, path)
    if curve.vary != p2 or "LP" in curve.labels:
        raise InputError("--fold-curve", f"'{path}' is not a fold curve in ({p1}, {p2}): write one with "
                                         f"folds --vary {p1} --along {p2}")
    return curve


def _write_hopf_curve(curve: Branch, out: str | None, plot: str | None, x: str, y: str, quiet: bool,
                      folds: Sequence[Branch] = ()) -> None:
    """The Hopf curve's table, its stability chart, and its special points with omega and l1."""
    from ..outputs.plotting import save_figure
    from ..outputs.stability_chart import stability_chart
    from ..outputs.tables import hopf_curve_lines

    write_branch(curve, out, None, x, y, quiet)
    if not quiet:
        for line in hopf_curve_lines(curve):
            click.echo(line)
    if plot:
        save_figure(stability_chart([curve], x, y, folds, title=f"{curve.model}: stability chart in ({x}, {y})"), plot)
        if not quiet:
            click.echo(f"wrote {plot}")
