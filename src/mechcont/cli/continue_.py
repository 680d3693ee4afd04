"""``mechcont continue``: a branch of equilibria in one parameter."""

from __future__ import annotations

import click

from ._app import cli
from ._parse import at_values as parse_at
from ._run import (
    check_outputs,
    common_options,
    continuation_options,
    held_states,
    load_at,
    run_continuation,
    solve_start,
    warn_unreached,
    write_branch,
)


@cli.command("continue")
@click.argument("model")
@common_options
@click.option("--vary", required=True, metavar="NAME", help="Continuation parameter (any variable).")
@click.option("--out", default=None, help="Branch table: .csv or .json.")
@click.option("--plot", default=None, help="Figure: .png, .svg or .pdf.")
@click.option("--x", "xname", default=None, help="Plot x axis (default: the --vary name).")
@click.option("--y", "yname", default=None, help="Plot y axis (default: the --start state).")
@click.option("--stops", "with_stops", is_flag=True,
              help="Let the description's stops make and lose contact (SC, SR): the start is found with a "
                   "consistent set of stops in contact (at a limit, as the one-sided tangents decide) and each "
                   "direction is followed as --vary is pushed; a release onto an unstable branch is a non-smooth "
                   "fold (NSF), and where the mechanism lands is printed.")
@click.option("--at", "at", multiple=True, metavar="P=V1,V2,...",
              help="Rows located exactly at these values of the --vary parameter P (SI units), labelled UZ.")
@click.option("--dynamic", is_flag=True,
              help="Add the dynamic stability of each point (eigenvalues of the linearised equations of motion: "
                   "mass, damping, tangent stiffness, element states): columns n_unstable_dynamic, leading_real "
                   "(1/s) and leading_frequency (rad/s).")
@click.option("--damping", default=0.0, show_default=True,
              help="Mass-proportional damping (1/s) added in the dynamic stability (--dynamic), as simulate's.")
def continue_command(model: str, sets: tuple[str, ...], starts: tuple[str, ...], holds: tuple[str, ...],
                     frees: tuple[str, ...], bnds: tuple[str, ...], ds: float | None, dsmax: float | None,
                     max_steps: int | None, quiet: bool, vary: str, out: str | None, plot: str | None,
                     xname: str | None, yname: str | None, with_stops: bool, at: tuple[str, ...], dynamic: bool,
                     damping: float) -> None:
    """Continue equilibria of MODEL in --vary, both directions, within --bounds (with --stops, through
    the contacts and releases of the description's stops).

    Example: mechcont continue overcentre --set LU=0.4 --start theta1=0.3 --vary F
    --bounds theta1=-1.2:1.2 --out branch.csv --plot branch.png
    """
    from .._signals import raise_held
    from ..continuation import continuation
    from ..errors import InputError
    from ._parse import assignments

    check_outputs(out, plot)
    at_values = parse_at(at, vary)
    if at_values and with_stops:
        raise InputError("--at", "is not available with --stops; continue without --stops to add UZ rows")
    if damping and not dynamic:
        raise InputError("--damping", "applies to the dynamic stability only: give --dynamic too")
    if not (damping >= 0 and damping < float("inf")):
        raise InputError("--damping", f"must be a non-negative number (1/s), got {damping}")
    holds, starts = held_states(holds, starts)
    options = continuation_options(bnds, ds, dsmax, max_steps)
    system = load_at(model, assignments(sets, "set"))
    if system.ode is not None and not system.ode.algebraic:
        dynamic = True  # an ODE file's stability is its dynamics': always the dynamic columns and Hopf points
    if dynamic and system.mechanics is None and system.ode is None:
        raise InputError("--dynamic", f"{system.name} has no equations of motion (neither a mechanism nor an ODE)")
    if damping and system.mechanics is None:
        raise InputError("--damping", f"{system.name} is not a mechanism: mass-proportional damping needs masses")
    stops = system.stops
    if with_stops:
        from ..analysis.stops import check_stop_lens

        if not stops:
            raise InputError("--stops", f"{system.name} has no stops; declare them as [stops.NAME] tables "
                                        "(condition, min or max) in its description")
        check_stop_lens(system, vary, holds, frees)
    if with_stops:
        from ..analysis import continuation_with_stops
        from ..analysis.rest_on_stops import start_on_stops

        x0 = start_on_stops(system, vary, values=assignments(sets, "set"), start=assignments(starts, "start"),
                            hold=holds, free=frees, start_field="--start", free_field="--free").x
    else:
        x0 = solve_start(system, sets, starts, vary, frees, holds)
    if with_stops:
        branch = run_continuation(continuation_with_stops, system, x0, vary, direction=0, hold=holds, free=frees,
                                  options=options, quiet=quiet, stop_on_signal=True).branch
    else:
        if stops and not quiet:
            click.echo(f"note: {system.name} has stops ({', '.join(s.name for s in stops)}); here they are free, "
                       "their reactions held at their values: --stops lets them make and lose contact")
        # an ODE model's equilibria, and a mechanism's with --dynamic, are watched for Hopf points
        from ..equations import dynamics_of

        hopf = False if not dynamic else (dynamics_of(system, damping=damping) if damping else True)
        branch = run_continuation(continuation, system, x0, vary, hold=holds, free=frees, options=options,
                                  quiet=quiet, stop_on_signal=True, at=at_values, hopf=hopf)
    # shown and plotted: the --start state, else (with --stops) the first stop's condition, else the first unknown
    stopped = [s.condition for s in stops if s.condition in branch.names] if with_stops else []
    first_state = next(iter(assignments(starts, "start")), None) or next(iter(stopped), None) or branch.unknowns[0]
    statics = branch  # the branch as continued: the redundancy report reads its rows as full vectors
    if dynamic:
        from ..analysis.dynamic_stability import with_dynamic_stability

        branch = with_dynamic_stability(system, branch, damping=damping)
        if not quiet and len(branch):
            n = int(sum(branch["n_unstable_dynamic"] > 0))
            click.echo(f"dynamic stability: {n} of {len(branch)} points dynamically unstable")
    write_branch(branch, out, plot, xname or vary, yname or first_state, quiet)
    if not quiet:
        from ..outputs.tables import hopf_lines

        for line in hopf_lines(branch):
            click.echo(line)
    warn_unreached(at_values, [p[vary] for p in branch.special("UZ")], vary, "branch")
    raise_held()  # a SIGTERM that ended the continuation: its branch is written, now the exit status says so
    if with_stops and not quiet:
        from ..outputs.tables import jump_lines

        for line in jump_lines(branch, vary, yname or first_state):
            click.echo(line)
    if not quiet and system.mechanics is not None and len(branch.values):
        from ..analysis.redundancy import redundancy_along

        report = redundancy_along(system, statics)
        if report.dropped or report.changes or report.states[0].indeterminate:
            click.echo("redundant constraints along the branch:")
            names = [""] * len(branch.values)
            for p, name in zip(branch.special_points, branch.point_names()):
                names[p.index] = name
            for line in report.lines(names):
                click.echo(f"  {line}")
