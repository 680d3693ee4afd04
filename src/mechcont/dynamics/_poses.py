"""Poses of a freefall: the retracted pose held by a force (:func:`held_pose`), the travel from it to the
lock (:func:`travel_of`), a condition's value at a pose (:func:`condition_value`) and the lock itself, a
stop or a condition's value (:func:`find_lock_stops`, :func:`lock_spec`)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import cast

import numpy as np

from ..equations import Model, StopLimit
from ..errors import InputError

#: What :func:`~mechcont.dynamics.freefall.freefall` takes as its lock: a stop's name, several, or a condition's
#: ``(name, value)``.
Lock = str | Sequence[str] | tuple[str, float]

__all__ = ["held_pose", "travel_of", "condition_value", "find_lock_stops", "lock_spec"]


def held_pose(system: Model, start: Mapping[str, float], held_by: str, *, values: Mapping[str, float] | None = None,
              guess: np.ndarray | None = None, steps: int = 8) -> np.ndarray:
    """The retracted pose as a static equilibrium: the ``start`` values held (SI, rad) and the parameter
    ``held_by`` (the force that holds the gear there, e.g. the retraction actuator's, N) solved for; then
    ``held_by`` is set back to its value (the model's, or ``values``'): the gear released at rest.

    Without it :func:`freefall` holds the gear by a reaction conjugate to each ``start`` value (a moment for an
    angle: :func:`~mechcont.dynamics.assemble`); here the actuator holds it, each compliant joint deflected by
    the load it then carries. Solved by Newton from ``guess`` (a full vector)
    or else followed from the model's own pose in ``steps`` equal steps of the held values, each solved from
    the last, so the mechanism keeps the assembly it moves through (as when the gear retracts). Returns the
    full vector; :class:`~mechcont.errors.InputError` naming ``held_by`` when it is not a parameter,
    :class:`~mechcont.errors.ConvergenceError` when no equilibrium is found on the way."""
    from ..continuation import find_equilibrium
    from ._simulate import assemble

    model = system
    if held_by not in model.names or model.variable(held_by).kind != "parameter":
        raise InputError("held_by", f"{held_by} is not a parameter of {model.name}; valid: "
                                    f"{', '.join(model.parameter_names)}")
    if values:
        model = model.with_values(dict(values))
    if guess is not None:
        x = find_equilibrium(model, hold=dict(start), free=[held_by],
                             guess=model.vector(dict(start), base=np.asarray(guess, float)))
    else:
        x = assemble(model, model.defaults(), kinematic=True)  # a start for Newton only
        begin = {n: condition_value(model, x, n) for n in start}
        for k in range(1, steps + 1):
            held = {n: begin[n] + (v - begin[n]) * k / steps for n, v in start.items()}
            x = find_equilibrium(model, hold=held, free=[held_by], guess=x)
    x[model.index(held_by)] = model.defaults()[model.index(held_by)]
    return x


def travel_of(system: Model, start: Mapping[str, float], lock: Lock,
              values: Mapping[str, float] | None = None) -> tuple[str, float, float]:
    """The travel of a freefall: ``(variable, value at the released pose, value at the lock)``.

    The variable is the lock stop's condition (the first of several; its limit is the lock value) or the lock
    condition's state; its start value is computed at the pose assembled from ``start``."""
    from ._simulate import assemble

    model = system
    if values:
        model = model.with_values(dict(values))
    stop, target = lock_spec(model, lock)
    name, end = (stop.condition, float(stop.limit)) if stop is not None else target  # type: ignore[misc]
    x0 = assemble(model, dict(start), hold=list(start))
    return name, condition_value(model, x0, name), end


def condition_value(system: Model, x: np.ndarray, name: str) -> float:
    """The value of the coordinate or declared condition ``name`` at the full vector ``x`` (its unit),
    computed from the coordinates (a condition's own entry in ``x`` need not be up to date)."""
    model = system
    rows = list(model.equation_names or ())
    if f"cond_{name}" not in rows:
        return float(x[model.index(name)])
    y = np.array(x, float)
    y[model.index(name)] = 0.0
    return float(model.residual(y)[rows.index(f"cond_{name}")])


def find_lock_stops(system: Model, lock: Lock) -> list[StopLimit] | None:
    """The lock stops named by ``lock`` (a stop's name or a sequence of names), None for a lock condition."""
    if isinstance(lock, str):
        names = [lock]
    elif isinstance(lock, Sequence) and lock and all(isinstance(n, str) for n in lock):
        names = [str(n) for n in lock]
    else:
        return None
    by_name = {s.name: s for s in system.stops}
    for n in names:
        if n not in by_name:
            raise InputError("lock", f"unknown stop {n!r}; stops of {system.name}: "
                                     f"{', '.join(by_name) or 'none (declare [stops.NAME] in the description)'}")
    if len(set(names)) != len(names):
        raise InputError("lock", f"stop {next(n for n in names if names.count(n) > 1)!r} is named twice")
    return [by_name[n] for n in names]


def lock_spec(system: Model, lock: Lock) -> tuple[StopLimit | None, tuple[str, float] | None]:
    """``(stop, None)`` for a lock stop's name (the first of several), ``(None, (state, value))`` for a
    lock condition."""
    stops = find_lock_stops(system, lock)
    if stops is not None:
        return stops[0], None
    try:
        name, value = cast("tuple[str, float]", lock)  # checked here: a user may pass anything
        value = float(value)
    except (TypeError, ValueError):
        raise InputError("lock", "give a stop's name or (condition, value)") from None
    if name not in system.names or system.variable(name).kind != "state":
        raise InputError("lock", f"{name} is not a state of {system.name} (a coordinate or a condition)")
    if not math.isfinite(value):
        raise InputError("lock", f"the lock value must be finite, got {value}")
    return None, (str(name), value)
