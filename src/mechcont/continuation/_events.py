"""Events: test functions whose sign change along a branch marks a special point.

Every event is a small object with a ``label``, a ``stop`` flag and ``value(state)``;
built-in folds (``LP``), branch points (``BP``) and bounds (``EP``) use the same
interface as user events such as "the lock links are aligned" (:class:`ValueEvent`).
The engine evaluates each event at every accepted point and, on a sign change, asks the
event to locate its zero along the step (:meth:`Event.locate`: by default Brent's method
on the step length, correcting every trial point back onto the branch; bounds solve for
the bound directly; folds take a secant guess that their polish then makes exact).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _dense
from .._roots import brentq
from ._problem import ContinuationProblem

if TYPE_CHECKING:
    from ..equations import EquationSystem
    from ._corrector import PseudoArclength

__all__ = ["Event", "FoldEvent", "BranchPointEvent", "BoundEvent", "LimitEvent", "ValueEvent", "PointState"]


@dataclass
class PointState:
    """A converged point seen by events.

    ``z``: scaled unknowns (u / scale); ``u``: unknowns in SI units; ``tangent``: unit
    tangent in scaled coordinates; ``jac``: the scaled Jacobian dG/dz (n x n+1);
    ``x``: the full variable vector; ``bp_test``: the branch-point test function when the
    stepper already knows it (the compiled corrector computes it from its factors), else None.
    """

    z: np.ndarray
    u: np.ndarray
    tangent: np.ndarray
    jac: np.ndarray
    x: np.ndarray
    bp_test: float | None = None


#: What :meth:`Event.locate` returns: the step position ``sigma`` (scaled arclength from the step's start), the
#: point there (None when not even the secant estimate converges) and its info (``{"status": ...}``)
Hit = tuple[float, PointState | None, dict[str, Any]]


class Event:
    """Base class: ``value(problem, state)`` changes sign at the event."""

    label = "EV"
    #: the variable or quantity the event watches (bounds, limits, value events), if any
    name = ""
    stop = False
    #: True when the test function is continuous along a branch, so a sign change without
    #: a zero between the two points reveals a jump to another branch.
    continuous = False
    #: Typical size of :meth:`value` (its unit): a value within rounding of it is zero (a start on a bound)
    scale = 1.0

    def value(self, problem: ContinuationProblem, state: PointState) -> float:  # pragma: no cover - interface
        raise NotImplementedError

    def refine(self, problem: ContinuationProblem, state: PointState) -> tuple[np.ndarray, dict[str, Any]] | None:
        """Optionally improve a located point; returns ``(u, info)`` or ``None``."""
        return None

    def point_info(self) -> dict[str, Any]:
        """Extra information recorded with the special point (e.g. why a branch ended)."""
        return {}

    def locate(self, stepper: PseudoArclength, problem: ContinuationProblem, cur: PointState, ds: float, v0: float,
               v1: float) -> Hit:
        """The zero of :meth:`value` between ``cur`` (sigma = 0) and the accepted step (sigma = ``ds``).

        ``stepper`` is the :class:`~mechcont.continuation._corrector.PseudoArclength` that took
        the step; ``v0``/``v1`` are the values at both ends (of opposite signs). Returns
        ``(sigma, state, info)`` with ``info["status"]`` ``"located"`` (Brent's method on
        sigma, each trial point corrected onto the branch) or ``"approximate"`` (the secant
        estimate, when root finding fails); ``state`` is None when not even that converges.

        Each trial point's corrector starts from the nearest point already on the branch
        (``cur`` or an earlier trial), moved along the tangent onto the trial's hyperplane:
        as Brent closes in, one Newton correction is enough.
        """
        cache: dict[float, PointState] = {0.0: cur}

        def f(sigma: float) -> float:
            near = min(cache, key=lambda s: abs(s - sigma))
            st = stepper.point_at(cur.z, cur.tangent, sigma, cache[near].z + (sigma - near) * cur.tangent)
            cache[sigma] = st
            return self.value(problem, st)

        try:
            sigma = brentq(f, 0.0, ds, xtol=1e-14 * max(1.0, ds), rtol=8.9e-16, maxiter=100, fa=v0, fb=v1)
            st = cache.get(sigma) if sigma != 0.0 else None
            st = st or stepper.point_at(cur.z, cur.tangent, sigma)
        except (RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
            return _secant(stepper, cur, ds, v0, v1, f"not located: {exc}")
        return sigma, st, {"status": "located"}


def _secant(stepper: PseudoArclength, cur: PointState, ds: float, v0: float, v1: float, reason: str | None = None) -> Hit:
    """The point at the secant estimate of a zero, marked approximate (``None`` if it fails)."""
    sigma = ds * v0 / (v0 - v1)
    info = {"status": "approximate", **({"reason": reason} if reason else {})}
    try:
        return sigma, stepper.point_at(cur.z, cur.tangent, sigma), info
    except (RuntimeError, np.linalg.LinAlgError):
        return ds, None, info


class FoldEvent(Event):
    """Limit point (fold, ``LP``): the continuation parameter's tangent component vanishes."""

    label = "LP"

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        return float(state.tangent[problem.param_index])

    def refine(self, problem: ContinuationProblem, state: PointState) -> tuple[np.ndarray, dict[str, Any]] | None:
        return problem.refine_fold(state)

    def locate(self, stepper: PseudoArclength, problem: ContinuationProblem, cur: PointState, ds: float, v0: float,
               v1: float) -> Hit:
        """A secant guess: close enough for the fold polish (:meth:`refine`) that follows."""
        hit = _secant(stepper, cur, ds, v0, v1)
        return hit if hit[1] is not None else super().locate(stepper, problem, cur, ds, v0, v1)


