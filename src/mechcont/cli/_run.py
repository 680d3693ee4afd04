"""Shared steps of the continuation commands: options, model, start point, outputs."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import TYPE_CHECKING, TypeVar

import click

from ..errors import InputError
from ._parse import assignments, bounds

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from ..continuation import Branch, ContinuationOptions
    from ..equations import Model

#: What a continuation run returns (:func:`run_continuation`).
R = TypeVar("R")
#: A click command function (:func:`common_options`).
F = TypeVar("F", bound=Callable[..., object])

__all__ = ["continuation_options", "solve_start", "write_branch", "common_options", "check_outputs", "run_continuation",
           "mechanism_only", "QUIET_HELP", "quiet_stdout"]

#: The help of every command's ``--quiet`` (tests/test_cli_options.py: one meaning per option name).
QUIET_HELP = "Print nothing but errors and warnings (on stderr); no progress bar. Files are still written."


@contextmanager
def quiet_stdout(quiet: bool) -> Iterator[None]:
    """With ``quiet``, drop what a command prints on stdout while the block runs (its report; errors and
    warnings go to stderr, files are still written); without, nothing changes. A command enters it for its
    whole run with ``click.get_current_context().with_resource(quiet_stdout(quiet))``."""
    if not quiet:
        yield
        return
    import io
    from contextlib import redirect_stdout

    with redirect_stdout(io.StringIO()):
        yield


def mechanism_only(model: str, what: str) -> None:
    """Before any work: :class:`InputError` when MODEL is an ODE file (a ``[system]`` table), for which
    ``what`` (a command or option) makes no sense."""
    from ..mechanism import is_system_file

    if is_system_file(model):
        raise InputError("model", f"{what} is a mechanism analysis; {model} is an ODE system")


def check_outputs(out: str | None, plot: str | None) -> None:
    """Check the --out branch table and --plot figure paths before any work (suffix, folder, writable)."""
    from .._io import check_output_path
    from ..outputs.plotting import FIGURE_SUFFIXES
    from ..outputs.tables import BRANCH_SUFFIXES

    check_output_path(out, "--out", BRANCH_SUFFIXES)
    check_output_path(plot, "--plot", FIGURE_SUFFIXES)


def common_options(f: F) -> F:
    """Options shared by `continue` and `folds`."""
    opts = [
        click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
                     help="Parameter value (SI units, or the units the file declares; angles in rad)."),
        click.option("--start", "starts", multiple=True, metavar="NAME=VALUE",
                     help="State held at a value to find the first solution (the --vary name is free then)."),
        click.option("--hold", "holds", multiple=True, metavar="NAME[=VALUE]",
                     help="State held during continuation (at VALUE when given, as in downlock/design/study)."),
        click.option("--free", "frees", multiple=True, metavar="NAME", help="Parameter solved for (keeps it square)."),
        click.option("--bounds", "bnds", multiple=True, metavar="NAME=LO:HI", help="Stop where NAME leaves [LO, HI]."),
        click.option("--ds", type=float, default=None, help="Initial step (scaled arclength)."),
        click.option("--dsmax", type=float, default=None, help="Largest step (scaled arclength)."),
        click.option("--max-steps", type=int, default=None, help="Most steps in each direction."),
        click.option("--quiet", is_flag=True, help=QUIET_HELP),
    ]
    for o in reversed(opts):
        f = o(f)
    return f


def continuation_options(bnds: Iterable[str], ds: float | None, dsmax: float | None,
                         max_steps: int | None) -> ContinuationOptions:
    """ContinuationOptions from the CLI values (:func:`mechcont.continuation.run_options`)."""
    from ..continuation import run_options

    return run_options(bounds(bnds), ds=ds, dsmax=dsmax, max_steps=max_steps, max_steps_field="--max-steps")


def held_states(holds: Iterable[str], starts: Sequence[str]) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """``--hold NAME`` or ``--hold NAME=VALUE`` (one meaning in every command: a held state; with a value it
    is held at that value, which then also finds the first solution, as ``--start NAME=VALUE`` does).
    Returns ``(held names, --start items)``; a state given a value by both options is an error."""
    names: list[str] = []
    given = {item.partition("=")[0].strip() for item in starts}
    extra: list[str] = []
    for item in holds:
        name, sep, _ = item.partition("=")
        name = name.strip()
        if sep:
            assignments([item], "hold")  # checks NAME=VALUE and the number
            if name in given:
                raise InputError("--hold", f"{name} is also given to --start: give its value once")
            extra.append(item)
        names.append(name)
    return tuple(names), (*starts, *extra)


def load_at(model: str, values: Mapping[str, float]) -> Model:
    """MODEL (a built-in name or a description file) at the ``--set`` ``values``: the one entry every
    command takes (:func:`mechcont.models.model_at`), so that what it writes in parameters (a stop's
    limit, a condition's target, the downlock hold, geometry, element values) follows them."""
    from ..models import model_at

    return model_at(model, values, field="--set")


def solve_start(system: Model, sets: Iterable[str], starts: Iterable[str], vary: str, frees: Iterable[str],
                holds: Iterable[str]) -> npt.NDArray[np.float64]:
    """The first equilibrium (:func:`mechcont.continuation.start_point`): ``--start`` states held, ``vary`` solved for."""
    from ..continuation import start_point

    return start_point(system, vary, values=assignments(sets, "set"), start=assignments(starts, "start"), free=frees,
                       hold=holds, start_field="--start", free_field="--free")


def run_continuation(fn: Callable[..., R], *args: object, quiet: bool = False, label: str = "continuation",
                     stop_on_signal: bool = False, **kwargs: object) -> R:
    """``fn(*args, progress=..., **kwargs)`` with a progress line (accepted steps) on a terminal.

    With ``stop_on_signal``, SIGTERM or SIGHUP ends the continuation where it is (the branch so far, its
    message saying so) instead of the command; the caller writes it and then calls
    :func:`mechcont._signals.raise_held` (exit status 128 + the signal)."""
    import contextlib

    from .._progress import Progress
    from .._signals import stop_gracefully

    with Progress(label, unit="steps", quiet=quiet) as bar, \
            (stop_gracefully() if stop_on_signal else contextlib.nullcontext()):
        return fn(*args, progress=bar if bar.enabled else None, **kwargs)


def write_branch(branch: Branch, out: str | None, plot: str | None, x: str, y: str, quiet: bool,
                 extra: Sequence[str] = ()) -> None:
    """Write the branch table (CSV or JSON by suffix) and the plot, checking paths first."""
    from ..outputs.plotting import branch_figure, save_figure
    from ..outputs.tables import approximate_warnings, special_table, write_branch_table

    check_outputs(out, plot)  # again: the folder may have changed during the run
    for name in (x, y):
        branch.column(name)
    if out:
        write_branch_table(branch, out)
    if plot:
        save_figure(branch_figure(branch, x, y, title=f"{branch.model}: {y} vs {x}"), plot)
    if not quiet:
        click.echo(special_table(branch, [x, y, *extra]))
        if branch.message:
            click.echo(f"ends: {branch.message}")
        for path in (out, plot):
            if path:
                click.echo(f"wrote {path}")
    if not branch.success:
        click.echo(f"warning: {branch.message}", err=True)
    for line in approximate_warnings(branch):
        click.echo(f"warning: {line}", err=True)


def warn_unreached(asked: Iterable[float], found: Iterable[float], vary: str, what: str) -> None:
    """Warn (stderr) of each ``--at`` value of ``vary`` with no UZ row among ``found`` (the UZ rows' values): the
    ``what`` (branch, family) never reached it, being outside its bounds."""
    found = list(found)
    for v in asked:
        if not any(abs(f - v) <= 1e-9 * max(1.0, abs(v)) for f in found):
            click.echo(f"warning: --at {vary}={v:g}: the {what} does not reach it (no UZ row)", err=True)
