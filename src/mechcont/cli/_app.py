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
            sys.exit(2)


@click.group(cls=_Group)
@click.version_option(package_name="mechcont")
def cli():
    """mechcont: numerical continuation for quasi-static mechanisms (landing gear)."""


def _register():
    # Each command module adds itself to `cli` on import.
    from . import _commands  # noqa: F401


def main(argv=None):
    """Entry point of the ``mechcont`` console script."""
    _register()
    cli.main(args=argv, prog_name="mechcont", standalone_mode=True)
