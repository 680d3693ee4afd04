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
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..continuation import Branch, ContinuationOptions, continuation, find_equilibrium
from ..equations import Model
from ..errors import ConvergenceError, InputError
from ._runs import early_stops
from .unlock import UnlockFolds, unlock_folds

__all__ = ["downlock", "downlock_table", "downlock_point", "downlock_condition", "downlocked_pose", "DownlockResult"]


@dataclass(frozen=True)
class DownlockResult:
    """A downlock branch and what it rests on.

    Attributes
    ----------
    branch:
        The :class:`~mechcont.continuation.Branch`: every variable along the run in the design
        parameter (``branch[force]`` is the downlock force, N).
    force:
        Name of the force solved for (N).
    condition:
        The held states ``{name: value}`` (e.g. ``{"aligned": 0.0}``).
    unlock:
        :class:`~mechcont.analysis.unlock.UnlockFolds` of the downlocked point at the start
        (the folds bounding the locked state, the unlock force); None when not computed.
    warnings:
        One line per run that stopped short (a failed direction, ``max_steps`` before the
        bounds, a release run without a fold): where and why.
    lock_stops:
        The stops the lock rests on (:func:`~mechcont.analysis.stop_lock.downlock_on_stops`); empty
        for a lock held at a condition.
    """

    branch: Branch
    force: str
    condition: Mapping[str, float]
    unlock: UnlockFolds | None = None
    warnings: list[str] = field(default_factory=list)
    lock_stops: tuple[str, ...] = ()

    def sensitivity(self, system: Model, point: str | int, params: Iterable[str], *, of: str | None = None,
                    keep: str | None = None, values: Mapping[str, float] | None = None):
        """:meth:`Branch.sensitivity <mechcont.continuation.Branch.sensitivity>` of the branch, of the downlock
        force unless ``of`` names another unknown."""
        return self.branch.sensitivity(system, point, params, of=of or self.force, keep=keep, values=values)


def downlock_condition(system: Model, hold: Mapping[str, float] | None = None,
                       force: str | None = None, *, condition: str | None = None) -> tuple[dict[str, float], str]:
    """The held states and the freed force of the downlock condition of ``system``.

    Uses ``hold`` (``{state: value}``) or ``condition`` (a declared condition's name, held at
    its target) when given, else the model's :attr:`~mechcont.equations.Model.downlock`
    (the built-in nose gear: ``{"theta4": 0.0}``, ``"F"``; a description: its ``[mechanism]
    downlock``). ``force`` defaults to the model's, else ``"F"``. Raises :class:`InputError`
    when nothing names the condition, a name is unknown, or both ``hold`` and ``condition``
    are given.
    """
    model = system
    if condition is not None:
        if hold:
            raise InputError("condition", "give either a condition or held states (hold), not both")
        declared = model.conditions
        if condition not in declared:
            valid = ", ".join(declared) or "none declared (add a [conditions] table to the description)"
            raise InputError("condition", f"unknown condition {condition!r} of model '{system.name}'; conditions: "
                                          f"{valid}")
        target = declared[condition]
        if target is None:
            raise InputError("condition", f"condition {condition!r} has no target; give target = VALUE under "
                                          f"[conditions] or hold it at a value ({condition}=VALUE)")
        hold = {condition: target}
    h = dict(hold) if hold else (dict(model.downlock.hold) if model.downlock is not None else None)
    if not h:
        names = ", ".join(model.conditions)
        hint = f"; declared conditions: {names}" if names else ""
        raise InputError("hold", f"model '{system.name}' defines no downlock condition; give the held lock-link state "
                                 f"(e.g. theta4=0) or a declared condition, or declare [mechanism] downlock = "
                                 f"{{condition = ..., force = ...}}{hint}")
    f = force if force is not None else (model.downlock.force if model.downlock is not None else "F")
    for n in h:
        if system.variable(n).kind != "state":
            raise InputError(n, "only states can be held for the downlock condition")
    if system.variable(f).kind != "parameter":
        raise InputError(f, "the downlock force must be a parameter of the model (it is freed)")
    return {k: float(v) for k, v in h.items()}, f


def downlocked_pose(model: Model) -> np.ndarray | None:
    """The model's downlocked equilibrium at its defaults (full vector), or None when it declares none."""
    return model.downlock.pose if model.downlock is not None else None


def downlock_point(system: Model, values: Mapping[str, float] | None = None, *,
                   hold: Mapping[str, float] | None = None, force: str | None = None,
                   free: Iterable[str] = (), condition: str | None = None) -> np.ndarray:
    """One downlocked equilibrium: the held lock-link state, the force solved for.

    Parameters
    ----------
    system:
        The model (e.g. :func:`mechcont.models.nose_gear.build_nose_gear`).
    values:
        Parameter values (SI) overriding the defaults.
    hold, force, condition:
        The downlock condition (defaults: the model's, see :func:`downlock_condition`).
    free:
        Further parameters solved for (each needs one more held state).

    Returns
    -------
    numpy.ndarray
        Full variable vector; ``x[system.index(force)]`` is the downlock force (N).

    Models may carry ``check_values(values)`` (raises :class:`InputError` for values out of
    range) and a downlock with a closed-form assembly (:attr:`DownlockFacts.assemble
    <mechcont.equations.DownlockFacts>`); both are used. Without the latter, Newton starts from
    the model's downlocked pose, else its default (assembled) configuration.
    """
    values = dict(values or {})
    if values:  # the model at the values: a hold target written in parameters follows them
        system = system.with_values({k: v for k, v in values.items() if system.variable(k).kind == "parameter"})
    h, f = downlock_condition(system, hold, force, condition=condition)
    for n in values:
        if n in h or n == f:
            raise InputError(n, "is fixed by the downlock condition; it cannot be set")
    model = system
    if model.check_values is not None:  # the model's own valid ranges (e.g. positive lengths)
        model.check_values(values)
    base = downlocked_pose(model)
    guess = system.vector(values, base=base) if base is not None else None
    if model.downlock is not None and model.downlock.assemble is not None:  # closed form: survives geometry changes
        try:
            guess = model.downlock.assemble(values, h)
        except InputError as exc:  # no closed-form pose nearby: Newton from the default pose decides
            try:
                return find_equilibrium(system, values=values, hold=h, free=[f, *free], guess=guess)
            except ConvergenceError:
                raise exc from None
    return find_equilibrium(system, values=values, hold=h, free=[f, *free], guess=guess)


def design_bounds(system: Model, vary: str, bounds: Mapping[str, tuple[float, float]] | None,
                  options: ContinuationOptions | None, values: Mapping[str, float] | None) -> tuple[dict, float]:
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
    from .sensitivity import with_sensitivity_columns
    from .unlock import with_unlock_columns

    result = downlock(system, vary, bounds, **options)
    result = with_unlock_columns(system, result, result.force, released=list(result.condition))
    params = list(sensitivity)
    return with_sensitivity_columns(system, result, params) if params else result
