"""Families of equilibria: branches in one parameter at a set of values of another.

Together with the fold curve (two-parameter continuation of a fold) they make the
paper's Figure 4a surface. Each member is started from the previous member's
equilibrium, re-converged by continuation in the family parameter, so the family stays
on one sheet of solutions.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import replace

import numpy as np

from ..continuation import Branch, ContinuationOptions, continuation
from ..equations import Model
from ..errors import InputError

__all__ = ["equilibrium_family"]


def equilibrium_family(system: Model, start: np.ndarray, vary: str, family: str,
                       values: Sequence[float], *, hold: Iterable[str] = (), free: Iterable[str] = (),
                       options: ContinuationOptions | None = None, move_hold: Iterable[str] | None = None,
                       move_free: Iterable[str] | None = None,
                       progress: Callable[[int, int], object] | None = None) -> list[Branch]:
    """Branches in ``vary`` at each value of ``family`` (a surface of equilibria).

    Parameters
    ----------
    system:
        The model.
    start:
        A converged full vector at ``family = values[0]`` (or near it).
    vary:
        The continuation parameter of every member (e.g. ``"F"``).
    family:
        The second parameter stepped through ``values`` (e.g. ``"LU"``).
    hold, free, options:
        As for :func:`~mechcont.continuation.continuation`.
    move_hold, move_free:
        The lens used to move from one member to the next in ``family`` (default: the
        members' own, with ``vary`` held). Holding a state and freeing ``vary`` (e.g.
        hold ``theta1``, free ``F``) avoids losing the start where the members fold.
    progress:
        Optional callable ``progress(i, n)`` after each member.

    Returns
    -------
    list[Branch]
        One branch per value, in order.
    """
    if len(values) == 0:
        raise InputError("values", "give at least one value of the family parameter")
    options = options or ContinuationOptions()
    system.index(family)
    out = []
    x = np.array(start, dtype=float)
    # move along the family parameter with the vary parameter held: a branch in `family`
    seed_opts = ContinuationOptions(ds=options.ds, dsmin=options.dsmin, dsmax=options.dsmax, stability=False,
                                    detect_folds=False, detect_branch_points=False, scales=options.scales)
    i_f = system.index(family)
    for i, val in enumerate(values):
        val = float(val)
        cur = x[i_f]
        if cur != val:
            pad = 1e-9 * max(1.0, abs(cur))
            bounds = {family: (cur - pad, val)} if val > cur else {family: (val, cur + pad)}
            seed = continuation(system, x, family, hold=hold if move_hold is None else move_hold,
                                free=free if move_free is None else move_free, direction=1 if val > cur else -1,
                                options=replace(seed_opts, bounds=bounds))
            ends = [p for p in seed.special("EP") if abs(p[family] - val) <= 1e-9 * max(1.0, abs(val))]
            if not ends:
                raise InputError(family, f"could not reach {family}={val:g} from the previous member: {seed.message}")
            x = ends[-1].x.copy()
        out.append(continuation(system, x, vary, hold=hold, free=free, options=options))
        if progress is not None:
            progress(i + 1, len(values))
    return out
