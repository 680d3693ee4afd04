"""The click group and the error handling shared by every command."""

from __future__ import annotations

import sys

import click

from ..errors import MechcontError


class _Group(click.Group):
    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except MechcontError as exc:  # bad input or failed solve: one line, exit 2, no traceback
            click.echo(f"error: {exc}", err=True)
            ctx.exit(2)


@click.group(cls=_Group)
@click.version_option(package_name="mechcont")
def cli():
    """mechcont: numerical continuation for quasi-static mechanisms (landing gear).

    Models are built-in names (see `mechcont models`) or mechanism description files
    (.toml). Values are SI units, angles in radians.
    """


def _register():
    # Each command module adds itself to `cli` on import.
    from . import _commands  # noqa: F401


def main(argv=None):
    """Entry point of the ``mechcont`` console script: bad input -> one line, exit 2."""
    _register()
    try:
        rv = cli.main(args=argv, prog_name="mechcont", standalone_mode=False)
    except click.exceptions.Exit as exc:
        sys.exit(exc.exit_code)
    except click.exceptions.Abort:
        click.echo("error: aborted", err=True)
        sys.exit(1)
    except click.UsageError as exc:
        click.echo(f"error: {exc.format_message()} (see 'mechcont {exc.ctx.command.name if exc.ctx else ''} --help')"
                   .replace("mechcont mechcont", "mechcont").replace(" ' --help'", " --help'"), err=True)
        sys.exit(2)
    except MechcontError as exc:
        click.echo(f"error: {exc}", err=True)
        sys.exit(2)
    sys.exit(rv if isinstance(rv, int) else 0)
