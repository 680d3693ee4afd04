"""The critical airspeed of a freefall: a bracket of dynamic runs, and its quasi-static predictor.

:func:`critical_airspeed` bisects on :func:`~mechcont.dynamics.freefall.freefall` runs for the airspeed (any
parameter) where the outcome changes, and reports the bracket by its two ends, each a value actually run with
its outcome: the run nearest the change that locked and the nearest that did not. :func:`quasi_static_critical`
is the predictor beside it: the equilibria the gear could hang in between the retracted and the locked pose
(the stall branch, continued in the pose with the airspeed solved for) and the airspeed at its fold, the value
the dynamic critical airspeed tends to as the damping grows (a heavily damped gear creeps through the slowest
point). :meth:`CriticalAirspeed.compare` says whether the two differ by more than the bracket resolves.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..equations import Model
from ..errors import InputError
from ._freefall import MOVING, freefall
from ._poses import Lock

if TYPE_CHECKING:
    from ..continuation import ContinuationOptions

__all__ = ["CriticalAirspeed", "critical_airspeed", "bisection_runs", "QuasiStaticCritical", "quasi_static_critical"]


@dataclass(frozen=True)
class CriticalAirspeed:
    """The value of a parameter (an airspeed, m/s) where the freefall outcome changes, bracketed by runs.

    Attributes
    ----------
    name:
        The parameter varied.
    locked:
        The value nearest the change at which a run locked (units of ``name``).
    failed:
        The value nearest the change at which a run did not lock.
    runs:
        ``(value, outcome)`` of every run, in the order simulated (both ends among them).
    unsettled:
        Values whose runs stayed undecided (still creeping, or bouncing on a lock that would hold) even when
        run longer: the bisection stopped there, the bracket holds the critical value but is wider than asked.
    stopped:
        Why the bisection stopped short of its tolerance ("" when it reached it): an undecided run, or the
        floating-point resolution (no representable value between the two ends).

    The critical value lies between ``locked`` and ``failed``; neither end is a midpoint: both were run.
    A run near the critical value creeps through its slowest point for a time that grows without bound,
    so a finite ``until`` biases the change towards the locking side; :attr:`undecided` says when the
    failing end was still moving at the end of its run.
    """

    name: str
    locked: float
    failed: float
    runs: list[tuple[float, str]] = field(default_factory=list)
    unsettled: list[float] = field(default_factory=list)
    stopped: str = ""

    @property
    def locks_below(self) -> bool:
        """True when the values below the change lock (airloads that oppose the fall)."""
        return self.locked < self.failed

    @property
    def low(self) -> float:
        """The lower end of the bracket."""
        return min(self.locked, self.failed)

    @property
    def high(self) -> float:
        """The upper end of the bracket."""
        return max(self.locked, self.failed)

    @property
    def width(self) -> float:
        """The bracket's width ``|failed - locked|``: the resolution of the critical value."""
        return abs(self.failed - self.locked)

    def outcome(self, value: float) -> str:
        """The outcome of the run at ``value`` (one of :attr:`runs`); KeyError when none was run there."""
        for v, outcome in self.runs:
            if v == value:
                return outcome
        raise KeyError(value)

    @property
    def undecided(self) -> bool:
        """True when the failing end was *still moving* at ``until``: a longer simulation might lock it, so
        the critical value may lie beyond the bracket."""
        return self.outcome(self.failed) == MOVING or bool(self.unsettled)

    def contradicts(self, quasi_static: float) -> bool:
        """True when a run that did not lock lies on the side of ``quasi_static`` where the gear has no
        equilibrium to hang in on its way (below it when the values below lock): statics forbid that outcome,
        so the run was not run long enough (or its integration is wrong), and the bracket cannot be trusted."""
        margin = 1e-9 * abs(quasi_static)
        return self.failed < quasi_static - margin if self.locks_below else self.failed > quasi_static + margin

    def compare(self, quasi_static: float) -> tuple[float, bool]:
        """``(locked - quasi_static, significant)``: the dynamic minus the quasi-static critical value, from the
        end that locked, and whether it exceeds the bracket's width (a smaller difference is the bisection's
        resolution, not dynamics)."""
        difference = self.locked - quasi_static
        return difference, abs(difference) > self.width

    def describe(self, unit: str = "") -> list[str]:
        """Readable lines: the bracket by its two runs and their outcomes."""
        u = f" {unit}" if unit else ""
        # as many digits as tell the two ends apart (6 at least)
        n = max(6, 2 + math.ceil(math.log10(max(abs(self.low), abs(self.high), 1e-300) / max(self.width, 1e-300))))
        n = min(n, 17)
        which = "largest" if self.locks_below else "smallest"
        other = "smallest" if self.locks_below else "largest"
        lines = [f"critical {self.name} between {self.low:.{n}g} and {self.high:.{n}g}{u} (width {self.width:.3g}{u}, "
                 f"{len(self.runs)} runs): the {which} run that locked {self.name} = {self.locked:.{n}g}{u}, "
                 f"the {other} that did not {self.name} = {self.failed:.{n}g}{u} ({self.outcome(self.failed)})"]
        if self.stopped:
            lines.append(f"bisection stopped at width {self.width:.3g}{u}: {self.stopped}")
        return lines


