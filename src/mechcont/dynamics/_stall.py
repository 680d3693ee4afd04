"""A simulation that stops moving where nothing stops it: one line that says where and why.

An integrator that crawls (its steps a thousandth of what they were, as where near-dependent
constraint rows were inverted) still "finishes", and a history that lost energy it had no way to
lose still has rows to the end: neither is a success to report silently. :func:`motion_warning`
reads the accepted steps, the energy audit and the redundant rows' choices of a finished history.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ._result import SimulationResult
    from ._udwadia_kalaba import ConstrainedDynamics

__all__ = ["motion_warning", "UNRESOLVED"]

#: The warning's opening words when the redundancy could not be resolved (the CLI exits 2 on it).
UNRESOLVED = "redundant constraints cannot be resolved"

#: A step-size collapse: the steps' running median (over this many steps) falls below ...
_WINDOW = 10
#: ... this fraction of the first steps' median and stays there.
_COLLAPSE = 1e-3


def _collapse(t: np.ndarray) -> tuple[float, float, float] | None:
    """``(time, step before, step after)`` (s) where the accepted steps ``diff(t)`` collapsed for good, or None."""
    h = np.diff(t)
    at = t[:-1][h > 0]  # each step's start (the rows after a stop event repeat its time)
    h = h[h > 0]
    if h.size < 4 * _WINDOW:
        return None
    first = float(np.median(h[:_WINDOW]))
    run = np.median(np.lib.stride_tricks.sliding_window_view(h, _WINDOW), axis=1)  # every window in one call
    low = np.flatnonzero(run < _COLLAPSE * first)
    if low.size == 0 or np.median(h[low[0]:]) >= 10 * _COLLAPSE * first:
        return None
    k = int(low[0])
    k += int(np.argmax(h[k:k + _WINDOW] < _COLLAPSE * first))  # the first collapsed step of the window
    return float(at[k]), first, float(np.median(h[k:]))


def motion_warning(result: SimulationResult, dyn: ConstrainedDynamics) -> str:
    """One line (empty when there is nothing to say) for a finished history ``result`` of the dynamics
    ``dyn``: the redundant rows that could not be resolved (their choice changing at most steps, or
    every choice rank deficient: a mechanism locked at a singular configuration), or the steps that
    collapsed, with the energy the audit cannot explain and the row changes near there."""
    steps = max(len(result.t) - 1, 1)
    kept = getattr(dyn, "kept", None)
    if kept is not None and (len(kept.changes) > max(20, steps // 2) or len(kept.singular) > max(5, steps // 10)):
        first = (kept.singular or kept.changes)[0]
        return (f"{UNRESOLVED}: the constraint rows kept for the solve lost rank {len(kept.changes)} times in "
                f"{steps} steps from t = {first:.6g} s ({len(kept.singular)} times with every choice rank deficient); "
                "the history up to there is kept")
    if result.integrator_failure or not result.success:  # the run's own message says where and why it ended
        return ""
    where = _collapse(np.asarray(result.t, float))
    if where is None:
        return ""
    t, before, after = where
    why = []
    if result.energy:
        b = result.balance
        if not b.closes:
            r = np.abs(result.energy["E_residual"])
            i = int(np.argmax(r > b.bound))
            why.append(f"energy residual {b.worst:.3g} J beyond the {b.bound:.3g} J the tolerances explain from "
                       f"t = {result.t[i]:.6g} s")
    if kept is not None and kept.changes:
        near = [c for c in kept.changes if c >= t - 10 * before]
        why.append(f"the redundant rows chosen again {len(kept.changes)} times"
                   + (f", first near it at t = {near[0]:.6g} s" if near else ""))
    return (f"the motion stalled at t = {t:.6g} s: the integrator's steps collapsed from {before:.3g} s to "
            f"{after:.3g} s where nothing stops the mechanism" + (f" ({'; '.join(why)})" if why else ""))
