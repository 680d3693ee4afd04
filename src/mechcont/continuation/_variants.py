"""Continuation across variants of a system: one branch through several square systems.

A model with a ``reselect`` (see :class:`~mechcont.equations.Model`) stands for a family of
systems with the same variables whose equations depend on a choice made at a configuration: for
a spatial ``redundant = "drop"`` mechanism, which of the dependent rigid rows are dropped. The
choice suits a region of the branch only (the kept rows can lose rank elsewhere), so the branch
is followed in pieces: a piece ends where ``reselect.quality`` turns negative (``RC``, located
like any event), ``reselect.switch`` gives the variant chosen there with the reactions solved
again, and the next piece starts from that point in the same sense of travel. The pieces are
joined into one :class:`Branch` (the switch row once, as the end of its piece; the
``RC`` point's ``extra["dropped"]`` (also in ``info``) holds the dropped rows before and after it, in branch order).
Every row solves the variant of its piece; the reactions that statics cannot determine change
their split at a switch, everything determinate (coordinates, loads solved for, the reactions'
part in the range of ``Phi_q``) is continuous.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any, Protocol

import numpy as np

from .._status import Status
from ..equations import Model
from ._branch import Branch, SpecialPoint
from ._events import Event, PointState
from ._options import ContinuationOptions
from ._problem import ContinuationProblem

__all__: list[str] = []

#: Largest number of switches in one direction (a choice that keeps flipping is reported).
MAX_SWITCHES = 50

#: One piece: ``run(model, x, vary, options, direction, events)``, a branch of one direction from ``x``
PieceRunner = Callable[[Model, np.ndarray, str, ContinuationOptions, int, list[Event]], Branch]
#: One direction: its pieces ``(branch, sign)`` in travel order, its status and message
Half = tuple[list[tuple[Branch, int]], Status, str]
#: A row of joined pieces: ``(x, s, n_unstable, label, special point or None)``
Record = tuple[np.ndarray, float, int, str, SpecialPoint | None]


class _Quality(Protocol):
    """What :class:`_Reselect` reads of a model's ``reselect``."""

    def quality(self, x: np.ndarray) -> float:
        """Positive while the model's dropped rows suit the full vector ``x``."""
        ...


class _Reselect(Event):
    """``RC``: the system's choice no longer suits the branch (``reselect.quality`` < 0); ends the piece."""

    label = "RC"
    stop = True

    def __init__(self, reselect: _Quality) -> None:
        self.reselect = reselect

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        return float(self.reselect.quality(state.x))

    def point_info(self) -> dict[str, Any]:
        return {"reason": "redundant rows to drop chosen again"}


def travel(branch: Branch, vary: str, sign: int) -> int:
    """+1 when ``vary`` was increasing at the end of a piece run in direction ``sign``, -1 when decreasing."""
    col = branch.values[:, branch.names.index(vary)]
    if sign < 0:
        col = col[::-1]
    if len(col) < 2 or col[-1] == col[-2]:
        return sign
    return 1 if col[-1] > col[-2] else -1


