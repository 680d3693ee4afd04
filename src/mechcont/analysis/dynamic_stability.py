"""Dynamic stability of equilibria: the eigenvalues of the linearised dynamics at each point of a branch.

An equilibrium is dynamically stable when every eigenvalue ``lambda`` of its linearised dynamics
(:meth:`~mechcont.equations.Dynamics.linearise`: for a mechanism the equations of motion on the
constraint manifold with mass, damping, the exact tangent stiffness and any first-order element
states; for an ODE model its Jacobian) has a negative real part. Static stability (the tangent
stiffness alone) misses what damping and non-conservative loads do: a follower load flutters where
the stiffness is still positive definite, and small damping can lower that flutter load.

Per point: ``n_unstable_dynamic`` (eigenvalues with ``Re lambda > rtol * max |lambda|``; a zero
eigenvalue, a neutral direction, counts as stable), ``leading_real`` (1/s, the largest real part)
and ``leading_frequency`` (rad/s, ``|Im|`` of that eigenvalue: 0 for a real one, a divergence; >0 an
oscillation, flutter when unstable; among eigenvalues whose real parts tie within the tolerance, as an
undamped mechanism's all do, the lowest frequency). Cost: one linearisation (for a mechanism: an SVD of the
constraint Jacobian for the allowed motions, one for the reactions, the compiled statics) and one
dense eigenvalue problem of size ``2 dof + states`` per point.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..equations import NEUTRAL_RTOL, Model, dynamics_of

if TYPE_CHECKING:
    from ..continuation import Branch

__all__ = ["DynamicStability", "dynamic_stability", "with_dynamic_stability", "DYNAMIC_COLUMNS"]

#: The columns :func:`with_dynamic_stability` adds, with their units (``Branch.read_csv`` leaves them out of
#: the variables: :data:`~mechcont.continuation._branch.DERIVED_COLUMNS`).
DYNAMIC_COLUMNS = {"n_unstable_dynamic": "", "leading_real": "1/s", "leading_frequency": "rad/s"}


@dataclass(frozen=True)
class DynamicStability:
    """The dynamic stability of one equilibrium: ``eigenvalues`` (1/s, largest real part first), the number
    with a positive real part ``n_unstable``, the leading one's real part (1/s) and ``|Im|`` (rad/s)."""

    eigenvalues: np.ndarray
    n_unstable: int
    leading_real: float
    leading_frequency: float

    @property
    def stable(self) -> bool:
        """True when no eigenvalue has a positive real part."""
        return self.n_unstable == 0


def _judge(lam: np.ndarray, rtol: float) -> DynamicStability:
    if lam.size == 0:
        return DynamicStability(lam, 0, float("nan"), float("nan"))
    tol = rtol * float(np.abs(lam).max())
    # the largest real part; among those within rounding of it (an undamped mechanism's modes all sit on
    # the imaginary axis), the slowest oscillation, so that the column does not jump between tied modes
    top = lam.real.max()
    tied = lam[lam.real >= top - tol]
    lead = tied[np.argmin(np.abs(tied.imag))]
    return DynamicStability(lam, int(np.count_nonzero(lam.real > tol)), float(lead.real), float(abs(lead.imag)))


def dynamic_stability(model: Model, x: np.ndarray, *, damping: float = 0.0, rtol: float = NEUTRAL_RTOL) -> DynamicStability:
    """The dynamic stability of the equilibrium ``x`` (a full vector of ``model``, SI).

    ``damping``: mass-proportional damping (1/s) added to a mechanism's own (as the time simulation's
    option); ``rtol``: a real part above ``rtol`` times the largest ``|lambda|`` is unstable (the rest is
    rounding: the linearisation of an undamped conservative mechanism has its eigenvalues on the imaginary
    axis to about 1e-15 of their size). Raises :class:`~mechcont.errors.InputError` for a model without
    dynamics.
    """
    dyn = dynamics_of(model, damping=damping)
    return _judge(dyn.linearise(np.asarray(x, dtype=float)).eigenvalues(), rtol)


def with_dynamic_stability(model: Model, branch: Branch, *, damping: float = 0.0, rtol: float = NEUTRAL_RTOL) -> Branch:
    """``branch`` (a :class:`~mechcont.continuation.Branch` of ``model``) with the columns of
    :data:`DYNAMIC_COLUMNS` added: per point the number of unstable eigenvalues of the linearised dynamics,
    the leading eigenvalue's real part (1/s) and its frequency ``|Im|`` (rad/s); see the module docstring.
    One linearisation and one dense eigenvalue problem per point. ``branch`` itself is unchanged."""
    dyn = dynamics_of(model, damping=damping)
    X = np.column_stack([branch.column(n) for n in model.names]) if len(branch) else np.zeros((0, len(model.names)))
    rows = [_judge(dyn.linearise(x).eigenvalues(), rtol) for x in X]
    columns = {"n_unstable_dynamic": np.array([r.n_unstable for r in rows], dtype=float),
               "leading_real": np.array([r.leading_real for r in rows], dtype=float),
               "leading_frequency": np.array([r.leading_frequency for r in rows], dtype=float)}
    return branch.with_columns(columns, DYNAMIC_COLUMNS)
