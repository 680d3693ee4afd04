"""The public Hopf functions: locate a Hopf point, continue it in two parameters (the Hopf curve)."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from ..equations import Dynamics, Model, dynamics_of
from ..errors import ConvergenceError, InputError
from ._api import _bound_events, _curve_unknowns, _limit_events, _run, _start_vector
from ._branch import Branch, SpecialPoint
from ._hopf import HopfProblem, hopf_point_of
from ._hopf_point import HopfTest, polish_hopf
from ._options import ContinuationOptions
from ._problem import EquilibriumProblem, choose_unknowns

if TYPE_CHECKING:
    from ._api import Start

__all__ = ["locate_hopf", "continue_hopf", "HOPF_COLUMNS"]

#: The columns a Hopf curve's table adds after the model's variables, with their units.
HOPF_COLUMNS = {"omega": "rad/s", "l1": "", "n_unstable_other": ""}


def locate_hopf(system: Model, point: Start, vary: str, *, hold: Iterable[str] = (), free: Iterable[str] = (),
                dynamics: Dynamics | None = None) -> SpecialPoint:
    """A Hopf point in ``vary`` polished to machine precision from a nearby ``point``.

    ``point``: a full vector, ``{name: value}`` or :class:`SpecialPoint` (its lens is reused);
    ``hold``/``free``: the lens otherwise (as in :func:`continuation`); ``dynamics``: the model's
    :class:`~mechcont.equations.Dynamics` (default ``dynamics_of(system)``). Returns a
    :class:`SpecialPoint` labelled ``HB`` with its :class:`~._hopf_point.HopfPoint` in ``extra["hopf"]``.
    Raises :class:`InputError` (field ``point``) when Newton does not converge there or the point is a
    neutral saddle (a real eigenvalue pair ``(kappa, -kappa)``), not a Hopf point.
    """
    system.compile()
    x0 = _start_vector(system, point)
    unknowns = (point.unknowns if isinstance(point, SpecialPoint) else None) or choose_unknowns(
        system, hold=hold, free=free, exclude=[vary])
    test = HopfTest(dynamics or dynamics_of(system), system)
    problem = EquilibriumProblem(system, x0, vary, list(unknowns), stability=False)
    try:
        u, pair, res = polish_hopf(test, problem, problem.u_of(x0))
    except ConvergenceError as exc:
        raise InputError("point", f"is not near a Hopf point in {vary}: {exc}") from None
    if not pair.complex:
        raise InputError("point", f"is a neutral saddle in {vary} (real eigenvalues {pair.lam[0].real:.6g} and "
                                  f"{pair.lam[1].real:.6g} 1/s), not a Hopf point")
    x = problem.full(u)
    return SpecialPoint("HB", 0, x, system.names, None, unknowns=tuple(unknowns), vary=vary, residual=res,
                        extra={"hopf": hopf_point_of(test, x, pair, res)})


def continue_hopf(system: Model, hopf: Start, vary: str, free: str, *, hold: Iterable[str] = (),
                  free_extra: Iterable[str] = (), options: ContinuationOptions | None = None, direction: int = 0,
                  dynamics: Dynamics | None = None, progress: Callable[[int], None] | None = None) -> Branch:
    """Continue a Hopf point of equilibria in two parameters: the Hopf curve, with ``BT`` and ``GH``.

    ``hopf``: a point labelled ``HB`` (its lens is reused) or a vector/dict near one; ``vary``: the
    parameter in which it is a Hopf point (``p1``); ``free``: the second parameter (``p2``, whose
    direction ``direction`` sets); ``hold``/``free_extra``: the branch's lens when ``hopf`` is not a
    SpecialPoint; ``options``: steps and bounds; ``dynamics``: as for :func:`locate_hopf`.

    Returns a :class:`Branch` of the curve (full variable vectors) with the columns ``omega``
    (rad/s; 0 at a Bogdanov–Takens point, NaN past it, where the curve goes on as neutral saddles), ``l1``
    (the first Lyapunov coefficient; NaN there too) and ``n_unstable_other`` (eigenvalues with
    positive real part besides the critical pair: 0 where crossing the curve changes stability);
    ``stable_<p1>``, ``stable_<p2>`` (the direction in the parameter plane, per unit of each, into
    which the critical pair turns stable: the stability chart's hatching); ``BT`` where ``omega``
    reaches 0, ``GH`` where ``l1`` changes sign, ``EP`` at the ends.
    """
    options = options or ContinuationOptions()
    system.compile()
    system.index(free)
    states = _curve_unknowns(system, hopf, vary, free, hold, free_extra)
    dyn = dynamics or dynamics_of(system)
    start = locate_hopf(system, hopf, vary, dynamics=dyn) if not isinstance(hopf, SpecialPoint) else (
        hopf if hopf.located and "hopf" in hopf.extra else
        locate_hopf(system, SpecialPoint("HB", 0, np.array(hopf.x, float), system.names, unknowns=tuple(states),
                                         vary=vary), vary, dynamics=dyn))
    test = HopfTest(dyn, system)
    problem = HopfProblem(system, start.x, vary, free, states, test, scales=options.scales)
    x = problem.full(problem.u0)
    system.check_limits(x)
    evs = problem.test_functions() + _bound_events(system, options) + _limit_events(system, (*states, vary, free))
    curve = _run(problem, system, problem.u0, replace(options, stability=False), evs, direction, free,
                 (*states, vary), progress=progress)
    return _with_hopf_columns(curve, problem)


def _with_hopf_columns(curve: Branch, problem: HopfProblem) -> Branch:
    """``curve`` with :data:`HOPF_COLUMNS` and the stable side of each point (``stable_<p1>``,
    ``stable_<p2>``: the direction in the parameter plane into which the critical pair turns stable)."""
    cols: dict[str, list[float]] = {"omega": [], "l1": [], "n_unstable_other": [],
                                    f"stable_{problem.p1}": [], f"stable_{problem.p2}": []}
    for x, label in zip(curve.values, curve.labels):
        pair = problem.test.pair(x)
        # at a BT point omega is 0 (kappa there is rounding, of either sign)
        cols["omega"].append(0.0 if label == "BT" else pair.omega if pair.complex else np.nan)
        cols["l1"].append(problem.lyapunov(x) if pair.complex and label != "BT" else np.nan)
        d1, d2, others = problem.side(x)
        cols["n_unstable_other"].append(float(others))
        cols[f"stable_{problem.p1}"].append(d1)
        cols[f"stable_{problem.p2}"].append(d2)
    return curve.with_columns({k: np.asarray(v) for k, v in cols.items()},
                              units={**HOPF_COLUMNS, f"stable_{problem.p1}": "", f"stable_{problem.p2}": ""})
