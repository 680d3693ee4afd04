"""``mechcont optimize``: a quantity minimised or maximised over design parameters, on exact gradients."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import click

from ..errors import InputError
from ._app import cli
from ._parse import assignments, bounds, branch_row, named_as, named_item

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from ..analysis.optimize import Constraint, OptimumResult
    from ..analysis.study import Distribution
    from ..equations import Model


@cli.command("optimize")
@click.argument("model")
@click.option("--minimize", "minimize_", metavar="QUANTITY",
              help="Quantity to minimise: downlock_force, unlock_force, fold_load, a parameter or (a lock on stops) "
                   "a stop's reaction R_NAME at rest.")
@click.option("--maximize", "maximize_", metavar="QUANTITY", help="Quantity to maximise (as --minimize).")
@click.option("--design", "designs", multiple=True, required=True, metavar="NAME=LO:HI",
              help="A design parameter and its bounds (SI units, rad); repeat for each.")
@click.option("--constraint", "constraints", multiple=True, metavar="'QUANTITY >= NUMBER'",
              help="A constraint, QUANTITY >= NUMBER or QUANTITY <= NUMBER (SI), or 'P(not locking) <= P' "
                   "(FORM over the --dist tolerances); 'stop_preload >= N' holds every stop's reaction at rest; "
                   "repeat for each.")
@click.option("--dist", "dists", multiple=True, metavar="NAME=KIND:...",
              help="A toleranced parameter for P(not locking): normal:MEAN:SD, uniform:LO:HI or "
                   "truncnormal:MEAN:SD:LO:HI (SI); on a --design parameter it moves with the design value.")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="Another parameter's value (SI units, or the units the file declares; angles in rad).")
@click.option("--force", "force", default=None, metavar="NAME",
              help="For unlock_force of a lock on stops: the force that opens it (default the model's downlock force).")
@click.option("--point", metavar="BRANCH.csv:LPn", help="For fold_load: the start fold, a point of a branch table.")
@click.option("--max-iter", type=click.IntRange(1, 1000), default=100, show_default=True, help="Most SLSQP iterations.")
@click.option("--starts", type=click.IntRange(1, 20), default=1, show_default=True,
              help="Also start SLSQP from N points per --design parameter (a grid over the bounds, corners "
                   "included) and keep the best feasible optimum: SLSQP alone finds a local one.")
@click.option("--out", default=None, metavar="FILE.json", help="Write the optimum as JSON (SI units).")
@click.option("--plot", default=None, metavar="FILE",
              help="With two --design parameters: the optimum on their design map, with the active constraints' "
                   "boundaries (.png, .svg, .pdf).")
def optimize_command(model: str, minimize_: str | None, maximize_: str | None, designs: tuple[str, ...],
                     constraints: tuple[str, ...], dists: tuple[str, ...], sets: tuple[str, ...], force: str | None,
                     point: str | None, max_iter: int, starts: int, out: str | None, plot: str | None) -> None:
    """Minimise or maximise a quantity over the --design parameters within their bounds, under --constraint.

    SLSQP on exact gradients (implicit-function theorem). Prints the optimum, the active
    constraints and bounds with their multipliers (the change of the optimum per unit of
    the bound), and the iterations.

    Example: mechcont optimize nose_gear --minimize k --design k=1000:8000
    --constraint "downlock_force >= 100"

    Reliability-based: mechcont optimize nose_gear --maximize LU --design LU=1.2:1.4
    --dist LU=normal:1.3:0.01 --constraint "P(not locking) <= 1e-6"

    On the design map: mechcont optimize nose_gear --maximize LU --design l_sp1=-0.175:0.175
    --design LU=1.25:1.35 --constraint "downlock_force >= 100" --plot optimum.png
    """
    from ._run import mechanism_only

    mechanism_only(model, "optimize")
    from .._io import check_output_path
    from ..analysis.optimize import NOT_LOCKING, Constraint, optimize
    from ..equations import check_values_at
    from ..models import model_at
    from ..outputs.plotting import FIGURE_SUFFIXES

    check_output_path(out, "--out", (".json",))
    plot_path = check_output_path(plot, "--plot", FIGURE_SUFFIXES)
    objective = minimize_ if maximize_ is None else maximize_
    if objective is None or (minimize_ is not None and maximize_ is not None):
        raise InputError("--minimize", "give exactly one of --minimize QUANTITY or --maximize QUANTITY")
    design = bounds(designs, "--design")
    values = assignments(sets, "set")
    if plot_path is not None and len(design) != 2:
        raise InputError("--plot", f"a design map needs exactly two --design parameters, got {len(design)}")
    system = model_at(model, values)
    for n, (lo, hi) in design.items():  # each finite bound a value the model accepts, as --set checks it
        for v in (lo, hi):
            if math.isfinite(v):
                check_values_at(system, {n: v}, "--design")
    if force is not None and force not in system.parameter_names:
        raise InputError("--force", f"'{force}' is not a parameter of {system.name}; parameters: "
                                    + ", ".join(system.parameter_names))
    fold = _fold(system, point) if point else None
    random = _distributions(dists)
    for n, d in random.items():  # each distribution's centre a value the model accepts, as --set checks it
        check_values_at(system, {n: d.centre}, "--dist")
    try:
        parsed = [Constraint.parse(c) for c in constraints]
        if random and not any(c.quantity == NOT_LOCKING for c in parsed):
            raise InputError("--dist", f"tolerances are for a constraint '{NOT_LOCKING} <= P'; none is given")
        result = optimize(system, objective, design, maximize=maximize_ is not None, constraints=parsed,
                          values=values, fold=fold, max_iter=max_iter, random=random, starts=starts, force=force)
    except InputError as exc:
        if exc.field in ("constraint", "dist"):
            raise InputError(f"--{exc.field}", str(exc)[len(exc.field) + 2:]) from None
        raise
    click.echo(result.summary())
    if out:
        check_output_path(out, "--out", (".json",))  # again: the folder may have changed meanwhile
        result.to_json(out)
        click.echo(f"wrote {out}")
    if plot_path is not None:
        _plot(system, result, "maximum" if maximize_ is not None else "minimum", design, parsed, values, random,
              plot_path)
    if not result.success:
        click.echo(f"warning: the optimiser did not converge: {result.message}", err=True)
    for c in result.violated:
        click.echo(f"warning: the design printed does not meet {c}: no design within the bounds may", err=True)


def _plot(system: Model, result: OptimumResult, sense: str, design: Mapping[str, tuple[float, float]],
          constraints: Sequence[Constraint], values: Mapping[str, float], random: Mapping[str, Distribution],
          path: Path) -> None:
    """The optimum on the design map of its two design parameters, written to ``path``."""
    from ..analysis.optimize import optimum_map
    from ..outputs.design_plots import optimum_figure
    from ..outputs.plotting import save_figure
    from .downlock import warn

    omap = optimum_map(system, result, design, constraints=constraints, values=values, random=random)
    warn([*omap.region.warnings, *omap.notes])
    unit = result.units.get(result.objective, "")
    fig = optimum_figure(omap, title=f"{system.name}: {sense} of {result.objective} on the design map",
                         value_text=f"{result.objective} = {result.value:.4g} {unit}".rstrip())
    save_figure(fig, path, dpi=120)
    click.echo(f"wrote {path}")


def _distributions(dists: Sequence[str]) -> dict[str, Distribution]:
    """``--dist NAME=KIND:...`` items -> ``{NAME: Distribution}`` (each name once)."""
    from ..analysis.study import parse_distribution

    out: dict[str, Distribution] = {}
    for item in dists:
        name, rest = named_item(item, "--dist", "NAME=KIND:... (e.g. LU=normal:1.3:0.01)")
        if name in out:
            raise InputError("--dist", f"{name} has two distributions")
        out[name] = parse_distribution(rest, f"--dist {name}")
    return out


def _fold(system: Model, point: str) -> tuple[npt.NDArray[np.float64], list[str], str]:
    """``--point BRANCH.csv:LPn``: the fold's full vector, the states solved for there and the branch's parameter."""
    from ..continuation.branch_rows import read_branch_row

    csv_path, row = branch_row(point, "--point", "LPn (e.g. branch.csv:LP1)")
    with named_as({"point": "--point"}):
        found = read_branch_row(system, csv_path, row)
    if found.point.label != "LP":
        raise InputError("--point", f"'{row}' is not a fold; fold_load follows a point labelled LP")
    found.check(system, "LP")
    return found.point.x, list(found.unknowns), found.vary
