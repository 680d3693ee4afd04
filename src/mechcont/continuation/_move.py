"""A special point moved to other parameter values stays itself: a homotopy in the changed parameters.

Re-solving a fold (or any point) found at one set of parameter values directly at another, from
the old row, lets Newton land wherever its basin sends it: on the *other* fold of an overcentre
lock, or on an unrelated singular point, with nothing to say so. :func:`move_point` instead
follows the point along the straight path ``values(t) = old + t (new - old)``, ``t`` from 0 to 1,
in steps that must each stay on the same point:

* the step's solve converges (the fold polished on the augmented system, an ordinary point by
  Newton with its lens);
* it moves the point by less than :data:`_STEP_MOVE` in the equilibrated unknowns (radians and
  the Jacobian's column scales, so units do not matter);
* at a fold, the normal-form coefficient ``a = w^T G_ss[v, v]`` (with ``w^T G_p > 0``) keeps its
  sign: it changes sign only through a cusp, where the fold meets its partner and ends.

A step that fails any of these is halved; when the step needed falls below :data:`_MIN_STEP`
of the path the point no longer exists there (a fold past a cusp, a fold whose load runs off
to infinity), and :func:`move_point` says so in one line (:class:`PointLost`) naming the values
where it was last seen.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..equations import EquationSystem
from ..errors import ConvergenceError, InputError
from ._fold_point import fold_quantities, fold_scaling, polish_fold

__all__ = ["move_point", "check_point", "PointLost", "MovedPoint"]

#: How far (equilibrated unknowns) a table's row may be from the point it claims to be: rows are written
#: to 17 digits; 1e-4 admits a table rounded to 6 digits and refuses a corrupted cell.
_ROW_TOL = 1e-4

#: Largest move of one step, in equilibrated unknowns (rad-like units: 0.25 is about 14 degrees).
_STEP_MOVE = 0.25
#: Smallest step, as a fraction of the path; below it the point is taken to have ended.
_MIN_STEP = 1e-5
#: Most steps along one path (a guard; a smooth path takes a few dozen).
_MAX_STEPS = 2000


class PointLost(InputError):
    """The point does not continue to the requested values (a fold past a cusp, a load run off to
    infinity): :attr:`last` holds the parameter values where it was last found, :attr:`x` the point there."""

    def __init__(self, what: str, message: str, last: Mapping[str, float], x: np.ndarray) -> None:
        super().__init__(what, message)
        self.last = dict(last)
        self.x = x


class MovedPoint:
    """A point followed to new parameter values: ``x`` (full vector, SI), ``v`` (a fold's null vector over
    its states, else None), ``steps`` (the homotopy's accepted steps) and ``coefficient`` (a fold's
    normal-form coefficient at the end, dimensionless sign; None elsewhere)."""

    def __init__(self, x: np.ndarray, v: np.ndarray | None, steps: int, coefficient: float | None) -> None:
        self.x, self.v, self.steps, self.coefficient = x, v, steps, coefficient


def _fold_at(system: EquationSystem, x: np.ndarray, states: Sequence[str], vary: str,
             v: np.ndarray | None) -> tuple[np.ndarray, np.ndarray, float]:
    fp = polish_fold(system, x, states, vary, v0=v)
    idx = np.array([system.index(n) for n in states])
    _, _, a = fold_quantities(system, fp.x, idx, system.index(vary), v=fp.v)
    return fp.x, fp.v, a


def _equilibrium_at(system: EquationSystem, x: np.ndarray, solved: Sequence[str]) -> np.ndarray:
    from ._newton import find_equilibrium

    held = {n: float(x[system.index(n)]) for n in system.state_names if n not in solved}
    free = [n for n in solved if system.variable(n).kind == "parameter"]
    return find_equilibrium(system, hold=held, free=free, guess=x)


def move_point(system: EquationSystem, x: np.ndarray, values: Mapping[str, float], *, solved: Sequence[str],
               vary: str | None = None, states: Sequence[str] | None = None, null_vector: np.ndarray | None = None,
               name: str = "the point") -> MovedPoint:
    """Follow a point from its own parameter values to ``values`` (``{name: value}``, SI), staying on the same point.

    ``x``: the point's full vector (SI) at its own values. A fold (``vary`` given: the
    parameter it is a fold in, ``states`` its unknown states) is followed as a fold: a
    two-parameter fold curve in ``vary`` and the changed parameters, taken along the straight
    path from the old to the new values; any other point with ``solved`` (the names solved for
    at it) as its lens. ``null_vector``: a fold's null vector over ``states`` (a guess).
    ``name`` names the point in messages (``"LP1"``).

    Returns a :class:`MovedPoint`. Raises :class:`InputError` for a value of a name solved for
    at the point or a non-finite value, and :class:`PointLost` (an :class:`InputError` on field
    ``point``) when the point ends on the way: one line with the values where it was last found.
    """
    x = np.array(x, dtype=float)
    for n, val in values.items():
        system.variable(n)
        if n in solved:
            held = [m for m in system.names if m not in solved]
            raise InputError("set", f"{n} is solved for at this point; set one of: {', '.join(held)}")
        if not np.isfinite(float(val)):
            raise InputError("set", f"{n} must be a finite number, got {val!r}")
    names = list(values)
    idx = np.array([system.index(n) for n in names], dtype=np.intp)
    old, new = x[idx].copy(), np.array([float(values[n]) for n in names])
    fold = vary is not None
    solve_idx = np.array([system.index(n) for n in solved], dtype=np.intp)
    scale = _scales(system, x, solve_idx)
    v: np.ndarray | None = None
    a0: float | None = None
    if vary is not None:
        x, v, a0 = _fold_at(system, x, list(states or ()), vary, null_vector)
    if np.array_equal(old, new):
        return MovedPoint(x, v, 0, a0)
    t, h, steps = 0.0, 1.0, 0
    while t < 1.0:
        if steps >= _MAX_STEPS or h < _MIN_STEP:
            last = dict(zip(names, old + t * (new - old)))
            where = ", ".join(f"{n} = {val:.6g}" for n, val in last.items())
            past = ("no fold of that sign exists: it has met its partner fold in a cusp, or its load runs off to "
                    "infinity" if fold else "no nearby solution follows")
            raise PointLost("point", f"{name} does not continue to the values asked: it ends near {where} "
                                     f"(past it {past})", last, x)
        t1 = min(1.0, t + h)
        trial = x.copy()
        trial[idx] = old + t1 * (new - old)
        vy: np.ndarray | None
        a: float | None
        try:
            if vary is not None:
                y, vy, a = _fold_at(system, trial, list(states or ()), vary, v)
            else:
                y, vy, a = _equilibrium_at(system, trial, solved), None, None
            moved = float(np.max(np.abs((y[solve_idx] - x[solve_idx]) / scale)))
            ok = np.isfinite(y).all() and moved <= _STEP_MOVE and (a is None or a0 is None or a * a0 > 0)
        except (ConvergenceError, InputError, np.linalg.LinAlgError, FloatingPointError):
            ok = False
        if not ok:
            h *= 0.5
            continue
        x, v, t, steps = y, vy, t1, steps + 1
        if a is not None:
            a0 = a
        h = min(2 * h, 1.0)
    x[idx] = new  # exactly the values asked (the last step's t1 is 1.0)
    return MovedPoint(x, v, steps, a0)


def _scales(system: EquationSystem, x: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """Column scales of the unknowns ``idx`` at ``x`` (radians 1, others read off the Jacobian)."""
    try:
        _, col = fold_scaling(system, x, idx)
    except (ValueError, np.linalg.LinAlgError):
        col = np.ones(len(idx))
    col = np.where(np.isfinite(col) & (col > 0), col, 1.0)
    rad = np.array([system.variables[i].unit == "rad" for i in idx], dtype=bool)
    return np.where(rad, 1.0, col)


def check_point(system: EquationSystem, x: np.ndarray, *, label: str, vary: str, states: Sequence[str],
                name: str) -> None:
    """Check that the row ``x`` (full vector, SI) of a table is the point it claims to be, at its own values.

    Every row must be an equilibrium: each residual at most :data:`_ROW_TOL` of the size of its
    terms. A fold (``label`` ``"LP"``) is also polished on the augmented system in ``vary`` with
    unknown ``states`` and must lie within :data:`_ROW_TOL` of the row (equilibrated unknowns): a
    corrupted cell would otherwise polish onto another singular point and be called that fold.
    Raises :class:`InputError` (field ``point``) in one line naming ``name`` and what was found.
    """
    x = np.asarray(x, dtype=float)
    with np.errstate(all="ignore"):
        _check_point(system, x, label, vary, states, name)


def _check_point(system: EquationSystem, x: np.ndarray, label: str, vary: str, states: Sequence[str],
                 name: str) -> None:
    r = system.residual(x)
    J = system.jacobian(x)
    # each equation's terms measured with the variables' column scales (radians 1): J x would call an angle of
    # 1e308 rad, whose sine is as good as any, a huge term and any residual small beside it
    every = np.arange(len(x))
    terms = np.abs(J) @ _scales(system, x, every) + np.abs(r)
    rel = np.abs(r) / np.maximum(terms, np.finfo(float).tiny)
    if not np.isfinite(rel).all() or rel.max() > _ROW_TOL:
        i = int(np.nanargmax(np.where(np.isfinite(rel), rel, np.inf)))
        raise InputError("point", f"{name} is not an equilibrium of the model: equation {system.equation_names[i]} "
                                  f"is off by {rel[i]:.3g} of its terms; was the table edited?")
    if label == "LP":
        idx = np.array([system.index(n) for n in [*states, vary]], dtype=np.intp)
        try:
            fp = polish_fold(system, x, states, vary)
        except (ConvergenceError, np.linalg.LinAlgError) as exc:
            raise InputError("point", f"{name} is not a fold of the model in {vary} (the fold polish from this row "
                                      f"fails: {str(exc).split(';')[0]}); was the table edited?") from None
        moved = np.abs((fp.x[idx] - x[idx]) / _scales(system, fp.x, idx))
        if not np.isfinite(moved).all() or moved.max() > _ROW_TOL:
            worst = [*states, vary][int(np.nanargmax(np.where(np.isfinite(moved), moved, np.inf)))]
            raise InputError("point", f"{name} is not a fold of the model in {vary}: the nearest fold is "
                                      f"{moved.max():.3g} (scaled) away, most in {worst} ({float(x[system.index(worst)])!r} in "
                                      f"the table, {fp.x[system.index(worst)]:.10g} at the fold); was the table edited?")
