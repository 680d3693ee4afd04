"""A lock that rests on its stops: the locked state, its preload along a design parameter, its unlock load.

With stops declared (``[stops.NAME]``), a lock is not held at a condition by a force: it rests on a
stop, and the stop's contact reaction ``R_NAME`` (>= 0) is what holds it. So the locked state is
the equilibrium with a consistent set of stops in contact at the force's value
(:func:`~mechcont.analysis.stops.equilibrium_on_stops`); the *preload* of the lock along a design
parameter is that reaction, continued with the stops switching (:func:`downlock_on_stops`; a
reaction reaching zero is where the design stops locking, ``SR``). Pushed open by the force, the
lock first leaves its stop (``SR``, the release load) and then gives way at the fold that follows,
smooth (``LP``) or not (``NSF``, the release is the snap): that fold's force is the unlock load
(:func:`stop_unlock`), reported in the :class:`~mechcont.analysis.unlock.UnlockFolds` of the
condition-held downlock.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from ..continuation import Branch, ContinuationOptions
from ..equations import Model
from ..errors import ConvergenceError, InputError
from ..units import shown
from ._runs import early_stops
from .downlock import DownlockResult, design_bounds, design_options
from .stops import GAP_TOL, continuation_with_stops, equilibrium_on_stops, stability_on_stops
from .unlock import RELEASE_FORCE_SPAN, UnlockFolds

__all__ = ["downlock_on_stops", "downlock_on_stops_table", "stop_unlock", "stop_unlock_along", "with_stop_unlock_column",
           "lock_force", "landing_after_unlock"]


def lock_force(system: Model, force: str | None = None) -> str:
    """The force (a parameter) that opens a lock on stops: ``force``, else the model's downlock force, else ``F``."""
    facts = system.downlock
    f = force if force is not None else (facts.force if facts is not None else "F")
    if system.variable(f).kind != "parameter":
        raise InputError(f, "the unlock force must be a parameter of the model (it is continued)")
    return f


def locked_on_stops(system: Model, values: Mapping[str, float] | None = None,
                    free: Iterable[str] = ()) -> tuple[np.ndarray, list[str]]:
    """The locked state: the equilibrium with a consistent set of stops in contact at ``values`` (SI), found
    from the description's assembled configuration, a stable one when there is one. Raises
    :class:`InputError` when no stop is in contact there (nothing rests on a stop: not a lock) or none
    is consistent."""
    try:
        x, contact = equilibrium_on_stops(system, system.vector(dict(values or {})), values=values, free=free,
                                          stable=True)
    except ConvergenceError as exc:
        raise InputError("stops", f"no locked state on the stops of {system.name}: {exc}") from None
    if not contact:
        names = ", ".join(s.name for s in system.stops)
        raise InputError("stops", f"{system.name} rests on none of its stops ({names}) at these values: not locked "
                                  "(the equilibrium found stands free)")
    return x, contact


