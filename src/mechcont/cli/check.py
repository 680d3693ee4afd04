"""``mechcont check``: what mechcont made of a mechanism description, and whether it is sound."""

from __future__ import annotations

from typing import TYPE_CHECKING

import click

from ..errors import InputError
from ._app import cli
from ._parse import assignments

if TYPE_CHECKING:
    from ..mechanism import CheckReport


@cli.command("check")
@click.argument("model")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="Override a parameter (SI units, or the units the file declares; angles in rad).")
@click.option("--reduced", is_flag=True, help="Check the reduced form (tree coordinates and their reactions "
                                               "eliminated).")
@click.option("--plot", default=None, metavar="FILE",
              help="Write a drawing of the assembled configuration with every body named, and every point of a "
                   "planar mechanism (.png, .svg or .pdf).")
@click.option("--label-points", is_flag=True, help="With --plot of a spatial mechanism: name every point too.")
@click.option("--quiet", is_flag=True, help="Print nothing but errors and findings (on stderr).")
@click.pass_context
def check_command(ctx: click.Context, model: str, sets: tuple[str, ...], reduced: bool, plot: str | None,
                  label_points: bool, quiet: bool) -> None:
    """Check the mechanism description MODEL (a .toml file, or the stem of a shipped one:
    overcentre means overcentre.toml, not the hand-formulated model).

    Prints the degrees of freedom from the rank of the constraint Jacobian (and the intended
    count), the system's size, redundant constraints and their joints, the loop-closure
    residual of every joint at the assembled configuration, the parameters, the states at
    the assembled configuration and at the equilibrium Newton reaches from it (angles in
    degrees), that equilibrium's stability and the continuation's variable scales.

    Warnings (sound, but likely not what was meant: a bar's point beyond its ends, measured from a
    hinge as if the bar began there) are listed before the findings and do not change the exit
    status. Exit status: 0 when all is well; 1 when there are findings (a degree-of-freedom count
    other than the declared dof, redundant constraints refused by redundant = "error", an
    open joint, no equilibrium found, no consistent set of stops in contact), listed at the
    end of the report (with --quiet: one line 'finding: ...' each on stderr); 2 for input
    the model cannot be built from (one line on stderr), e.g. a loop that cannot close.

    An ODE file ([system] table, docs/ode-format.md): its states, parameters and rates, the residual
    and the eigenvalues of df/du at the initial state, and the equilibrium Newton reaches from there.
    """
    from ..mechanism import check_report, is_system_file

    overrides = assignments(sets, "set")
    if is_system_file(model):
        return _check_ode(ctx, model, overrides, reduced=reduced, plot=plot, quiet=quiet)
    path = None
    if plot is not None:  # checked before any work
        from .._io import check_output_path
        from ..outputs.drawing import IMAGE_SUFFIXES

        path = check_output_path(plot, "--plot", IMAGE_SUFFIXES)
    if overrides:
        _check_values(model, overrides)
    report = check_report(model, reduced=reduced, **overrides)
    stops, finding = _stops_text(report)
    if finding:
        from dataclasses import replace

        report = replace(report, findings=(*report.findings, finding))
    if path is not None:
        from ..outputs.drawing import draw

        draw(report.system, report.x, path, labels=True, title=f"{report.name}: assembled configuration",
             label_points=label_points)
    if not quiet:
        click.echo(report.to_text(stops))
        if path is not None:
            click.echo(f"drawing: {path}")
    else:
        for warning in report.warnings:
            click.echo(f"warning: {warning}", err=True)
        for finding in report.findings:
            click.echo(f"finding: {finding}", err=True)
    if report.findings:
        ctx.exit(1)


def _check_values(model: str, values: dict[str, float]) -> None:
    """The ``--set`` values checked as every command checks them (:func:`mechcont.equations.check_values_at`);
    the report is then the description built at them, the model :func:`mechcont.models.model_at` gives."""
    from ..equations import check_values_at
    from ..mechanism import find_description
    from ..models import load_model

    path = find_description(model)
    if path is None:  # check_report says what is wrong with the name
        return
    system = load_model(path)
    for n in values:  # a description checked at parameter values: no state guesses here
        if n not in system.parameter_names:
            raise InputError(n, f"not a parameter of {system.name}; valid: {', '.join(system.parameter_names)}")
    check_values_at(system, values, "--set")


def _stops_text(report: CheckReport) -> tuple[str, str]:
    """The stops section (:func:`mechcont.analysis.rest_on_stops.stops_at_rest` from the assembled configuration;
    empty when the mechanism has no stops), and a finding when there is no equilibrium on them."""
    from ..analysis.rest_on_stops import stops_at_rest

    if not report.system.stops:
        return "", ""
    rest = stops_at_rest(report.system, report.x)
    return "\n".join(rest.lines()), rest.failure


def _check_ode(ctx: click.Context, model: str, overrides: dict[str, float], *, reduced: bool, plot: str | None,
               quiet: bool) -> None:
    """``check`` of an ODE file (:func:`mechcont.analysis.ode_check.ode_report`); exit status 1 with findings."""
    from ..analysis.ode_check import ode_report
    from ..models import model_at

    for given, option in ((reduced, "--reduced"), (plot is not None, "--plot")):
        if given:
            raise InputError(option, f"is a mechanism option (a drawing, a reduced form); {model} is an ODE system")
    report = ode_report(model_at(model, overrides, field="--set"))
    if not quiet:
        click.echo(report.to_text())
    else:
        for finding in report.findings:
            click.echo(f"finding: {finding}", err=True)
    if report.findings:
        ctx.exit(1)
