"""Downlock-force analysis: hold the lock links aligned, free the force, continue in a design parameter.

The paper (Section III-B) defines the downlock force as the value of the applied force
``F`` at which the lock links are level and aligned (theta4 = 0, overcentre angle 180 deg).
Holding that state and solving for ``F`` turns every parameter — airspeed, spring stiffness,
unstrained length, attachment positions — into a continuation parameter: one run gives
the downlock force as a function of it, where the traditional approach needs one slow
time simulation per value. ``F > 0`` (the unlock direction) means the gear locks unaided.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from ..continuation import Branch, ContinuationOptions, continuation, find_equilibrium
from ..equations import EquationSystem
from ..errors import ConvergenceError, InputError

__all__ = ["downlock", "downlock_point", "downlock_condition"]


def downlock_condition(system: EquationSystem, hold: Mapping[str, float] | None = None,
                       force: str | None = None) -> tuple[dict[str, float], str]:
    """The held states and the freed force of the downlock condition of ``system``.

    Uses ``hold``/``force`` when given, else the model's ``downlock_hold`` /
    ``downlock_force`` attributes (the built-in nose gear: ``{"theta4": 0.0}``, ``"F"``).
    Raises :class:`InputError` when neither names the condition or a name is unknown.
    """
    h = dict(hold) if hold is not None else getattr(system, "downlock_hold", None)
    if not h:
        raise InputError("hold", f"model '{system.name}' defines no downlock condition; "
                                 "give the held lock-link state, e.g. theta4=0")
    f = force if force is not None else getattr(system, "downlock_force", "F")
    for n in h:
        if system.variable(n).kind != "state":
            raise InputError(n, "only states can be held for the downlock condition")
    if system.variable(f).kind != "parameter":
        raise InputError(f, "the downlock force must be a parameter of the model (it is freed)")
    return {k: float(v) for k, v in h.items()}, f


def downlock_point(system: EquationSystem, values: Mapping[str, float] | None = None, *,
                   hold: Mapping[str, float] | None = None, force: str | None = None,
                   free: Iterable[str] = ()) -> np.ndarray:
    """One downlocked equilibrium: the held lock-link state, the force solved for.

    Parameters
    ----------
    system:
        The model (e.g. :func:`mechcont.models.nose_gear.build_nose_gear`).
    values:
        Parameter values (SI) overriding the defaults.
    hold, force:
        The downlock condition (defaults: the model's, see :func:`downlock_condition`).
    free:
        Further parameters solved for (each needs one more held state).

    Returns
    -------
    numpy.ndarray
        Full variable vector; ``x[system.index(force)]`` is the downlock force (N).

    Models may carry ``check_values(values)`` (raises :class:`InputError` for values out of
    range) and ``assemble_downlocked(values, hold)`` (a closed-form guess); both are used.
    """
    h, f = downlock_condition(system, hold, force)
    values = dict(values or {})
    for n in values:
        if n in h or n == f:
            raise InputError(n, "is fixed by the downlock condition; it cannot be set")
    check = getattr(system, "check_values", None)
    if callable(check):  # the model's own valid ranges (e.g. positive lengths)
        check(values)
    assemble = getattr(system, "assemble_downlocked", None)
    base = getattr(system, "downlocked", None)
    guess = system.vector(values, base=base) if base is not None else None
    if callable(assemble):  # closed-form assembly at these values: a guess that survives geometry changes
        try:
            guess = assemble(values, h)
        except InputError as exc:  # no closed-form pose nearby: Newton from the default pose decides
            try:
                return find_equilibrium(system, values=values, hold=h, free=[f, *free], guess=guess)
            except ConvergenceError:
                raise exc from None
    return find_equilibrium(system, values=values, hold=h, free=[f, *free], guess=guess)


def downlock(system: EquationSystem, vary: str, bounds: Mapping[str, tuple[float, float]] | None = None, *,
             free: Iterable[str] = (), values: Mapping[str, float] | None = None,
             hold: Mapping[str, float] | None = None, force: str | None = None,
             options: ContinuationOptions | None = None, direction: int = 0) -> Branch:
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
    hold, force:
        The downlock condition (defaults: the model's, see :func:`downlock_condition`).
    options:
        Step control; ``bounds`` given here are merged into it.
    direction:
        ``0`` both ways from the start value, ``+1``/``-1`` one way.

    Returns
    -------
    Branch
        Columns of every variable along the branch (``branch[force]`` is the downlock
        force, N); stability from the mechanics; ``LP`` where ``vary`` turns back.

    Raises
    ------
    InputError
        Unknown names, ``vary`` without bounds or equal to the force or a held state, a
        start value outside its bounds.
    """
    h, f = downlock_condition(system, hold, force)
    system.variable(vary)
    if vary == f:
        raise InputError("vary", f"'{vary}' is the downlock force, which is solved for; vary a design parameter")
    if vary in h:
        raise InputError("vary", f"'{vary}' is held by the downlock condition; vary a design parameter")
    free = list(free)
    if vary in free:
        raise InputError("vary", f"'{vary}' cannot be both varied and freed")
    all_bounds = dict(options.bounds) if options is not None else {}
    all_bounds.update(bounds or {})
    for n in all_bounds:
        system.variable(n)
    if vary not in all_bounds:
        raise InputError("bounds", f"give a range for the varied parameter, e.g. {vary}=LO:HI")
    lo, hi = all_bounds[vary]
    values = dict(values or {})
    start = values.get(vary, system.variable(vary).value)
    if not lo <= start <= hi:
        raise InputError(vary, f"start value {start:g} lies outside its bounds {lo:g}:{hi:g}; set it with values")
    x0 = downlock_point(system, values, hold=h, force=f, free=free)
    if options is None:
        span = hi - lo if np.isfinite(hi - lo) else 1.0
        scale = system.variable(vary).scale
        options = ContinuationOptions(ds=min(0.02, 0.5 * span / scale), dsmin=1e-9,
                                      dsmax=max(0.02, min(0.5, 0.1 * span / scale)), bounds=all_bounds)
    else:
        from dataclasses import replace

        options = replace(options, bounds=all_bounds)
    branch = continuation(system, x0, vary, hold=list(h), free=[f, *free], options=options, direction=direction)
    branch.downlock_force = f
    return branch
