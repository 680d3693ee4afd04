"""The equilibrium of a mechanism on its stops: a consistent set of stops in contact, found by an active-set search.

A stop in contact holds its condition at its limit with a contact reaction ``R_NAME`` >= 0; a free
stop has ``R_NAME = 0`` and its condition on the allowed side (complementarity).
:func:`equilibrium_on_stops` walks from a guess (adding the stop most past its limit, releasing the
reaction pulling most) and, when that walk cycles or a solve diverges, tries every other set of stops
in contact in turn. The stops' lens (:func:`contact_lens`, :func:`with_contacts`) and the stability on
a contact set (:func:`stability_on_stops`) are shared with the continuation through contact changes
(:mod:`mechcont.analysis.stops`).
"""

from __future__ import annotations

from collections.abc import Container, Iterable, Mapping, Sequence
from itertools import combinations

import numpy as np

from ..continuation import find_equilibrium
from ..equations import Model, StabilityResult, StopLimit
from ..errors import ConvergenceError, InputError

__all__ = ["GAP_TOL", "n_unstable_on", "check_start_contacts", "at_switch",
           "equilibrium_on_stops", "stops_in_contact", "check_stop_lens", "stability_on_stops",
           "named_stops", "contact_lens", "with_contacts"]

#: A stop counts as touching when its condition is within this of the limit (condition units: a
#: sine, rad or m), far below any physical gap and far above the solver's residual.
GAP_TOL = 1e-9


def named_stops(system: Model, names: Iterable[str] | None) -> tuple[StopLimit, ...]:
    """The model's stops called ``names`` (all of them for None), in that order; :class:`InputError` naming
    the valid ones for an unknown name."""
    have = system.stops
    if names is None:
        return have
    by_name = {s.name: s for s in have}
    out = []
    for n in names:
        if n not in by_name:
            valid = ", ".join(by_name) or "none (declare [stops.NAME] in the description)"
            raise InputError("stops", f"unknown stop {n!r}; stops of {system.name}: {valid}")
        out.append(by_name[n])
    return tuple(out)


def stops_in_contact(system: Model, x: np.ndarray, stops: Sequence[StopLimit] | None = None) -> list[str]:
    """Names of the stops touching at the full vector ``x``: condition at its limit and reaction > 0."""
    stops = named_stops(system, None) if stops is None else stops
    return [s.name for s in stops
            if abs(s.gap(x[system.index(s.condition)])) <= GAP_TOL and x[system.index(s.reaction)] > 0]


def check_stop_lens(system: Model, vary: str, hold: Iterable[str] = (), free: Iterable[str] = (),
                    stops: Iterable[str] | None = None) -> None:
    """Raise a one-line :class:`~mechcont.errors.InputError` when ``vary``, ``hold`` or ``free`` names a stop's
    reaction or condition: with stops those are switched by contact, not chosen."""
    managed = {n: s.name for s in named_stops(system, stops) for n in (s.reaction, s.condition)}
    for what, names in (("vary", [vary]), ("hold", list(hold)), ("free", list(free))):
        for n in names:
            if n in managed:
                raise InputError(what, f"{n} is switched by the stop {managed[n]} (held at its limit with the "
                                       "reaction free in contact, free with a zero reaction out of it); "
                                       f"{'vary a load or parameter' if what == 'vary' else 'leave it out'}")


def contact_lens(stops: Sequence[StopLimit], active: Iterable[str], hold: Iterable[str],
                 free: Iterable[str]) -> tuple[list[str], list[str]]:
    """``(hold, free)`` names of a solve with the stops ``active`` in contact: their conditions added to
    ``hold`` (at their limits), their reactions to ``free``."""
    active = set(active)
    hold_ = [*hold, *(s.condition for s in stops if s.name in active)]
    free_ = [*free, *(s.reaction for s in stops if s.name in active)]
    return hold_, free_


def with_contacts(system: Model, x: np.ndarray, stops: Iterable[StopLimit], active: Container[str]) -> np.ndarray:
    """``x`` with the active stops' conditions exactly at their limits and the free stops' reactions 0."""
    y = np.array(x, dtype=float)
    for s in stops:
        if s.name in active:
            y[system.index(s.condition)] = s.limit
        else:
            y[system.index(s.reaction)] = 0.0
    return y


