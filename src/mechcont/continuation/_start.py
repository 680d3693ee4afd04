"""The rules of a run as a user states it: step sizes given alone or together, and the first
equilibrium from the values given, the states held to find it and the parameter to vary."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ._newton import find_equilibrium
from ._options import ContinuationOptions

if TYPE_CHECKING:
    from ..equations import EquationSystem

__all__ = ["MAX_STEPS", "check_max_steps", "run_options", "start_point"]

#: Most continuation steps each way a run accepts: more would run for days where no bound ends the branch.
MAX_STEPS = 100_000


def check_max_steps(max_steps: int | None, field: str = "max_steps") -> None:
    """:class:`InputError` naming ``field`` unless ``max_steps`` is None or a whole number in 1..:data:`MAX_STEPS`."""
    if max_steps is not None and not 1 <= max_steps <= MAX_STEPS:
        raise InputError(field, f"must be a positive whole number 1..{MAX_STEPS}, got {max_steps}")


def run_options(bounds: Mapping[str, tuple[float, float]] | None = None, *, ds: float | None = None,
                dsmax: float | None = None, max_steps: int | None = None,
                max_steps_field: str = "max_steps") -> ContinuationOptions:
    """:class:`ContinuationOptions` from the step sizes a user gave (scaled arclength), each optional.

    ``ds`` alone raises the largest step to at least ``ds``; ``dsmax`` alone lowers the first step
    to at most ``dsmax``; both are taken as given (and checked by the options). ``max_steps`` is
    checked by :func:`check_max_steps` (errors name ``max_steps_field``).
    """
    kw: dict = {"bounds": dict(bounds or {})}
    if dsmax is not None:
        kw["dsmax"] = dsmax
    if ds is not None:
        kw["ds"] = ds
        kw.setdefault("dsmax", max(ds, ContinuationOptions.dsmax))
    elif dsmax is not None:
        kw["ds"] = min(ContinuationOptions.ds, dsmax)
    if max_steps is not None:
        check_max_steps(max_steps, max_steps_field)
        kw["max_steps"] = max_steps
    return ContinuationOptions(**kw)


def start_point(system: EquationSystem, vary: str, *, values: Mapping[str, float] | None = None,
                start: Mapping[str, float] | None = None, free: Iterable[str] = (), hold: Iterable[str] = (),
                start_field: str = "start", free_field: str = "free") -> np.ndarray:
    """The first equilibrium of a run in ``vary``: ``start`` states held at their values, ``vary`` (and ``free``) solved for.

    ``values`` sets variables (SI units, radians); each ``hold`` state is held at its value there.
    When ``vary`` is a state it is prescribed (at its ``start`` value or its default); when it is a
    parameter and ``start`` holds states that ``hold`` does not, it is freed for this first solve. Errors name the
    variable, or ``start_field``/``free_field`` for a wrong use of ``start``/``free``.
    """
    values = dict(values or {})
    held = dict(start or {})
    free, hold = list(free), list(hold)
    for name in [*values, *held, vary, *free, *hold]:
        system.index(name)
    for n in free:
        if system.variable(n).kind != "parameter":  # a state is always solved for: freeing one would be ignored
            valid = ", ".join(system.parameter_names)
            raise InputError(free_field, f"{n} is a state, which is always solved for; free a parameter: {valid}")
    base = system.vector(values)
    for n in hold:
        held.setdefault(n, float(base[system.index(n)]))
    if system.variable(vary).kind == "state":
        # a state as the parameter: it is prescribed, at its start value or its default
        held.setdefault(vary, float(base[system.index(vary)]))
        solved = [n for n in free if n != vary]
    else:
        if vary in held:
            raise InputError(start_field, f"{vary} is the continuation parameter; hold a state instead")
        # a start state held only for the first solve frees the parameter to be varied then (one held
        # during the continuation too, e.g. --hold NAME=VALUE, adds no equation the run lacks)
        extra = set(start or {}) - set(hold)
        solved = [*([vary] if extra else []), *(n for n in free if n != vary)]
    return find_equilibrium(system, values=values, hold=held, free=solved)
