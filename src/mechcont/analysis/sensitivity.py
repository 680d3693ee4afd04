"""Exact sensitivities to parameters: of equilibria, folds and branch points, and of downlock forces.

The derivatives of equilibria, folds and branch points are the engine's
(:mod:`mechcont.continuation._sensitivity`: the implicit-function theorem on exact Jacobians,
nothing differenced), re-exported here; this module adds the downlock force (the lock
condition held, the force among the unknowns) and a branch's columns of derivatives. Results
are in SI units per SI unit (``N/(N/m)`` for a force by a stiffness); angles in radians.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from ..continuation import (
    Sensitivity,
    check_parameters,
    choose_unknowns,
    equilibrium_sensitivity,
    fold_sensitivity,
    point_sensitivity,
    polish_fold,
    write_json,
)
from ..equations import Model, units_of
from ..errors import InputError
from ..units import derivative_unit
from ._downlock_point import DownlockResult, downlock_condition, downlock_point
from .unlock import B

__all__ = ["Sensitivity", "equilibrium_sensitivity", "fold_sensitivity", "downlock_sensitivity", "point_sensitivity",
           "release_sensitivity", "margin_sensitivity", "cusp_sensitivity", "derivative_unit", "check_parameters",
           "write_json", "with_sensitivity_columns"]


def downlock_sensitivity(system: Model, params: Iterable[str], values: Mapping[str, float] | None = None, *,
                         hold: Mapping[str, float] | None = None, force: str | None = None,
                         condition: str | None = None, x: np.ndarray | None = None) -> Sensitivity:
    """Derivatives of the downlock force (condition held, force solved) with respect to ``params``.

    Solves the downlocked point at ``values`` (:func:`~mechcont.analysis.downlock.downlock_point`)
    unless ``x`` gives it, then :func:`equilibrium_sensitivity` with the condition's states
    held and the force among the unknowns. Returns a :class:`Sensitivity` of kind
    ``"downlock"`` (N per unit of each parameter).
    """
    if values:  # the model at the values: a hold target written in parameters follows them
        system = system.with_values({k: v for k, v in values.items() if system.variable(k).kind == "parameter"})
    h, f = downlock_condition(system, hold, force, condition=condition)
    if x is None:
        x = downlock_point(system, values, hold=h, force=f)
    unknowns = choose_unknowns(system, hold=h, free=[f])
    # a hold target written in parameters moves with them
    return through_limits(system, params, [] if hold else h, targets=True,
                          compute=lambda names: equilibrium_sensitivity(system, x, unknowns, names, f, kind="downlock"))


def _switch_or_cusp(system: Model, x: np.ndarray, params: Iterable[str], vary: str, label: str, info: dict[str, Any],
                    unknowns: Sequence[str] | None, values: Mapping[str, float] | None) -> Sensitivity:
    """:func:`point_sensitivity` at a stop's release (``SR``) or a fold curve's cusp (``CP``): the
    handler :mod:`mechcont.analysis` registers for those labels (:data:`SPECIAL_POINTS`)."""
    if label in ("SR", "NSF"):
        # the stops' limits at the row's own parameter values (a limit written in parameters), then at ``values``
        own = {n: float(x[system.index(n)]) for n in system.parameter_names}
        stop = info.get("stop") or _released_stop(system.with_values(own), x, label)
        system = system.with_values({**own, **(values or {})})
        if values:
            x = system.vector(values, base=x)
            system.check_limits(x)
        return replace(release_sensitivity(system, x, stop, vary, params), point=f"{label}: release of stop {stop}")
    lens = list(unknowns or info.get("unknowns") or [])
    if len(lens) != system.n_equations + 1:
        raise InputError("unknowns", "a cusp's unknowns are the fold's states and then its parameter (a fold "
                                     "curve's points record them); give them")
    return cusp_sensitivity(system, x, lens[:-1], lens[-1], vary, params)


def _released_stop(system: Model, x: np.ndarray, label: str) -> str:
    """The stop whose reaction is zero at ``x`` while its condition is at its limit (the one releasing at an
    ``SR`` or ``NSF`` row); :class:`InputError` naming what was found when there is none."""
    from .stops import GAP_TOL

    found = [s for s in system.stops
             if abs(x[system.index(s.reaction)]) <= 1e-9 * system.variable(s.reaction).scale
             and abs(s.gap(x[system.index(s.condition)])) <= max(GAP_TOL, 1e-6)]
    if len(found) != 1:
        what = "no stop" if not found else f"{len(found)} stops ({', '.join(s.name for s in found)})"
        raise InputError("point", f"{what} at its limit with a zero reaction here: not a release ({label}) of one stop")
    return found[0].name


def with_sensitivity_columns(system: Model, result: B, params: Iterable[str], of: str | None = None) -> B:
    """A new ``result`` (a :class:`~mechcont.continuation.Branch`, or a
    :class:`~mechcont.analysis.downlock.DownlockResult` with a new branch) with ``d<of>_d<p>`` columns:
    the exact derivative at every row (SI units).

    ``of`` is an unknown of the branch (default: a downlock result's force), differentiated
    with the continuation parameter held (:func:`equilibrium_sensitivity` at each row). The
    units of the new columns are those of the derivatives (``N/(N/m)``).
    """
    branch = result.branch if isinstance(result, DownlockResult) else result
    of = of or (result.force if isinstance(result, DownlockResult) else None)
    if of is None:
        raise InputError("sensitivity", "name the unknown of the branch to differentiate")
    params = list(params)
    unknowns = list(branch.unknowns)
    check_parameters(system, params, unknowns)
    X = np.column_stack([branch.column(n) for n in system.names])  # the model's variables (other columns may follow)
    rows = [equilibrium_sensitivity(system, x, unknowns, params, of) for x in X]
    cols = {f"d{of}_d{p}": np.array([r[p] for r in rows]) for p in params}
    units = {f"d{of}_d{p}": rows[0].units[p] if rows else "" for p in params}
    out = branch.with_columns(cols, units)
    return replace(result, branch=out) if isinstance(result, DownlockResult) else out


def release_sensitivity(system: Model, x: np.ndarray, stop: str, vary: str, params: Iterable[str], *,
                        polish: bool = True) -> Sensitivity:
    """Derivatives of a stop's release load: the value of ``vary`` where the stop's reaction reaches zero.

    At a release (``SR`` of :func:`~mechcont.analysis.stops.continuation_with_stops`) the stop is
    still in contact (its condition held at the limit) and its reaction ``R`` is zero, so the
    release is the square solve ``G = 0`` with every touching stop's condition held at its limit,
    ``R = 0`` held and ``vary`` freed beside the other touching stops' reactions:
    :func:`equilibrium_sensitivity` of ``vary`` there.

    Parameters
    ----------
    system, x:
        A model with stops and a point at (or, with ``polish``, near) the release.
    stop:
        The releasing stop's name.
    vary:
        The load continued (e.g. the unlock force).
    params:
        Held names to differentiate by (not a touching stop's condition or reaction).
    polish:
        Solve the release exactly first (Newton from ``x``: ``R = 0``, ``vary`` freed).

    Returns a :class:`Sensitivity` of kind ``"release"`` (its ``x`` the solved release).
    """
    from .stops import GAP_TOL

    stops = {s.name: s for s in system.stops}
    if stop not in stops:
        raise InputError("stop", f"unknown stop {stop!r}; stops of {system.name}: {', '.join(stops) or 'none'}")
    x = np.asarray(x, dtype=float).copy()
    touching = [s for s in stops.values()
                if s.name == stop or abs(s.gap(x[system.index(s.condition)])) <= max(GAP_TOL, 1e-6)]
    hold = {s.condition: float(s.limit) for s in touching}
    free = [vary, *(s.reaction for s in touching if s.name != stop)]
    for s in touching:
        x[system.index(s.condition)] = s.limit
    x[system.index(stops[stop].reaction)] = 0.0
    if polish:
        from ..continuation import find_equilibrium

        x = find_equilibrium(system, hold=hold, free=free, guess=x)
    unknowns = choose_unknowns(system, hold=list(hold), free=free)
    # a limit written in parameters moves the held conditions

    sens = through_limits(system, params, hold,
                          lambda names: equilibrium_sensitivity(system, x, unknowns, names, vary, kind="release"))
    return replace(sens, point=sens.point or f"release of stop {stop}")


def margin_sensitivity(system: Model, design: str, params: Iterable[str],
                       values: Mapping[str, float] | None = None, *, kind: str = "fold", at: float | None = None,
                       bounds: tuple[float, float] | None = None, hold: Mapping[str, float] | None = None,
                       force: str | None = None, condition: str | None = None) -> Sensitivity:
    """Derivatives of the design map's margins along ``design`` (:mod:`mechcont.analysis.design`).

    * ``kind="fold"``: the margin to the fold, ``|x0 - x_f|`` with ``x_f`` the nearest extremum of
      the downlock force in ``design`` (a fold in the force with ``design`` solved for). ``dx_f/dp``
      is the ``design`` row of :func:`fold_sensitivity`'s augmented system.
    * ``kind="lock"``: the signed lock margin, ``+|x0 - x_c|`` when the design locks unaided
      (force > 0 at ``x0``), ``-|x0 - x_c|`` when not, ``x_c`` the nearest ``F = 0`` crossing:
      ``dx_c/dp`` from :func:`equilibrium_sensitivity` with ``F = 0`` held and ``design`` freed.

    ``x0`` is ``design``'s value in ``values`` (else the model's). The fold or crossing is the
    one near ``at`` (SI), else the nearest found by continuation of the force in ``design``
    within ``bounds``. The derivative by ``design`` itself is the margin's sign change of
    ``x0``; by any other parameter it is ``-sign(x0 - x_f) dx_f/dp`` (times the lock's sign).
    Returns a :class:`Sensitivity` of kind ``"fold_margin"`` or ``"lock_margin"`` (unit of
    ``design``); :class:`InputError` when there is no fold or crossing in ``bounds``.
    """
    from ..continuation import find_equilibrium
    if kind not in ("fold", "lock"):
        raise InputError("kind", f"'{kind}' is not a margin; valid: fold, lock")
    h, f = downlock_condition(system, hold, force, condition=condition)
    values = dict(values or {})
    system.variable(design)
    x0 = float(values.get(design, system.variable(design).value))
    lens = choose_unknowns(system, hold=h, free=[design])
    params = check_parameters(system, params, [f, *(n for n in lens if n != design)])
    others = [p for p in params if p != design]
    if at is None:
        at = _nearest(system, design, values, kind, bounds, h, f, x0)
    start = downlock_point(system, {**values, design: at}, hold=h, force=f)
    if kind == "fold":
        s = fold_sensitivity(system, start, lens, f, others) if others else None
        xq = s.x if s is not None else polish_fold(system, start, lens, f).x
        d_x = {p: s.states[p][design] for p in others} if s is not None else {}
        sign = 1.0
    else:
        guess = start.copy()
        guess[system.index(f)] = 0.0
        held = {k: v for k, v in values.items() if k != design}  # the design value would override the start
        xq = find_equilibrium(system, values={**held, f: 0.0}, hold=h, free=[design], guess=guess)
        d_x = (equilibrium_sensitivity(system, xq, lens, others, design).derivatives if others else {})
        F0 = float(downlock_point(system, values, hold=h, force=f)[system.index(f)])
        sign = 1.0 if F0 > 0 else -1.0
    assert xq is not None
    xc = float(xq[system.index(design)])
    side = sign * (1.0 if x0 >= xc else -1.0)
    deriv = {p: side * (1.0 if p == design else -d_x[p]) for p in params}
    unit = system.variable(design).unit
    return Sensitivity(f"{kind}_margin", side * (x0 - xc), unit, f"{kind}_margin", deriv,
                       {p: derivative_unit(unit, system.variable(p).unit) for p in params}, {}, xq,
                       f"{'fold' if kind == 'fold' else f + ' = 0'} at {design} = {xc:.10g}")


def _nearest(system: Model, design: str, values: Mapping[str, float], kind: str, bounds: tuple[float, float] | None,
             h: Mapping[str, float], f: str, x0: float) -> float:
    """The fold (extremum of ``f`` in ``design``) or ``f = 0`` crossing nearest ``x0``, by continuation in ``f``."""
    from ..continuation import ContinuationOptions, continuation
    if bounds is None:
        raise InputError("bounds", f"give the range of {design} to look for the {kind} margin in (or 'at')")
    lo, hi = map(float, bounds)
    big = 1e6 * units_of(system).from_si(system.variable(f).unit)  # 1e6 N (N m) in the file's units
    opts = ContinuationOptions(ds=0.02, dsmin=1e-9, dsmax=0.5, bounds={design: (lo, hi), f: (-big, big)},
                               max_steps=2000)
    br = continuation(system, downlock_point(system, {**values, design: min(max(x0, lo), hi)}, hold=h, force=f), f,
                      hold=list(h), free=[design], options=opts)
    if kind == "fold":
        found = [p[design] for p in br.special("LP")]
    else:
        xs, Fs = br[design], br[f]
        cross = np.nonzero(np.sign(Fs[:-1]) * np.sign(Fs[1:]) < 0)[0]
        found = [xs[i] - Fs[i] * (xs[i + 1] - xs[i]) / (Fs[i + 1] - Fs[i]) for i in cross]
    if not found:
        what = f"fold (extremum of {f})" if kind == "fold" else f"{f} = 0 crossing"
        raise InputError(design, f"no {what} in {design} = {lo:g}..{hi:g}")
    return float(min(found, key=lambda v: abs(v - x0)))


# the cusp's location lives in its own module (it uses the helpers above); re-exported here
from ._cusp import cusp_sensitivity  # noqa: E402


def through_limits(system: Model, params: Iterable[str], held: Iterable[str],
                   compute: Callable[[list[str]], Sensitivity], *, targets: bool = False) -> Sensitivity:
    """A sensitivity by ``params`` of a quantity solved with the conditions ``held`` at their stops' limits (or,
    ``targets``, at their declared targets: the downlock hold), each the function of the parameters its
    description writes (:meth:`~mechcont.equations.Model.limit_derivatives`, ``target_derivatives``):
    ``compute(names)`` differentiates by ``names`` (``params`` and the held conditions that depend on them), and
    ``dq/dp = dq/dp|held + sum_c dq/dc dc/dp``. A stop's limit is then a parameter like any other (its
    derivative is not 0). Returns the :class:`Sensitivity` by ``params`` alone."""
    params, held = list(params), set(held)
    if targets:
        grads = {c: system.target_derivatives(c, params) for c in held if c in system.conditions and c not in params}
    else:
        grads = {s.condition: system.limit_derivatives(s.name, params) for s in system.stops
                 if s.condition in held and s.condition not in params}
    grads = {c: g for c, g in grads.items() if any(g.values())}
    sens = compute([*params, *grads])
    if not grads:
        return sens
    d = sens.derivatives
    for p in params:
        d[p] = d[p] + sum(d[c] * g[p] for c, g in grads.items())
    for p in params:
        if p in sens.states:
            row = sens.states[p]
            for u in row:
                row[u] = row[u] + sum(sens.states[c].get(u, 0.0) * g[p] for c, g in grads.items())
    for c in grads:
        d.pop(c, None)
        sens.units.pop(c, None)
        sens.states.pop(c, None)
    return sens
