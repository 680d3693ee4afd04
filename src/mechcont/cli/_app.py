"""The click group and the error handling shared by every command."""

from __future__ import annotations

import sys

import click

from ..errors import MechcontError


class _Group(click.Group):
    """Every failure the user can fix is one line on stderr and exit status 2."""

    def main(self, args=None, prog_name=None, standalone_mode=True, **extra):
        if not standalone_mode:
            return super().main(args, prog_name, standalone_mode=False, **extra)
        try:
            rv = super().main(args, prog_name, standalone_mode=False, **extra)
        except click.exceptions.Exit as exc:
            sys.exit(exc.exit_code)
        except click.exceptions.Abort:
            click.echo("error: aborted", err=True)
            sys.exit(1)
        except click.UsageError as exc:
            where = f"{exc.ctx.command_path} --help" if exc.ctx else "mechcont --help"
            click.echo(f"error: {exc.format_message()} (see '{where}')", err=True)
            sys.exit(2)
        except MechcontError as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(2)
        sys.exit(rv if isinstance(rv, int) else 0)


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
    """Entry point of the ``mechcont`` console script."""
    _register()
    cli.main(args=argv, prog_name="mechcont")
