"""A study's cost, estimated before it starts: a few samples timed in this process, times the samples to do.

A study of ten million samples is accepted by its size limits but would compute for hours; it is
refused at once, with its estimate, unless the limit (``max_seconds``; ``mechcont study --max-hours``)
is raised. The pilot solves the first samples of the study's first chunk to do: one untimed (the
first solve of a model pays for its lazily compiled parts), then 4, 16 and 64 timed, stopping as
soon as the estimate is within the limit or the pilot has spent :data:`PILOT_SECONDS`; its results
are not kept. A study of at most :data:`PILOT_SAMPLES` samples to do is not estimated.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from ...errors import InputError
from ._kernels import run_chunk
from ._spec import StudySpec

if TYPE_CHECKING:
    from ...equations import Model

__all__ = ["Estimate", "estimate_study", "check_cost", "MAX_SECONDS", "PILOT_SAMPLES", "PILOT_SECONDS", "duration"]

#: Default limit on a study's estimated computing time, s (one hour).
MAX_SECONDS = 3600.0
#: Largest pilot, samples; a study with no more than this to do is not estimated.
PILOT_SAMPLES = 64
#: Time after which the pilot stops growing, s.
PILOT_SECONDS = 2.0


@dataclass(frozen=True)
class Estimate:
    """``seconds`` of computing for ``samples`` samples, from ``per_sample`` seconds each timed on ``timed`` samples."""

    seconds: float
    samples: int
    per_sample: float
    timed: int

    def describe(self) -> str:
        """``"about 2.08 h of computing (10000000 samples x 0.75 ms, timed on 64)"``."""
        return (f"about {duration(self.seconds)} of computing ({self.samples} samples x "
                f"{duration(self.per_sample)}, timed on {self.timed} in this process)")


def duration(seconds: float) -> str:
    """``0.00075`` -> ``"0.75 ms"``, ``7500`` -> ``"2.08 h"``: seconds in the unit that reads best."""
    for unit, size in (("d", 86400.0), ("h", 3600.0), ("min", 60.0), ("s", 1.0), ("ms", 1e-3)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds * 1e6:.3g} us"


def estimate_study(system: Model, spec: StudySpec, samples: np.ndarray, todo_rows: np.ndarray,
                   max_seconds: float = MAX_SECONDS) -> Estimate | None:
    """The estimated computing time of the rows ``todo_rows`` of ``samples`` (None when there are at most
    :data:`PILOT_SAMPLES`): a pilot on the first of them, grown until its estimate is within
    ``max_seconds`` or it has taken :data:`PILOT_SECONDS`."""
    todo = len(todo_rows)
    if todo <= PILOT_SAMPLES:
        return None

    def timed(m: int) -> float:
        S = samples[todo_rows[:m]]
        t = time.perf_counter()
        run_chunk(system, replace(spec, n=m, chunk=m), 0, samples=S)
        return time.perf_counter() - t

    t0 = time.perf_counter()
    timed(1)  # the first solve compiles what the model compiles lazily: not the cost of a sample
    m = 4
    while True:
        per = timed(m) / m
        est = Estimate(per * todo, todo, per, m)
        if est.seconds <= max_seconds or m >= PILOT_SAMPLES or time.perf_counter() - t0 >= PILOT_SECONDS:
            return est
        m *= 4


def check_cost(est: Estimate | None, max_seconds: float, field: str = "max_seconds") -> None:
    """InputError naming ``field`` when the estimate is above ``max_seconds``."""
    if est is not None and est.seconds > max_seconds:
        raise InputError(field, f"the study would take {est.describe()}, above the limit of {duration(max_seconds)}: "
                                "use fewer samples, a faster analysis, or raise the limit")
