"""Options of the pseudo-arclength continuation, validated on construction."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from ..errors import InputError
from ._linalg import DenseLU, LinearSolver

__all__ = ["ContinuationOptions"]


@dataclass(frozen=True)
class ContinuationOptions:
    """Step control, tolerances and detection switches (AUTO's vocabulary).

    All step sizes are in the *scaled* arclength: every unknown is divided by its
    typical magnitude (``Variable.scale``, or ``scales`` here) before lengths and angles
    are measured, so newtons and radians weigh alike.

    Parameters
    ----------
    ds:
        Initial step (scaled arclength).
    dsmin, dsmax:
        Smallest and largest step. Falling below ``dsmin`` ends the branch with status
        ``"step size underflow"``.
    max_steps:
        Maximum number of accepted steps in each direction.
    bounds:
        ``{name: (low, high)}``: the branch ends (``EP``, located exactly) where a named
        variable leaves its interval.
    newton_tol:
        Newton converged when the scaled correction's max-norm, or the distance to the
        solution that the last two corrections' contraction bounds, is below this ...
    residual_tol:
        ... and each residual is below this (equation units), or at its floating-point
        floor where the row's terms are too large for that (see ``residual_met``).
    max_newton:
        Corrector iterations before the step is rejected and halved.
    max_contraction:
        A corrector whose step does not shrink by at least this factor per iteration is
        rejected (it is converging slowly, possibly towards another branch).
    max_angle:
        Largest angle (rad) between successive tangents; a larger turn rejects the step.
    grow, shrink:
        Step growth after an easy step, reduction after a rejected one.
    detect_folds, detect_branch_points:
        Locate ``LP`` (sign change of the continuation parameter's tangent component) and
        ``BP`` (sign change of det [G_u; tangent]).
    stability:
        Evaluate physical stability at every point (needs the model's mechanics).
    scales:
        ``{name: typical magnitude}`` overriding the model's scales.
    linear_solver:
        Solver of the bordered systems (:class:`~mechcont.continuation.DenseLU` by default;
        :class:`~mechcont.continuation.MinimumNorm` tolerates dependent rows).
    """

    ds: float = 0.02
    dsmin: float = 1e-9
    dsmax: float = 0.1
    max_steps: int = 2000
    bounds: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    newton_tol: float = 1e-10
    residual_tol: float = 1e-10
    max_newton: int = 8
    max_contraction: float = 0.3
    max_angle: float = 0.35
    grow: float = 1.5
    shrink: float = 0.5
    detect_folds: bool = True
    detect_branch_points: bool = True
    stability: bool = True
    scales: Mapping[str, float] = field(default_factory=dict)
    linear_solver: LinearSolver = field(default_factory=DenseLU)

    def __post_init__(self) -> None:
        def positive(name: str, value: object) -> None:
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(name, f"must be a positive number, got {value!r}")

        for name in ("ds", "dsmin", "dsmax", "newton_tol", "residual_tol", "max_angle"):
            positive(name, getattr(self, name))
        if self.dsmin > self.dsmax:
            raise InputError("dsmin", f"must not exceed dsmax ({self.dsmin} > {self.dsmax})")
        if not self.dsmin <= abs(self.ds) <= self.dsmax:
            raise InputError("ds", f"must lie between dsmin={self.dsmin} and dsmax={self.dsmax}, got {self.ds}")
        for name in ("max_steps", "max_newton"):
            v = getattr(self, name)
            if not (isinstance(v, int) and v >= 1):
                raise InputError(name, f"must be a positive integer, got {v!r}")
        if not 0 < self.max_contraction < 1:
            raise InputError("max_contraction", f"must lie in (0, 1), got {self.max_contraction}")
        if not (self.grow >= 1 and 0 < self.shrink < 1):
            raise InputError("grow", "grow must be >= 1 and shrink in (0, 1)")
        for name, b in self.bounds.items():
            try:
                lo, hi = (float(b[0]), float(b[1]))
            except (TypeError, ValueError, IndexError):
                raise InputError(name, f"bounds must be a pair (low, high), got {b!r}") from None
            if not (math.isfinite(lo) or math.isfinite(hi)) or math.isnan(lo) or math.isnan(hi):
                raise InputError(name, f"bounds must be numbers with at least one finite, got {b!r}")
            if not lo < hi:
                raise InputError(name, f"empty or inverted bounds {lo}:{hi}; need low < high")
        for name, v in self.scales.items():
            positive(f"scales[{name}]", v)
        if not isinstance(self.linear_solver, LinearSolver):
            raise InputError("linear_solver", f"must have a solve(A, b) method, got {self.linear_solver!r}")
