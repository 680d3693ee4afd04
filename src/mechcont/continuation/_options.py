"""Options of the pseudo-arclength continuation, validated on construction.

:class:`ContinuationOptions` is what a user chooses (steps, bounds, what to detect);
:class:`EngineSettings`, one of its fields, the engine's internals (corrector tolerances and the
step-size control's factors), which a user rarely needs to touch: apart so that the options say
what a run is and the settings how the engine gets there.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from ..errors import InputError
from ._linalg import DenseLU, LinearSolver

__all__ = ["ContinuationOptions", "EngineSettings"]


def _positive(name: str, value: object) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise InputError(name, f"must be a positive number, got {value!r}")


@dataclass(frozen=True)
class EngineSettings:
    """The corrector's tolerances and the step-size control's factors (AUTO's vocabulary).

    Parameters
    ----------
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
    """

    newton_tol: float = 1e-10
    residual_tol: float = 1e-10
    max_newton: int = 8
    max_contraction: float = 0.3
    max_angle: float = 0.35
    grow: float = 1.5
    shrink: float = 0.5

    def __post_init__(self) -> None:
        for name in ("newton_tol", "residual_tol", "max_angle"):
            _positive(name, getattr(self, name))
        if not (isinstance(self.max_newton, int) and self.max_newton >= 1):
            raise InputError("max_newton", f"must be a positive integer, got {self.max_newton!r}")
        if not 0 < self.max_contraction < 1:
            raise InputError("max_contraction", f"must lie in (0, 1), got {self.max_contraction}")
        if not (self.grow >= 1 and 0 < self.shrink < 1):
            raise InputError("grow", "grow must be >= 1 and shrink in (0, 1)")


@dataclass(frozen=True)
class ContinuationOptions:
    """Steps, bounds and detection switches of a continuation run (AUTO's vocabulary).

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
    engine:
        The engine's internals (:class:`EngineSettings`: tolerances, step-size factors).
    """

    ds: float = 0.02
    dsmin: float = 1e-9
    dsmax: float = 0.1
    max_steps: int = 2000
    bounds: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    detect_folds: bool = True
    detect_branch_points: bool = True
    stability: bool = True
    scales: Mapping[str, float] = field(default_factory=dict)
    linear_solver: LinearSolver = field(default_factory=DenseLU)
    engine: EngineSettings = field(default_factory=EngineSettings)

    def __post_init__(self) -> None:
        for name in ("ds", "dsmin", "dsmax"):
            _positive(name, getattr(self, name))
        if self.dsmin > self.dsmax:
            raise InputError("dsmin", f"must not exceed dsmax ({self.dsmin} > {self.dsmax})")
        if not self.dsmin <= abs(self.ds) <= self.dsmax:
            raise InputError("ds", f"must lie between dsmin={self.dsmin} and dsmax={self.dsmax}, got {self.ds}")
        if not (isinstance(self.max_steps, int) and self.max_steps >= 1):
            raise InputError("max_steps", f"must be a positive integer, got {self.max_steps!r}")
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
            _positive(f"scales[{name}]", v)
        if not isinstance(self.linear_solver, LinearSolver):
            raise InputError("linear_solver", f"must have a solve(A, b) method, got {self.linear_solver!r}")
        if not isinstance(self.engine, EngineSettings):
            raise InputError("engine", f"must be EngineSettings(...), got {self.engine!r}")
