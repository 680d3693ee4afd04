"""Continuation of a mechanism with stops: contact and release switch the equations on the way.

A stop (``[stops.NAME]`` of a description, :class:`~mechcont.equations.StopLimit` of a model)
keeps a condition ``c`` on one side of a limit. Along a branch each stop is either

* *in contact*: ``c`` held at the limit, the contact reaction ``R_NAME`` solved for (it must stay
  >= 0: a stop pushes, it does not pull), or
* *free*: ``R_NAME = 0`` and ``c`` solved for (it must stay on the allowed side of the limit).

:func:`continuation_with_stops` continues with one such *active set* until a reaction reaches
zero (``SR``, stop released) or a free condition reaches its limit (``SC``, stop contact), then
continues from the located switch point in the same sense along the branch with the contact set
the one-sided tangents choose (the same choice decides a start exactly on a limit, which is the
switch itself and keeps its label: ``SR`` or ``NSF``). Where no set
continues, the switch is a non-smooth fold (``NSF``: e.g. a release onto an unstable free branch,
a snap-through); the branch goes on through it like through a smooth fold, and the ``NSF`` point
says where the mechanism lands (its :class:`~mechcont.continuation.NonSmoothFold`'s ``landing``). The pieces are joined into one
:class:`~mechcont.continuation.Branch`: its points carry
the full variable vector (the conditions and reactions are columns), ``SC``/``SR`` label the
switches, ``LP`` the folds of the piece they lie on (each keeps its own lens in
``unknowns``, so :func:`~mechcont.continuation.continue_folds` follows it in a second
parameter with the stops it had in contact held).

:func:`equilibrium_on_stops` (in :mod:`._stop_search`, with the stops' lens) finds the start: an
equilibrium whose active set is consistent (every reaction >= 0, every free condition on its side),
by adding the most violated stop or releasing the most negative reaction until none is left (a small
active-set method), and when that cycles or a solve diverges, by trying every other contact set in turn.
"""

# Why one module of about 490 lines: the continuation with its switches and the joining of its pieces
# are one algorithm over the same state (the pieces, the switches, the folds); the equilibrium on the
# stops, their lens and the stability on a contact set are in _stop_search.py, its events in _stop_events.py.

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from itertools import combinations

import numpy as np

from .._status import Status
from ..continuation import (
    Branch,
    ContinuationOptions,
    Landing,
    NonSmoothFold,
    SpecialPoint,
    choose_unknowns,
    continuation,
    find_equilibrium,
)
from ..continuation import travel as _travel
from ..equations import Model, StopLimit
from ..errors import ConvergenceError, InputError
from ._stop_events import FirstFold, StopEvent
from ._stop_search import (
    GAP_TOL,
    at_switch,
    check_start_contacts,
    check_stop_lens,
    contact_lens,
    equilibrium_on_stops,
    n_unstable_on,
    named_stops,
    stability_on_stops,
    stops_in_contact,
    with_contacts,
)

__all__ = ["StopRun", "continuation_with_stops", "equilibrium_on_stops", "stops_in_contact", "check_stop_lens",
           "stability_on_stops", "GAP_TOL"]


@dataclass
class StopRun:
    """The result of :func:`continuation_with_stops`.

    Attributes
    ----------
    branch:
        All pieces joined in order (arclength continued across switches); ``SC``/``SR`` label
        where a stop made or lost contact, ``LP`` the folds, ``EP`` the ends.
    pieces:
        The branch of each piece, with ``contact[i]`` the stops in contact along piece ``i``.
    contact:
        Per piece, the names of the stops in contact.
    directions:
        Per piece, +1 when it was run increasing the parameter at its start, -1 decreasing (a
        piece's rows run in arclength order, so a -1 piece is travelled from its last row).
    switches:
        ``(label, stop name, index into branch)`` of every switch.
    message:
        Why the run ended (the last piece's end, or the switch limit).
    """

    branch: Branch
    pieces: list[Branch] = field(default_factory=list)
    contact: list[tuple[str, ...]] = field(default_factory=list)
    switches: list[tuple[str, str, int]] = field(default_factory=list)
    message: str = ""
    directions: list[int] = field(default_factory=list)

    def first_fold(self) -> SpecialPoint | None:
        """The first fold along the run from its start, smooth (``LP``) or not (``NSF``), or None."""
        return next((p for p in self.branch.special_points if p.label in ("LP", "NSF")), None)


