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

import numpy as np

from ..errors import ConvergenceError, InputError
from ._collocation import Mesh
from ._cycle_system import CycleSystem, NewtonFailure, phase_reference

__all__ = ["CycleStart", "HopfPoint", "hopf_point", "hopf_start", "samples_start", "period_from_samples"]


@dataclass(frozen=True)
class HopfPoint:
    """A Hopf point: equilibrium state ``z`` (state units), full vector ``x``, frequency ``omega``
    (rad/s) and critical eigenvector ``q`` (complex, ``A q = i omega q``, ``|q| = 1``)."""

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


def hopf_point(model, dynamics, x: np.ndarray, vary: str, tol: float = 1e-12, max_iter: int = 30) -> HopfPoint:
    """The Hopf point nearest the full vector ``x`` (on or near an equilibrium branch in ``vary``).

    Newton on the extended system ``f(z; p) = 0``, ``A(z; p) q = i omega q``, ``c . q = 1`` (real and
    imaginary parts: ``3n + 2`` equations in ``z, p, omega, Re q, Im q``); its residual is exact, its
    Jacobian by central differences of ``A`` (second derivatives are not needed exactly: the iteration
    still converges to the exact root). Raises :class:`InputError` (field ``point``) when there is no
    complex pair nearby or the refinement does not converge: the point is not a Hopf point.
    """
    x = np.array(x, float)
    j = model.index(vary)
    z = dynamics.state_at(x)
    n = len(z)
    for _ in range(max_iter):  # onto the equilibrium first (a row of a table is rounded; a point may be near it)
        try:
            dz = np.linalg.solve(dynamics.rates_jacobian(z, x), -dynamics.rates(z, x))
        except np.linalg.LinAlgError:
            break
        z = z + dz
        if np.max(np.abs(dz)) <= tol * max(1.0, float(np.max(np.abs(z)))):
            break
    if not np.all(np.isfinite(z)):
        raise InputError("point", f"no equilibrium near the point at {vary} = {x[j]:.6g}: not a Hopf point")
    lam, q = _critical(dynamics.rates_jacobian(z, x))
    if abs(lam.real) > 0.5 * abs(lam):
        raise InputError("point", f"the eigenvalues nearest the imaginary axis are {lam.real:.4g} ± {abs(lam.imag):.4g}i:"
                                  " not a Hopf point (give the HB row of a continue table)")
    c = q.conj()  # normalisation c . q = 1 (c real part and imaginary part as two rows)

    def residual(v):
        zz, p, om = v[:n], v[n], v[n + 1]
        qr, qi = v[n + 2:2 * n + 2], v[2 * n + 2:]
        xx = x.copy()
        xx[j] = p
        A = dynamics.rates_jacobian(zz, xx)
        cq = c @ (qr + 1j * qi)
        return np.concatenate([dynamics.rates(zz, xx), A @ qr + om * qi, A @ qi - om * qr, [cq.real - 1.0, cq.imag]])

    v = np.concatenate([z, [x[j], lam.imag], q.real, q.imag])
    scale = np.maximum(np.abs(v), 1.0)
    for _ in range(max_iter):
        r = residual(v)
        J = np.empty((len(v), len(v)))
        for k in range(len(v)):
            h = 1e-6 * scale[k]
            e = np.zeros(len(v))
            e[k] = h
            J[:, k] = (residual(v + e) - residual(v - e)) / (2 * h)
        try:
            dv = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            break
        v = v + dv
        if np.max(np.abs(dv) / scale) < tol:
            if abs(v[n] - x[j]) > 0.1 * max(abs(x[j]), model.variable(vary).scale):
                break  # a Hopf point, but far from the point given: not this one
            xh = x.copy()
            xh[j] = v[n]
            xh = dynamics.full_vector(v[:n], xh)
            qv = v[n + 2:2 * n + 2] + 1j * v[2 * n + 2:]
            return HopfPoint(v[:n].copy(), xh, abs(float(v[n + 1])), qv / np.linalg.norm(qv))
    raise InputError("point", f"no Hopf point found near {vary} = {x[j]:.6g} (the extended system did not "
                              "converge): not a Hopf point")


def hopf_start(system: CycleSystem, hopf: HopfPoint) -> CycleStart:
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
