"""Running a study: chunk by chunk in this process, or on a Dask cluster, written as it goes.

:func:`run_study` computes the chunks not yet on disk (see :class:`StudyStore`), writes each
as soon as it is done, and combines them into ``results.parquet`` at the end. Where the
chunks run (:func:`~._schedule.run_parts`):

* ``scheduler=None`` (or ``"serial"``): in this process, one after the other;
* ``scheduler="auto"``: the first chunk in this process, timed; the others on a local cluster
  only when the computing left, estimated from it, would pay for the cluster's start
  (see :mod:`._schedule`), else here too;
* ``scheduler="local"``: a :class:`dask.distributed.LocalCluster` of worker processes
  (one thread each, ``workers`` of them, default one per core), started and stopped here
  (not when one chunk is left to compute: that runs in this process);
* ``scheduler="tcp://HOST:PORT"`` (any address): an existing Dask scheduler.

On Dask the model reaches each worker once: the study spec (with the description file's
text, when the model is a file) is scattered to every worker, each worker loads and compiles
the model on its first task (from the disk cache of compiled code where it has one:
``MECHCONT_CACHE_DIR``) and keeps it for every further task. Tasks are whole chunks (a
chunk of the default size takes >= 0.1 s, well above Dask's ~1 ms per task), results come
back as plain arrays and are written by this process only, so workers need no access to the
study folder. Every chunk runs the same :func:`run_chunk` on the same compiled code wherever
it runs, so the results agree whichever scheduler ran them (to the solves' rounding: another
process may sit on another BLAS kernel).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...equations import units_of
from ...errors import InputError
from ._dask import STUDY_EXTRA_HINT
from ._estimate import MAX_SECONDS, PILOT_SAMPLES, Estimate, check_cost, estimate_study
from ._kernels import COLUMNS, check_spec, result_columns, run_chunk
from ._schedule import check_scheduler, run_parts
from ._spec import StudySpec
from ._store import StudyStore

if TYPE_CHECKING:
    import pandas as pd
    from distributed import Client

    from ...equations import Model

__all__ = ["run_study", "StudyResult", "ModelSource", "load_study_model"]

@dataclass(frozen=True)
class ModelSource:
    """How a worker gets the model: a built-in name, or a description file's name and text."""

    model: str
    text: str | None = None

    @classmethod
    def of(cls, model: str) -> ModelSource:
        """The source of ``model`` (reads a description file's text)."""
        from ...mechanism import find_description
        from ...models import BUILTIN_MODELS

        if model in BUILTIN_MODELS:
            return cls(model)
        path = find_description(model)
        if path is None:
            return cls(model)  # load_model names what is wrong
        return cls(str(model), Path(path).read_text(encoding="utf-8"))


_LOADED: dict[ModelSource, Model] = {}


def load_study_model(source: ModelSource) -> Model:
    """The compiled model of ``source``, loaded once per process (a worker keeps it for every chunk)."""
    if source not in _LOADED:
        from ...models import load_model

        if source.text is None:
            _LOADED[source] = load_model(source.model)
        else:
            path = Path(source.model)
            if not (path.is_file() and path.read_text(encoding="utf-8") == source.text):
                import tempfile

                # a worker without the file (another machine): the shipped text, under the same name
                folder = Path(tempfile.mkdtemp(prefix="mechcont-study-"))
                path = folder / (path.name if path.suffix == ".toml" else f"{path.name}.toml")
                path.write_text(source.text, encoding="utf-8")
            _LOADED[source] = load_model(str(path))
    return _LOADED[source]


def _chunk_task(source: ModelSource, spec: StudySpec, k: int) -> tuple[int, dict, float]:
    """One chunk on a worker: ``(k, columns, seconds)``."""
    t0 = time.perf_counter()
    system = load_study_model(source)
    cols = run_chunk(system, spec, k, samples=_samples(spec))
    return k, cols, time.perf_counter() - t0


_SAMPLES: dict[StudySpec, np.ndarray] = {}


def _samples(spec: StudySpec) -> np.ndarray:
    """All samples of ``spec``, drawn once per process."""
    if spec not in _SAMPLES:
        _SAMPLES.clear()
        _SAMPLES[spec] = spec.samples()
    return _SAMPLES[spec]


@dataclass(frozen=True)
class StudyResult:
    """What :func:`run_study` did.

    Attributes
    ----------
    folder:
        The study folder; ``results`` is its ``results.parquet``.
    computed, reused:
        Chunks computed by this run, and chunks found done on disk (resumed).
    seconds:
        Wall time of this run (s), including starting a cluster.
    samples:
        Number of samples in the study.
    ran_on:
        Where the chunks ran: ``"this process"``, a local cluster, or the scheduler's address.
    """

    folder: Path
    results: Path
    computed: list[int]
    reused: list[int]
    seconds: float
    samples: int
    ran_on: str = "this process"

    def frame(self) -> pd.DataFrame:
        """The results as a :class:`pandas.DataFrame` (units in ``.attrs["units"]``)."""
        from ._results import read_results

        return read_results(self.results)


