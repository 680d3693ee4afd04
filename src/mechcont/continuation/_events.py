"""Events: test functions whose sign change along a branch marks a special point.

Every event is a small object with a ``label``, a ``stop`` flag and ``value(state)``;
built-in folds (``LP``), branch points (``BP``) and bounds (``EP``) use the same
interface as user events such as "the lock links are aligned" (:class:`ValueEvent`).
The engine evaluates each event at every accepted point and, on a sign change, locates
the zero along the step (Brent's method on the step length, correcting every trial
point back onto the branch).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Event", "FoldEvent", "BranchPointEvent", "BoundEvent", "LimitEvent", "ValueEvent", "PointState"]


@dataclass
class PointState:
    """A converged point seen by events.

    ``z``: scaled unknowns (u / scale); ``u``: unknowns in SI units; ``tangent``: unit
    tangent in scaled coordinates; ``jac``: the scaled Jacobian dG/dz (n x n+1);
    ``x``: the full variable vector.
    """

    z: np.ndarray
    u: np.ndarray
    tangent: np.ndarray
    jac: np.ndarray
    x: np.ndarray


class Event:
    """Base class: ``value(problem, state)`` changes sign at the event."""

    label = "EV"
    stop = False
    #: True when the test function is continuous along a branch, so a sign change without
    #: a zero between the two points reveals a jump to another branch.
    continuous = False

    def value(self, problem, state: PointState) -> float:  # pragma: no cover - interface
        raise NotImplementedError

    def refine(self, problem, state: PointState):
        """Optionally improve a located point; returns ``(u, info)`` or ``None``."""
        return None

    def point_info(self) -> dict:
        """Extra information recorded with the special point (e.g. why a branch ended)."""
        return {}


class FoldEvent(Event):
    """Limit point (fold, ``LP``): the continuation parameter's tangent component vanishes."""

    label = "LP"

    def value(self, problem, state):
        return float(state.tangent[problem.param_index])

    def refine(self, problem, state):
        refine = getattr(problem, "refine_fold", None)
        return refine(state) if refine is not None else None


class BranchPointEvent(Event):
    """Branch point (``BP``): det [dG/dz; tangent^T] changes sign (it does not at folds)."""

    label = "BP"
    continuous = True

    def value(self, problem, state):
        A = np.vstack([state.jac, state.tangent])
        sign, logdet = np.linalg.slogdet(A)
        # a continuous, scale-tamed version of the determinant
        return float(sign * np.exp(logdet / len(A))) if np.isfinite(logdet) else 0.0


class BoundEvent(Event):
    """End point (``EP``): the full variable ``index`` crosses ``bound``; stops the branch.

    ``side`` is +1 for a lower bound, -1 for an upper bound, so the value is positive
    inside the allowed interval.
    """

    label = "EP"
    stop = True

    def __init__(self, name: str, index: int, bound: float, side: int = 1):
        self.name, self.index, self.bound, self.side = name, index, bound, side

    def value(self, problem, state):
        return float(self.side * (state.x[self.index] - self.bound))


class LimitEvent(Event):
    """End point (``EP``) at the edge of a physical range: ``system.limits[index]`` reaches 0.

    A length, mass or stiffness that the continuation parameter (or a freed parameter)
    drives to zero ends the branch there, located exactly, instead of continuing into
    values no mechanism can have.
    """

    label = "EP"
    stop = True

    def __init__(self, system, index: int):
        self.system, self.index = system, index
        self.limit = system.limits[index]
        self.name = self.limit.name

    def value(self, problem, state):
        return float(self.system.limit_values(state.x)[self.index])

    def point_info(self) -> dict:
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

    def __init__(self, name: str, target: float, label: str = "UZ", stop: bool = False):
        self.name, self.target, self.label, self.stop = name, float(target), label, stop
        self._index = None

    def value(self, problem, state):
        if self._index is None:
            self._index = problem.system.index(self.name)
        return float(state.x[self._index] - self.target)
