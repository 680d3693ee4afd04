"""``mechcont study``: design and tolerance studies (grids, Latin hypercube, Monte Carlo), resumable, on Dask."""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import click

from ..errors import InputError
from ..units import derivative_unit as per_unit  # noqa: F401 - the slope's unit, by the name it had here
from ._app import cli
from ._parse import assignments, named_as, named_item, renamed

if TYPE_CHECKING:
    import pandas as pd

    from ..analysis.study import StudyResult, StudySpec


class _Estimate(Protocol):
    """What the study's cost estimate offers the command (:func:`mechcont.analysis.study.run_study`'s on_estimate)."""

    @property
    def seconds(self) -> float: ...

    def describe(self) -> str: ...


def _spec(model: str, sample: str | None, n: int | None, seed: int, dists: Sequence[str], grids: Sequence[str],
          spec_file: str | None, analyses: Sequence[str], sets: Sequence[str], holds: Sequence[str],
          condition: str | None, force: str | None, chunk: int | None, lock: Sequence[str] = (),
          until: float | None = None) -> StudySpec:
    """The study's :class:`~mechcont.analysis.study.StudySpec` from the --spec file or the options."""
    from ..analysis.study import Distribution, GridAxis, StudySpec, parse_axis, parse_distribution

    if spec_file is not None:
        if dists or grids:
            raise InputError("--spec", "give the parameters either in the --spec file or as --dist/--grid, not both")
        return StudySpec.read(spec_file, model, field="--spec")
    if grids and dists:
        raise InputError("--grid", "a study samples either a grid (--grid) or distributions (--dist), not both")
    if not grids and not dists:
        raise InputError("--dist", "give the sampled parameters: --dist NAME=normal:MEAN:SD (or uniform:LO:HI, "
                                   "truncnormal:MEAN:SD:LO:HI) or --grid NAME=LO:HI:N")

    def split(item: str, option: str) -> tuple[str, str]:
        return named_item(item, option, "NAME=...")

    params: tuple[tuple[str, GridAxis | Distribution], ...]
    if grids:
        if sample is not None:
            raise InputError("--sample", "a --grid study takes every grid point; --sample is for --dist studies")
        params = tuple((nm, parse_axis(r, f"--grid {nm}")) for nm, r in (split(g, "--grid") for g in grids))
        sampling = "grid"
    else:
        params = tuple((nm, parse_distribution(r, f"--dist {nm}")) for nm, r in (split(d, "--dist") for d in dists))
        sampling = sample or "mc"
        if n is None:
            raise InputError("--n", "give the number of samples, e.g. --n 10000")
    return StudySpec(model=model, sampling=sampling, parameters=params, n=n or 0, seed=seed,
                     analyses=tuple(analyses) or ("downlock",), values=tuple(assignments(sets, "set").items()),
                     hold=tuple(assignments(holds, "hold").items()), condition=condition, force=force, chunk=chunk or 0,
                     lock=tuple(lock), until=until or 0.0)


@cli.command("study")
@click.argument("model")
@click.option("--dist", "dists", multiple=True, metavar="NAME=KIND:...",
              help="A sampled parameter: uniform:LO:HI, normal:MEAN:SD or truncnormal:MEAN:SD:LO:HI (SI units).")
@click.option("--grid", "grids", multiple=True, metavar="NAME=LO:HI:N",
              help="A grid axis: N values from LO to HI (the last --grid varies fastest).")
@click.option("--sample", type=click.Choice(["mc", "lhs"]), default=None,
              help="Monte Carlo (default) or Latin hypercube, for --dist.")
@click.option("--method", default="sampling", show_default=True, metavar="sampling|form",
              help="sampling: solve every sample; form: the most probable failure point (FORM, SORM) and an "
                   "importance-sampling check of --n samples around it, written to DIR/reliability.json.")
@click.option("--n", type=int, default=None, help="Number of samples (--dist; with --method form the importance "
                                                  "samples, default 2000, 0 for none).")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the random samples.")
@click.option("--spec", "spec_file", default=None, metavar="FILE.toml",
              help="The study's settings from a TOML file instead of --dist/--grid/--n/--seed.")
@click.option("--analysis", "analyses", multiple=True, type=click.Choice(["downlock", "unlock", "branch", "freefall"]),
              help="Per sample: the downlock force (default); the unlock folds and fold margin; a summary of "
                   "the sample's own release run (branch); a freefall from --start (the released pose) until --lock.")
@click.option("--lock", multiple=True, metavar="STOP", help="--analysis freefall: a lock stop (repeatable).")
@click.option("--until", type=float, default=None, metavar="SECONDS", help="--analysis freefall: longest simulated time.")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="Fix a parameter (SI units, or the units the file declares; angles in rad).")
@click.option("--hold", "holds", multiple=True, metavar="NAME=VALUE",
              help="Downlock condition: a state held at a value (default: the model's).")
@click.option("--start", "starts", multiple=True, metavar="NAME=VALUE",
              help="--analysis freefall: the released pose, a coordinate or condition held while assembling "
                   "(as freefall --start).")