def continuation_with_stops(system: Model, start: np.ndarray, vary: str, *, direction: int = 1,
                            hold: Iterable[str] = (), free: Iterable[str] = (), stops: Iterable[str] | None = None,
                            contact: Iterable[str] | None = None, options: ContinuationOptions | None = None,
                            stop_at_fold: bool = False, max_switches: int = 20,
                            progress: Callable[[int], None] | None = None) -> StopRun:
    """Continue equilibria in ``vary`` with stops making and losing contact on the way.

    Where a stop is at its limit with a zero reaction (the start exactly on a limit, or a located
    ``SC``/``SR``), the stops in contact on the way on are decided by the one-sided tangents: of the
    sets that continue as ``vary`` is pushed with every reaction growing from zero or every
    released condition moving to its allowed side, the one with the most stops in contact (a
    stop pushed into stays in contact). When no set continues, the point is a *non-smooth fold*
    (``NSF``, e.g. a release onto an unstable free branch: a snap-through): the branch goes on
    through it like through a smooth fold (``vary`` turns back, on the other set), and when the
    mechanism arrived there stable, ``extra["landing"]`` of the ``NSF`` point is where it lands:
    the first equilibrium further along the branch at the same value of ``vary`` (the next
    equilibrium in the direction the mechanism moves, for one degree of freedom exactly where a
    heavily damped motion comes to rest), with ``extra["landing_contact"]`` and
    ``extra["landing_stable"]``; None when the bounds come first. ``extra["jump"]`` says whether the
    mechanism arrived there stable (False: an unstable branch meets a stop, nothing jumps).

    Parameters
    ----------
    system:
        A model with stops.
    start:
        A converged full vector with a consistent contact set (see :func:`equilibrium_on_stops`);
        a stop at its limit with a zero reaction is decided as above.
    vary:
        The continuation parameter (e.g. an unlock force ``F_fwd``, N).
    direction:
        +1: start by increasing ``vary``; -1: decreasing; 0: both, joined into one branch from the
        end of the decreasing run to the end of the increasing one (each run follows the
        mechanism as the parameter is pushed one way from the start).
    hold, free:
        The lens besides the stops (states held, parameters freed), as :func:`continuation`.
    stops:
        The stops considered (default: all of the model's); the others stay as they are in ``start``.
    contact:
        The stops in contact at ``start`` (default: those touching there, :func:`stops_in_contact`,
        and those at their limit with a zero reaction as the tangents decide).
    options:
        Continuation options; its ``bounds`` end the whole run.
    stop_at_fold:
        End the run at the first fold, ``LP`` or ``NSF`` (e.g. the unlock load).
    max_switches:
        Largest number of contact changes before the run ends.
    progress:
        Called with 1 after every accepted step.

    Returns
    -------
    StopRun
        The joined branch, its pieces and switches (``SC``, ``SR`` and ``NSF``). A piece that fails
        ends the run with its message; what was computed up to there is returned. A start exactly
        on a limit is the switch it sits on: ``SR`` at the start when a stop there goes free this
        way and a set continuing the other way holds it in contact (by complementarity a stop at its
        limit is in contact), ``NSF`` when no set continues this way.
    """
    # longer than 60 lines: one loop over the pieces whose steps share its state (the point, the
    # contact set, the run so far); what does not (the start's checks, the switch rules, the joining,
    # the landings) is in the helpers below
    hold, free = list(hold), list(free)
    contact = None if contact is None else list(contact)
    if direction not in (-1, 0, 1):
        raise InputError("direction", f"must be +1, -1 or 0 (both ways, each pushed from the start), got {direction!r}")
    runs = [_one_way(system, start, vary, d, hold, free, stops, contact, options, stop_at_fold, max_switches, progress)
            for d in ((-1, 1) if direction == 0 else (direction,))]
    # the landings once the run is whole: a mechanism jumping back along one half may land on the other
    run, row_piece = runs[0] if direction else _both_ways(system, runs[0], runs[1])
    _land(system, run, row_piece, vary, hold, free, named_stops(system, stops))
    return run


