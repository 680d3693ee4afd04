"""``mechcont sensitivity``: exact derivatives of a fold load, a branch point or the downlock force."""

from __future__ import annotations

from dataclasses import replace

import click

from ..errors import InputError
from ._app import cli
from ._parse import assignments, names

#: Keys of the JSON document besides the parameters' names.
_RESERVED = ("units", "quantity")
#: Fields of the API's errors that name an option of this command.
_OPTIONS = ("params", "keep", "set", "point", "of")


@cli.command("sensitivity")
@click.argument("model")
@click.option("--point", metavar="BRANCH.csv:ROW",
              help="The point: a row of a branch table written by continue/folds/downlock (a label such as LP1, "
                   "SR1 or NSF1 of a continue --stops table, or a 0-based row number); the row must be the point "
                   "it claims.")
@click.option("--downlock", is_flag=True, help="The downlock force at the --set values instead of a branch point.")
@click.option("--params", "params_text", required=True, metavar="NAMES",
              help="Comma-separated parameters to differentiate by, e.g. LU,k.")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="Change a held value first (SI units, rad); the point is followed there from its own values "
                   "(one line when it ends on the way, e.g. a fold past its cusp).")
@click.option("--hold", "holds", multiple=True, metavar="NAME", help="States held on the branch (as given to continue).")
@click.option("--free", "frees", multiple=True, metavar="NAME",
              help="Parameters solved for on the branch (as given to continue).")
@click.option("--keep", metavar="STATE",
              help="At a point that is not a fold: the state held at its value there (the continuation parameter "
                   "is solved for).")
@click.option("--of", "of", metavar="NAME",
              help="Differentiate this unknown of the branch instead (the continuation parameter held) "
                   "[the continuation parameter; a downlock table's force].")
@click.option("--out", default=None, metavar="FILE.json", help="Write the derivatives as JSON (SI units).")
def sensitivity_command(model, point, downlock, params_text, sets, holds, frees, keep, of, out):
    """Exact derivatives (implicit-function theorem) of a point's quantity with respect to --params.

    At a fold (e.g. --point branch.csv:LP1) the quantity is the fold load: the value of the
    branch's continuation parameter there. Elsewhere on a branch it is the continuation
    parameter at the --keep state held at its value, or the unknown --of. With --downlock it
    is the downlock force. SI units per SI unit; JSON {"LU": ..., "k": ..., "units": {...},
    "quantity": {...}}.

    Example: mechcont sensitivity overcentre --point branch.csv:LP1 --params LU,k --out s.json
    """
    from .._io import check_output_path
    from ..models import model_at

    check_output_path(out, "--out", (".json",))
    params = names(params_text, "params")
    for p in params:
        if p in _RESERVED:
            raise InputError("--params", f"'{p}' is a key of the JSON output; rename the parameter")
    values = assignments(sets, "set")
    system = model_at(model, values)  # the model at the --set values: a stop's limit follows them
    if (point is None) == (not downlock):
        raise InputError("--point", "give either --point BRANCH.csv:ROW or --downlock")
    try:
        sens = _compute(system, point, downlock, params, values, holds, frees, keep, of)
    except InputError as exc:  # the API's field names as the options that set them
        if exc.field not in _OPTIONS:
            raise
        raise InputError(f"--{exc.field}", str(exc)[len(exc.field) + 2:]) from None
    click.echo(sens.table())
    if out:
        check_output_path(out, "--out", (".json",))  # again: the folder may have changed meanwhile
        replace(sens, point="downlock" if downlock else point.rpartition(":")[2]).to_json(out)
        click.echo(f"wrote {out}")


def _compute(system, point, downlock, params, values, holds, frees, keep, of):
    if downlock:
        for opt, given in (("--hold", holds), ("--free", frees), ("--keep", keep), ("--of", of)):
            if given:
                raise InputError(opt, "is for a branch point; --downlock uses the model's downlock condition")
        return _downlock(system, params, values)
    return _at_point(system, point, params, values, holds, frees, keep, of)


def _downlock(system, params, values):
    from ..analysis.downlock import downlock_condition
    from ..analysis.sensitivity import check_parameters, downlock_sensitivity
    from ..continuation import choose_unknowns

    hold, force = downlock_condition(system)
    check_parameters(system, params, choose_unknowns(system, hold=hold, free=[force]))  # before the solve
    return downlock_sensitivity(system, params, values)


def _at_point(system, point, params, values, holds, frees, keep, of):
    from ..analysis.sensitivity import point_sensitivity
    from ..continuation import Branch, PointLost, check_branch_table, check_point, choose_unknowns

    csv_path, sep, row = point.rpartition(":")
    if not sep or not csv_path or not row:
        raise InputError("--point", f"'{point}' is not BRANCH.csv:ROW (e.g. branch.csv:LP1)")
    branch = Branch.read_csv(csv_path, model=system.name)
    check_branch_table(branch, system, csv_path)
    if not branch.vary:
        raise InputError("--point", f"'{csv_path}' has no vary column naming its continuation parameter")
    if branch.vary not in system.names:
        raise InputError("--point", f"'{csv_path}': its vary column names '{branch.vary}', not a variable of model "
                                    f"'{system.name}'")
    target = branch.point(row)
    lens = choose_unknowns(system, hold=holds, free=frees, exclude=[branch.vary])
    if of is not None and of != branch.vary and of not in lens:
        raise InputError("--of", f"'{of}' is not solved for on the branch; one of: {', '.join([branch.vary, *lens])}")
    check_point(system, target.x, label=target.label, vary=branch.vary, states=lens, name=f"{csv_path}:{row}")
    try:
        return point_sensitivity(system, target, params, vary=branch.vary, unknowns=lens, of=of, keep=keep,
                                 values=values)
    except PointLost as exc:  # name the row as the user did
        raise InputError("--point", f"{row}{str(exc).split(' point', 1)[1]}") from None