def bisection_runs(low: float, high: float, tol: float) -> int:
    """How many runs :func:`critical_airspeed` makes on ``[low, high]`` to a bracket of width ``tol`` when every
    run is decided the first time: its two ends, then one per halving, ``ceil(log2((high - low) / tol))``."""
    return 2 + max(0, math.ceil(math.log2((high - low) / tol)))


def critical_airspeed(system: Model, start: Mapping[str, float], vary: str, low: float, high: float, *, tol: float,
                      lock: Lock, until: float, values: Mapping[str, float] | None = None, extend: float = 4.0,
                      progress: Callable[[], None] | None = None, **options: Any) -> CriticalAirspeed:
    """Bisect on freefall runs for the value of the parameter ``vary`` (an airspeed, m/s) in
    ``[low, high]`` where the outcome changes between locked and not locked.

    The two ends must differ (one locks, one does not); the bracket is halved until its width is
    at most ``tol`` (units of ``vary``), or no representable value lies between its ends. A run whose outcome
    is undecided at ``until`` (:attr:`~mechcont.dynamics.freefall.FreefallResult.decided`: creeping near a
    fold's ghost, bouncing on a lock that would hold) is run again for ``extend`` times as long; still
    undecided, the bisection stops there (:attr:`CriticalAirspeed.unsettled`) with the bracket it has, which
    holds the critical value, rather than guess. An end that stays undecided is an :class:`InputError`.
    ``options`` go to :func:`~mechcont.dynamics.freefall.freefall`; ``progress()`` is called after each value's
    run (a progress bar's count: :func:`bisection_runs` of them, and one per undecided end or value run longer).
    Returns the :class:`CriticalAirspeed` whose ends ``locked`` and ``failed`` are runs made.
    """
    model = system
    if vary not in model.names or model.variable(vary).kind != "parameter":
        raise InputError("critical", f"{vary} is not a parameter of {model.name}")
    if not (math.isfinite(low) and math.isfinite(high) and low < high):
        raise InputError("critical", f"needs LO < HI, finite, got {low:g}:{high:g}")
    if not (math.isfinite(tol) and tol > 0):
        raise InputError("tol", f"must be a positive number (units of {vary}), got {tol:g}")
    if not (math.isfinite(extend) and extend >= 1):
        raise InputError("extend", f"must be a finite factor >= 1, got {extend:g}")
    base = dict(values or {})
    runs: list[tuple[float, str]] = []

    def locks(v: float) -> bool | None:
        """True/False: locked or not; None: undecided even when run ``extend`` times longer."""
        # only the outcome is read: no energy audit (options may still ask for one)
        for t_end in (until, until * extend) if extend > 1 else (until,):
            try:
                r = freefall(model, start, lock=lock, until=t_end, values={**base, vary: v},
                             **{"audit": False, **options})
            except InputError as exc:
                if exc.field != "values":
                    raise
                raise InputError("critical", f"{vary} = {v:g}: {str(exc).split(': ', 1)[-1]}") from None
            if r.decided:
                break
        runs.append((v, r.outcome))
        if progress is not None:
            progress()
        return r.locked if r.decided else None

    lo_locks, hi_locks = locks(low), locks(high)
    for v, verdict in ((low, lo_locks), (high, hi_locks)):
        if verdict is None:
            raise InputError("critical", f"the run at {vary} = {v:g} is undecided after {until * extend:g} s "
                                         f"({dict(runs)[v]}: creeping, or bouncing on a lock that would hold): "
                                         "give a longer --until or move that end")
    if lo_locks == hi_locks:
        what = "lock" if lo_locks else "fail to lock"
        raise InputError("critical", f"both ends {vary} = {low:g} and {high:g} {what}: widen the bracket "
                                     f"(outcomes {runs[0][1]}, {runs[1][1]})")
    a, b = low, high
    unsettled: list[float] = []
    stopped = ""
    while b - a > tol:
        mid = 0.5 * a + 0.5 * b  # no overflow at the ends of the floats
        if not a < mid < b:
            stopped = f"no floating-point value between {a!r} and {b!r} (the resolution of {vary} there)"
            break
        verdict = locks(mid)
        if verdict is None:
            unsettled.append(mid)
            stopped = (f"the run at {vary} = {mid:.9g} is still undecided after {until * extend:g} s (creeping "
                       "near the fold's ghost, or bouncing on a lock that would hold); a longer --until may narrow it")
            break
        if verdict == lo_locks:
            a = mid
        else:
            b = mid
    return CriticalAirspeed(vary, a if lo_locks else b, b if lo_locks else a, runs, unsettled, stopped)