def _one_way(system: Model, start: np.ndarray, vary: str, direction: int, hold: list[str], free: list[str],
             stops: Iterable[str] | None, contact: list[str] | None, options: ContinuationOptions | None,
             stop_at_fold: bool, max_switches: int,
             progress: Callable[[int], None] | None) -> tuple[StopRun, list[int]]:
    """:func:`continuation_with_stops` pushed one way (``direction`` +1 or -1), without the landings: the run
    and the piece of each of its rows."""
    st = named_stops(system, stops)
    check_stop_lens(system, vary, hold, free, [s.name for s in st])
    options = options or ContinuationOptions()
    if stop_at_fold:
        options = replace(options, detect_folds=False)
    x = np.array(start, dtype=float)
    undecided = at_switch(system, x, st)
    active = set(stops_in_contact(system, x, st) if contact is None else contact) - undecided
    check_start_contacts(system, x, st, active, undecided)
    run = StopRun(branch=None)  # type: ignore[arg-type]
    sign = direction
    arriving: set[str] | None = None   # the set of the piece that ended at x (None at the start)
    folds: dict[int, NonSmoothFold] = {}  # switch number (-1: the start) -> the NSF there
    released: list[str] = []            # the stops released at the start itself (an SR there)
    run.message = ""
    for _ in range(max_switches + 1):
        if undecided:
            x = with_contacts(system, x, st, active)
            for s in st:
                if s.name in undecided:
                    x[system.index(s.condition)], x[system.index(s.reaction)] = s.limit, 0.0
            ahead = _continuing_sets(system, x, vary, sign, st, active, undecided, hold, free)
            if ahead:
                active = ahead[0]
                if arriving is None:   # a start exactly on a limit
                    released = _released_at_start(system, x, vary, sign, st, active, undecided, hold, free)
            else:   # a non-smooth fold: nothing continues this way; go on through it, the way turned back
                back = _continuing_sets(system, x, vary, -sign, st, active, undecided, hold, free)
                came = arriving if arriving is not None else (back[0] if back else None)
                through = [a for a in back if a != came]
                n_came = None if came is None else n_unstable_on(system, x, came)
                n_through = n_unstable_on(system, x, through[0]) if through else None
                stable = n_came == 0
                # a stable piece leaving the fold reaches it too when pushed in sign: its mechanism jumps, backwards
                behind = not stable and arriving is not None and n_through == 0
                folds[len(run.switches) - 1] = NonSmoothFold(
                    ", ".join(sorted(undecided)), vary, float(x[system.index(vary)]), sign, stable or behind,
                    behind=behind, sides=tuple(sorted(n for n in (n_came, n_through) if n is not None)))
                if run.switches:
                    lab, name, i = run.switches[-1]
                    run.switches[-1] = ("NSF", name, i)
                if stop_at_fold or not through:
                    run.message = ("stopped at the non-smooth fold (NSF)" if stop_at_fold else
                                   "no equilibrium continues the branch through the non-smooth fold (NSF)")
                    if not run.pieces:
                        run.pieces.append(_single(system, x, vary, hold, free, st, came or active))
                        run.contact.append(tuple(s.name for s in st if s.name in (came or active)))
                        run.directions.append(sign)
                    break
                active, sign = through[0], -sign
        x = with_contacts(system, x, st, active)
        events = [StopEvent(s, s.name in active) for s in st] + ([FirstFold()] if stop_at_fold else [])
        hold_k, free_k = contact_lens(st, active, hold, free)
        # with stops in contact the stability holds them (below): the free mechanics' is not computed
        piece = continuation(system, x, vary, hold=hold_k, free=free_k, direction=sign, events=events,
                             options=replace(options, stability=False) if active else options, progress=progress)
        if active and options.stability:
            piece = _contact_stability(system, piece, [s.name for s in st if s.name in active])
        run.pieces.append(piece)
        run.contact.append(tuple(s.name for s in st if s.name in active))
        run.directions.append(sign)
        last = len(piece) - 1 if sign > 0 else 0  # a branch's rows run in increasing arclength
        end = next((p for p in piece.special_points if p.index == last and p.label in ("SC", "SR")), None)
        if end is None or end.stop is None:
            # the piece's own "+: "/"-: " says its sense; the run's is the one it was started in
            why = "; ".join(m.split(": ", 1)[-1] for m in piece.message.split("; ")) if piece.message else ""
            run.message = f"{'+' if direction > 0 else '-'}: {why or f'ended: {piece.status}'}"
            break
        run.switches.append((end.label, end.stop, -1))
        arriving = set(active)
        sign = _travel(piece, vary, sign)
        x = piece.values[last]
        undecided = at_switch(system, x, st) | {end.stop}
    else:
        run.message = (f"stopped after {max_switches} contact changes at {vary} = {x[system.index(vary)]:.6g} "
                       "(the contact keeps switching there)")
    run.branch, row_piece = _join(system, run.pieces, vary, run, folds, _start_release(system, run, vary, released))
    return run, row_piece


