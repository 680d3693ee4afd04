"""The downlocked point: the downlock condition of a model (held states, freed force), one downlocked equilibrium,
and :class:`DownlockResult`, the record of a downlock run (:mod:`mechcont.analysis.downlock` runs it; the unlock
and sensitivity columns of :mod:`.unlock` and :mod:`.sensitivity` are added to it)."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..continuation import Branch, find_equilibrium
from ..equations import Model
from ..errors import ConvergenceError, InputError

if TYPE_CHECKING:
    from ..continuation import Sensitivity
    from .unlock import UnlockFolds

__all__ = ["DownlockResult", "downlock_condition", "downlocked_pose", "downlock_point"]


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
                    keep: str | None = None, values: Mapping[str, float] | None = None) -> Sensitivity:
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
