"""``mechcont draw`` and ``mechcont animate``: pictures of a mechanism at a solution or along a branch."""

from __future__ import annotations

import click

from .._io import check_output_path
from ..errors import InputError
from ._app import cli
from ._parse import assignments, branch_row, freed_parameters, names
from ._run import QUIET_HELP, load_at, quiet_stdout


@cli.command("draw")
@click.argument("model")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="Set a parameter (SI units, or the units the file declares; angles in rad).")
@click.option("--start", "starts", multiple=True, metavar="NAME=VALUE",
              help="Hold a state at a value while solving (use with --free).")
@click.option("--free", "frees", multiple=True, metavar="NAME", help="A parameter solved for instead (e.g. F).")
@click.option("--point", metavar="BRANCH.csv:ROW",
              help="Draw row ROW (0-based, or a label such as LP1) of a branch CSV instead of solving.")
@click.option("--annotate", metavar="NAMES",
              help="Comma-separated variables to print on the figure [F,theta1 or the first angle].")
@click.option("--vary", metavar="NAME",
              help="With --point: the branch's continuation parameter, printed first "
                   "[the one parameter that changes along the branch].")
@click.option("--no-forces", is_flag=True, help="Do not draw the applied forces and moments.")
@click.option("--label-points", is_flag=True, help="Name the described points too (bodies are named in any case "
                                                   "in a spatial drawing).")
@click.option("--out", required=True, metavar="FILE", help="Output .png, .svg or .pdf.")
def draw_command(model: str, sets: tuple[str, ...], starts: tuple[str, ...], frees: tuple[str, ...], point: str | None,
                 annotate: str | None, vary: str | None, no_forces: bool, label_points: bool, out: str) -> None:
    """Draw MODEL (a built-in name or a description .toml) at one equilibrium or at a branch point.

    The equilibrium is solved at the --set values with the --start states held and the
    --free parameters solved for (e.g. --start theta1=0.3 --free F).
    """
    from ._run import mechanism_only

    mechanism_only(model, "draw")
    from ..outputs.animation import branch_frames
    from ..outputs.drawing import IMAGE_SUFFIXES, default_annotate, draw

    path = check_output_path(out, "--out", IMAGE_SUFFIXES)
    if point is not None and (sets or starts or frees):
        raise InputError("--point", "a branch point fixes every value; do not combine it with --set/--start/--free")
    system = load_at(model, assignments(sets, "set"))
    shown = names(annotate, "annotate") or default_annotate(system)
    if vary is not None:
        if point is None:
            raise InputError("--vary", "names the continuation parameter of a branch; use it with --point")
        system.index(vary)
    stable: bool | None = None
    label = ""
    if point is not None:
        csv_path, row = branch_row(point, "--point", "ROW")
        frames = branch_frames(system, csv_path)
        i = frames.row(row)
        x, stable, label = frames.values[i], frames.stable[i], frames.numbered_labels[i]
        lead = vary or frames.vary
        shown = tuple(dict.fromkeys([*([lead] if lead else []), *shown]))
    else:
        from ..continuation import find_equilibrium

        x = find_equilibrium(system, values=assignments(sets, "set"), hold=assignments(starts, "start"),
                             free=freed_parameters(system, frees))
        if system.mechanics is not None:
            stable = bool(system.mechanics.stability(x).stable)
    draw(system, x, path, annotate=shown, stable=stable, label=label, show_forces=not no_forces,
         label_points=label_points)
    click.echo(str(path))


@cli.command("animate")
@click.argument("model")
@click.option("--branch", "branch_csv", required=True, metavar="BRANCH.csv", help="Branch written by mechcont continue.")
@click.option("--out", required=True, metavar="FILE",
              help="Output .gif, .html (a page with play controls) or .mp4 (when ffmpeg is installed).")
@click.option("--fps", type=float, default=None,
              help="Frames per second [chosen so that the animation lasts at least 6 s, at most 15 fps].")
@click.option("--every", type=int, default=1, show_default=True,
              help="Use every N-th branch point (special points such as folds are always used).")
@click.option("--pause", type=float, default=0.6, show_default=True, help="Extra seconds on each special point.")
@click.option("--hold", "old_hold", type=float, default=None, hidden=True)  # deprecated spelling of --pause
@click.option("--annotate", metavar="NAMES",
              help="Comma-separated variables printed on each frame [F,theta1 or the first angle].")
@click.option("--vary", metavar="NAME",
              help="The branch's continuation parameter, printed first on each frame "
                   "[the one parameter that changes along the branch].")
@click.option("--diagram", metavar="X,Y",
              help="The panel beside the mechanism: the branch in the plane of two variables, with the current point "
                   "[the continuation parameter and the first annotated state]; 'none' for no panel.")
@click.option("--no-forces", is_flag=True, help="Do not draw the applied forces and moments.")
@click.option("--no-progress", is_flag=True, help="No progress bar (the results are printed).")
@click.option("--quiet", is_flag=True, help=QUIET_HELP)
def animate_command(model: str, branch_csv: str, out: str, fps: float | None, every: int, pause: float,
                    old_hold: float | None, annotate: str | None, vary: str | None, diagram: str | None,
                    no_forces: bool, no_progress: bool, quiet: bool) -> None:
    """Animate MODEL along a branch CSV (columns: variables, s, stability, label).

    Each frame prints the continuation parameter (--vary), the --annotate variables (angles
    in degrees), stable/unstable/fold and the special-point label; every special point is a
    frame and is held --pause seconds. Beside the mechanism the branch is drawn with the
    current point marked.
    """
    click.get_current_context().with_resource(quiet_stdout(quiet))
    from ._run import mechanism_only

    mechanism_only(model, "animate")
    from .._progress import Progress
    from ..outputs.animation import ANIMATION_SUFFIXES, animate, branch_frames, check_fps, check_hold, frame_rows
    from ..outputs.drawing import default_annotate

    path = check_output_path(out, "--out", ANIMATION_SUFFIXES)
    if fps is not None:
        check_fps(fps)
    # --hold names a held state in continue, folds and sensitivity (one meaning per option): the old spelling still works
    pause = check_hold(pause, "--pause") if old_hold is None else check_hold(old_hold, "--hold")
    if every < 1:
        raise InputError("--every", f"must be an integer >= 1, not {every}")
    system = load_at(model, {})
    shown = names(annotate, "annotate") or default_annotate(system)
    if vary is not None:
        system.index(vary)
    frames = branch_frames(system, branch_csv)
    pair: tuple[str, str] | None = None
    if diagram is None:  # the continuation parameter against the first annotated state
        x = vary or frames.vary
        y = next((n for n in shown if n != x and system.variable(n).kind == "state"), None)
        pair = (x, y) if x and y else None
    elif diagram.strip().lower() != "none":
        given = names(diagram, "diagram")
        if len(given) != 2:
            raise InputError("--diagram", f"give exactly two variable names X,Y (or none), not '{diagram}'")
        pair = (given[0], given[1])
    total = len(frame_rows(frames, every))
    if old_hold is not None:  # said once the input is known good, so that an error stays one line
        click.echo("note: animate --hold SECONDS is now --pause SECONDS (--hold will be removed)", err=True)
    with Progress("animation", total=total, unit="frames", quiet=no_progress or quiet) as bar:
        n = animate(system, frames, path, fps=fps, every=every, annotate=shown, vary=vary, diagram=pair,
                    show_forces=not no_forces, hold=pause, on_frame=bar.update if bar.enabled else None)
    click.echo(f"{path} ({n} frames)")
