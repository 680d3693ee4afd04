"""Sweeps against continuation: jump-to-fold gaps, gap versus sweep rate (their plots: outputs.sweep_plots)."""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ._sweep import Jump, SweepResult, sweep

if TYPE_CHECKING:
    from ..continuation import Branch
    from ..equations import Model

__all__ = ["JumpGap", "jump_gaps", "runaway_gap", "branch_jump_gaps", "branch_runaway_gap", "branch_differences", "RateGap",
           "gap_versus_rate"]


@dataclass(frozen=True)
class JumpGap:
    """A jump (or a sweep's runaway) paired with the fold it follows.

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
    folds = _fold_array(fold_values)
    return [_pair(j, folds) for j in result.jumps]


def runaway_gap(result: SweepResult, fold_values: Sequence[float]) -> JumpGap | None:
    """The runaway of ``result`` (:attr:`SweepResult.runaway`) paired with the fold it follows, as a jump is
    (:func:`jump_gaps`): ``jump_value`` the load where the runaway started, ``gap`` its delay past the fold
    (units of the parameter). None when the sweep ended at rest."""
    folds = _fold_array(fold_values)
    return None if result.runaway is None else _pair(result.runaway, folds)


def _fold_array(fold_values: Sequence[float]) -> np.ndarray:
    """The fold loads as an array; :class:`InputError` when there is none."""
    folds = np.asarray(list(fold_values), float)
    if folds.size == 0:
        raise InputError("fold_values", "give at least one fold load")
    return folds


def _pair(j: Jump, folds: np.ndarray) -> JumpGap:
    """The jump (or runaway) ``j`` and the nearest fold of ``folds`` on the side its ramp came from (the nearest
    overall if none lies there)."""
    behind = folds[(folds - j.value) * j.direction <= 0]
    pool = behind if behind.size else folds
    f = float(pool[np.argmin(np.abs(pool - j.value))])
    gap = j.value - f
    return JumpGap(j.value, f, gap, j.direction, bool(j.direction * gap > 0))


def _branch_folds(result: SweepResult, branch: Branch) -> list[tuple[str, float]]:
    """The folds (``LP``) of ``branch`` as (name as the branch numbers it, load of the ramped parameter)."""
    name = result.ramps[0].name
    return [(n, p[name]) for n, p in zip(branch.point_names(), branch.special_points) if p.label == "LP"]


def _named(folds: Sequence[tuple[str, float]], gap: JumpGap) -> tuple[str, JumpGap]:
    """``(name of the fold in folds that gap pairs with, gap)``."""
    return next(n for n, v in folds if v == gap.fold_value), gap


def branch_jump_gaps(result: SweepResult, branch: Branch) -> list[tuple[str, JumpGap]]:
    """Each jump of ``result`` paired with the fold (``LP``) of a continuation ``branch`` in the ramped
    parameter that it follows: ``(fold name as the branch numbers it, e.g. "LP2", gap)``, one per jump.

    ``[]`` when there is no jump or the branch has no fold (see :func:`jump_gaps`).
    """
    folds = _branch_folds(result, branch)
    if not folds or not result.jumps:
        return []
    return [_named(folds, g) for g in jump_gaps(result, [v for _, v in folds])]


def branch_runaway_gap(result: SweepResult, branch: Branch) -> tuple[str, JumpGap] | None:
    """The runaway of ``result`` paired with the fold (``LP``) of ``branch`` it follows, as
    :func:`branch_jump_gaps` pairs a jump: ``(fold name, e.g. "LP1", gap)``; None without a runaway or a fold."""
    folds = _branch_folds(result, branch)
    g = runaway_gap(result, [v for _, v in folds]) if folds and result.runaway is not None else None
    return None if g is None else _named(folds, g)


def branch_differences(system: Model, branch: Branch, ignore: Sequence[str] = ()) -> list[tuple[str, float, float]]:
    """The parameters of ``system`` (not in ``ignore``) whose value on ``branch`` differs from the system's
    and changes the equilibrium equations at the branch's points: ``(name, on branch, system's)``.

    A parameter the equilibrium equations do not use (a damping coefficient, in the dynamic model
    only) moves no fold, so a branch continued with another value of it is still the system's; such
    a parameter leaves the compiled residual bit for bit the same (the same code on the same
    arguments), which is what is tested.
    """
    rows = np.column_stack([np.asarray(branch[n], dtype=float) for n in system.names])
    base = system.residual_batch(rows)
    out = []
    for n in system.parameter_names:
        if n in ignore:
            continue
        on_branch, here = float(branch[n][0]), float(system.variable(n).value)
        if np.isclose(on_branch, here, rtol=1e-9, atol=0.0):
            continue
        moved = rows.copy()
        moved[:, system.index(n)] = here
        if np.array_equal(system.residual_batch(moved), base):
            continue  # not in the equilibrium equations (at these points): the branch's folds are the system's
        out.append((n, on_branch, here))
    return out


@dataclass(frozen=True)
class RateGap:
    """One sweep of a rate study: rate (units/s), jump load, gap to the fold, CPU time (s)."""

    rate: float
    jump_value: float
    gap: float
    seconds: float


def gap_versus_rate(system: Model, x0: np.ndarray | Mapping[str, float] | Sequence[float], parameter: str, start: float,
                    stop: float, rates: Sequence[float], fold_value: float, *, watch: str,
                    **sweep_options: Any) -> list[RateGap]:
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