def equilibrium_on_stops(system: Model, guess: np.ndarray | Mapping[str, float], *,
                         values: Mapping[str, float] | None = None, hold: Mapping[str, float] | None = None,
                         free: Iterable[str] = (), stops: Iterable[str] | None = None,
                         contact: Iterable[str] | None = None, stable: bool = False) -> tuple[np.ndarray, list[str]]:
    """An equilibrium with a consistent set of stops in contact.

    Parameters
    ----------
    system:
        A model with stops (``system.stops``).
    guess:
        Full vector or ``{name: value}`` near the equilibrium.
    values, hold, free:
        As :func:`~mechcont.continuation.find_equilibrium` (parameters set, states held, parameters freed).
    stops:
        Names of the stops to consider (default: all of the model's).
    contact:
        The stops to try in contact first (default: those whose condition is at or past its limit
        at ``guess``).
    stable:
        When the equilibrium found is unstable (e.g. Newton from the guess went to the unstable
        straight toggle of a clamp whose lock rests on a stop past it), try each further stop in
        contact first and return the first consistent stable equilibrium, if any.

    Returns
    -------
    (x, contact)
        The full vector (reactions of free stops 0, reactions in contact >= 0, free conditions on
        their sides) and the names of the stops in contact.

    Raises
    ------
    ConvergenceError
        When no active set gives a consistent equilibrium: every set was tried (the walk from
        ``guess``, then each other set with its conditions at their limits); the message names
        each with why it fails (a reaction that pulls, a condition past a limit, no convergence).
    """
    x, found = _active_set(system, guess, values, hold, free, stops, contact)
    if not stable or system.mechanics is None or stability_on_stops(system, x, found).stable:
        return x, found
    for s in named_stops(system, stops):
        if s.name in found:
            continue
        try:
            y, there = _active_set(system, guess, values, hold, free, stops, [*found, s.name])
        except ConvergenceError:
            continue
        if stability_on_stops(system, y, there).stable:
            return y, there
    return x, found


def _active_set(system: Model, guess: np.ndarray | Mapping[str, float], values: Mapping[str, float] | None,
                hold: Mapping[str, float] | None, free: Iterable[str], stops: Iterable[str] | None,
                contact: Iterable[str] | None) -> tuple[np.ndarray, list[str]]:
    """:func:`equilibrium_on_stops`' active-set method from one guess and first contact set.

    First the small active-set walk (add the stop most past its limit, else release the reaction
    pulling most); when it cycles or a solve diverges (e.g. the free Newton from a pose on one stop
    running off past it), each untried contact set in turn, fewest stops first, solved from the guess
    with its conditions held at their limits: the first consistent one is taken."""
    st = named_stops(system, stops)
    x0 = system.vector(guess) if isinstance(guess, Mapping) else np.array(guess, dtype=float)
    active = set(contact) if contact is not None else {s.name for s in st
                                                       if s.gap(x0[system.index(s.condition)]) <= GAP_TOL}
    tried: dict[frozenset[str], str] = {}      # contact set -> why it is not the answer
    x = x0
    for _ in range(2 ** len(st) + 1):
        y, worst_past, worst_pull, why = _solve_set(system, x, active, values, hold, free, st)
        if y is not None and not why:
            return y, [s.name for s in st if s.name in active]
        tried[frozenset(active)] = why
        if y is None:
            break
        if worst_past is not None:
            active.add(worst_past)
        else:
            active.discard(worst_pull)
        if frozenset(active) in tried:
            break
        x = y
    for k in range(len(st) + 1):   # the stops in contact, each candidate set in turn
        for chosen in combinations([s.name for s in st], k):
            if frozenset(chosen) in tried or not _compatible(st, chosen):
                continue
            y, _, _, why = _solve_set(system, x0, set(chosen), values, hold, free, st)
            if y is not None and not why:
                return y, list(chosen)
            tried[frozenset(chosen)] = why
    sets = "; ".join(f"{', '.join(s.name for s in st if s.name in a) or 'none'} in contact: {why}"
                     for a, why in tried.items())
    raise ConvergenceError(f"no consistent set of stops in contact; tried: {sets}")


def _compatible(stops: Sequence[StopLimit], chosen: Iterable[str]) -> bool:
    """False when two of the stops ``chosen`` would hold one condition at two different limits."""
    held: dict[str, float] = {}
    for s in stops:
        if s.name in chosen and held.setdefault(s.condition, s.limit) != s.limit:
            return False
    return True