def _continuing_sets(system: Model, x: np.ndarray, vary: str, sign: int, stops: Sequence[StopLimit],
                     active: set[str], undecided: set[str], hold: list[str], free: list[str]) -> list[set[str]]:
    """The contact sets that continue from ``x`` as ``vary`` is pushed in ``sign``, most stops in contact first.

    The ``undecided`` stops (at their limit, zero reaction) are tried in and out of contact; a set
    continues when, along its branch's tangent, every undecided reaction in contact grows and
    every undecided free condition moves to its allowed side (to first order; a zero rate counts).
    """
    names = [s.name for s in stops if s.name in undecided]
    by_name = {s.name: s for s in stops}
    fixed = set(active) - undecided
    sc = system.scales()
    out = []
    for k in range(len(names), -1, -1):
        for chosen in combinations(names, k):
            trial = fixed | set(chosen)
            hold_k, free_k = contact_lens(stops, trial, hold, free)
            cols = [system.index(n) for n in (*choose_unknowns(system, hold_k, free_k, exclude=[vary]), vary)]
            J = system.jacobian(x)[:, cols] * sc[cols]
            t = np.linalg.svd(J)[2][-1]      # the null vector: the branch's unit tangent, scaled
            if abs(t[-1]) < 1e-10:           # a fold of this set at x: it cannot be pushed in vary
                continue
            t *= sign * np.sign(t[-1])
            rate = dict(zip((system.names[c] for c in cols), t))
            tol = -1e-9
            if all(rate[by_name[n].reaction] >= tol if n in chosen else by_name[n].side * rate[by_name[n].condition] >= tol
                   for n in names):
                out.append(trial)
    return out


def _released_at_start(system: Model, x: np.ndarray, vary: str, sign: int, stops: Sequence[StopLimit],
                       active: set[str], undecided: set[str], hold: list[str], free: list[str]) -> list[str]:
    """The ``undecided`` stops at a start exactly on their limits that the set ``active`` leaves free this way
    but some set continuing the other way holds in contact: the start is their release (``SR``). By
    complementarity a stop at its limit is in contact (its reaction, zero here, may be >= 0), so going
    free from there releases it, whichever side the run leaves to; a stop free on both sides (grazing its
    limit) releases nothing."""
    off = undecided - active
    if not off:
        return []
    back = _continuing_sets(system, x, vary, -sign, stops, active, undecided, hold, free)
    return sorted(n for n in off if any(n in b for b in back))


def _start_release(system: Model, run: StopRun, vary: str, released: Sequence[str]) -> SpecialPoint | None:
    """The ``SR`` point at the start of ``run`` for the stops ``released`` there (None when none): exact, as
    the start is a solution with the conditions at their limits and the reactions zero; its lens is the
    contact set's (the released stops held), as for a release located along a piece."""
    if not released or not run.pieces:
        return None
    p0 = run.pieces[0]
    x0 = p0.values[0 if run.directions[0] > 0 else len(p0) - 1].copy()
    by_name = {s.name: s for s in system.stops}
    swap = {by_name[n].condition: by_name[n].reaction for n in released}
    unknowns = [swap.get(n, n) for n in p0.unknowns]
    return SpecialPoint("SR", 0, x0, p0.names, None, stop=", ".join(released), status=Status.LOCATED,
                        vary=vary, unknowns=unknowns)


def _single(system: Model, x: np.ndarray, vary: str, hold: list[str], free: list[str], stops: Sequence[StopLimit],
            active: set[str]) -> Branch:
    """A one-row branch at ``x`` (a run that ends where it starts: a non-smooth fold at the start)."""
    hold_k, free_k = contact_lens(stops, active, hold, free)
    unknowns = tuple(choose_unknowns(system, hold_k, free_k, exclude=[vary]))
    st = stability_on_stops(system, x, sorted(active)).n_unstable if system.mechanics is not None else -1
    return Branch(system.names, np.array([x]), [0.0], [st], [""], [], vary, unknowns, "completed", "", system.name,
                  units={v.name: v.unit for v in system.variables})


def _contact_stability(system: Model, piece: Branch, contact: Sequence[str]) -> Branch:
    """The piece with :func:`stability_on_stops` at every point, the stops ``contact`` in contact (its
    ``n_unstable``)."""
    return piece.replace(n_unstable=[stability_on_stops(system, x, contact).n_unstable for x in piece.values])


