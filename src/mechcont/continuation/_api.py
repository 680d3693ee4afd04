"""The public continuation functions: equilibria in one parameter, folds in two."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, TypeAlias

import numpy as np

from .._status import Status
from ..equations import EquationSystem, Model
from ..errors import ConvergenceError, InputError
from ._branch import Branch, SpecialPoint
from ._events import BoundEvent, BranchPointEvent, Event, FoldEvent, LimitEvent, PointState, ValueEvent
from ._fold_point import fold_quantities, polish_fold, refine_fold
from ._folds import FoldProblem
from ._newton import residual_met
from ._options import ContinuationOptions
from ._palc import DirectionResult, run_direction
from ._problem import ContinuationProblem, EquilibriumProblem, choose_unknowns

if TYPE_CHECKING:
    import numpy.typing as npt  # (17 ms to import: for the type checker only)

    from ..equations import Dynamics

    #: A point to start from: a :class:`SpecialPoint`, ``{name: value}`` (SI; the others at their defaults) or a
    #: full vector ordered like the system's names
    Start: TypeAlias = SpecialPoint | Mapping[str, float] | npt.ArrayLike

__all__ = ["continuation", "continue_folds", "locate_fold", "switch_branch"]


class _Equilibria(EquilibriumProblem):
    def refine_fold(self, state: PointState) -> tuple[np.ndarray, dict[str, Any]]:
        """The fold polished to machine precision, or the located guess marked approximate.

        The null vector's first guess is the branch tangent's states part (exact at the fold;
        near a stiff compliance the smallest singular vector may be the compliance's, not
        the fold's), then, if that fails, the smallest singular vector."""
        states, param = self.names[:-1], self.names[-1]
        tangent = np.asarray(state.tangent, float)[:-1] * np.asarray(self.scale, float)[:-1]
        try:
            fp = polish_fold(self.system, state.x, states, param, v0=tangent)
        except ConvergenceError:
            try:
                fp = polish_fold(self.system, state.x, states, param)
            except ConvergenceError as exc:
                return state.u, {"status": "approximate", "reason": str(exc)}
        return self.u_of(fp.x), {"null_vector": fp.v, "status": "located", **fp.precision()}


def _curve_unknowns(system: EquationSystem, point: Start, vary: str, free: str, hold: Iterable[str],
                    free_extra: Iterable[str]) -> list[str]:
    """The unknowns of a two-parameter curve through ``point`` (a fold or Hopf point): its branch's lens (the
    point's own, else from ``hold``/``free_extra``), without ``vary`` and the second parameter ``free``. Raises
    :class:`InputError` when ``free`` was one of the branch's unknowns."""
    states = (point.unknowns if isinstance(point, SpecialPoint) else None) or choose_unknowns(
        system, hold=hold, free=free_extra, exclude=[vary])
    states = [s for s in states if s != free]
    if len(states) != system.n_equations:
        raise InputError(free, "is one of the unknowns of the branch; choose a parameter that was held")
    return states


def _start_vector(system: EquationSystem, start: Start) -> np.ndarray:
    if isinstance(start, SpecialPoint):
        return np.array(start.x, float)
    if isinstance(start, Mapping):
        return system.vector(start)
    x = np.asarray(start, dtype=float)
    if x.shape != (len(system.names),):
        raise InputError("start", f"must be a full vector of {len(system.names)} values (ordered like system.names)")
    return x


def _bound_events(system: EquationSystem, options: ContinuationOptions) -> list[Event]:
    evs: list[Event] = []
    for name, (lo, hi) in options.bounds.items():
        i = system.index(name)
        for b, side in ((lo, 1), (hi, -1)):
            if np.isfinite(b):
                evs.append(BoundEvent(name, i, float(b), side))
    return evs


def _limit_events(system: EquationSystem, moving: Iterable[str]) -> list[Event]:
    """``EP`` at the edge of every physical range that the ``moving`` parameters change."""
    params = [n for n in moving if system.variable(n).kind == "parameter"]
    return [LimitEvent(system, i) for i in system.limits_of(params)]


def _equilibrium_events(system: EquationSystem, options: ContinuationOptions, events: Iterable[Event],
                        moving: Iterable[str] = ()) -> list[Event]:
    evs: list[Event] = []
    if options.detect_folds:
        evs.append(FoldEvent())
    if options.detect_branch_points:
        evs.append(BranchPointEvent())
    return evs + list(events) + _bound_events(system, options) + _limit_events(system, moving)


def _check_start(system: EquationSystem, problem: ContinuationProblem, u0: np.ndarray, options: ContinuationOptions,
                 start_x: np.ndarray) -> None:
    system.check_limits(start_x)
    r, J = problem.evaluate(u0)
    # relative to the sizes of each row's terms (residual_met's floor): the same mechanism written in
    # millimetres and grams has rows a million times larger, solved just as well
    if not np.all(np.isfinite(r)) or not residual_met(r, J, u0, 1e3 * options.engine.residual_tol):
        raise InputError("start", f"is not an equilibrium of {system.name} (largest residual {np.max(np.abs(r)):.3g}, "
                                  "above the rounding of its terms); start from a solved point: hold a state at a "
                                  "value (--start NAME=VALUE) to find one")
    for name, (lo, hi) in options.bounds.items():
        v = start_x[system.index(name)]
        if not lo <= v <= hi:
            raise InputError(name, f"start value {v:.6g} lies outside its bounds {lo:g}:{hi:g}")


def _run(problem: ContinuationProblem, system: EquationSystem, u0: np.ndarray, options: ContinuationOptions,
         events: list[Event], direction: int, vary: str, unknowns: Sequence[str], tangent0: np.ndarray | None = None,
         progress: Callable[[int], object] | None = None) -> Branch:
    if direction not in (-1, 0, 1):
        raise InputError("direction", f"must be -1, 0 (both) or +1, got {direction!r}")
    dirs = [direction] if direction else [-1, 1]
    parts = {d: run_direction(problem, u0, d, options, events, tangent0=tangent0, progress=progress, stability=False)
             for d in dirs}
    rows: list[PointState] = []
    labels: list[str] = []
    infos: list[Mapping[str, Any]] = []
    s: list[float] = []

    def take(p: DirectionResult, indices: Iterable[int], sign: int) -> None:
        for i in indices:
            rows.append(p.states[i])
            labels.append(p.labels[i])
            infos.append(p.info[i])
            s.append(sign * p.arclength[i])

    if -1 in parts:  # backwards part reversed, so the branch runs in arclength order
        p = parts[-1]
        take(p, range(len(p.states) - 1, 0 if 1 in parts else -1, -1), -1)
    if 1 in parts:
        p, k0 = parts[1], len(rows)
        take(p, range(len(p.states)), 1)
        if -1 in parts and parts[-1].labels[0] and not p.labels[0]:
            # the start's own label (e.g. EP: started on a bound) was found going backwards
            labels[k0], infos[k0] = parts[-1].labels[0], parts[-1].info[0]
    values = np.array([st.x for st in rows])
    # the whole branch's stability in one batch
    stab = problem.stability_batch(np.array([st.u for st in rows])) if options.stability else [-1] * len(rows)
    special = []
    for i, (lab, st, inf) in enumerate(zip(labels, rows, infos)):
        if lab:
            special.append(SpecialPoint(lab, i, st.x.copy(), system.names, st.tangent.copy(), inf,
                                        unknowns=tuple(unknowns), vary=vary))
    status = Status.first_failure(parts[d].status for d in dirs)
    message = "; ".join(f"{'+' if d > 0 else '-'}: {parts[d].message}" for d in dirs if parts[d].message)
    return Branch(system.names, values, s, stab, labels, special, vary, unknowns, status, message, system.name,
                  units={v.name: v.unit for v in system.variables})


def continuation(system: Model, start: Start, vary: str, *, hold: Iterable[str] = (), free: Iterable[str] = (),
                 options: ContinuationOptions | None = None, direction: int = 0,
                 events: Sequence[Event] = (), progress: Callable[[int], None] | None = None,
                 hopf: bool | Dynamics = False, at: Iterable[float] = ()) -> Branch:
    """Continue equilibria of ``system`` in the variable ``vary``.

    Parameters
    ----------
    system:
        The equation system (compiled on first use).
    start:
        A converged point: full vector (ordered like ``system.names``), ``{name: value}``
        or a :class:`SpecialPoint`. Use :func:`find_equilibrium` to get one.
    vary:
        The continuation parameter: any variable, a parameter (``"F"``) or a state
        (``"theta1"``, which is then prescribed).
    hold:
        States held at their start values (e.g. ``["theta4"]``).
    free:
        Parameters solved for (e.g. ``["F"]``); with ``hold`` they keep the system square.
    options:
        :class:`ContinuationOptions` (steps, bounds, tolerances).
    direction:
        ``0`` both directions, ``+1``/``-1`` only increasing/decreasing ``vary`` at the start.
    events:
        Extra :class:`~mechcont.continuation.Event` objects (e.g. ``ValueEvent("theta4", 0)``).
    progress:
        Called with ``1`` after every accepted step (e.g. a progress bar's ``update``).
    hopf:
        Detect Hopf points (``HB``) from the eigenvalues of the model's dynamics at every point:
        ``True`` for ``dynamics_of(system)``, or a :class:`~mechcont.equations.Dynamics` to use.
        Each is located on the extended system and carries a
        :class:`~mechcont.continuation.HopfPoint` (``point.extra["hopf"]``: frequency, ``l1``).
    at:
        Values of ``vary`` (SI units) at which to add rows located exactly there, labelled ``UZ``
        (AUTO's user points).

    Returns
    -------
    Branch
        Points with stability (from the mechanics), ``LP``/``BP`` (and ``HB``) located to the
        tolerances, ``UZ`` at the ``at`` values, ``EP`` at the ends. The branch is returned even when a direction
        fails; ``branch.status``/``branch.message`` then say where and why.
    """
    options = options or ContinuationOptions()
    system.compile()
    x0 = _start_vector(system, start)
    unknowns = choose_unknowns(system, hold=hold, free=free, exclude=[vary])
    events = [*events, *_user_points(vary, at)]
    if hopf is not False:
        from ..equations import dynamics_of
        from ._hopf import HopfEvent

        events.append(HopfEvent(dynamics_of(system) if hopf is True else hopf, system))

    def piece(model: Model, x: np.ndarray, vary_: str, opts: ContinuationOptions, sense: int,
              evs_: Sequence[Event]) -> Branch:
        model.compile()
        problem = _Equilibria(model, x, vary_, unknowns, scales=opts.scales, stability=opts.stability)
        u0 = problem.u_of(x)
        _check_start(model, problem, u0, opts, x)
        evs = _equilibrium_events(model, opts, evs_, moving=(*unknowns, vary_))
        return _run(problem, model, u0, opts, evs, sense, vary_, unknowns, progress=progress)

    if system.reselect is not None:  # a choice of dropped rows made again along the branch
        from ._variants import across_variants

        return _start_at_user_point(across_variants(piece, system, x0, vary, options, direction, events, unknowns),
                                    at)
    return _start_at_user_point(piece(system, x0, vary, options, direction, events), at)


def _start_at_user_point(branch: Branch, at: Iterable[float]) -> Branch:
    """``branch`` with its start row labelled ``UZ`` when ``vary`` starts at one of the ``at`` values (a step's
    test function changes sign only strictly inside it, so a start on the value is never found by stepping)."""
    starts = np.flatnonzero(branch.s == 0.0)
    if not starts.size or branch.labels[starts[0]]:
        return branch
    i = int(starts[0])
    v0 = float(branch.values[i, branch.names.index(branch.vary)])
    if not any(abs(float(v) - v0) <= 4 * np.finfo(float).eps * max(1.0, abs(v0)) for v in at):
        return branch
    labels = list(branch.labels)
    labels[i] = "UZ"
    point = SpecialPoint("UZ", i, branch.values[i].copy(), branch.names, status=Status.LOCATED)
    return branch.replace(labels=labels, special_points=[*branch.special_points, point])


def _user_points(vary: str, at: Iterable[float]) -> list[Event]:
    """A ``UZ`` event at each value of ``at`` (finite numbers, SI units)."""
    evs: list[Event] = []
    for v in at:
        v = float(v)
        if not np.isfinite(v):
            raise InputError("at", f"{v} is not a finite value of {vary}")
        evs.append(ValueEvent(vary, v))
    return evs


def locate_fold(system: EquationSystem, point: Start, vary: str, *, hold: Iterable[str] = (),
                free: Iterable[str] = ()) -> tuple[np.ndarray, np.ndarray, float]:
    """Polish an approximate fold in ``vary`` to machine precision.

    ``point`` is a full vector, dict or :class:`SpecialPoint` near a fold. Returns
    ``(x, v, a)``: the full vector at the fold, the null vector (over the unknown states)
    and the normalised quadratic coefficient (its sign tells which side the branch bends).
    """
    x0 = _start_vector(system, point)
    states = (point.unknowns if isinstance(point, SpecialPoint) else None) or choose_unknowns(
        system, hold=hold, free=free, exclude=[vary])
    x, v = refine_fold(system, x0, states, vary)
    idx = np.array([system.index(n) for n in states])
    _, _, a = fold_quantities(system, x, idx, system.index(vary), v)
    return x, v, a


def continue_folds(system: EquationSystem, fold: Start, vary: str, free: str, *, hold: Iterable[str] = (),
                   free_extra: Iterable[str] = (), options: ContinuationOptions | None = None,
                   direction: int = 0, stop_at_cusp: bool = False,
                   progress: Callable[[int], None] | None = None) -> Branch:
    """Continue a fold of equilibria in two parameters: the fold curve, with cusps (``CP``).

    Parameters
    ----------
    system:
        The equation system.
    fold:
        A fold: a :class:`SpecialPoint` labelled ``LP`` (its lens is reused), or a full
        vector/dict near a fold.
    vary:
        The parameter in which ``fold`` is a fold (``p1``, e.g. ``"F"``).
    free:
        The second parameter (``p2``, e.g. ``"LU"``), whose direction ``direction`` sets.
    hold, free_extra:
        The lens of the equilibrium branch when ``fold`` is not a SpecialPoint.
    options:
        Steps and bounds (bounds on ``p2`` usually end the curve).
    direction:
        ``0`` both ways, ``+1``/``-1``: increasing/decreasing ``free`` at the start.
    stop_at_cusp:
        End the curve at the first cusp instead of continuing onto the other fold.
    progress:
        Called with ``1`` after every accepted step (e.g. a progress bar's ``update``).

    Returns
    -------
    Branch
        One row per fold-curve point (full variable vectors; stability not evaluated:
        a fold is neutral by definition), ``CP`` at cusps, ``EP`` at the ends.
    """
    options = options or ContinuationOptions()
    system.compile()
    system.index(free)
    states = _curve_unknowns(system, fold, vary, free, hold, free_extra)
    x0 = _start_vector(system, fold)
    problem = None
    if isinstance(fold, SpecialPoint) and fold.located and fold.vary == vary:
        # a fold the branch already polished: start from it as it is, if it still solves the fold system
        problem = FoldProblem(system, x0, vary, free, states, scales=options.scales)
        if not problem.solves(problem.u0):
            problem = None
    if problem is None:
        x, _ = refine_fold(system, x0, states, vary)
        problem = FoldProblem(system, x, vary, free, states, scales=options.scales)
    x = problem.full(problem.u0)
    from dataclasses import replace

    opts = replace(options, stability=False)
    system.check_limits(x)
    evs = problem.test_functions() + _bound_events(system, options) + _limit_events(system, (*states, vary, free))
    if stop_at_cusp:
        for ev in evs:
            if ev.label == "CP":
                ev.stop = True
    return _run(problem, system, problem.u0, opts, evs, direction, free, (*states, vary), progress=progress)


def switch_branch(system: EquationSystem, bp: SpecialPoint, *, options: ContinuationOptions | None = None,
                  direction: int = 0, events: Sequence[Event] = ()) -> Branch:
    """Continue the other branch through a branch point (``BP``) of a computed branch.

    At a simple branch point the Jacobian ``G_z`` (n x n+1) has a two-dimensional null
    space ``{phi1 = old tangent, phi2}`` and a left null vector ``w``. Tangents of the
    branches through the point are ``a phi1 + b phi2`` with ``(a, b)`` roots of the
    algebraic branching equation ``w^T G_zz[a phi1 + b phi2, a phi1 + b phi2] = 0``.
    ``(1, 0)`` is one root (the old branch), so the coefficient of ``a^2`` vanishes and the
    other root is ``(a, b) = (c22, -2 c12)`` with ``c_ij = w^T G_zz[phi_i, phi_j]``. From
    there the ordinary pseudo-arclength engine takes over, in both directions unless
    ``direction`` says.

    Parameters
    ----------
    system:
        The equation system of the branch.
    bp:
        A special point labelled ``BP`` (from :func:`continuation`, which records its lens
        and tangent).
    options, direction, events:
        As for :func:`continuation` (use the same ``scales`` as for the first branch).

    Returns
    -------
    Branch
        The new branch; the start row is labelled ``BP``.
    """
    if (not isinstance(bp, SpecialPoint) or bp.label != "BP" or bp.tangent is None or bp.vary is None
            or bp.unknowns is None):
        raise InputError("bp", "give a special point labelled BP from a continuation branch")
    options = options or ContinuationOptions()
    vary, unknowns = bp.vary, list(bp.unknowns)
    problem = _Equilibria(system, bp.x, vary, unknowns, scales=options.scales, stability=options.stability)
    u0 = problem.u_of(bp.x)
    D = problem.scale
    Gz = problem.jacobian(u0) * D
    U, _, vt = np.linalg.svd(Gz)
    null = vt[-2:].T  # two smallest right singular vectors span the null space at a simple BP
    c = null.T @ bp.tangent
    phi1 = bp.tangent / np.linalg.norm(bp.tangent)
    phi2 = null @ np.array([-c[1], c[0]])
    phi2 /= np.linalg.norm(phi2)
    w = U[:, -1]
    x = problem.full(u0)

    def second(a: np.ndarray, b: np.ndarray) -> float:  # w^T G_zz[a, b] in scaled variables
        va = np.zeros(len(x))
        va[problem.idx] = D * a
        return float(w @ (system.jacobian_derivative(x, va)[:, problem.idx] * D) @ b)

    c12, c22 = second(phi1, phi2), second(phi2, phi2)
    if abs(c12) + abs(c22) == 0:
        raise InputError("bp", "degenerate branch point (second derivatives vanish); the new direction is unknown")
    t_new = c22 * phi1 - 2 * c12 * phi2
    t_new /= np.linalg.norm(t_new)
    evs = _equilibrium_events(system, options, events, moving=(*unknowns, vary))
    branch = _run(problem, system, u0, options, evs, direction, vary, unknowns, tangent0=t_new)
    i0 = int(np.argmin(np.abs(branch.s)))
    if not branch.labels[i0]:
        labels = list(branch.labels)
        labels[i0] = "BP"
        bp = SpecialPoint("BP", i0, branch.values[i0].copy(), system.names, t_new, unknowns=tuple(unknowns), vary=vary,
                          extra={"switched": True})
        branch = branch.replace(labels=labels, special_points=[*branch.special_points, bp])  # sorted by the Branch
    return branch