def _one_way(run: PieceRunner, system: Model, x0: np.ndarray, vary: str, sign: int, options: ContinuationOptions,
             events: Sequence[Event]) -> Half:
    """The pieces ``(branch, sign)`` of one direction in travel order, its status and message."""
    pieces: list[tuple[Branch, int]] = []
    model, x, budget = system, x0, options.max_steps
    message = ""
    r = model.residual(x)
    reselect = model.reselect
    assert reselect is not None, "continued across variants: a model with a reselect"
    if reselect.quality(x) < 0 or not np.max(np.abs(r), initial=0.0) <= 1e3 * options.engine.residual_tol:
        # a start the system's choice does not suit, or one solved by another variant (the end of a
        # branch that switched): the choice made here, the reactions solved again
        forced = reselect.switch(model, x, force=True)
        assert forced is not None, "a forced switch returns the model chosen"
        model, x = forced
    for _ in range(MAX_SWITCHES + 1):
        extra = [_Reselect(model.reselect)] if model.reselect is not None else []
        piece = run(model, x, vary, replace(options, max_steps=budget), sign, [*events, *extra])
        pieces.append((piece, sign))
        last = len(piece) - 1 if sign > 0 else 0   # a branch's rows run in increasing arclength
        budget -= len(piece) - 1
        reselect = model.reselect
        if piece.labels[last] != "RC" or budget <= 0 or reselect is None:
            message = piece.message
            break
        before = tuple(model.dropped_constraints)
        out = reselect.switch(model, piece.values[last])
        if out is None:  # the best choice is the one in use: go on without the check
            model, x = model.evolve(reselect=None), piece.values[last]
        else:
            model, x = out
        for sp in piece.special_points:
            if sp.index == last:  # (before, after) in the sense of travel; join_variants orders them along the branch
                sp.extra["dropped"] = (before, tuple(model.dropped_constraints))
        sign = travel(piece, vary, sign)
    else:
        message = f"{'+' if sign > 0 else '-'}: stopped after {MAX_SWITCHES} changes of the dropped redundant rows"
    status = pieces[-1][0].status
    return pieces, status, message


def _records(pieces: list[tuple[Branch, int]]) -> list[Record]:
    """Rows of the pieces in travel order: ``(x, s, n_unstable, label, special point or None)``; each
    switch row once (the end of its piece)."""
    out: list[Record] = []
    offset = 0.0
    for i, (p, sign) in enumerate(pieces):
        order = list(range(len(p))) if sign > 0 else list(range(len(p) - 1, -1, -1))
        special = {sp.index: sp for sp in p.special_points}
        s0 = p.s[order[0]]
        for k, j in enumerate(order):
            if i > 0 and k == 0:
                continue
            out.append((p.values[j], offset + abs(p.s[j] - s0), int(p.n_unstable[j]), p.labels[j], special.get(j)))
        offset = out[-1][1] if out else 0.0
    return out


def join_variants(system: Model, halves: dict[int, Half], vary: str, unknowns: Sequence[str]) -> Branch:
    """One branch of the pieces of each direction (``{-1: ..., +1: ...}``): the decreasing one reversed,
    the shared start once."""
    rows: list[Record] = []
    if -1 in halves:
        back = _records(halves[-1][0])
        rows += [(x, -s, n, lab, sp) for x, s, n, lab, sp in reversed(back[1:] if 1 in halves else back)]
    if 1 in halves:
        fwd = _records(halves[1][0])
        if -1 in halves and not fwd[0][3]:
            fwd[0] = _records(halves[-1][0])[0]  # the start's own label, if found going backwards
        rows += fwd
    special = []
    n_back = len(rows) - (len(fwd) if 1 in halves else 0)
    for i, (_, _, _, lab, sp) in enumerate(rows):
        if lab and sp is not None:
            extra = dict(sp.extra)
            if i < n_back and "dropped" in extra:  # travelled backwards: before and after swap along the branch
                extra["dropped"] = extra["dropped"][::-1]
            special.append(replace(sp, index=i, x=sp.x.copy(), extra=extra))
    dirs = sorted(halves)
    status = Status.first_failure(halves[d][1] for d in dirs)
    message = "; ".join(halves[d][2] for d in dirs if halves[d][2])   # each piece's says its direction
    return Branch(system.names, np.array([r[0] for r in rows]), [r[1] for r in rows], [r[2] for r in rows],
                  [r[3] for r in rows], special, vary, unknowns, status, message, system.name,
                  units={v.name: v.unit for v in system.variables})


def across_variants(run: PieceRunner, system: Model, x0: np.ndarray, vary: str, options: ContinuationOptions,
                    direction: int, events: Sequence[Event], unknowns: Sequence[str]) -> Branch:
    """Continue in ``vary`` from ``x0`` with ``run(model, x, vary, options, direction, events) -> Branch``
    (one piece, one direction), switching variants where ``system.reselect`` says (see the module)."""
    dirs = [direction] if direction else [-1, 1]
    halves = {d: _one_way(run, system, x0, vary, d, options, events) for d in dirs}
    return join_variants(system, halves, vary, unknowns)
