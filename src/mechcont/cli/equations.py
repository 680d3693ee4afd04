"""``mechcont equations``: print the equations of a model or of a mechanism description file."""

from __future__ import annotations

import click

from ..errors import InputError
from ._app import cli


def _system(model: str, reduced: bool, overrides: dict[str, float]):
    """A built-in hand model by name, else a description file (path or shipped stem)."""
    from ..mechanism import builtin_descriptions, find_description, load
    from ..models import build_overcentre

    hand = {"overcentre": build_overcentre}
    if model in hand:
        if reduced:
            raise InputError("--reduced", f"'{model}' is a hand-formulated model; --reduced needs a description file")
        return hand[model](**overrides)
    if find_description(model) is None:
        raise InputError("model", f"unknown model '{model}'; valid: {', '.join(sorted(hand))}, a shipped "
                                  f"description ({', '.join(builtin_descriptions())}) or a path to a .toml file")
    return load(model, reduced=reduced, **overrides)


def _assignments(items) -> dict[str, float]:
    out = {}
    for item in items:
        name, sep, value = item.partition("=")
        try:
            if not sep or not name.strip():
                raise ValueError
            out[name.strip()] = float(value)
        except ValueError:
            raise InputError("--set", f"'{item}' is not NAME=VALUE with a number (SI units, radians)") from None
    return out


@cli.command("equations")
@click.argument("model")
@click.option("--latex", is_flag=True, help="Print a LaTeX align environment instead of plain text.")
@click.option("--reduced", is_flag=True, help="The reduced form (description files only): tree coordinates "
                                               "and their reactions eliminated.")
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE", help="Override a parameter (SI units).")
def equations_command(model: str, latex: bool, reduced: bool, settings: tuple[str, ...]):
    """Print the equations G(x) = 0 of MODEL: a built-in model name (overcentre), a shipped
    description stem (e.g. fourbar) or a mechanism description file (.toml)."""
    system = _system(model, reduced, _assignments(settings))
    if latex:
        click.echo(system.latex())
        return
    click.echo(f"# {system.name}: {len(system.equations)} equations in {len(system.state_names)} states")
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
    click.echo(system.pretty())