@click.option("--condition", default=None, metavar="NAME", help="Downlock condition: a declared [conditions] name.")
@click.option("--force", default=None, metavar="NAME", help="The downlock force (default: the model's, F).")
@click.option("--dir", "out_dir", default=None, metavar="DIR", help="Study folder (results.parquet, parts/, study.json); "
              "required.")
@click.option("--out", "old_out", default=None, hidden=True)  # its spelling before --out meant a file everywhere else
@click.option("--resume", is_flag=True, help="Continue the study in --dir: finished chunks are kept, not recomputed.")
@click.option("--chunk", type=int, default=None, help="Samples per task and per written part (default by analysis).")
@click.option("--scheduler", default="auto", show_default=True, metavar="auto|local|serial|ADDRESS",
              help="Where chunks run: auto (the first chunk here, timed; a local cluster only when the work left "
                   "pays for its start), a local cluster of worker processes, this process, or a Dask scheduler.")
@click.option("--workers", type=int, default=None, help="Worker processes of the local cluster (default: cores).")
@click.option("--plot", default=None, metavar="FILE", help="Figure: contour map (2-D grid) or histogram and sensitivities.")
@click.option("--max-hours", type=float, default=1.0, show_default=True, metavar="HOURS",
              help="Refuse a study whose computing time, estimated from a few samples timed first, is longer.")
@click.option("--verbose", is_flag=True, help="One line per chunk written.")
@click.option("--quiet", is_flag=True, help="Print nothing but errors.")
def study_command(model: str, dists: tuple[str, ...], grids: tuple[str, ...], sample: str | None, method: str,
                  n: int | None, seed: int, spec_file: str | None, analyses: tuple[str, ...], lock: tuple[str, ...],
                  until: float | None, sets: tuple[str, ...], holds: tuple[str, ...], starts: tuple[str, ...],
                  condition: str | None, force: str | None, out_dir: str | None, old_out: str | None, resume: bool,
                  chunk: int | None, scheduler: str, workers: int | None, plot: str | None, max_hours: float,
                  verbose: bool, quiet: bool) -> None:
    """Sample MODEL's parameters and solve the downlock (and unlock folds) at every sample.

    Results go to --dir as Parquet, one part per chunk as soon as it is done, then
    results.parquet; an interrupted study keeps its finished chunks and --resume computes
    only the rest. Each sample has a status: converged, or failed and why; failures never
    stop the study. Prints the probability of not locking unaided (downlock force <= 0) with
    its 95 % Clopper-Pearson interval and, for sampled tolerances, the sensitivity ranking.

    With --method form: the first- and second-order reliability of the same distributions
    (beta, P = Phi(-beta), SORM, the most probable failure point and each variable's
    importance alpha^2), checked by importance sampling around that point.
    """
    from .._io import check_output_folder, check_output_path
    from ..outputs.plotting import FIGURE_SUFFIXES

    if method not in ("sampling", "form"):
        raise InputError("--method", f"unknown method '{method}'; valid: sampling, form")
    from ..analysis.study import check_scheduler

    check_scheduler(scheduler)  # a misspelt scheduler is refused before anything runs, whichever path uses it
    plot_path = check_output_path(plot, "--plot", FIGURE_SUFFIXES)
    out, option = renamed(out_dir, old_out, "--dir", "--out")
    if out is None:
        raise InputError("--dir", "give the study's folder (--dir DIR)")
    check_output_folder(out, option)
    if not (math.isfinite(max_hours) and 0 < max_hours <= 1e6):
        raise InputError("--max-hours", f"must be a number of hours, 0 < HOURS <= 1e6, got {max_hours:g}")
    if starts:  # the released pose of a freefall study (its old spelling --hold still works)
        if "freefall" not in analyses:
            raise InputError("--start", "is the released pose of --analysis freefall (a downlock condition is --hold)")
        if holds:
            raise InputError("--start", "give the released pose by --start or its old spelling --hold, not both")
        holds = starts
    with named_as({"folder": option, "max_seconds": "--max-hours", **({"hold": "--start"} if starts else {})}):
        _study(model, dists, grids, sample, method, n, seed, spec_file, analyses, lock, until, sets, holds, condition,
               force, out, resume, chunk, scheduler, workers, plot, plot_path, verbose, quiet, max_hours * 3600.0)


