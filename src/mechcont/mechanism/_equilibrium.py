"""The free equilibrium ``mechcont check`` looks for: every state of the square system solved from the
assembled configuration, first by Newton, then by a trust-region least-squares search.

Plain Newton from the assembled configuration fails where the equilibrium is far from it (a linkage
that must swing half a turn under gravity: Bricard's over-constrained 6R loop, whose Newton steps
grew to 1e127) or where a compliant joint's stiff rows make the first steps overshoot. SciPy's
trust-region reflective least squares (``least_squares(method="trf")``, steps limited to a region
where the linear model holds, on the variables' scales) reaches the equilibrium from there; Newton
then polishes it. "No equilibrium" is said only with what was tried and the residual each reached.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import ConvergenceError
from ._assembly import assemble

if TYPE_CHECKING:
    from ..equations import Model

__all__ = ["free_equilibrium"]

#: Evaluations the trust-region search may use (the 6R loop needs ~90; each is one residual).
_MAX_NFEV = 2000


def _tolerance(system: Model) -> float:
    """The largest residual (N, N m, m, rad) accepted as an equilibrium: :func:`assemble`'s own test."""
    return 1e-8 * max(1.0, float(np.max(np.abs(system.scales()))))


def free_equilibrium(system: Model, x: np.ndarray) -> tuple[np.ndarray, str]:
    """An equilibrium of ``system`` near the assembled full vector ``x`` (SI), every state free.

    Returns ``(x_equilibrium, how)``: the full vector and how it was found ("Newton" or "a trust-region
    least-squares search (N evaluations), then Newton"). Raises :class:`ConvergenceError` naming both
    attempts and the residual each reached when neither finds one."""
    try:
        return assemble(system, guess=x), "Newton"
    except ConvergenceError as exc:
        newton = exc
    u = np.array([system.index(n) for n in system.state_names])
    scale = system.scales()[u]
    base = np.array(x, float)

    def full(z: np.ndarray) -> np.ndarray:
        y = base.copy()
        y[u] = z
        return y

    from scipy.optimize import least_squares  # only when Newton failed: a warm `check` imports no scipy.optimize

    fit = least_squares(lambda z: system.residual(full(z)), base[u], jac=lambda z: system.jacobian(full(z))[:, u],
                        x_scale=scale, method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=_MAX_NFEV)
    reached = float(np.max(np.abs(fit.fun))) if fit.fun.size else 0.0
    found = f"a trust-region least-squares search ({fit.nfev} evaluations)"
    candidate, how = None, ""
    if np.all(np.isfinite(fit.fun)) and reached <= 1e3 * _tolerance(system):
        try:
            candidate, how = assemble(system, guess=full(fit.x)), f"{found}, then Newton"
        except ConvergenceError:  # a root where the Jacobian is singular (e.g. links aligned): Newton cannot polish it
            if reached <= _tolerance(system):
                candidate = full(fit.x)
                how = f"{found} (max residual {reached:.3g}; Newton cannot refine it: its Jacobian is singular there)"
    if candidate is None:
        raise ConvergenceError(f"tried Newton ({newton}) and {found}: its max residual stalled at {reached:.3g}, "
                               "a local minimum of the residual that is not zero", partial=full(fit.x))
    dof, there = _dof(system, x), _dof(system, candidate)
    if there != dof:  # a root on another assembly mode (a rigid one): not where the mechanism can move to
        raise ConvergenceError(f"tried Newton ({newton}) and {found}: it closed the equations (max residual "
                               f"{reached:.3g}) only in another assembly mode, with {there} degree(s) of freedom instead "
                               f"of {dof}", partial=candidate)
    return candidate, how


def _dof(system: Model, x: np.ndarray) -> int:
    """Coordinates less the rank of the rigid constraint rows at ``x`` (singular values above 1e-9 of the largest)."""
    mech = system.mechanics
    assert mech is not None  # a description's build: its coordinates' mechanics
    A = mech.phi_q(x)
    if A.size == 0:
        return len(mech.q_index)
    sv = np.linalg.svd(A, compute_uv=False)
    return len(mech.q_index) - int(np.count_nonzero(sv > 1e-9 * sv[0]))