def _join(system: Model, pieces: list[Branch], vary: str, run: StopRun, folds: Mapping[int, NonSmoothFold],
          start: SpecialPoint | None = None) -> tuple[Branch, list[int]]:
    """One branch of the pieces in travel order; each switch row appears once (the end of its piece), labelled
    with its switch's label (``NSF`` with its fold of ``folds``), the release at the start ``start`` (if any) first;
    and the piece of each row."""
    rows: list[np.ndarray] = []
    s: list[float] = []
    stab: list[int] = []
    labels: list[str] = []
    special: list[SpecialPoint] = []
    row_piece: list[int] = []
    offset = 0.0
    k_switch = 0
    if start is not None and -1 not in folds:   # a release at the start itself
        special.append(start)
    if -1 in folds and pieces:   # a non-smooth fold at the start itself
        p0 = pieces[0]
        j0 = 0 if run.directions[0] > 0 else len(p0) - 1
        special.append(SpecialPoint("NSF", 0, p0.values[j0].copy(), p0.names, None, nonsmooth=folds[-1]))
    for i, (p, sign) in enumerate(zip(pieces, run.directions)):
        order = list(range(len(p))) if sign > 0 else list(range(len(p) - 1, -1, -1))
        pos = {j: k for k, j in enumerate(order)}
        first = 1 if i > 0 else 0  # a piece starts at the previous piece's switch point
        base = len(rows) - first
        s0 = p.s[order[0]] if order else 0.0
        for j in order[first:]:
            rows.append(p.values[j])
            s.append(offset + abs(p.s[j] - s0))
            stab.append(int(p.n_unstable[j]))
            labels.append(p.labels[j])
            row_piece.append(i)
        for sp_ in sorted(p.special_points, key=lambda q: pos[q.index]):
            k = pos[sp_.index]
            if k < first:
                continue
            idx = base + k
            label, fold = sp_.label, None
            if sp_.label in ("SC", "SR") and k == len(order) - 1 and k_switch < len(run.switches):
                label, name, _ = run.switches[k_switch]
                run.switches[k_switch] = (label, name, idx)
                fold = folds.get(k_switch)
                labels[idx] = label
                if fold is not None and fold.sides:
                    stab[idx] = _fold_row_stability(fold)
                k_switch += 1
            special.append(replace(sp_, label=label, index=idx, x=sp_.x.copy(), extra=dict(sp_.extra),
                                   nonsmooth=fold, stop=sp_.stop if fold is None else fold.stop))
        offset = s[-1] if s else 0.0
    if -1 in folds and rows:   # the start belongs to the set the mechanism rests on, not to the one through the fold
        labels[0], stab[0] = "NSF", _fold_row_stability(folds[-1])
        run.switches.insert(0, ("NSF", folds[-1].stop, 0))
    elif start is not None and rows:
        labels[0] = "SR"
        run.switches.insert(0, ("SR", start.stop or "", 0))
    unknowns = pieces[0].unknowns if pieces else ()
    status = pieces[-1].status if pieces else Status.FAILED
    branch = Branch(system.names, np.array(rows), s, stab, labels, special, vary, unknowns, status, run.message,
                    system.name, units={v.name: v.unit for v in system.variables})
    return branch, row_piece


def _fold_row_stability(fold: NonSmoothFold) -> int:
    """The ``n_unstable`` of a non-smooth fold's row: that of the more stable of the pieces meeting there (the
    one a mechanism can rest on up to the fold), whichever the run walked first; 0 exactly when a stable
    mechanism reaches it (``fold.jump``)."""
    return fold.sides[0] if fold.sides else (0 if fold.jump else 1)