def _study(model: str, dists: Sequence[str], grids: Sequence[str], sample: str | None, method: str, n: int | None,
           seed: int, spec_file: str | None, analyses: Sequence[str], lock: Sequence[str], until: float | None,
           sets: Sequence[str], holds: Sequence[str], condition: str | None, force: str | None, out: str,
           resume: bool, chunk: int | None, scheduler: str, workers: int | None, plot: str | None,
           plot_path: Path | None, verbose: bool, quiet: bool, max_seconds: float) -> None:
    """The study, its inputs checked for the folder and the figure."""
    import time

    if method == "form":
        for option, given in (("--lock", lock), ("--until", until is not None)):
            if given:  # they belong to --analysis freefall, which FORM does not run
                raise InputError(option, "does not apply to --method form (FORM on the downlock force; --lock and "
                                         "--until are for --analysis freefall with --method sampling)")
        return _form(model, dists, grids, sample, n, seed, spec_file, analyses, sets, holds, condition, force, out,
                     resume, chunk, scheduler, workers, plot, quiet)
    for name, v in (("--n", n), ("--chunk", chunk), ("--workers", workers)):
        if v is not None and v < 1:
            raise InputError(name, f"must be a positive whole number, got {v}")
    try:
        from ..analysis import study as st
    except ImportError:  # pragma: no cover - the study modules import no optional package at import time
        raise
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        raise InputError("study", f"needs pyarrow; {_hint()}") from None
    spec = _spec(model, sample, n, seed, dists, grids, spec_file, analyses, sets, holds, condition, force, chunk, lock, until)
    if plot_path is not None and "freefall" in spec.analyses:
        raise InputError("--plot", "a freefall study has no figure; read its results.parquet (column locked)")
    if plot_path is not None and spec.sampling == "grid" and len(spec.parameters) > 2:
        raise InputError("--plot", f"a grid over {len(spec.parameters)} parameters has no figure; use one or two --grid")
    from .._progress import Progress

    def chunk_line(k: int, seconds: float) -> None:
        if verbose:
            click.echo(f"chunk {k} written ({seconds:.3g} s)")
            sys.stdout.flush()

    def estimate_line(est: _Estimate) -> None:
        if not quiet and est.seconds >= 60:  # a study of a minute or more says what it is in for
            click.echo(f"study: {est.describe()}")
            sys.stdout.flush()

    t0 = time.perf_counter()
    with Progress("study", total=spec.size, unit="samples", quiet=quiet) as bar:
        result = st.run_study(spec, out, resume=resume, scheduler=scheduler, workers=workers,
                              progress=bar.update if bar.enabled else None, on_chunk=chunk_line,
                              on_warning=lambda line: click.echo(f"warning: {line}", err=True),
                              max_seconds=max_seconds, on_estimate=estimate_line)
    seconds = time.perf_counter() - t0
    df = result.frame()
    if not quiet:
        _report(df, spec, result, seconds)
    if plot_path is not None:
        from ..outputs.study_plots import plot_study

        plot_study(df, plot_path)
        if not quiet:
            click.echo(f"wrote {plot_path}")


def _form(model: str, dists: Sequence[str], grids: Sequence[str], sample: str | None, n: int | None, seed: int,
          spec_file: str | None, analyses: Sequence[str], sets: Sequence[str], holds: Sequence[str],
          condition: str | None, force: str | None, out: str, resume: bool, chunk: int | None, scheduler: str,
          workers: int | None, plot: str | None, quiet: bool) -> None:
    """``--method form``: FORM, SORM and importance sampling; DIR/reliability.json."""
    from ..analysis.reliability import DEFAULT_SAMPLES, downlock_reliability

    for option, given in (("--sample", sample), ("--resume", resume), ("--plot", plot), ("--grid", grids),
                          ("--analysis", [a for a in analyses if a != "downlock"])):
        if given:
            raise InputError(option, "does not apply to --method form (FORM on the downlock force of --dist "
                                     "distributions)")
    for name, v in (("--n", n), ("--chunk", chunk), ("--workers", workers)):
        if v is not None and v < (0 if name == "--n" else 1):
            raise InputError(name, f"must be a {'non-negative' if name == '--n' else 'positive'} whole number, got {v}")
    spec = _spec(model, None, DEFAULT_SAMPLES if n is None else max(n, 1), seed, dists, grids, spec_file, analyses,
                 sets, holds, condition, force, chunk)
    if spec.sampling == "grid":
        raise InputError("--spec", "--method form needs distributions, not a grid")
    samples = spec.n if n is None else n  # the spec keeps at least 1 sample; 0 here means no sampling check
    result = downlock_reliability(spec, n=samples, scheduler=scheduler, workers=workers)
    Path(out).mkdir(parents=True, exist_ok=True)
    path = Path(out) / "reliability.json"
    result.to_json(path)
    if not quiet:
        click.echo(result.summary())
        click.echo(f"wrote {path}")
    for line in result.findings:
        click.echo(f"warning: {line}", err=True)


def _hint() -> str:
    from ..analysis.study import STUDY_EXTRA_HINT

    return STUDY_EXTRA_HINT


def _report(df: pd.DataFrame, spec: StudySpec, result: StudyResult, seconds: float) -> None:
    """The study's summary lines (:func:`mechcont.analysis.study.study_report`), its warnings on stderr."""
    from ..analysis.study import study_report

    lines, warnings = study_report(df, spec, result, seconds)
    for i, line in enumerate(lines):
        click.echo(line)
        if i == 1:  # the failures right after the probability line, as they were found
            for w in warnings:
                click.echo(f"warning: {w}", err=True)