def _solve_set(system: Model, x: np.ndarray, active: set[str], values: Mapping[str, float] | None,
               hold: Mapping[str, float] | None, free: Iterable[str],
               stops: Sequence[StopLimit]) -> tuple[np.ndarray | None, str | None, str | None, str]:
    """The equilibrium with the stops ``active`` in contact (conditions held at their limits, reactions freed),
    the others free (reactions 0), from ``x``: ``(y, most past free stop, most pulling stop, why)``, ``why`` ""
    when the set is consistent (complementarity: every reaction >= 0, every free condition on its side, to
    within rounding), else what is wrong (``y`` None when Newton does not converge)."""
    hold_k = {**dict(hold or {}), **{s.condition: s.limit for s in stops if s.name in active}}
    free_k = [*free, *(s.reaction for s in stops if s.name in active)]
    try:
        y = find_equilibrium(system, values={**(values or {}), **{s.reaction: 0.0 for s in stops
                                                                 if s.name not in active}},
                             hold=hold_k, free=free_k, guess=with_contacts(system, x, stops, active))
    except ConvergenceError:
        return None, None, None, "Newton from the guess did not converge"
    sc = system.scales()
    pulls = {s.name: y[system.index(s.reaction)] / sc[system.index(s.reaction)] for s in stops if s.name in active}
    past = {s.name: s.gap(y[system.index(s.condition)]) for s in stops if s.name not in active}
    worst_pull = min(pulls, key=pulls.__getitem__, default=None)
    worst_past = min(past, key=past.__getitem__, default=None)
    by_name = {s.name: s for s in stops}
    if worst_past is not None and past[worst_past] < -GAP_TOL:
        s = by_name[worst_past]
        c = system.variable(s.condition)
        return y, worst_past, None, (f"{s.condition} = {y[system.index(s.condition)]:.6g} {c.unit}".rstrip()
                                     + f", {-past[worst_past]:.3g} past the {s.key} of {s.name} ({s.limit:.6g})")
    if worst_pull is not None and pulls[worst_pull] < -GAP_TOL:
        s = by_name[worst_pull]
        R = system.variable(s.reaction)
        return y, None, worst_pull, f"{s.reaction} = {f'{y[system.index(s.reaction)]:.6g} {R.unit}'.rstrip()} pulls"
    return y, None, None, ""


def stability_on_stops(system: Model, x: np.ndarray, contact: Iterable[str]) -> StabilityResult:
    """Physical stability at the full vector ``x`` with the stops ``contact`` (names) in contact.

    A stop that pushes (reaction > 0) forbids motion across it, so its condition's gradient (the
    Jacobian row ``cond_<condition>`` over the coordinates) is held like a joint's; its reaction's
    curvature is already in the forces. Returns the mechanics'
    :class:`~mechcont.equations.StabilityResult`."""
    mech = system.mechanics
    assert mech is not None, "stability needs the model's mechanics (callers check)"
    touching = named_stops(system, list(contact))
    if not touching:
        return mech.stability(x)
    cols = [system.index(q) for q in mech.coordinates]
    rows = [system.equation_names.index(f"cond_{s.condition}") for s in touching]
    return mech.stability(x, held=system.jacobian(x)[np.ix_(rows, cols)])


def n_unstable_on(system: Model, x: np.ndarray, contact: Iterable[str]) -> int:
    """The number of unstable directions of the equilibrium ``x`` with the stops ``contact`` in contact (holding
    their conditions); 0 when it is stable."""
    return stability_on_stops(system, x, sorted(contact)).n_unstable


def check_start_contacts(system: Model, x: np.ndarray, stops: Sequence[StopLimit], active: set[str],
                          undecided: set[str]) -> None:
    """:class:`InputError` unless every stop not ``undecided`` is consistently in (``active``) or out of
    contact at ``x``: in contact, its condition at the limit and a reaction >= 0; free, a zero reaction
    and its condition on the allowed side."""
    for s in stops:
        R, gap = x[system.index(s.reaction)], s.gap(x[system.index(s.condition)])
        if s.name in undecided:
            continue
        if (s.name in active and (R < 0 or abs(gap) > GAP_TOL)) or (s.name not in active and (R != 0 or gap < -GAP_TOL)):
            raise InputError("start", f"stop {s.name} is not consistently in or out of contact there (reaction "
                                      f"{s.reaction} = {R:.6g}, {s.condition} {gap:+.3g} from its limit): a stop in "
                                      "contact has its condition at the limit and a reaction >= 0, a free one a zero "
                                      "reaction and its condition on the allowed side; find the start with "
                                      "equilibrium_on_stops")


def at_switch(system: Model, x: np.ndarray, stops: Sequence[StopLimit]) -> set[str]:
    """The stops at their limit with a zero reaction at ``x``: in or out of contact is for the tangents to say."""
    sc = system.scales()
    return {s.name for s in stops if abs(s.gap(x[system.index(s.condition)])) <= GAP_TOL
            and abs(x[system.index(s.reaction)]) <= GAP_TOL * sc[system.index(s.reaction)]}