def stop_unlock(system: Model, x: np.ndarray, force: str, *, max_steps: int = 400,
                stability: bool = True, both: bool = True, span: float = RELEASE_FORCE_SPAN) -> UnlockFolds:
    """The unlock loads of a lock resting on its stops at ``x``: the force continued both ways from there
    with the stops switching (:func:`~mechcont.analysis.stops.continuation_with_stops`), each way ended at its
    first fold, ``LP`` or ``NSF``. ``above`` is the unlock load (force increasing), ``below`` the other side;
    the notes name the release (``SR``) before each and where a non-smooth fold lands. The force may move by
    :data:`~mechcont.analysis.unlock.RELEASE_FORCE_SPAN` of its scales (``span`` of them when given). ``both=False``:
    increasing only."""
    F0 = float(x[system.index(force)])
    contact = [s.name for s in system.stops if abs(s.gap(x[system.index(s.condition)])) <= GAP_TOL
               and x[system.index(s.reaction)] >= 0]
    stable = bool(stability_on_stops(system, x, contact).stable) if system.mechanics is not None else None
    sc = system.variable(force).scale
    options = ContinuationOptions(ds=0.02, dsmax=0.5, max_steps=max_steps, detect_folds=False, stability=stability,
                                  bounds={force: (F0 - span * sc, F0 + span * sc)})
    try:
        run = continuation_with_stops(system, x, force, direction=0 if both else 1, stop_at_fold=True,
                                      options=options, contact=contact)
    except (ConvergenceError, InputError) as exc:
        return UnlockFolds(force, F0, stable, None, None, None, warnings=[f"release run in {force} failed: {exc}"])
    b = run.branch
    folds = [p for p in b.special_points if p.label in ("LP", "NSF")]
    below = max((p for p in folds if p[force] < F0), key=lambda p: p[force], default=None)
    above = min((p for p in folds if p[force] > F0), key=lambda p: p[force], default=None)
    unit = system.variable(force).unit
    notes = []
    for side, p in (("decreasing", below), ("increasing", above)):
        if p is None:
            if side == "increasing" or both:
                end = F0 + (span if side == "increasing" else -span) * sc
                forces = b.column(force)
                reached = float(forces.max() if side == "increasing" else forces.min())
                if abs(reached - end) <= 1e-6 * span * sc:
                    notes.append(f"no fold {side} {force} within the release run ({force} moved by {span:g} of its "
                                 f"scales, to {end:.6g} {unit}; a larger span searches further)".replace(" ;", ";"))
                else:  # the run ended short of its span (max_steps, a failed step): say where, not where it aimed
                    notes.append(f"no fold {side} {force} within the release run, which ended early at {force} = "
                                 f"{reached:.6g} {unit} (its span reaches {end:.6g} {unit})".replace(" )", ")"))
            continue
        releases = [q for q in b.special("SR") if min(F0, p[force]) <= q[force] <= max(F0, p[force])]
        rel = "; ".join(f"stop {q.stop} releases at {force} = {q[force]:.6g} {unit} (SR)" for q in releases)
        what = f"{'a non-smooth fold (NSF): the release is the snap' if p.label == 'NSF' else 'a fold (LP)'}"
        land = ""
        landing = p.nonsmooth.landing if p.label == "NSF" and p.nonsmooth is not None else None
        if landing is not None:
            on = ", ".join(landing.contact) or "no stop"
            land = f", the mechanism lands on {on} ({'stable' if landing.stable else 'UNSTABLE'})"
        notes.append(f"{side} {force}: {rel + '; then ' if rel else ''}{what} at {force} = {p[force]:.6g} {unit}{land}")
    warnings = early_stops(b, f"release run in {force}")
    return UnlockFolds(force, F0, stable, below, above, b, notes, warnings)


def landing_after_unlock(system: Model, x: np.ndarray, unlock: UnlockFolds, span: float = RELEASE_FORCE_SPAN) -> str:
    """Where the lock at ``x`` lands when its unlock load (``unlock.above``) is a non-smooth fold: one line
    (from a run through the fold, :func:`~mechcont.analysis.stops.continuation_with_stops`), "" otherwise."""
    p = unlock.above
    if p is None or p.label != "NSF":
        return ""
    f, F0 = unlock.force, unlock.downlock_force
    sc = system.variable(f).scale
    options = ContinuationOptions(ds=0.02, dsmax=0.5, max_steps=400, detect_folds=False,
                                  bounds={f: (F0 - span * sc, F0 + span * sc)})
    try:
        run = continuation_with_stops(system, x, f, direction=1, options=options, max_switches=6)
    except (ConvergenceError, InputError):
        return ""
    nsf = next((q for q in run.branch.special("NSF") if abs(q[f] - p[f]) <= 1e-6 * max(abs(p[f]), sc)), None)
    landing = None if nsf is None or nsf.nonsmooth is None else nsf.nonsmooth.landing
    if landing is None:
        return f"the lock snaps at {f} = {p[f]:.6g}; no equilibrium at that {f} catches it within the release run"
    at = dict(zip(run.branch.names, landing.x))
    on = ", ".join(landing.contact) or "no stop"
    names = system.mechanics.coordinates if system.mechanics is not None else system.state_names
    moved = max(names, key=lambda n: abs(at[n] - p[n]) / system.variable(n).scale)  # the coordinate that jumps most
    how = "stable" if landing.stable else "UNSTABLE"
    unit = system.variable(moved).unit

    return (f"the lock snaps at {f} = {p[f]:.6g} {system.variable(f).unit} and lands on {on} ({how}; {moved} from "
            f"{shown(p[moved], unit)} to {shown(at[moved], unit)})")


