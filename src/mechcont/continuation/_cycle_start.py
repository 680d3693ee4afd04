"""Where a family of periodic orbits starts: at a Hopf point, or from a cycle of a time simulation.

:func:`hopf_start` refines a point near a Hopf bifurcation of an equilibrium branch (a row of a
``continue`` table) to the Hopf point itself, with its frequency and critical eigenvector, and
gives the zero-amplitude start of the family with the eigenvector's orbit as its tangent (AUTO's
start from an HB point). :func:`samples_start` takes a periodic solution sampled in time (a converged
time simulation), estimates its period from its returns to a Poincaré section, and corrects it to a
collocation orbit at its parameter value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ConvergenceError, InputError
from ._collocation import Mesh
from ._cycle_system import CycleSystem, NewtonFailure, phase_reference

if TYPE_CHECKING:
    from ..equations import Dynamics, Model

__all__ = ["CycleStart", "HopfOrigin", "hopf_point", "hopf_start", "samples_start", "period_from_samples"]


@dataclass(frozen=True)
class HopfOrigin:
    """Where a family of cycles starts: the Hopf point's equilibrium state ``z`` (state units), full vector
    ``x``, frequency ``omega`` (rad/s) and critical eigenvector ``q`` of the rates' Jacobian (complex,
    ``(df/dz) q = i omega q``, ``|q| = 1``, over the rates' state, which for a mechanism is its minimal
    coordinates and velocities rather than the linearisation's)."""

    z: np.ndarray
    x: np.ndarray
    omega: float
    q: np.ndarray


@dataclass(frozen=True)
class CycleStart:
    """The first point of a family: the orbit ``X`` on ``mesh`` (see :class:`~._cycle_system.CycleSystem`),
    the unit tangent ``tangent`` (or None: from the Jacobian's null vector), and the first row's label."""

    mesh: Mesh
    X: np.ndarray
    tangent: np.ndarray | None
    label: str
    x_base: np.ndarray


def _critical(A: np.ndarray) -> tuple[complex, np.ndarray]:
    """The eigenvalue with positive imaginary part nearest the imaginary axis, and its unit eigenvector."""
    lam, V = np.linalg.eig(A)
    cand = [i for i in range(len(lam)) if lam[i].imag > 1e-12 * max(1.0, abs(lam[i]))]
    if not cand:
        raise InputError("point", "no complex pair of eigenvalues here (eigenvalues: "
                                  f"{', '.join(f'{v:.4g}' for v in lam)}): not a Hopf point")
    i = min(cand, key=lambda k: abs(lam[k].real) / abs(lam[k]))
    return complex(lam[i]), V[:, i] / np.linalg.norm(V[:, i])


def hopf_point(model: Model, dynamics: Dynamics, x: np.ndarray, vary: str) -> HopfOrigin:
    """The Hopf point nearest the full vector ``x`` (on or near an equilibrium branch in ``vary``), located by
    :func:`~._hopf_api.locate_hopf` (to machine precision), with the critical eigenvector of the rates'
    Jacobian there. Raises :class:`InputError` (field ``point``) when there is none nearby: not a Hopf point.
    """
    from ._hopf_api import locate_hopf

    x = np.array(x, float)
    j = model.index(vary)
    if not np.all(np.isfinite(dynamics.rates(dynamics.state_at(x), x))):
        raise InputError("point", f"the rates are not finite at {vary} = {x[j]:.6g}: not a Hopf point")
    found = locate_hopf(model, x, vary, dynamics=dynamics)
    xh = found.x
    if abs(xh[j] - x[j]) > 0.1 * max(abs(x[j]), model.variable(vary).scale):
        raise InputError("point", f"the Hopf point nearest {vary} = {x[j]:.6g} lies at {xh[j]:.6g}, far from it: "
                                  "not a Hopf point")
    z = dynamics.state_at(xh)
    lam, q = _critical(dynamics.rates_jacobian(z, xh))
    return HopfOrigin(z, xh, float(found.extra["hopf"].frequency), q)


def hopf_start(system: CycleSystem, hopf: HopfOrigin) -> CycleStart:
    """The zero-amplitude orbit at ``hopf`` (period ``2 pi / omega``) and the family's tangent: the orbit
    ``Re(q exp(2 pi i tau))`` of the critical eigenvector, with no change of period or parameter."""
    me = system.mesh
    tau = me.times()
    phi = np.outer(np.cos(2 * np.pi * tau), hopf.q.real) - np.outer(np.sin(2 * np.pi * tau), hopf.q.imag)
    u = np.repeat(hopf.z[None, :], me.n_nodes, axis=0)
    p = float(hopf.x[system.rates.p_index])
    X = system.pack(u, 2 * np.pi / hopf.omega, p)
    t = system.pack(phi, 0.0, 0.0)
    return CycleStart(me, X, t / system.norm(t), "HB", hopf.x)


def period_from_samples(t: np.ndarray, Z: np.ndarray) -> tuple[float, float]:
    """``(t0, T)``: the last two upward crossings of the first state's mean by a sampled periodic
    solution (a Poincaré section; crossing times by linear interpolation), ``T`` their distance (s).
    Raises :class:`InputError` (field ``samples``) when there are fewer than two crossings."""
    t, Z = np.asarray(t, float), np.asarray(Z, float)
    if Z.ndim != 2 or len(t) != len(Z) or len(t) < 8:
        raise InputError("samples", "give times (m,) and states (m, n) of one simulation, m >= 8")
    s = Z[:, 0] - 0.5 * (Z[:, 0].max() + Z[:, 0].min())
    up = np.nonzero((s[:-1] < 0) & (s[1:] >= 0))[0]
    if len(up) < 2:
        raise InputError("samples", "the simulation does not return to its section twice: no period found "
                                    "(simulate longer, until the motion repeats)")
    cross = [t[i] - s[i] * (t[i + 1] - t[i]) / (s[i + 1] - s[i]) for i in up[-2:]]
    return cross[0], cross[1] - cross[0]


def samples_start(system: CycleSystem, t: np.ndarray, Z: np.ndarray, x_base: np.ndarray, tol: float = 1e-10,
                  max_iter: int = 20) -> CycleStart:
    """The collocation orbit through a sampled periodic solution (``t`` (m,) in s, ``Z`` (m, n)) at the
    parameter value of ``x_base``: one period is cut at a Poincaré section (:func:`period_from_samples`),
    interpolated to the mesh's nodes, and corrected by Newton with the parameter held. Raises
    :class:`ConvergenceError` when the correction fails (the samples are not near a periodic orbit)."""
    t0, T = period_from_samples(t, Z)
    tau = system.mesh.times()
    t = np.asarray(t, float)
    u = np.column_stack([np.interp(t0 + tau * T, t, np.asarray(Z, float)[:, k]) for k in range(system.n)])
    p = float(x_base[system.rates.p_index])
    X = system.pack(u, T, p)
    closing = np.zeros(system.size)
    closing[-1] = 1.0
    try:
        X, _, _ = system.newton(X, phase_reference(system, X), closing, p, tol, max_iter)
    except NewtonFailure as exc:
        raise ConvergenceError(f"the sampled solution (period about {T:.6g} s) does not correct to a periodic "
                               f"orbit: {exc}") from None
    if not math.isfinite(X[-2]) or X[-2] <= 0:
        raise ConvergenceError(f"the corrected orbit has period {X[-2]:.6g} s")
    return CycleStart(system.mesh, X, None, "", np.array(x_base, float))
