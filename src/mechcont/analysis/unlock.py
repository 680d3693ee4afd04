"""The unlock folds: from a downlocked point, release the condition and continue in the force.

At the downlocked point the lock condition is held and the force ``F`` solved for. Released
(the held states free again, ``F`` the continuation parameter), the same equilibrium lies on
the branch of the mechanism under the force alone. Along it the locked state is the segment
through the downlocked point between the nearest folds (``LP``) on either side: beyond a fold
the lock cannot carry the force and the mechanism snaps. Those folds are the *unlock loads*:
``below`` is reached by decreasing ``F``, ``above`` by increasing it. Following the paper
(positive ``F`` acts in the unlock direction), :attr:`UnlockFolds.unlock_force` is ``above``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TypeVar

import numpy as np

from ..continuation import Branch, ContinuationOptions, EngineSettings, FoldEvent, SpecialPoint, continuation
from ..equations import Model
from ..errors import ConvergenceError, InputError
from ._downlock_point import DownlockResult
from ._runs import early_stops

#: A branch, or a downlock result holding one (the functions that add columns give back the same kind).
B = TypeVar("B", Branch, "DownlockResult")

__all__ = ["UnlockFolds", "unlock_folds", "unlock_force_along", "with_unlock_columns"]


@dataclass(frozen=True)
class UnlockFolds:
    """The folds that bound the locked state through a downlocked point.

    Attributes
    ----------
    force:
        Name of the force (N) continued.
    downlock_force:
        Its value at the downlocked point (N).
    stable:
        Whether the downlocked point itself is physically stable (a lock); None if unknown.
    below, above:
        The bounding fold reached by decreasing / increasing the force (a located ``LP``),
        or None when there is none before the run ended (see :attr:`notes`).
    branch:
        The release run: continuation in the force from the downlocked point, both ways,
        each direction stopped at its first fold.
    notes:
        Why a side has no fold (none within the release run's bounds), or that a fold is
        only approximate (one line each).
    warnings:
        Release runs that failed or stopped short of their bounds: where and why.
    """

    force: str
    downlock_force: float
    stable: bool | None
    below: SpecialPoint | None
    above: SpecialPoint | None
    branch: Branch | None
    notes: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)

    @property
    def unlock_force(self) -> float:
        """The force (N) at the fold reached by increasing it (the paper's unlock direction); nan if none."""
        return float(self.above[self.force]) if self.above is not None else float("nan")

    @property
    def locked_range(self) -> tuple[float, float]:
        """``(F_below, F_above)`` (N): the forces the locked state carries (-inf/inf where no fold)."""
        lo = float(self.below[self.force]) if self.below is not None else -np.inf
        hi = float(self.above[self.force]) if self.above is not None else np.inf
        return lo, hi

    def summary(self, condition: str = "", unit: str = "N") -> str:
        """One line: the downlocked point, its stability, and the bounding folds (the unlock force), the force
        in ``unit`` (its own: N, N m, m/s for an airspeed)."""
        f = self.force
        held = f"{condition}, " if condition else ""
        state = {True: "stable", False: "UNSTABLE: not a lock", None: "stability unknown"}[self.stable]
        side = []
        if self.above is not None:
            side.append(f"{f} = {self.unlock_force:.6g} {unit} increasing (the unlock force)")
        if self.below is not None:
            side.append(f"{f} = {self.locked_range[0]:.6g} {unit} decreasing")
        found = "; ".join(side) or "none within the release run (see below)"
        return (f"unlock folds of the downlocked point ({held}{f} = {self.downlock_force:.6g} {unit}, {state}): "
                f"{found}").replace(" ,", ",").replace(" )", ")")


#: The release run ends where the force has moved by this many of its scales (N), or a
#: released state by RELEASE_STATE_SPAN of its scales (e.g. 2 rad), if no fold comes first.
RELEASE_FORCE_SPAN, RELEASE_STATE_SPAN = 50.0, 2.0
#: First and largest step of the release run (scaled arclength). Away from its folds a release
#: run is nearly straight (the released states saturate as the force grows), so it may take long
#: steps: the step grows from RELEASE_DS by 1.5 per easy step, up to RELEASE_DSMAX, a tenth of
#: the force span. Near a fold the tangent turns and the step control shortens the steps
#: (RELEASE_MAX_ANGLE per step at most); the first fold each way is then located by the sign
#: change of the force's tangent component and polished to machine precision, so the folds
#: found do not depend on these steps.
RELEASE_DS, RELEASE_DSMAX, RELEASE_MAX_ANGLE = 0.1, 0.1 * RELEASE_FORCE_SPAN, 0.2


def _release_options(system: Model, x: np.ndarray, released: Iterable[str], force: str, max_steps: int,
                     bounds: Mapping[str, tuple[float, float]] | None, stability: bool = True) -> ContinuationOptions:
    """Steps and bounds of the release run (see :data:`RELEASE_FORCE_SPAN`); ``bounds`` take precedence."""
    b = dict(bounds or {})
    for n, span in ((force, RELEASE_FORCE_SPAN), *((n, RELEASE_STATE_SPAN) for n in released)):
        v, sc = x[system.index(n)], system.variable(n).scale
        b.setdefault(n, (v - span * sc, v + span * sc))
    return ContinuationOptions(ds=RELEASE_DS, dsmax=RELEASE_DSMAX, max_steps=max_steps, bounds=b, detect_folds=False,
                               stability=stability, engine=EngineSettings(max_angle=RELEASE_MAX_ANGLE))


def unlock_folds(system: Model, x: np.ndarray, force: str, released: Sequence[str] = (), *, max_steps: int = 400,
                 bounds: Mapping[str, tuple[float, float]] | None = None, stability: bool = True) -> UnlockFolds:
    """The folds bounding the locked state through the downlocked point ``x``.

    Parameters
    ----------
    system:
        The model.
    x:
        A downlocked equilibrium (full vector; e.g. from :func:`~mechcont.analysis.downlock_point`).
    force:
        The force (a parameter, N) that the downlock solved for; it is continued.
    released:
        The states the downlock held (they are free again); listed only to bound the run:
        each may move by two of its scales (e.g. 2 rad) before the run ends.
    max_steps:
        Most continuation steps each way.
    bounds:
        ``{name: (low, high)}`` bounds of the release run; by default the force may move by
        :data:`RELEASE_FORCE_SPAN` of its scales and each released state by
        :data:`RELEASE_STATE_SPAN` of its scales.
    stability:
        Whether the points of the release run (:attr:`UnlockFolds.branch`) get their physical
        stability. The folds, the notes and the warnings do not depend on it; a caller that
        keeps only those (:func:`unlock_force_along`) saves the stability analysis of every
        point. :attr:`UnlockFolds.stable` (the downlocked point's) is computed either way.

    Returns
    -------
    UnlockFolds
        Never raises for a run that fails: the failure is in :attr:`UnlockFolds.warnings`.
    """
    F0 = float(x[system.index(force)])
    stable = None
    if system.mechanics is not None:
        stable = bool(system.mechanics.stability(x).stable)
    fold = FoldEvent()
    fold.stop = True  # the first fold each way bounds the locked segment
    try:
        branch = continuation(system, x, force, events=[fold],
                              options=_release_options(system, x, released, force, max_steps, bounds, stability))
    except (ConvergenceError, InputError) as exc:
        return UnlockFolds(force, F0, stable, None, None, None, warnings=[f"release run in {force} failed: {exc}"])
    below = above = None
    for p in branch.special("LP"):
        if p[force] < F0 and (below is None or p[force] > below[force]):
            below = p
        elif p[force] > F0 and (above is None or p[force] < above[force]):
            above = p
    warnings = early_stops(branch, f"release run in {force}", show=(*released,))
    notes = []
    ends = branch[force][[0, -1]] if len(branch) else np.array([F0, F0])
    for side, fold_point, end in (("decreasing", below, ends.min()), ("increasing", above, ends.max())):
        if fold_point is None:
            unit = system.variable(force).unit
            notes.append(f"no fold {side} {force} from {F0:.6g} {unit} to {end:.6g} {unit} (where the release run "
                         "ended)".replace("  ", " "))
        elif not fold_point.located:
            notes.append(f"the fold {side} {force} is approximate: {fold_point.reason or 'not located'}")
    return UnlockFolds(force, F0, stable, below, above, branch, notes, warnings)


def unlock_force_along(system: Model, branch: Branch, force: str, released: Sequence[str] = (), *, max_steps: int = 400,
                       known: UnlockFolds | None = None) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """The unlock folds (N) at every point of a downlock ``branch``, each from its own release run.

    Every row of a downlock branch is a downlocked point; :func:`unlock_folds` is run from
    each (``released``: the held states). ``known``: the release run of one of its points (a
    :class:`~mechcont.analysis.downlock.DownlockResult`'s ``unlock``, its start's): that row reuses it.
    Returns ``(above, below, warnings)``: the force at the fold reached by increasing /
    decreasing it (nan where there is none), and one line per release run that stopped short
    of its bounds.
    """
    above, below = np.full(len(branch), np.nan), np.full(len(branch), np.nan)
    warnings: list[str] = []
    start = None
    if known is not None and known.branch is not None and len(known.branch):
        start = known.branch.values[int(np.argmin(np.abs(known.branch.s)))]  # the point it was released from
    for i, x in enumerate(branch.values):
        if known is not None and start is not None and np.array_equal(x, start):
            u = known  # the same run (its stability does not change its folds)
        else:
            # only the folds are kept: the release run's own stability is not needed
            u = unlock_folds(system, x, force, released, max_steps=max_steps, stability=False)
        lo, hi = u.locked_range
        above[i] = hi if np.isfinite(hi) else np.nan
        below[i] = lo if np.isfinite(lo) else np.nan
        warnings += [f"{branch.vary} = {x[system.index(branch.vary)]:.6g}: {w}" for w in u.warnings]
    return above, below, warnings


def with_unlock_columns(system: Model, result: B, force: str, released: Sequence[str] = ()) -> B:
    """A new ``result`` with the unlock folds (N) of every point as extra columns of its branch.

    ``result`` is a :class:`~mechcont.continuation.Branch` or a
    :class:`~mechcont.analysis.downlock.DownlockResult` (whose start's release run is reused and
    whose ``warnings`` gain the release runs'). ``unlock_<F>``: the fold reached by increasing the
    force (the paper's unlock direction); ``unlock_<F>_decreasing``: the one reached by decreasing
    it; a column only when some point has that fold (see :func:`unlock_force_along`).
    """
    if not isinstance(result, DownlockResult):
        above, below, _ = unlock_force_along(system, result, force, released)
        return result.with_columns(*_unlock_columns(force, above, below))
    more: list[str]
    above, below, more = unlock_force_along(system, result.branch, force, released, known=result.unlock)
    return replace(result, branch=result.branch.with_columns(*_unlock_columns(force, above, below)),
                   warnings=[*result.warnings, *(f"unlock folds along the branch: {w}" for w in more)])


def _unlock_columns(force: str, above: np.ndarray, below: np.ndarray) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """The unlock columns (those with some fold) and their units (N)."""
    cols = {name: col for name, col in ((f"unlock_{force}", above), (f"unlock_{force}_decreasing", below))
            if np.isfinite(col).any()}
    return cols, dict.fromkeys(cols, "N")
