"""Downlock-force analysis: hold the lock links aligned, free the force, continue in a design parameter.

The paper (Section III-B) defines the downlock force as the value of the applied force
``F`` at which the lock links are level and aligned (theta4 = 0, overcentre angle 180 deg).
Holding that state and solving for ``F`` turns every parameter — airspeed, spring stiffness,
unstrained length, attachment positions — into a continuation parameter: one run gives
the downlock force as a function of it, where the traditional approach needs one slow
time simulation per value. ``F > 0`` (the unlock direction) means the gear locks unaided.

The condition is any held state: the nose gear's ``theta4 = 0``, or a condition declared in
a mechanism description (``[conditions]``, held at its ``target``; ``[mechanism] downlock =
{condition, force}`` makes it the default). The result also carries the unlock folds of the
downlocked point at the start (:mod:`mechcont.analysis.unlock`) and names every run that
stopped short of its bounds (:attr:`DownlockResult.warnings`); the branch itself is a plain
:class:`~mechcont.continuation.Branch` the result holds.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from ..continuation import ContinuationOptions, continuation
from ..equations import Model
from ..errors import InputError
from ._downlock_point import DownlockResult, downlock_condition, downlock_point, downlocked_pose
from ._runs import early_stops
from .sensitivity import with_sensitivity_columns
from .unlock import unlock_folds, with_unlock_columns

__all__ = ["downlock", "downlock_table", "downlock_point", "downlock_condition", "downlocked_pose", "DownlockResult"]


def design_bounds(system: Model, vary: str, bounds: Mapping[str, tuple[float, float]] | None,
                  options: ContinuationOptions | None,
                  values: Mapping[str, float] | None) -> tuple[dict[str, tuple[float, float]], float]:
    """The bounds of a run in the design parameter ``vary`` (``options``' merged with ``bounds``) and its start
    value; :class:`InputError` for an unknown name, no range for ``vary`` or a start outside it."""
    all_bounds = dict(options.bounds) if options is not None else {}
    all_bounds.update(bounds or {})
    for n in all_bounds:
        system.variable(n)
    if vary not in all_bounds:
        raise InputError("bounds", f"give a range for the varied parameter, e.g. {vary}=LO:HI")
    lo, hi = all_bounds[vary]
    start = (values or {}).get(vary, system.variable(vary).value)
    if not lo <= start <= hi:
        raise InputError(vary, f"start value {start:g} lies outside its bounds {lo:g}:{hi:g}; set it with values")
    return all_bounds, start


def design_options(system: Model, vary: str, bounds: Mapping[str, tuple[float, float]],
                   options: ContinuationOptions | None, max_steps: int | None) -> ContinuationOptions:
    """Continuation options of a run in the design parameter ``vary`` within ``bounds``: steps sized to
    its range and scale unless ``options`` are given (their bounds replaced by ``bounds``)."""
    steps: dict[str, Any] = {"max_steps": max_steps} if max_steps else {}
    if options is not None:
        from dataclasses import replace

        return replace(options, bounds=dict(bounds), **steps)
    lo, hi = bounds[vary]
    span = hi - lo if np.isfinite(hi - lo) else 1.0
    scale = system.variable(vary).scale
    return ContinuationOptions(ds=min(0.02, 0.5 * span / scale), dsmin=1e-9, dsmax=max(0.02, min(0.5, 0.1 * span / scale)),
                               bounds=dict(bounds), **steps)


def downlock(system: Model, vary: str, bounds: Mapping[str, tuple[float, float]] | None = None, *,
             free: Iterable[str] = (), values: Mapping[str, float] | None = None,
             hold: Mapping[str, float] | None = None, force: str | None = None,
             options: ContinuationOptions | None = None, direction: int = 0, condition: str | None = None,
             unlock: bool = True, max_steps: int | None = None) -> DownlockResult:
    """The downlock force as a function of the parameter ``vary``, by continuation.

    Parameters
    ----------
    system:
        The model.
    vary:
        Continuation parameter (any parameter other than the force, e.g. ``"U"``, ``"k"``,
        ``"LU"``, ``"l_sp1"``), or a state other than the held one.
    bounds:
        ``{name: (low, high)}``; must include ``vary``. The branch ends where a bounded
        variable leaves its interval.
    free:
        Further parameters solved for (each needs a further held state in ``hold``).
    values:
        Parameter values (SI) at the start, overriding the defaults.
    hold, force, condition:
        The downlock condition (defaults: the model's, see :func:`downlock_condition`).
    options:
        Step control; ``bounds`` given here are merged into it.
    direction:
        ``0`` both ways from the start value, ``+1``/``-1`` one way.
    unlock:
        Also find the unlock folds of the downlocked point at the start (one more
        continuation run, in the force with the condition released).
    max_steps:
        Most continuation steps each way (default: the options', else 2000).

    Returns
    -------
    DownlockResult
        Its ``branch``: columns of every variable along the branch (``branch[force]`` is the
        downlock force, N); stability from the mechanics; ``LP`` where ``vary`` turns back.
        Also ``unlock`` (the unlock folds at the start) and ``warnings`` (runs that stopped
        short of their bounds: where and why).

    Raises
    ------
    InputError
        Unknown names, ``vary`` without bounds or equal to the force or a held state, a
        start value outside its bounds.
    """
    h, f = downlock_condition(system, hold, force, condition=condition)
    system.variable(vary)
    if vary == f:
        raise InputError("vary", f"'{vary}' is the downlock force, which is solved for; vary a design parameter")
    if vary in h:
        raise InputError("vary", f"'{vary}' is held by the downlock condition; vary a design parameter")
    free = list(free)
    if vary in free:
        raise InputError("vary", f"'{vary}' cannot be both varied and freed")
    all_bounds, start = design_bounds(system, vary, bounds, options, values)
    values = dict(values or {})
    x0 = downlock_point(system, values, hold=h, force=f, free=free)
    options = design_options(system, vary, all_bounds, options, max_steps)
    branch = continuation(system, x0, vary, hold=list(h), free=[f, *free], options=options, direction=direction)
    held = ", ".join(f"{k} = {v:g}" for k, v in h.items())
    warnings = early_stops(branch, f"downlock branch in {vary} ({held})", show=(f,))
    found = None
    if unlock:
        found = unlock_folds(system, x0, f, released=list(h))
        warnings += [f"unlock folds at {vary} = {start:g}: {n}" for n in found.warnings]
    return DownlockResult(branch, f, h, found, warnings)


def downlock_table(system: Model, vary: str, bounds: Mapping[str, tuple[float, float]] | None = None, *,
                   sensitivity: Iterable[str] = (), **options: Any) -> DownlockResult:
    """:func:`downlock` with the columns ``mechcont downlock`` writes: the unlock folds of every point
    (``unlock_<F>``, ``unlock_<F>_decreasing``, N; see :func:`~mechcont.analysis.unlock.with_unlock_columns`)
    and, for each parameter of ``sensitivity``, the exact derivative of the downlock force ``d<F>_d<p>``
    (:func:`~mechcont.analysis.sensitivity.with_sensitivity_columns`). ``options`` are :func:`downlock`'s.
    Raises :class:`InputError` (field ``params``) for a ``sensitivity`` name that is not a parameter held
    along the branch."""
    result = downlock(system, vary, bounds, **options)
    result = with_unlock_columns(system, result, result.force, released=list(result.condition))
    params = list(sensitivity)
    return with_sensitivity_columns(system, result, params) if params else result
