"""The optimiser's quantities of a lock resting on its stops: each stop's preload at rest and the unlock load.

* The preload of stop ``S`` is its contact reaction ``R_S`` with the force at its value and every
  stop of the model held at its limit (the reactions freed): signed and smooth in the design, so a
  design that no longer rests on a stop shows as a negative reaction rather than a switch. Its
  exact gradient is :func:`~mechcont.analysis.sensitivity.equilibrium_sensitivity` of ``R_S``
  with the stops held.
* The unlock load is that of :func:`~mechcont.analysis.stop_lock.stop_unlock`: the lock pushed open
  from rest, the stops releasing (``SR``), up to the first fold. Its gradient is
  :func:`~mechcont.analysis.sensitivity.fold_sensitivity` at a smooth fold (``LP``, with the
  stops still touching there held), or :func:`~mechcont.analysis.sensitivity.release_sensitivity`
  of the last release when the fold is non-smooth (``NSF``: the release is the snap).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..continuation import choose_unknowns, find_equilibrium
from ..equations import Model
from ..errors import InputError
from .sensitivity import Sensitivity, equilibrium_sensitivity, fold_sensitivity, release_sensitivity

__all__ = ["stop_reactions", "preload_sensitivity", "stop_unlock_sensitivity"]


def stop_reactions(system: Model) -> dict[str, str]:
    """``{reaction name: stop name}`` of the model's stops (empty for a model without stops)."""
    return {s.reaction: s.name for s in system.stops}


def preload_sensitivity(system: Model, values: Mapping[str, float], reaction: str, params: Sequence[str],
                        guess: np.ndarray | None = None) -> Sensitivity:
    """The reaction ``reaction`` (N or N m) of a stop at rest, every stop held at its limit, and its derivatives by
    ``params`` (SI). ``guess``: a full vector near the solution (default: the locked state found from the
    description's configuration). Raises :class:`~mechcont.errors.ConvergenceError` when Newton fails."""
    stops = system.stops
    hold = {s.condition: float(s.limit) for s in stops}
    free = [s.reaction for s in stops]
    if guess is None:
        from .stop_lock import locked_on_stops

        guess, _ = locked_on_stops(system, values)
    x = find_equilibrium(system, values=dict(values), hold=hold, free=free, guess=guess)
    unknowns = choose_unknowns(system, hold=list(hold), free=free)
    s = equilibrium_sensitivity(system, x, unknowns, list(params), reaction, kind="preload")
    s.point = s.point or "lock at rest, all stops held"
    return s


def stop_unlock_sensitivity(system: Model, values: Mapping[str, float], force: str,
                            params: Sequence[str]) -> Sensitivity:
    """The unlock load (N) of the lock on stops at ``values`` (the force increased from its value to the first
    fold, :func:`~mechcont.analysis.stop_lock.stop_unlock`) and its derivatives by ``params``. Raises
    :class:`InputError` when the release run finds no fold (the notes say why)."""
    from .stop_lock import locked_on_stops, stop_unlock

    x, _ = locked_on_stops(system, values)
    found = stop_unlock(system, x, force, stability=False, both=False)
    p = found.above
    if p is None:
        raise InputError("unlock_force", "; ".join([*found.notes, *found.warnings]) or "no unlock fold")
    assert found.branch is not None and p.unknowns is not None  # a fold found is a point of the release run
    if p.label == "NSF":
        releases = [q for q in found.branch.special("SR") if q[force] <= p[force] + 1e-9 * abs(p[force])]
        if not releases:
            raise InputError("unlock_force", f"a non-smooth fold at {force} = {p[force]:.6g} without a release before it")
        last = max(releases, key=lambda q: q[force])
        return release_sensitivity(system, last.x, last.extra["stop"], force, params)
    return fold_sensitivity(system, p.x, list(p.unknowns), force, params, null_vector=p.null_vector)
