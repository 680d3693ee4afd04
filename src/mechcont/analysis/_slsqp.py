"""SLSQP's side of :func:`~mechcont.analysis.optimize.optimize`: its start points, which of two of its results is
better, and the multipliers of the active constraints and bounds at its optimum (all in the scaled design ``t``,
each design variable mapped to ``[0, 1]`` by its bounds)."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, TypedDict

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from scipy.optimize import OptimizeResult

    from .optimize import Constraint

__all__ = ["Inequality", "start_points", "better", "multipliers", "unmet"]


class Inequality(TypedDict):
    """One constraint as SLSQP takes it: ``fun(t) >= 0`` with its gradient ``jac(t)`` (``type`` is ``"ineq"``)."""

    type: str
    fun: Callable[[np.ndarray], float]
    jac: Callable[[np.ndarray], np.ndarray]


def start_points(z0: np.ndarray, lo: np.ndarray, hi: np.ndarray, n: int) -> Iterator[np.ndarray]:
    """The scaled start points: the given design, then (``n`` > 1) an ``n``-per-axis grid over the bounds."""
    if n < 1:
        raise InputError("starts", f"must be a positive whole number, got {n}")
    yield (z0 - lo) / (hi - lo)
    if n > 1:
        for t in itertools.product(np.linspace(0.0, 1.0, n), repeat=len(z0)):
            yield np.array(t)


def unmet(constraints: Sequence[Inequality], t: np.ndarray, tol: float = 1e-6) -> list[int]:
    """The positions of the scaled ``constraints`` that the design ``t`` (scaled to 0..1) misses by more than
    ``tol``."""
    return [i for i, c in enumerate(constraints) if c["fun"](t) < -tol]


def better(r: OptimizeResult, best: OptimizeResult, constraints: Sequence[Inequality], tol: float = 1e-6) -> bool:
    """Is SLSQP result ``r`` better than ``best``: feasible (to ``tol`` of the scaled
    constraints, :func:`unmet`) first, then lower."""
    def feasible(res: OptimizeResult) -> bool:
        return bool(res.success) and not unmet(constraints, np.clip(res.x, 0.0, 1.0), tol)

    fr, fb = feasible(r), feasible(best)
    return fr and (not fb or float(r.fun) < float(best.fun) - 1e-12 * max(1.0, abs(float(best.fun))))


def multipliers(design: Sequence[str], t: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                at: Mapping[str, tuple[float, np.ndarray]], objective: str, constraints: Sequence[Constraint],
                g_scale: Sequence[float], tol: float = 1e-6) -> list[tuple[str, float]]:
    """Active constraints and bounds with ``mu`` solving ``grad f = sum mu_i grad g_i`` (least squares).

    ``mu_i = d f* / d b_i``: the change of the optimum per unit of the bound ``b_i``. ``t`` is the scaled optimum,
    ``lo``/``hi`` the design's bounds (SI), ``at`` every quantity's value and gradient there, ``g_scale`` each
    constraint's scale (a constraint within ``tol`` of its scale of its bound, a bound within ``tol`` in ``t``, is
    active).
    """
    rows, what = [], []
    for i, c in enumerate(constraints):
        v, g = at[c.quantity]
        if abs(v - c.bound) <= tol * g_scale[i]:
            rows.append(g)
            what.append(str(c))
    for j, n in enumerate(design):
        for side, edge, sense in ((t[j] <= tol, lo[j], ">="), (t[j] >= 1 - tol, hi[j], "<=")):
            if side:
                rows.append(np.eye(len(design))[j])
                what.append(f"{n} {sense} {edge:g}")
    if not rows:
        return []
    mu, *_ = np.linalg.lstsq(np.array(rows).T, at[objective][1], rcond=None)
    return [(w, float(m) + 0.0) for w, m in zip(what, mu)]
