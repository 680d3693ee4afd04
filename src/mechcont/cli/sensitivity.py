"""``mechcont sensitivity``: exact derivatives of a fold load, a branch point or the downlock force."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import click

from ..errors import InputError
from ._app import cli
from ._parse import assignments, branch_row, names

if TYPE_CHECKING:
    from ..analysis.sensitivity import Sensitivity
    from ..equations import Model

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
@click.option("--hold", "holds", multiple=True, metavar="NAME[=VALUE]",
              help="States held on the branch (as given to continue; a VALUE must be the row's).")
@click.option("--free", "frees", multiple=True, metavar="NAME",
              help="Parameters solved for on the branch (as given to continue).")
@click.option("--keep", metavar="STATE",
              help="At a point that is not a fold: the state held at its value there (the continuation parameter "
                   "is solved for).")
@click.option("--of", "of", metavar="NAME",
              help="Differentiate this unknown of the branch instead (the continuation parameter held) "
                   "[the continuation parameter; a downlock table's force].")
@click.option("--out", default=None, metavar="FILE.json", help="Write the derivatives as JSON (SI units).")
def sensitivity_command(model: str, point: str | None, downlock: bool, params_text: str, sets: tuple[str, ...],
                        holds: tuple[str, ...], frees: tuple[str, ...], keep: str | None, of: str | None,
                        out: str | None) -> None:
    """Exact derivatives (implicit-function theorem) of a point's quantity with respect to --params.

    At a fold (e.g. --point branch.csv:LP1) the quantity is the fold load: the value of the
    branch's continuation parameter there. Elsewhere on a branch it is the continuation
    parameter at the --keep state held at its value, or the unknown --of. With --downlock it
    is the downlock force. Each derivative is in the quantity's unit per the parameter's; JSON
    {"LU": ..., "k": ..., "units": {...}, "quantity": {...}}.

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
        replace(sens, point="downlock" if point is None else branch_row(point)[1]).to_json(out)
        click.echo(f"wrote {out}")


def _compute(system: Model, point: str | None, downlock: bool, params: Sequence[str], values: Mapping[str, float],
             holds: Sequence[str], frees: Sequence[str], keep: str | None, of: str | None) -> Sensitivity:
    """The derivatives at the --point row or of the downlock force (--downlock), the options checked."""
    if downlock:
        for opt, given in (("--hold", holds), ("--free", frees), ("--keep", keep), ("--of", of)):
            if given:
                raise InputError(opt, "is for a branch point; --downlock uses the model's downlock condition")
        return _downlock(system, params, values)
    assert point is not None  # exactly one of --point and --downlock (checked by the caller)
    return _at_point(system, point, params, values, holds, frees, keep, of)


def _downlock(system: Model, params: Sequence[str], values: Mapping[str, float]) -> Sensitivity:
    """The derivatives of the downlock force at ``values`` (the model's downlock condition)."""
    from ..analysis.downlock import downlock_condition
    from ..analysis.sensitivity import check_parameters, downlock_sensitivity
    from ..continuation import choose_unknowns

    hold, force = downlock_condition(system)
    check_parameters(system, params, choose_unknowns(system, hold=hold, free=[force]))  # before the solve
    return downlock_sensitivity(system, params, values)


def _at_point(system: Model, point: str, params: Sequence[str], values: Mapping[str, float], holds: Sequence[str],
              frees: Sequence[str], keep: str | None, of: str | None) -> Sensitivity:
    """The derivatives at the row ``point`` (``BRANCH.csv:ROW``) of a branch table of ``system``."""
    from ..analysis.sensitivity import point_sensitivity
    from ..continuation import PointLost
    from ..continuation.branch_rows import read_branch_row
    from ._run import held_states

    csv_path, row = branch_row(point)
    names, with_values = held_states(holds, ())
    found = read_branch_row(system, csv_path, row, hold=names, free=frees)
    for name, value in assignments(with_values, "hold").items():  # held there: the row has that value
        if name in system.names and not math.isclose(found.point[name], value, rel_tol=1e-9, abs_tol=1e-12):
            raise InputError("--hold", f"{name} is {found.point[name]:.10g} at {found.name}, not {value:g}: give "
                                       "the value it was held at on the branch, or the name alone")
    vary, lens = found.vary, list(found.unknowns)
    if of is not None and of != vary and of not in lens:
        raise InputError("--of", f"'{of}' is not solved for on the branch; one of: {', '.join([vary, *lens])}")
    found.check(system)
    try:
        return point_sensitivity(system, found.point, params, vary=vary, unknowns=lens, of=of, keep=keep,
                                 values=values)
    except PointLost as exc:  # name the row as the user did
        raise InputError("--point", f"{row}{str(exc).split(' point', 1)[1]}") from None
