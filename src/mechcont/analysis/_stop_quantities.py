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
from dataclasses import replace

import numpy as np

from ..continuation import choose_unknowns, find_equilibrium
from ..equations import Model
from ..errors import InputError
from .sensitivity import Sensitivity, equilibrium_sensitivity, fold_sensitivity, release_sensitivity, through_limits
from .stop_lock import locked_on_stops, stop_unlock

__all__ = ["stop_reactions", "preload_sensitivity", "stop_unlock_sensitivity"]


def stop_reactions(system: Model) -> dict[str, str]:
    """``{reaction name: stop name}`` of the model's stops (empty for a model without stops)."""
    return {s.reaction: s.name for s in system.stops}


def preload_sensitivity(system: Model, values: Mapping[str, float], reaction: str, params: Sequence[str],
                        guess: np.ndarray | None = None) -> Sensitivity:
    """The reaction ``reaction`` (N or N m) of a stop at rest, every stop held at its limit, and its derivatives by
    ``params`` (SI; a stop's limit written in a parameter follows it). ``values``: parameter values (SI), the model
    taken at them (:meth:`~mechcont.equations.Model.with_values`: the limits follow). ``guess``: a full vector near
    the solution (default: the locked state found from the description's configuration). Raises
    :class:`~mechcont.errors.ConvergenceError` when Newton fails."""
    system = system.with_values(dict(values)) if values else system
    stops = system.stops
    hold = {s.condition: float(s.limit) for s in stops}
    free = [s.reaction for s in stops]
    if guess is None:
        guess, _ = locked_on_stops(system, values)
    x = find_equilibrium(system, values=dict(values), hold=hold, free=free, guess=guess)
    unknowns = choose_unknowns(system, hold=list(hold), free=free)
    s = through_limits(system, params, hold,
                       lambda names: equilibrium_sensitivity(system, x, unknowns, names, reaction, kind="preload"))
    return replace(s, point=s.point or "lock at rest, all stops held")


def stop_unlock_sensitivity(system: Model, values: Mapping[str, float], force: str,
                            params: Sequence[str]) -> Sensitivity:
    """The unlock load (N) of the lock on stops at ``values`` (the force increased from its value to the first
    fold, :func:`~mechcont.analysis.stop_lock.stop_unlock`) and its derivatives by ``params``. Raises
    :class:`InputError` when the release run finds no fold (the notes say why). The model is taken at ``values``
    (:meth:`~mechcont.equations.Model.with_values`: a stop's limit written in a parameter follows it)."""
    system = system.with_values(dict(values)) if values else system
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
        assert last.stop is not None  # an SR point names its stop
        return release_sensitivity(system, last.x, last.stop, force, params)
    unknowns = list(p.unknowns)
    held = [c.condition for c in system.stops if c.condition not in unknowns]
    return through_limits(system, params, held, lambda names: fold_sensitivity(system, p.x, unknowns, force, names,
                                                                              null_vector=p.null_vector))
