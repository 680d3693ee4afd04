"""Automatic detection of jumps in a recorded sweep.

A jump is a sudden change of the watched quantity ``w`` while a load ramps slowly. On a
stable branch ``w`` moves at the quasi-static rate ``(dw/dp) (dp/dt)``; when the branch
ends at a fold the mechanism leaves it dynamically, at a rate set by its own inertia and
stiffness, not by the sweep. So a jump starts where ``|dw/dt|`` first exceeds a threshold
well above the quasi-static rate. The default threshold is ``factor`` times the average
rate ``span(w) / moving time`` of the segment (``span`` over the whole sweep; the moving time
is the segment's duration less the time ``w`` rests, e.g. on a stop, see :func:`moving_time`),
so a smooth response never qualifies; above-threshold intervals separated by short pauses (overshoot
and ringing after the jump) are merged, and a jump must change ``w`` by at least
``min_change`` of its span. With ``through=value`` the jump is instead timed where ``w``
passes through ``value`` (e.g. a lock-link angle passing 180 degrees). A runaway (a fast motion
that never settles, whose span would inflate that threshold without bound) is found by
:func:`find_runaway` on a rate scale it does not move.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

__all__ = ["JumpWindow", "find_jump_windows", "find_runaway", "moving_time"]

REST_FRACTION = 1e-6
"""A sample step where ``|dw/dt|`` stays below this fraction of ``span / duration`` is at rest: all such steps
together move ``w`` by less than this fraction of its span, which is covered in the rest of the time. A coordinate
held on a stop rests at ~1e-9 of that rate (its numerical noise); a damped mechanism settling on its branch stays
above it, so a sweep that never rests keeps its whole duration (the paper's hysteresis loops, to 6 digits)."""

RUNAWAY_REST_FRACTION = 1e-6
"""For :func:`find_runaway`, whose span a runaway inflates: a sample where ``|dw/dt|`` is below this fraction of
its largest value in the record is at rest (numerical noise on a stop is ~1e-10 of it; a quasi-static rate is
rarely below 1e-3 of a dynamic one, the jumps' threshold resolving a tenth of that)."""


@dataclass(frozen=True)
class JumpWindow:
    """Times of one detected jump (s): detection time, start and end of the fast motion."""

    time: float
    t_start: float
    t_end: float
    i_start: int
    i_end: int


def _cross_time(t: np.ndarray, f: np.ndarray, i: int) -> float:
    """Time where f (linear between samples i and i+1) crosses zero."""
    a, b = f[i], f[i + 1]
    if b == a:
        return float(t[i + 1])
    return float(t[i] + (t[i + 1] - t[i]) * a / (a - b))


def _fast_intervals(rate: np.ndarray, thr: float) -> list[tuple[int, int]]:
    """Index intervals [i, j] where |rate| > thr, merging those split by short pauses."""
    above = np.abs(rate) > thr
    if not above.any():
        return []
    d = np.diff(above.astype(int))
    starts: list[int] = (np.flatnonzero(d == 1) + 1).tolist()
    ends: list[int] = np.flatnonzero(d == -1).tolist()
    if above[0]:
        starts.insert(0, 0)
    if above[-1]:
        ends.append(len(rate) - 1)
    return list(zip(starts, ends))


def moving_time(t: np.ndarray, wdot: np.ndarray, level: float) -> float:
    """Time (s) during which ``w`` moves: the sample steps of ``t`` where ``|wdot|`` (units/s) exceeds ``level``
    (units/s) at either end.

    A mechanism resting on a stop for most of a segment covers its span in the rest of it, at a rate the
    segment's whole duration underestimates (a leg held on its downlock for 87 % of the ramp, then released:
    8 times), so the ordinary ringing of its quasi-static motion would pass for jumps."""
    if len(t) < 2:
        return 0.0
    r = np.abs(wdot)
    moving = np.maximum(r[:-1], r[1:]) > level
    return float(np.sum(np.diff(t)[moving]))


def find_jump_windows(t: np.ndarray, w: np.ndarray, wdot: np.ndarray, lo: int, hi: int, *, span: float,
                      threshold: float | None = None, factor: float = 10.0, min_change: float = 0.05,
                      crossings: Iterable[float] | None = None) -> tuple[list[JumpWindow], float]:
    """Jumps of ``w`` among the samples ``lo..hi`` (inclusive) of one sweep segment.

    Parameters
    ----------
    t, w, wdot:
        Sample times (s), watched values and their time derivatives (units/s).
    lo, hi:
        Sample index range of the segment.
    span:
        Range of ``w`` over the whole sweep (its units); sets the quasi-static rate scale.
    threshold:
        Rate above which the motion counts as a jump (units of ``w`` per s); default
        ``factor * span / moving time`` (:func:`moving_time`: the segment's duration less the
        steps where ``|wdot|`` stays below ``REST_FRACTION * span / duration``; infinite, no jump,
        when ``w`` never moves).
    min_change:
        Smallest change of ``w`` across a jump, as a fraction of ``span``.
    crossings:
        If given, the times (s) where ``w`` passed a chosen value (located by the
        integrator's event detection): one jump per crossing, timed there.

    Returns
    -------
    (list of JumpWindow, threshold used)
    """
    tt, ww, rr = t[lo:hi + 1], w[lo:hi + 1], wdot[lo:hi + 1]
    duration = float(tt[-1] - tt[0]) if len(tt) > 1 else 0.0
    if duration <= 0 or span <= 0:
        return [], float("inf") if threshold is None else threshold
    if threshold is None:
        moving = moving_time(tt, rr, REST_FRACTION * span / duration)
        thr = factor * span / moving if moving > 0 else float("inf")
    else:
        thr = float(threshold)
    merged: list[list[int]] = []
    for i, j in _fast_intervals(rr, thr):
        if merged:
            pi, pj = merged[-1]
            if tt[i] - tt[pj] <= tt[pj] - tt[pi]:  # a pause shorter than the motion so far: same jump
                merged[-1][1] = j
                continue
        merged.append([i, j])
    out: list[JumpWindow] = []
    for i, j in merged:
        if crossings is not None:
            break
        if abs(ww[j] - ww[i]) < min_change * span:
            continue
        ts = _cross_time(tt, np.abs(rr) - thr, i - 1) if i > 0 else float(tt[i])
        out.append(JumpWindow(ts, ts, float(tt[j]), lo + max(i - 1, 0), lo + j))
    if crossings is not None:
        for tc in crossings:
            if not tt[0] <= tc <= tt[-1]:
                continue
            k = min(max(int(np.searchsorted(tt, tc)) - 1, 0), len(tt) - 2)  # sample step holding tc
            enclosing = [(i, j) for i, j in merged if i <= k + 1 and k <= j]
            i, j = enclosing[0] if enclosing else (k, k + 1)
            ts = _cross_time(tt, np.abs(rr) - thr, i - 1) if enclosing and i > 0 else float(tt[i])
            out.append(JumpWindow(float(tc), min(ts, float(tc)), max(float(tt[j]), float(tc)),
                                  lo + max(i - 1, 0), lo + j))
    return out, thr


def _time_weighted_median(t: np.ndarray, x: np.ndarray, keep: np.ndarray) -> float:
    """Median of ``x`` over time among the samples ``keep`` (a boolean mask): each sample weighted by half the
    time to its neighbours (s)."""
    weights = (np.gradient(t) if len(t) > 1 else np.ones(1))[keep]
    x = x[keep]
    order = np.argsort(x)
    cum = np.cumsum(weights[order])
    return float(x[order][min(int(np.searchsorted(cum, 0.5 * cum[-1])), len(x) - 1)])


def find_runaway(t: np.ndarray, w: np.ndarray, wdot: np.ndarray, lo: int, hi: int, *, duration: float,
                 factor: float = 10.0, min_change: float = 0.05) -> JumpWindow | None:
    """A runaway of ``w`` at the end of the samples ``lo..hi`` (inclusive): a fast motion that never settles.

    A runaway (a crank spinning away past its last fold) inflates the span of ``w`` without bound, so the rate
    threshold of :func:`find_jump_windows` (``span / duration``) may never be reached. Here the rate scale is the
    median of ``|dw/dt|`` over the time ``w`` moves (samples at rest, below ``RUNAWAY_REST_FRACTION`` of the largest
    rate, left out: on a stop its numerical noise would set the scale), which the runaway does not move while it
    lasts less than half of that time: the motion is fast where ``|dw/dt|`` exceeds ``factor`` times that median
    (pauses merged as for jumps), and a runaway is a fast interval that reaches the last sample and changes ``w`` by
    at least ``min_change`` of its span over the record and by more than the span of everything before it (a jump
    lands among the equilibria the sweep visits; a runaway leaves them all behind, as a crank turning over does). It
    must not have settled: over its last tenth ``w`` still moves faster than the jumps' threshold with the span
    before it, ``factor * span / duration`` (``duration``, s, of the sweep's last segment), so a quasi-static
    response that steepens towards the end of a sweep is no runaway.

    Returns the runaway's window (``time`` and ``t_start`` where it started, s; ``t_end`` the last
    sample) or None.
    """
    tt, ww, rr = t[lo:hi + 1], w[lo:hi + 1], np.abs(wdot[lo:hi + 1])
    span = float(np.ptp(ww)) if len(ww) else 0.0
    if len(tt) < 3 or span <= 0:
        return None
    moves = rr > RUNAWAY_REST_FRACTION * float(rr.max())
    if not moves.any():
        return None
    scale = _time_weighted_median(tt, rr, moves)
    thr = factor * max(scale, 1e-9 * span / float(tt[-1] - tt[0]))  # a record at rest: its noise is no runaway
    fast = _fast_intervals(rr, thr)
    if not fast or fast[-1][1] != len(tt) - 1:
        return None
    i, j = fast[-1]
    for pi, pj in reversed(fast[:-1]):  # the pauses of the motion (a crank slowing at each turn) joined
        if tt[i] - tt[pj] > tt[j] - tt[i]:
            break
        i = pi
    before = float(np.ptp(ww[:i + 1]))
    if abs(ww[j] - ww[i]) < max(min_change * span, before):
        return None
    k = min(int(np.searchsorted(tt, tt[j] - 0.1 * (tt[j] - tt[i]))), j - 1)  # the last tenth of it
    if abs(ww[j] - ww[k]) / (tt[j] - tt[k]) <= factor * before / duration:
        return None
    ts = _cross_time(tt, rr - thr, i - 1) if i > 0 else float(tt[i])
    return JumpWindow(ts, ts, float(tt[j]), lo + max(i - 1, 0), lo + j)