def _units(system: Model, spec: StudySpec, force: str | None) -> dict[str, str]:
    # the force columns in the downlock force's own unit (N, or N m for a moment, or g mm/s^2 for a file in mm
    # and g), the others as COLUMNS says
    unit = system.variable(force).unit if force is not None else ""
    forces = {n: unit or units_of(system).label(u) for n, (u, _) in COLUMNS.items() if u == "N"}
    return {**forces, **{n: system.variable(n).unit for n in spec.names}}


def run_study(spec: StudySpec, folder: str | Path, *, resume: bool = False, scheduler: str | None = None,
              workers: int | None = None, progress: Callable[[int], None] | None = None,
              on_chunk: Callable[[int, float], None] | None = None,
              on_warning: Callable[[str], None] | None = None, max_seconds: float | None = None,
              on_estimate: Callable[[Estimate], None] | None = None) -> StudyResult:
    """Run ``spec`` into ``folder``, computing only the chunks not already there.

    Parameters
    ----------
    spec:
        The study.
    folder:
        The study folder (see :class:`StudyStore`).
    resume:
        Continue the study already in ``folder`` (same spec): finished chunks are kept.
    scheduler:
        ``None`` or ``"serial"`` (this process), ``"auto"`` (the first chunk here, timed, the others on a
        local cluster only when the computing left would pay for its start: :mod:`._schedule`),
        ``"local"`` (a local cluster of worker processes) or a Dask scheduler's address.
    workers:
        Worker processes of the local cluster (default: the number of cores).
    progress:
        Called with the number of samples of each chunk written.
    on_chunk:
        Called with ``(k, seconds)`` after chunk ``k`` is written.
    on_warning:
        Called with one line per part found on disk that is not this study's (another
        study's settings or samples, truncated, not Parquet): that chunk is computed again.
    max_seconds:
        Limit on the estimated computing time (s; default :data:`~._estimate.MAX_SECONDS`, one
        hour): a study of more than :data:`~._estimate.PILOT_SAMPLES` samples to do is timed on a
        few of them first (:func:`~._estimate.estimate_study`) and refused when above it.
    on_estimate:
        Called with the :class:`~._estimate.Estimate` before anything is written (not for a small study).

    Returns
    -------
    StudyResult

    Raises
    ------
    InputError
        Unknown names, an unknown scheduler, a folder holding another study, a spec that does not fit the model, an
        estimate above ``max_seconds``: all before anything is written.
    """
    t0 = time.perf_counter()
    check_scheduler(scheduler, workers)
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        raise InputError("study", f"needs pyarrow; {STUDY_EXTRA_HINT}") from None
    spec = spec.with_model_hash()
    source = ModelSource.of(spec.model)
    system = load_study_model(source)
    _, force = check_spec(system, spec)
    units = _units(system, spec, force)
    store = StudyStore(folder, spec, resume=resume)
    for k, why in store.verify(result_columns(spec)).items():
        if on_warning is not None:
            on_warning(f"part {k} of the study ({store.parts.name}/chunk-{k:06d}.parquet) {why}; computing it again")
    todo = [k for k in range(spec.n_chunks) if k not in store.done()]
    limit = MAX_SECONDS if max_seconds is None else max_seconds
    rows = np.concatenate([np.arange(*spec.chunk_rows(k)) for k in todo]) if todo else np.zeros(0, dtype=int)
    # a freefall sample is a time integration, bounded by its own estimate (its until and stiffness)
    est = estimate_study(system, spec, _samples(spec), rows, limit) \
        if len(rows) > PILOT_SAMPLES and "freefall" not in spec.analyses else None
    check_cost(est, limit, "max_seconds")
    if est is not None and on_estimate is not None:
        on_estimate(est)
    computed: list[int] = []

    def finished(k: int, cols: dict, seconds: float) -> None:
        store.write(k, cols, units)
        computed.append(k)
        if progress is not None:
            progress(len(cols["sample"]))
        if on_chunk is not None:
            on_chunk(k, seconds)

    samples = _samples(spec)
    done: set[int] = set()

    def opened() -> None:
        done.update(store.open())

    def here(k: int) -> float:
        t = time.perf_counter()
        cols = run_chunk(system, spec, k, samples=samples)
        seconds = time.perf_counter() - t
        finished(k, cols, seconds)
        return seconds

    def there(client: Client, ks: Sequence[int]) -> None:
        _run_dask(client, spec, source, [k for k in ks if k not in done], finished)

    ran_on = run_parts({k: len(range(*spec.chunk_rows(k))) for k in todo}, here, there, scheduler, workers, opened)
    store.combine()
    return StudyResult(store.folder, store.results, computed, sorted(done), time.perf_counter() - t0, spec.size,
                       ran_on)


def _run_dask(client: Client, spec: StudySpec, source: ModelSource, todo: Sequence[int],
              finished: Callable[[int, dict, float], None]) -> None:
    from dask.distributed import as_completed

    # the spec and the model's source go to every worker once; tasks refer to them
    shipped_source, shipped_spec = client.scatter([source, spec], broadcast=True)
    futures = [client.submit(_chunk_task, shipped_source, shipped_spec, k, pure=False) for k in todo]
    try:
        for fut in as_completed(futures):
            k, cols, seconds = fut.result()
            finished(k, cols, seconds)
    finally:
        for fut in futures:
            fut.cancel()
