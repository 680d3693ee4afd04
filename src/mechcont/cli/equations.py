"""``mechcont equations``: print the equations of a model or of a mechanism description file."""

from __future__ import annotations

from typing import TYPE_CHECKING

import click

from ..errors import InputError
from ._app import cli
from ._parse import assignments

if TYPE_CHECKING:
    from ..equations import Model


def _system(model: str, reduced: bool, overrides: dict[str, float]) -> Model:
    """A built-in model or description (see ``load_model``); ``reduced`` needs a description."""
    from ..equations import check_values_at
    from ..mechanism import find_description, load
    from ..models import BUILTIN_MODELS, load_model, model_at

    if not reduced:
        return model_at(model, overrides)
    from ._run import mechanism_only

    mechanism_only(model, "--reduced")
    path = None if model in BUILTIN_MODELS else find_description(model)
    if path is None:
        raise InputError("--reduced", f"'{model}' is not a mechanism description file; --reduced needs one "
                                      "(e.g. overcentre.toml, fourbar)")
    check_values_at(load_model(path), overrides, "--set")  # the values checked as every command checks them
    return load(model, reduced=True, **overrides)


@cli.command("equations")
@click.argument("model")
@click.option("--latex", is_flag=True, help="Print a LaTeX align environment instead of plain text.")
@click.option("--reduced", is_flag=True, help="The reduced form (description files only): tree coordinates "
                                               "and their reactions eliminated.")
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
              help="Override a parameter (SI units, or the units the file declares; angles in rad).")
@click.option("--shared", is_flag=True, help="Name repeated sub-expressions (w0, w1, ...) and list them first.")
def equations_command(model: str, latex: bool, reduced: bool, settings: tuple[str, ...], shared: bool) -> None:
    """Print the equations G(x) = 0 of MODEL: a built-in model name (overcentre), a shipped
    description stem (e.g. fourbar) or a mechanism description file (.toml)."""
    system = _system(model, reduced, assignments(settings, "set"))
    if system.ode is not None and not shared:
        from ..analysis.ode_check import ode_equations

        if not latex:
            kind = "0 = g(u, p), algebraic" if system.ode.algebraic else "du/dt = f(u, p)"
            click.echo(f"# {system.name}: ODE system {kind}, {len(system.state_names)} states")
            _header(system)
        click.echo(ode_equations(system, latex=latex))
        return
    if latex:
        click.echo(system.latex())
        return
    click.echo(f"# {system.name}: {len(system.equations)} equations in {len(system.state_names)} states")
    _header(system)
    click.echo(system.pretty(shared=shared))


def _header(system: Model) -> None:
    """The description, states and parameters of ``system`` as comment lines."""
    if system.description:
        click.echo(f"# {system.description}")
    click.echo("# states:")
    for name in system.state_names:
        v = system.variable(name)
        click.echo(f"#   {name} [{v.unit}] {v.description}".rstrip())
    click.echo("# parameters:")
    for name in system.parameter_names:
        v = system.variable(name)
        click.echo(f"#   {name} = {v.value:g} {v.unit}  {v.description}".rstrip())
