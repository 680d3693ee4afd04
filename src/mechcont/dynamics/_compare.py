"""Sweeps against continuation: jump-to-fold gaps, gap versus sweep rate (their plots: outputs.sweep_plots)."""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ._sweep import SweepResult, sweep

__all__ = ["JumpGap", "jump_gaps", "RateGap", "gap_versus_rate"]


@dataclass(frozen=True)
class JumpGap:
    """A jump paired with the fold it follows.

    ``gap = jump load - fold load`` (units of the parameter); ``past`` is True when the jump
    happened after the ramp passed the fold (``direction * gap > 0``), as it must.
    """

    jump_value: float
    fold_value: float
    gap: float
    direction: int
    past: bool


def jump_gaps(result: SweepResult, fold_values: Sequence[float]) -> list[JumpGap]:
    """Pair each jump of ``result`` with the nearest fold load it has passed.

    ``fold_values`` are the fold loads of the ramped parameter (e.g. ``branch["LP1"]["F"]``
    or ``symmetric_folds``); the fold chosen for a jump is the nearest one on the side the
    ramp came from (the nearest overall if none lies there).
    """
    folds = np.asarray(list(fold_values), float)
    if folds.size == 0:
        raise InputError("fold_values", "give at least one fold load")
    out = []
    for j in result.jumps:
        behind = folds[(folds - j.value) * j.direction <= 0]
        pool = behind if behind.size else folds
        f = float(pool[np.argmin(np.abs(pool - j.value))])
        gap = j.value - f
        out.append(JumpGap(j.value, f, gap, j.direction, bool(j.direction * gap > 0)))
    return out


@dataclass(frozen=True)
class RateGap:
    """One sweep of a rate study: rate (units/s), jump load, gap to the fold, CPU time (s)."""

    rate: float
    jump_value: float
    gap: float
    seconds: float


def gap_versus_rate(system, x0, parameter: str, start: float, stop: float, rates: Sequence[float],
                    fold_value: float, *, watch: str, **sweep_options) -> list[RateGap]:
    """Sweep ``parameter`` from ``start`` to ``stop`` at each rate; gap of the first jump to the fold.

    Returns one :class:`RateGap` per rate (``nan`` when no jump was found). Slow passage
    through a saddle-node predicts ``gap ~ rate^(2/3)``.
    """
    out = []
    for rate in rates:
        t0 = time.perf_counter()
        r = sweep(system, x0, {parameter: (start, stop, rate)}, watch=watch, **sweep_options)
        dt = time.perf_counter() - t0
        v = r.jumps[0].value if r.jumps else float("nan")
        out.append(RateGap(float(rate), v, v - fold_value, dt))
    return out
