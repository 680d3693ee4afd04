"""``mechcont paper``: reproduce the paper's analyses as figures plus a Markdown summary."""

from __future__ import annotations

import sys

import click

from ._app import cli
from ._parse import named_as, renamed


@cli.command("paper")
@click.option("--dir", "out_dir", default=None, metavar="DIR", help="Folder for figures and summary [paper-output].")
@click.option("--out", "old_out", default=None, hidden=True)  # its spelling before --out meant a file everywhere else
@click.option("--only", default=None,
              help="Comma-separated sections to run (default: the paper's; dual_sidestay only when named).")
@click.option("--quiet", is_flag=True, help="Print nothing but errors.")
@click.option("--readme-images", "readme_dir", default=None, metavar="DIR",
              help="Only draw the README's images (three of the paper's figures) into DIR, with readme-images.json "
                   "recording what they show (the repository's: docs).")
def paper_command(out_dir: str | None, old_out: str | None, only: str | None, quiet: bool,
                  readme_dir: str | None) -> None:
    """Reproduce the paper's analyses with the built-in models (figures, summary.md, timings.txt).

    summary.md holds the results only, so two runs give identical files; run times go to
    stdout and timings.txt. A progress line shows on a terminal (not with --quiet).
    """
    if readme_dir is not None:
        from .._io import check_output_folder
        from ..paper.readme_images import write

        images = check_output_folder(readme_dir, "--readme-images")
        images.mkdir(parents=True, exist_ok=True)
        for path in write(images):
            if not quiet:
                click.echo(f"wrote {path}")
        return
    from .._io import check_output_folder
    from ..paper.sections import chosen_sections, run_sections

    with named_as({"only": "--only"}):
        chosen = chosen_sections(only)
    folder, option = renamed(out_dir, old_out, "--dir", "--out")
    out = check_output_folder(folder or "paper-output", option)
    out.mkdir(parents=True, exist_ok=True)
    verbose = not quiet and sys.stderr.isatty()

    def started(name: str, title: str) -> None:
        if verbose:
            click.echo(f"[{name}] {title} ...", err=True)

    run = run_sections(out, chosen, quiet=quiet, on_section=started)
    if not quiet:
        click.echo("run times:\n" + run.timings_table())
        click.echo(f"wrote {run.summary} and {len(list(out.glob('*.png')))} figures in {out}")
