"""``mechcont explore``: a self-contained HTML page to explore branches and see the mechanism at each point."""

from __future__ import annotations

import click

from ._app import cli
from ._parse import assignments


@cli.command("explore")
@click.argument("model")
@click.option("--branch", "branches", multiple=True, required=True, metavar="FILE.csv",
              help="A branch, fold-curve, time-history or cycles table (mechcont continue/folds/downlock/sweep/simulate/"
                   "cycles --out); repeat for several in one page.")
@click.option("--orbits", "orbits", multiple=True, metavar="FILE.csv",
              help="The orbits of a cycles table (mechcont cycles --orbits), one per cycles --branch in their order: "
                   "a cycle row then plays one period of the motion (an ODE: its phase portrait).")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="A variable's value (SI units, radians) on every row: one a table lacks.")
@click.option("--max-rows", type=int, default=None, metavar="N",
              help="Rows per branch embedded at most; a longer table is thinned, special points kept [3000].")
@click.option("--out", required=True, metavar="FILE.html", help="The page to write (.html).")
def explore_command(model: str, branches: tuple[str, ...], orbits: tuple[str, ...], sets: tuple[str, ...],
                    max_rows: int | None, out: str) -> None:
    """Write one HTML page to explore the branches of MODEL in a browser, offline.

    The bifurcation diagram (any two columns on the axes, stable solid, unstable dashed,
    special points marked and listed) beside the mechanism drawn at the point hovered,
    clicked or chosen with the slider (a spatial mechanism in front, side and top views),
    with its loads and values. A family of cycles is drawn as its amplitude (max and min of a state over
    each orbit); its rows play one period of the orbit. Example: mechcont explore overcentre --branch branch.csv --out branch.html
    """
    from .._io import check_output_path
    from ..models import model_at
    from ..outputs.explore import EXPLORE_SUFFIXES, MAX_ROWS, write_explore

    path = check_output_path(out, "--out", EXPLORE_SUFFIXES)
    values = assignments(sets, "set")
    written = write_explore(path, model_at(model, values), list(branches), values=values,
                            max_rows=MAX_ROWS if max_rows is None else max_rows, orbits=list(orbits))
    click.echo(f"wrote {written}")