def _land(system: Model, run: StopRun, row_piece: list[int], vary: str, hold: list[str], free: list[str],
          stops: Sequence[StopLimit]) -> None:
    """Where the mechanism lands after each ``NSF`` it reached stable: the first equilibrium further along
    the branch at the fold's value of ``vary``, solved on that piece's contact set (the ``landing`` of the
    point's :class:`~mechcont.continuation.NonSmoothFold`)."""
    b = run.branch
    col = b.values[:, b.names.index(vary)] if len(b) else np.zeros(0)
    landed: dict[int, SpecialPoint] = {}  # position among the special points -> the NSF with its landing
    for k, p in enumerate(b.special_points):
        if p.label != "NSF" or (fold := p.nonsmooth) is None or not fold.jump:
            continue
        v, sign = fold.value, fold.sign
        ahead = (col - v) * sign
        step = -1 if fold.behind else 1    # the jumping mechanism moves along the run, or back along it
        rows = range(p.index - 2, -1, -1) if fold.behind else range(p.index + 2, len(b))
        j = next((j for j in rows if ahead[j] >= 0 > ahead[j - step]), None)
        if j is None:
            note = (f"the mechanism jumps at the non-smooth fold ({vary} = {v:.6g}); no equilibrium at that "
                    f"{vary} {'back' if fold.behind else 'further'} along the branch, within its bounds")
            run.message = f"{run.message}; {note}" if run.message else note
            run.branch = run.branch.replace(message=run.message)
            continue
        active = run.contact[row_piece[j]]
        w = ahead[j] / (ahead[j] - ahead[j - step])
        guess = w * b.values[j - step] + (1 - w) * b.values[j]
        guess[system.index(vary)] = v
        hold_k, free_k = contact_lens(stops, active, hold, free)
        held = {n: float(guess[system.index(n)]) for n in hold_k if system.variable(n).kind == "state"}
        held.update({s.condition: s.limit for s in stops if s.name in active})
        if system.variable(vary).kind == "state":
            held[vary] = v
        try:
            x = find_equilibrium(system, hold=held, free=free_k, guess=guess)
        except ConvergenceError:
            continue
        stable = stability_on_stops(system, x, list(active)).n_unstable == 0 if system.mechanics is not None else None
        landed[k] = replace(p, nonsmooth=replace(fold, landing=Landing(x, tuple(active), stable)))
    run.branch = run.branch.replace(special_points=[landed.get(k, p) for k, p in enumerate(b.special_points)])


def _both_ways(system: Model, down_run: tuple[StopRun, list[int]],
               up_run: tuple[StopRun, list[int]]) -> tuple[StopRun, list[int]]:
    """The decreasing run reversed, then the increasing one (the shared start once), as one run, with the
    piece of each row. The decreasing run's non-smooth folds are turned with its rows: a mechanism that
    jumps further along it jumps back along the joined run."""
    (down, down_rows), (up, up_rows) = down_run, up_run
    bd, bu = down.branch, up.branch
    n = len(bd)
    rows = np.vstack([bd.values[::-1], bu.values[1:]])
    s = np.concatenate([-bd.s[::-1], bu.s[1:]])
    stab = np.concatenate([bd.n_unstable[::-1], bu.n_unstable[1:]])
    labels = list(bd.labels[::-1]) + list(bu.labels[1:])
    special = [replace(p, index=n - 1 - p.index, extra=dict(p.extra),
                       nonsmooth=None if p.nonsmooth is None else replace(p.nonsmooth, behind=not p.nonsmooth.behind))
               for p in reversed(bd.special_points)]
    # the start's own points (a release or a non-smooth fold exactly there) may come from either run: once each
    at_start = {p.label for p in bd.special_points if p.index == 0}
    special += [replace(p, index=n - 1 + p.index, extra=dict(p.extra)) for p in bu.special_points
                if p.index > 0 or p.label not in at_start]
    if bu.labels[0] and (not labels[n - 1] or bu.labels[0] == "NSF"):
        labels[n - 1] = bu.labels[0]
    fold = next((p.nonsmooth for p in special if p.index == n - 1 and p.label == "NSF" and p.nonsmooth), None)
    if fold is not None:   # the start's row is the fold's, whichever run found it
        stab[n - 1] = _fold_row_stability(fold)
    message = "; ".join(r.message for r in (down, up) if r.message)   # each says its direction
    status = Status.first_failure([bd.status, bu.status])
    branch = Branch(system.names, rows, s, stab, labels, special, bu.vary, bu.unknowns, status, message,
                    system.name, units={v.name: v.unit for v in system.variables})
    first = {lab for lab, _, i in down.switches if i == 0}
    switches = ([(lab, name, n - 1 - i) for lab, name, i in reversed(down.switches)]
                + [(lab, name, n - 1 + i) for lab, name, i in up.switches if i > 0 or lab not in first])
    row_piece = down_rows[::-1] + [len(down.pieces) + i for i in up_rows[1:]]
    return StopRun(branch, down.pieces + up.pieces, down.contact + up.contact, switches, message,
                   down.directions + up.directions), row_piece
