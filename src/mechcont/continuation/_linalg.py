"""Linear solvers of the continuation engine: one small interface, chosen in the options.

The corrector, the tangent and the bound solves all solve a square bordered system
``[G_z; b^T] dz = rhs``. Dense LU suits the planar mechanisms of today; a minimum-norm
least-squares solve keeps going where the Jacobian has a dependent row (the redundant
constraints of an over-constrained spatial gear), at a higher cost per step.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from .. import _dense

__all__ = ["LinearSolver", "DenseLU", "MinimumNorm"]


@runtime_checkable
class LinearSolver(Protocol):
    """``solve(A, b)`` -> ``x`` with ``A x = b``, or ``None`` when ``A`` is singular."""

    def solve(self, A: np.ndarray, b: np.ndarray) -> np.ndarray | None: ...


class DenseLU:
    """LU with partial pivoting (LAPACK ``dgesv``): exact, fast for a few hundred unknowns."""

    def solve(self, A: np.ndarray, b: np.ndarray) -> np.ndarray | None:
        """Solve ``A x = b``; ``None`` when an exact zero pivot shows ``A`` singular (or the result is
        not finite: a non-finite ``A`` or ``b``)."""
        return _dense.solve(A, b)

    def __repr__(self) -> str:
        return "DenseLU()"

    def __eq__(self, other: object) -> bool:
        return type(other) is DenseLU

    def __hash__(self) -> int:
        return hash(DenseLU)


class MinimumNorm:
    """Least-squares solution of minimum norm (SVD, ``numpy.linalg.lstsq``).

    Singular values below ``rcond`` times the largest are treated as zero, so a system
    with dependent rows (redundant constraints) still yields the minimum-norm correction.
    Returns ``None`` only when the result is not finite.
    """

    def __init__(self, rcond: float = 1e-12):
        self.rcond = float(rcond)

    def solve(self, A: np.ndarray, b: np.ndarray) -> np.ndarray | None:
        """Minimum-norm least-squares ``x`` of ``A x = b``."""
        x = np.linalg.lstsq(A, b, rcond=self.rcond)[0]
        return x if np.all(np.isfinite(x)) else None

    def __repr__(self) -> str:
        return f"MinimumNorm(rcond={self.rcond:g})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, MinimumNorm) and other.rcond == self.rcond

    def __hash__(self) -> int:
        return hash((MinimumNorm, self.rcond))