def stop_unlock_along(system: Model, branch: Branch, force: str,
                      span: float = RELEASE_FORCE_SPAN) -> tuple[np.ndarray, list[str]]:
    """The unlock load (force increasing, nan where none) at every row of a lock-on-stops ``branch``, each
    from its own release run (:func:`stop_unlock`, increasing only), and the runs' warnings."""
    out = np.full(len(branch), np.nan)
    warnings: list[str] = []
    for i, x in enumerate(branch.values):
        u = stop_unlock(system, x, force, stability=False, both=False, span=span)
        out[i] = u.unlock_force
        warnings += [f"{branch.vary} = {x[system.index(branch.vary)]:.6g}: {w}" for w in u.warnings]
    return out, warnings


def with_stop_unlock_column(system: Model, result: DownlockResult, force: str,
                            span: float = RELEASE_FORCE_SPAN) -> tuple[DownlockResult, np.ndarray]:
    """``(new result, unlock loads)``: the lock-on-stops ``result`` with the unlock load of every row
    (:func:`stop_unlock_along`, unit of ``force``) as column ``unlock_<force>`` of its branch when some row
    has one, and the release runs' warnings added to its ``warnings``."""
    unlock, more = stop_unlock_along(system, result.branch, force, span)
    col = f"unlock_{force}"
    branch = (result.branch.with_columns({col: unlock}, {col: system.variable(force).unit}) if np.isfinite(unlock).any()
              else result.branch)
    return replace(result, branch=branch,
                   warnings=[*result.warnings, *(f"unlock loads along the branch: {w}" for w in more)]), unlock


def downlock_on_stops_table(system: Model, vary: str, bounds: Mapping[str, tuple[float, float]] | None = None,
                            **options: Any) -> tuple[DownlockResult, np.ndarray]:
    """:func:`downlock_on_stops` (``options`` are its) with the unlock load of every row as a column
    (:func:`with_stop_unlock_column`): the table ``mechcont downlock`` writes for a lock on stops, and the
    unlock loads (unit of the force; nan where a row has none)."""
    result = downlock_on_stops(system, vary, bounds, **options)
    return with_stop_unlock_column(system, result, result.force, options.get("span", RELEASE_FORCE_SPAN))


def downlock_on_stops(system: Model, vary: str, bounds: Mapping[str, tuple[float, float]] | None = None, *,
                      force: str | None = None, free: Iterable[str] = (), values: Mapping[str, float] | None = None,
                      options: ContinuationOptions | None = None, direction: int = 0, unlock: bool = True,
                      max_steps: int | None = None, span: float = RELEASE_FORCE_SPAN) -> DownlockResult:
    """The lock resting on its stops as a function of the design parameter ``vary``, by continuation.

    Parameters
    ----------
    system:
        A model with stops; the locked state is found at ``values`` with the force at its value.
    vary, bounds, free, values, options, direction, max_steps:
        As :func:`~mechcont.analysis.downlock.downlock`.
    force:
        The force that opens the lock (a parameter; default the model's downlock force, else ``F``).
    unlock:
        Also find the unlock loads of the locked state at the start (:func:`stop_unlock`).
    span:
        How far the release runs push the force: this many of its scales each way.

    Returns
    -------
    DownlockResult
        Its ``branch``: the run in ``vary`` with the stops switching (their reactions ``R_NAME`` are the lock's
        preload: > 0 locked, ``SR`` where a design stops locking); ``condition`` maps each stop's
        condition in contact at the start to its limit; ``unlock`` the :class:`UnlockFolds` of the
        start; ``warnings`` the runs that stopped short; ``lock_stops`` the stops in contact at the start.
    """
    f = lock_force(system, force)
    system.variable(vary)
    if vary == f:
        raise InputError("vary", f"'{vary}' is the unlock force, which is continued to open the lock; vary a design "
                                 "parameter")
    all_bounds, start = design_bounds(system, vary, bounds, options, values)
    x0, contact = locked_on_stops(system, values, free)
    opts = design_options(system, vary, all_bounds, options, max_steps)
    run = continuation_with_stops(system, x0, vary, direction=direction, free=list(free), options=opts, contact=contact)
    stops = {s.name: s for s in system.stops}
    condition = {stops[n].condition: float(stops[n].limit) for n in contact}
    warnings = early_stops(run.branch, f"lock on stops ({', '.join(contact)}) in {vary}",
                           show=[stops[n].reaction for n in contact])
    found = None
    if unlock:
        found = stop_unlock(system, x0, f, span=span)
        warnings += [f"unlock loads at {vary} = {start:g}: {w}" for w in found.warnings]
        landing = landing_after_unlock(system, x0, found, span)
        if landing:
            found.notes.append(landing)
    return DownlockResult(run.branch, f, condition, found, warnings, tuple(contact))
