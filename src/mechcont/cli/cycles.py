"""``mechcont cycles``: the family of periodic orbits born at a Hopf point, continued in one parameter."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from typing import TYPE_CHECKING

import click

from ..errors import ConvergenceError, InputError
from ._app import cli
from ._parse import assignments, at_values, branch_row
from ._run import check_outputs, continuation_options, load_at, run_continuation, warn_unreached

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from ..continuation import Branch, CycleBranch
    from ..equations import Model

#: Fields of the API's errors that name an option of this command.
_OPTIONS = {"point": "--point", "branch": "--point", "ntst": "--ntst", "ncol": "--ncol", "bounds": "--bounds",
            "vary": "--vary"}


@contextlib.contextmanager
def _as_option() -> Iterator[None]:
    """Re-raise the API's :class:`InputError` naming a field this command sets as naming its option."""
    try:
        yield
    except InputError as exc:
        if exc.field not in _OPTIONS:
            raise
        raise InputError(_OPTIONS[exc.field], str(exc)[len(exc.field) + 2:]) from None


def hopf_row(system: Model, point: str) -> tuple[npt.NDArray[np.float64], Branch]:
    """The model vector of ``BRANCH.csv:HBn`` (a row labelled HB of a table of this model) and the branch; one-line
    :class:`InputError` (field ``--point``) when the text, the table or the row is not that."""
    from ..continuation.branch_rows import read_branch_row

    csv_path, row = branch_row(point, "--point", "HBn (e.g. branch.csv:HB1)")
    with _as_option():
        found = read_branch_row(system, csv_path, row)
    branch, p = found.branch, found.point
    if p.label != "HB":
        raise InputError("--point", f"'{row}' of '{csv_path}' is {'labelled ' + p.label if p.label else 'not labelled'}"
                                    ", not a Hopf point (HB); the family of cycles starts at an HB row")
    return system.vector({n: float(p[n]) for n in system.names}), branch


@cli.command("cycles")
@click.argument("model")
@click.option("--point", required=True, metavar="BRANCH.csv:HBn",
              help="The Hopf point the family starts at: a row labelled HB of a continue table (e.g. branch.csv:HB1).")
@click.option("--vary", required=True, metavar="P", help="Parameter in which the family is continued.")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="Parameter value (SI units, or the units the file declares; angles in rad).")
@click.option("--bounds", "bnds", multiple=True, metavar="NAME=LO:HI",
              help="Stop where P (or the period, NAME=period, s) leaves [LO, HI].")
@click.option("--at", "at", multiple=True, metavar="P=V1,V2,...",
              help="Add orbits located exactly at these values of P (labelled UZ).")
@click.option("--ntst", type=int, default=20, show_default=True, help="Mesh intervals per orbit.")
@click.option("--ncol", type=int, default=4, show_default=True, help="Collocation points per interval (2..7).")
@click.option("--ds", type=float, default=None, help="Initial step (the orbit's L2 norm and P's scale).")
@click.option("--dsmax", type=float, default=None, help="Largest step.")
@click.option("--max-steps", type=int, default=None, help="Most steps.")
@click.option("--out", default=None, help="Table of the orbits: .csv.")
@click.option("--orbits", "orbits", default=None, metavar="FILE.csv",
              help="Table of one period of every orbit as the model's full vectors (for mechcont explore --orbits).")
@click.option("--plot", default=None, help="Amplitude diagram: .png, .svg or .pdf (max and min of a state against P).")
@click.option("--quiet", is_flag=True, help="Print nothing but errors.")
def cycles_command(model: str, point: str, vary: str, sets: tuple[str, ...], bnds: tuple[str, ...],
                   at: tuple[str, ...], ntst: int, ncol: int, ds: float | None, dsmax: float | None,
                   max_steps: int | None, out: str | None, orbits: str | None, plot: str | None, quiet: bool) -> None:
    """Continue the periodic orbits born at the Hopf point --point in --vary (orthogonal collocation,
    NTST intervals of NCOL Gauss points, mesh adaptation, Floquet multipliers).

    The table has per orbit: P, the period (s), min and max of every state, the largest
    non-trivial Floquet multiplier's modulus, stability and labels LPC (fold of cycles), PD
    (period doubling), NS (torus), UZ (--at) and EP (end).

    Example: mechcont cycles examples/ab.toml --set B=17 --point ab.csv:HB1 --vary D --bounds D=0:0.2
    --bounds period=0:100 --out cycles.csv
    """
    from ..continuation import cycles_from_hopf

    if out is not None and not str(out).lower().endswith(".csv"):
        raise InputError("--out", f"'{out}': the table of cycles is written as .csv")
    check_outputs(out, plot)
    _check_orbits(orbits)
    system = load_at(model, assignments(sets, "set"))
    system.index(vary)
    x, branch = hopf_row(system, point)
    x = system.vector(assignments(sets, "set"), base=x)
    options = continuation_options(bnds, ds, dsmax, max_steps)
    values = at_values(at, vary)
    try:
        with _as_option():
            family = run_continuation(cycles_from_hopf, system, x, vary, options=options, ntst=ntst, ncol=ncol,
                                      at=values, quiet=quiet, label="cycles")
        failure = None if family.status.success else family.message
    except ConvergenceError as exc:
        from ..continuation import CycleBranch

        if not isinstance(exc.partial, CycleBranch):  # no orbit continued: nothing to write
            raise
        family, failure = exc.partial, str(exc)
    shown = branch if branch.vary == vary else None
    if plot and shown is not None and "n_unstable_dynamic" not in shown.names:
        from ..analysis import with_dynamic_stability

        # the equilibria drawn beneath the cycles as their dynamics judge them (a mechanism's table holds its
        # static stability unless written by continue --dynamic): the family is born where that changes
        shown = with_dynamic_stability(system, shown)
    _write(family, out, plot, quiet, shown)
    if orbits:
        from ..outputs.cycle_orbits import write_orbits

        _check_orbits(orbits)
        write_orbits(family, system, orbits)
        if not quiet:
            click.echo(f"wrote {orbits}")
    warn_unreached(values, [float(v) for v, lab in zip(family.p, family.labels) if lab == "UZ"], vary, "family")
    if failure:
        raise ConvergenceError(failure)


def _check_orbits(path: str | None) -> None:
    """Check the --orbits table's path (a .csv, its folder writable) before any work."""
    from .._io import check_output_path

    check_output_path(path, "--orbits", (".csv",))


def _write(family: CycleBranch, out: str | None, plot: str | None, quiet: bool,
           branch: Branch | None = None) -> None:
    """The family's table (``--out``), amplitude diagram (``--plot``) and its orbits printed one a line."""
    from ..outputs.cycle_plots import amplitude_figure
    from ..outputs.plotting import save_figure
    from ..outputs.tables import cycle_lines

    check_outputs(out, plot)  # again: the folder may have changed during the run
    if out:
        family.to_csv(out)
    if plot:
        save_figure(amplitude_figure(family, branch=branch, title=f"{family.model}: cycles in {family.vary}"), plot)
    if quiet:
        return
    for line in cycle_lines(family):
        click.echo(line)
    for path in (out, plot):
        if path:
            click.echo(f"wrote {path}")