@dataclass(frozen=True)
class QuasiStaticCritical:
    """The quasi-static predictor of the critical airspeed.

    ``value`` is the lowest (``side = "min"``) or highest airspeed at which the gear has an
    equilibrium between the retracted and the locked pose (it could hang there); ``fold`` is True
    when that extreme is a fold of the stall branch (inside the travel), False when it lies at an
    end of the travel. ``pose`` is the travel variable there; ``branch`` the stall branch
    (continued in the travel variable with ``vary`` solved for)."""

    name: str
    value: float
    pose: float
    fold: bool
    branch: object


def quasi_static_critical(system: Model, travel: str, start_value: float, lock_value: float, vary: str, *,
                          side: str = "min", values: Mapping[str, float] | None = None, samples: int = 17,
                          options: ContinuationOptions | None = None) -> QuasiStaticCritical:
    """The airspeed ``vary`` at the extreme of the stall branch over the travel.

    The equilibria along the travel ``travel`` (a coordinate or condition, from ``start_value``
    to ``lock_value``) are continued with ``travel`` prescribed and ``vary`` solved for; the
    airspeed where the gear could first hang is their minimum (``side = "min"``: airloads that
    oppose the fall, so the gear locks below it) or maximum (``"max"``). An interior extreme is a
    fold of the branch in ``vary``, polished with :func:`~mechcont.continuation.locate_fold`.
    Stops are free (their reactions at 0): the intermediate equilibria are off the stops. The branch
    starts from the extreme of ``samples`` equilibria spread over the travel (only positive airspeeds:
    a negative one reverses the airloads).
    """
    from ..continuation import ContinuationOptions, continuation, find_equilibrium, locate_fold
    if side not in ("min", "max"):
        raise InputError("side", f"must be 'min' or 'max', got {side!r}")
    model = system
    if values:
        model = model.with_values(dict(values))
    for n in (travel, vary):
        if n not in model.names:
            raise InputError(n, f"is not a variable of {model.name}")
    lo, hi = sorted((float(start_value), float(lock_value)))
    iv = model.index(vary)
    found = []
    for p in np.linspace(lo, hi, samples):  # equilibria across the travel, the airspeed solved for
        try:
            x = find_equilibrium(model, hold={travel: float(p)}, free=[vary])
        except InputError:
            continue
        if math.isfinite(x[iv]) and x[iv] > 0:  # an airspeed; a negative one would reverse the airloads
            found.append(x)
    if not found:
        raise InputError("quasi-static", f"no equilibrium with a positive {vary} was found along {travel} in "
                                         f"[{lo:g}, {hi:g}]: the gear cannot hang anywhere in its travel")
    x = (min if side == "min" else max)(found, key=lambda y: y[iv])
    # continued from the sample nearest the extreme; bounded in vary so that the branch does not run off
    # through a pose where the airload has no lever (there vary goes to infinity)
    top = 4.0 * float(x[iv]) if side == "min" else math.inf
    opts = options or ContinuationOptions(bounds={travel: (lo, hi), vary: (0.0, top)}, max_steps=2000)
    branch = continuation(model, x, travel, free=[vary], options=opts)
    column, poses = branch[vary], branch[travel]
    k = int(np.argmin(column) if side == "min" else np.argmax(column))
    value, pose, fold = float(column[k]), float(poses[k]), False
    width = hi - lo
    if min(pose - lo, hi - pose) > 1e-6 * width:  # inside the travel: a fold in vary, polished
        fx, _, _ = locate_fold(model, branch.values[k], vary)
        if lo <= fx[model.index(travel)] <= hi:
            value, pose, fold = float(fx[iv]), float(fx[model.index(travel)]), True
    return QuasiStaticCritical(vary, value, pose, fold, branch)
