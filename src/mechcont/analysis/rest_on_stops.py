"""Where a mechanism with stops rests: the equilibrium with a consistent set of stops in contact, as ``check`` reports
it (:func:`stops_at_rest`) and as ``continue --stops`` starts from it (:func:`start_on_stops`)."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..equations import Model
from ..errors import ConvergenceError, InputError
from .stops import equilibrium_on_stops, stability_on_stops

__all__ = ["StopAtRest", "StopsAtRest", "stops_at_rest", "StopsStart", "start_on_stops"]


@dataclass(frozen=True)
class StopAtRest:
    """One stop at the equilibrium of :func:`stops_at_rest`.

    ``key`` is ``"min"`` or ``"max"``, ``limit`` the stop's limit (``condition_unit``); in contact, ``value`` is the
    stop's reaction ``reaction`` (``unit``, >= 0); free, ``value`` is the condition's value (``condition_unit``) and
    ``gap`` how far it is from the stop (>= 0 on the allowed side)."""

    name: str
    key: str
    condition: str
    condition_unit: str
    limit: float
    reaction: str
    in_contact: bool
    value: float
    unit: str
    gap: float


@dataclass(frozen=True)
class StopsAtRest:
    """The equilibrium of a mechanism with stops found from a configuration (:func:`stops_at_rest`).

    ``x`` is the full vector (SI, rad) and ``contact`` the names of the stops in contact there; ``stops`` one
    :class:`StopAtRest` per stop of the model, in its order; ``n_unstable`` the unstable directions with the stops
    in contact holding their conditions (0: stable). ``failure`` says why there is none (``x`` is then ``None``,
    ``stops`` empty)."""

    x: npt.NDArray[np.float64] | None
    contact: tuple[str, ...]
    stops: tuple[StopAtRest, ...]
    n_unstable: int
    failure: str = ""

    @property
    def stable(self) -> bool:
        """Whether the equilibrium is stable (with its stops in contact)."""
        return self.failure == "" and self.n_unstable == 0

    def lines(self) -> list[str]:
        """The stops section of ``mechcont check``: a heading, one line per stop and the stability (or why there is
        no equilibrium)."""
        out = ["stops (one-sided limits of conditions; the equilibrium above leaves them free), the equilibrium with "
               "those in contact that push:"]
        if self.failure:
            return [*out, f"  {self.failure}"]
        width = max(len(s.name) for s in self.stops)
        for s in self.stops:
            bound = f"{s.key} of {s.condition} = {s.limit:.6g}{' ' + s.condition_unit if s.condition_unit else ''}"
            if s.in_contact:
                state = f"in contact, reaction {s.reaction} = {s.value:.6g} {s.unit}"
            else:
                state = f"free, {s.condition} = {s.value:.6g} ({s.gap:.3g} from it)"
            out.append(f"  {s.name:<{width}}  {bound}: {state}")
        out.append(f"  stability there (a stop in contact holds its condition): "
                   f"{'stable' if self.stable else f'UNSTABLE in {self.n_unstable} direction(s)'}")
        return out


def stops_at_rest(system: Model, x: npt.NDArray[np.float64]) -> StopsAtRest:
    """The stable equilibrium with a consistent set of stops in contact nearest the full vector ``x`` (SI, rad; e.g.
    the assembled configuration), each stop's state there and its stability
    (:func:`~mechcont.analysis.equilibrium_on_stops`, :func:`~mechcont.analysis.stability_on_stops`).

    A mechanism with no such equilibrium gives a result whose ``failure`` says why (a finding, not an error)."""
    try:
        at, contact = equilibrium_on_stops(system, x, stable=True)
    except (ConvergenceError, InputError) as exc:
        return StopsAtRest(None, (), (), 0, f"no equilibrium with a consistent set of stops in contact: {exc}")
    rows = []
    for s in system.stops:
        c = system.variable(s.condition)
        value = float(at[system.index(s.condition)])
        if s.name in contact:
            rows.append(StopAtRest(s.name, s.key, s.condition, c.unit, s.limit, s.reaction, True,
                                   float(at[system.index(s.reaction)]), system.variable(s.reaction).unit, 0.0))
        else:
            rows.append(StopAtRest(s.name, s.key, s.condition, c.unit, s.limit, s.reaction, False, value, c.unit,
                                   s.gap(value)))
    st = stability_on_stops(system, at, contact)
    return StopsAtRest(at, tuple(contact), tuple(rows), int(st.n_unstable))


@dataclass(frozen=True)
class StopsStart:
    """The first point of a continuation with stops (:func:`start_on_stops`): the full vector ``x`` (SI, rad), the
    stops in contact there, and whether the search began at the description's configuration (``True``: free of its
    stops the mechanism had no equilibrium near its pose, and nothing was held) rather than at the free equilibrium."""

    x: npt.NDArray[np.float64]
    contact: tuple[str, ...]
    from_description: bool


def start_on_stops(system: Model, vary: str, *, values: Mapping[str, float] | None = None,
                   start: Mapping[str, float] | None = None, hold: Iterable[str] = (), free: Iterable[str] = (),
                   start_field: str = "start", free_field: str = "free") -> StopsStart:
    """Where ``continue --stops`` starts: the equilibrium with a consistent set of stops in contact nearest the first
    equilibrium of a run in ``vary`` (:func:`~mechcont.continuation.start_point` with ``start`` states held and
    ``vary`` solved for), the ``hold`` states kept at their values there.

    Free of its stops a mechanism may have no equilibrium near its pose (a lock held on a stop): with nothing held
    or started (``start`` and ``hold`` empty) the search then begins at the description's configuration at
    ``values``. Raises :class:`~mechcont.errors.ConvergenceError` when there is no equilibrium either way."""
    from ..continuation import start_point

    hold, free = list(hold), list(free)
    from_description = False
    try:
        x0 = start_point(system, vary, values=values, start=start, free=free, hold=hold, start_field=start_field,
                         free_field=free_field)
    except ConvergenceError:
        if start or hold:
            raise
        x0, from_description = system.vector(dict(values or {})), True
    x, contact = equilibrium_on_stops(system, x0, hold={h: x0[system.index(h)] for h in hold}, free=free)
    return StopsStart(x, tuple(contact), from_description)
