"""Where a study's parts run: in this process, on a local Dask cluster, at a scheduler's address, or ``"auto"``.

``scheduler="auto"`` (the command's default) computes the first part in this process, timed, and
estimates the work left as its mean time per sample times the samples left, ``W`` seconds in this
process. A local cluster of ``n`` worker processes would take about ``S + W/n`` for it, ``S``
(:data:`CLUSTER_START_SECONDS`) being what the cluster costs before its results come back at the
rate of this process: starting the scheduler and the workers, and each worker importing mechcont
and loading the model on its first task. The cluster is started only when it would save at least
its own start-up again, ``W - (S + W/n) >= S``, that is when ``W >= 2 S n/(n - 1)``
(:func:`cluster_threshold`: 40 s of computing on 2 cores, 23 s on 8, never on one): the margin
covers the estimate's errors (one part's time per sample; ``S`` measured on one machine) and
the cluster's other costs (the memory and CPU of ``n`` fresh processes) where the gain would be
small. Otherwise the rest runs here too. Where the parts ran, and why, is said in the phrase
:func:`run_parts` returns.
"""

from __future__ import annotations

import importlib.util
import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ...errors import InputError
from ._dask import dask_client, local_cluster_name, local_workers
from ._estimate import duration

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["SCHEDULERS", "CLUSTER_START_SECONDS", "Choice", "cluster_threshold", "choose", "check_scheduler",
           "run_parts"]

#: The schedulers named by a word; anything else must be a Dask scheduler's address.
SCHEDULERS = ("auto", "local", "serial")
#: What a local cluster costs before it computes at this process's rate, s: about 4.5 s on the idle 2-core
#: machine (docs/benchmarks.md); when it is shared, starting two workers took 2-4 s and each worker's first
#: 1000-sample chunk of the nose gear 7.8-8.7 s against 0.24 s in this process (a fresh process importing
#: mechcont, loading the model and compiling its lazily compiled parts).
CLUSTER_START_SECONDS = 10.0
#: A scheduler's address: ``[SCHEME://]HOST:PORT`` (which schemes are served is the connection's check).
_ADDRESS = re.compile(r"(?:[A-Za-z][A-Za-z0-9+.-]*://)?[^\s:/]+:\d+|(?:[A-Za-z][A-Za-z0-9+.-]*://)?\[[0-9A-Fa-f:.]+\]:\d+")


def check_scheduler(scheduler: str | None, workers: int | None = None) -> None:
    """InputError unless ``scheduler`` is ``None``, one of :data:`SCHEDULERS` or an address ``[SCHEME://]HOST:PORT``,
    and ``workers`` (worker processes of a local cluster) is ``None`` or 1..256; before anything is computed."""
    if workers is not None and not 1 <= workers <= 256:
        raise InputError("--workers", f"must be 1..256, got {workers}")
    if scheduler is None or scheduler in SCHEDULERS or _ADDRESS.fullmatch(scheduler):
        return
    raise InputError("--scheduler", f"unknown scheduler {scheduler!r}; valid: auto (a local cluster only when the work "
                                    "pays for its start), local, serial, or a Dask scheduler's address tcp://HOST:PORT")


def cluster_threshold(workers: int, start: float = CLUSTER_START_SECONDS) -> float:
    """The computing time (s, in this process) above which ``workers`` worker processes started in ``start``
    seconds save at least ``start`` again: ``2 start n/(n - 1)``; infinite for one worker."""
    return math.inf if workers <= 1 else 2.0 * start * workers / (workers - 1)


@dataclass(frozen=True)
class Choice:
    """What ``"auto"`` chose: a local cluster of ``workers`` (``cluster``) or this process, for ``seconds_left``
    seconds of computing estimated for ``samples_left`` samples, against ``threshold`` (s)."""

    cluster: bool
    seconds_left: float
    samples_left: int
    workers: int
    threshold: float

    def describe(self) -> str:
        """``"auto: 9000 samples left, about 2.1 s of computing; a local cluster of 2 workers pays off above 40 s"``."""
        left = f"auto: {self.samples_left} samples left, about {duration(self.seconds_left)} of computing"
        if math.isinf(self.threshold):
            return f"{left}; with one worker a local cluster cannot pay off"
        return f"{left}; a local cluster of {self.workers} workers pays off above {duration(self.threshold)}"


def choose(seconds: float, samples: int, samples_left: int, workers: int | None, start: float | None = None) -> Choice:
    """The choice of ``"auto"`` after ``samples`` samples took ``seconds`` (s) in this process with ``samples_left``
    to do: a local cluster of ``workers`` (default one per core) when the estimate ``seconds/samples * samples_left``
    reaches :func:`cluster_threshold` for a cluster start of ``start`` s (default :data:`CLUSTER_START_SECONDS`)."""
    n = local_workers(workers)
    left = seconds / max(samples, 1) * samples_left
    threshold = cluster_threshold(n, CLUSTER_START_SECONDS if start is None else start)
    return Choice(left >= threshold, left, samples_left, n, threshold)


def run_parts(parts: Mapping[int, int], here: Callable[[int], float], there: Callable[[Client, Sequence[int]], None],
              scheduler: str | None, workers: int | None = None, before: Callable[[], None] | None = None) -> str:
    """Compute the ``parts`` (``{part: its samples}``, in order) where ``scheduler`` says; return where they ran.

    ``here(k)`` computes part ``k`` in this process and returns the seconds its computing took (what is done
    here wherever the part is computed, writing it, not counted); ``there(client, ks)`` computes the parts ``ks``
    on a Dask client; ``before()`` is called once before the first part is computed (after a cluster given by
    name or address has started, so that a scheduler that cannot be reached stops the run before anything is
    written; with ``"auto"`` the first part is computed, and written, before a cluster is started).
    ``scheduler``: ``None`` or ``"serial"`` (this process), ``"local"`` (a local cluster of ``workers`` worker
    processes; this process when one part is to do), ``"auto"`` (see the module's docstring) or an address.
    Returns ``"this process"``, ``"a local cluster of 2 worker processes"``, the address, or with ``"auto"`` the
    choice made and why (:meth:`Choice.describe`) in brackets.
    """
    check_scheduler(scheduler, workers)
    order = list(parts)
    if not order or scheduler in (None, "serial") or (scheduler in ("local", "auto") and len(order) <= 1):
        if before is not None:
            before()
        for k in order:
            here(k)
        return "this process"
    if scheduler == "auto":
        if before is not None:
            before()
        choice = choose(here(order[0]), parts[order[0]], sum(parts[k] for k in order[1:]), workers)
        if choice.cluster and importlib.util.find_spec("distributed") is not None:
            with dask_client("local", workers) as client:
                there(client, order[1:])
            return f"this process, then {local_cluster_name(workers)} ({choice.describe()})"
        for k in order[1:]:
            here(k)
        why = choice.describe() if not choice.cluster else f"{choice.describe()}, but dask.distributed is not installed"
        return f"this process ({why})"
    assert scheduler is not None
    with dask_client(scheduler, workers) as client:  # reached before anything is written
        if before is not None:
            before()
        there(client, order)
    return local_cluster_name(workers) if scheduler == "local" else scheduler