def branch_point_test(sign: float, logdet: float, size: int) -> float:
    """The branch-point test function from ``det [G_z; tangent^T]`` given as its sign and log of its
    magnitude, for a matrix of ``size`` rows: ``sign |det|^(1/size)``, a continuous, scale-tamed
    version of the determinant (0 for an exactly singular matrix)."""
    return float(sign * math.exp(logdet / size)) if math.isfinite(logdet) else 0.0


class BranchPointEvent(Event):
    """Branch point (``BP``): det [dG/dz; tangent^T] changes sign (it does not at folds)."""

    label = "BP"
    continuous = True

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        if state.bp_test is not None:
            return state.bp_test
        A = np.empty((len(state.tangent), len(state.tangent)))
        A[:-1] = state.jac
        A[-1] = state.tangent
        sign, logdet = _dense.slogdet(A)
        return branch_point_test(sign, logdet, len(A))


class BoundEvent(Event):
    """End point (``EP``): the full variable ``index`` crosses ``bound``; stops the branch.

    ``side`` is +1 for a lower bound, -1 for an upper bound, so the value is positive
    inside the allowed interval.
    """

    label = "EP"
    stop = True

    def __init__(self, name: str, index: int, bound: float, side: int = 1) -> None:
        self.name, self.index, self.bound, self.side = name, index, bound, side
        self.scale = max(1.0, abs(bound))

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        return float(self.side * (state.x[self.index] - self.bound))

    def point_info(self) -> dict[str, Any]:
        return {"bound_of": self.name, "bound": self.bound}

    def locate(self, stepper: PseudoArclength, problem: ContinuationProblem, cur: PointState, ds: float, v0: float,
               v1: float) -> Hit:
        """Newton on ``[G; x_k - bound] = 0`` when the bounded name is an unknown, else Brent."""
        st = solve_at_value(stepper, problem, cur, ds, v0, v1, self.index, self.bound)
        if st is not None:
            return float(cur.tangent @ (st.z - cur.z)), st, {"status": "located"}
        return super().locate(stepper, problem, cur, ds, v0, v1)


def solve_at_value(stepper: PseudoArclength, problem: ContinuationProblem, cur: PointState, ds: float, v0: float,
                   v1: float, index: int, target: float) -> PointState | None:
    """The branch point where the full variable ``index`` equals ``target`` (SI), by Newton on
    ``[G; x_k - target] = 0`` from the secant guess within the step, or None when that variable is not an
    unknown of ``problem`` or Newton fails."""
    idx = problem.idx
    if idx is None or index not in idx:
        return None
    from ._newton import residual_met

    k = int(np.flatnonzero(idx == index)[0])
    z = cur.z + (ds * v0 / (v0 - v1)) * cur.tangent
    target = target / stepper.D[k]
    A = np.zeros((stepper.n + 1, stepper.n + 1))
    A[-1, k] = 1.0
    b = np.empty(stepper.n + 1)
    options = stepper.options
    for _ in range(options.engine.max_newton + 2):
        r, jac = stepper.evaluate(z)
        if not math.isfinite(r.sum()):
            return None
        b[:-1] = -r
        b[-1] = target - z[k]
        if residual_met(r, jac, z, options.engine.residual_tol) and abs(b[-1]) < 1e-15 * max(1.0, abs(target)):
            try:
                return stepper.state(z, stepper.tangent(z, cur.tangent, jac), jac)
            except np.linalg.LinAlgError:
                return None
        A[:-1] = jac
        dz = options.linear_solver.solve(A, b)
        if dz is None:
            return None
        z = z + dz
        if np.abs(dz).max() < options.engine.newton_tol:
            z[k] = target
    return None


class LimitEvent(Event):
    """End point (``EP``) at the edge of a physical range: ``system.limits[index]`` reaches 0.

    A length, mass or stiffness that the continuation parameter (or a freed parameter)
    drives to zero ends the branch there, located exactly, instead of continuing into
    values no mechanism can have.
    """

    label = "EP"
    stop = True

    def __init__(self, system: EquationSystem, index: int) -> None:
        self.system, self.index = system, index
        self.limit = system.limits[index]
        self.name = self.limit.name

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        return float(self.system.limit_values(state.x)[self.index])

    def point_info(self) -> dict[str, Any]:
        what = self.limit.description or self.name
        return {"limit": self.name, "reason": f"physical limit: {self.name} ({what}) reaches 0"}


class ValueEvent(Event):
    """A user event: variable ``name`` passes through ``target`` (e.g. theta4 = 0).

    Parameters
    ----------
    name:
        Variable name.
    target:
        Value (SI units, radians) at which the event fires.
    label:
        Label written in the branch (default ``"UZ"`` as in AUTO).
    stop:
        End the branch there.
    """

    def __init__(self, name: str, target: float, label: str = "UZ", stop: bool = False) -> None:
        self.name, self.target, self.label, self.stop = name, float(target), label, stop
        self._index: int | None = None

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        if self._index is None:
            self._index = problem.system.index(self.name)
        return float(state.x[self._index] - self.target)

    def locate(self, stepper: PseudoArclength, problem: ContinuationProblem, cur: PointState, ds: float, v0: float,
               v1: float) -> Hit:
        """Exactly at ``target`` when ``name`` is an unknown of the branch (Newton on ``[G; x - target]``),
        else Brent's method on the step."""
        if self._index is None:
            self._index = problem.system.index(self.name)
        st = solve_at_value(stepper, problem, cur, ds, v0, v1, self._index, self.target)
        if st is not None:
            return float(cur.tangent @ (st.z - cur.z)), st, {"status": "located"}
        return super().locate(stepper, problem, cur, ds, v0, v1)
