"""The physical mechanism behind an equation system: coordinates, constraints, forces, masses.

A :class:`MechanicalModel` is what both physical stability and time simulation need:

* generalised coordinates ``q`` (planar: x, y, theta per body), a subset of the
  system's variables;
* holonomic constraints ``Phi(q, p) = 0``;
* generalised applied forces ``Q(q, qdot, p)`` (gravity, springs, dampers, loads);
* the mass matrix ``M(q, p)``.

Static equilibrium is ``Q - Phi_q^T lambda = 0, Phi = 0`` (lambda: joint reactions).
Stability (see :meth:`MechanicalModel.stability`) uses the tangent stiffness
``K = -dQ/dq + sum_k lambda_k Hess(Phi_k)`` reduced to the null space of ``Phi_q``: the
constraint-curvature term is what hand-made codes forget.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..errors import InputError
from ._codegen import compile_dense, compile_sparse, derivative_entries, to_engine

__all__ = ["MechanicalModel", "StabilityResult", "velocity_symbol"]


def velocity_symbol(name: str) -> sp.Symbol:
    """The symbol standing for the time derivative of coordinate ``name`` (``name_dot``)."""
    return sp.Symbol(f"{name}_dot", real=True)


@dataclass(frozen=True)
class StabilityResult:
    """Stability of one equilibrium.

    Attributes
    ----------
    n_unstable:
        Number of unstable directions (negative stiffness eigenvalues, or eigenvalues
        with negative real part / complex pairs for non-conservative loads).
    eigenvalues:
        Eigenvalues of the reduced stiffness ``Z^T K Z`` (conservative, units of the
        stiffness) or of ``(Z^T M Z)^-1 Z^T K Z`` (omega^2, 1/s^2) otherwise.
    conservative:
        Whether the reduced stiffness was symmetric.
    """

    n_unstable: int
    eigenvalues: np.ndarray
    conservative: bool

    @property
    def stable(self) -> bool:
        """True when no direction is unstable."""
        return self.n_unstable == 0


class MechanicalModel:
    """Coordinates, constraints, applied forces and masses of a mechanism, compiled.

    Parameters
    ----------
    names:
        All variable names of the owning :class:`EquationSystem` (numeric vectors ``x``
        are ordered like this).
    coordinates:
        Names of the generalised coordinates ``q`` (a subset of ``names``).
    constraints:
        SymPy expressions ``Phi_k`` that vanish when the mechanism is assembled.
    forces:
        Generalised applied forces ``Q_i`` conjugate to each coordinate; may use the
        velocity symbols ``velocity_symbol(q_i)`` (dampers). At rest they are zero.
    mass_matrix:
        SymPy matrix ``M`` (n_q x n_q).
    """

    def __init__(self, names: Sequence[str], coordinates: Sequence[str], constraints: Sequence[sp.Expr],
                 forces: Sequence[sp.Expr], mass_matrix: sp.Matrix):
        self.names = tuple(names)
        self.coordinates = tuple(coordinates)
        missing = [c for c in self.coordinates if c not in self.names]
        if missing:
            raise InputError(missing[0], "coordinate is not a variable of the system")
        self.q_index = np.array([self.names.index(c) for c in self.coordinates])
        nq = len(self.coordinates)
        self.constraints = [sp.sympify(c, strict=True) for c in constraints]
        self.forces = [sp.sympify(f, strict=True) for f in forces]
        self.mass_matrix = sp.Matrix(mass_matrix)
        if len(self.forces) != nq:
            raise InputError("forces", f"need one generalised force per coordinate ({nq}), got {len(self.forces)}")
        if self.mass_matrix.shape != (nq, nq):
            raise InputError("mass_matrix", f"must be {nq}x{nq}, got {self.mass_matrix.shape}")
        syms = [sp.Symbol(n, real=True) for n in self.names]
        qs = [syms[i] for i in self.q_index]
        qd = [velocity_symbol(c) for c in self.coordinates]
        allowed = set(syms) | set(qd)
        for e in [*self.constraints, *self.forces, *self.mass_matrix]:
            bad = e.free_symbols - allowed
            if bad:
                raise InputError(str(sorted(map(str, bad))[0]), "used in the mechanical model but not a variable")
        self._syms, self._qs, self._qd = syms, qs, qd

    _COMPILED = ("_phi", "_phi_q", "_phi_hess", "_gamma", "_Q", "_dQdq", "_dQdqd", "_statics", "_M")

    def __getattr__(self, name):
        # only reached for missing attributes: the compiled functions, built on first use
        if name in MechanicalModel._COMPILED:
            self._compile()
            return self.__dict__[name]
        raise AttributeError(name)

    def _compile(self) -> None:
        """Differentiate and compile Phi, Phi_q, its Hessians, gamma, Q, dQ/dq, dQ/dqdot, M."""
        syms, qs, qd = self._syms, self._qs, self._qd
        nq = len(self.coordinates)
        # symbolic work in the engine (see _codegen): fast exact derivatives
        args = to_engine(syms + qd)
        qs_e, qd_e = to_engine(qs), to_engine(qd)
        cons = to_engine(self.constraints)
        forces_e = to_engine(self.forces)
        nc = len(cons)
        phi_q = derivative_entries(cons, qs_e)
        self._phi = compile_dense(args, cons)
        self._phi_q = compile_sparse(args, phi_q, (nc, nq))
        # Hessians of the constraints, for the curvature term sum_k lambda_k Hess(Phi_k)
        hess = [((k, i, j), d2) for (k, i), d in phi_q for (_, j), d2 in derivative_entries([d], qs_e)]
        self._phi_hess = compile_sparse(args, hess, (nc, nq, nq))
        # gamma = -(d/dq (Phi_q qdot)) qdot: right-hand side of Phi_q qddot = gamma
        rows = [0] * nc
        for (k, i), d in phi_q:
            rows[k] = rows[k] + d * qd_e[i]
        gamma = [0] * nc
        for (k, j), d in derivative_entries(rows, qs_e):
            gamma[k] = gamma[k] - d * qd_e[j]
        self._gamma = compile_dense(args, gamma)
        self._Q = compile_dense(args, forces_e)
        self._dQdq = compile_sparse(args, derivative_entries(forces_e, qs_e), (nq, nq))
        self._dQdqd = compile_sparse(args, derivative_entries(forces_e, qd_e), (nq, nq))
        # everything stability needs at rest, in one compiled call
        statics = [0] * (nc * nq + nq + nq * nq + nc * nq * nq)
        for (k, i), d in phi_q:
            statics[k * nq + i] = d
        o = nc * nq
        for i, f in enumerate(forces_e):
            statics[o + i] = f
        o += nq
        for (i, j), d in derivative_entries(forces_e, qs_e):
            statics[o + i * nq + j] = d
        o += nq * nq
        for (k, i, j), d2 in hess:
            statics[o + (k * nq + i) * nq + j] = d2
        self._statics = compile_dense(args, statics)
        M = self.mass_matrix
        self._M = compile_sparse(args, [((i, j), M[i, j]) for i in range(nq) for j in range(nq) if M[i, j] != 0], (nq, nq))

    # -- numeric evaluation (x: full variable vector, qdot: coordinate velocities) ---------
    def _args(self, x, qdot=None):
        qd = np.zeros(len(self.coordinates)) if qdot is None else qdot
        return np.concatenate([np.asarray(x, float), np.asarray(qd, float)])

    def phi(self, x, qdot=None) -> np.ndarray:
        """Constraint residuals Phi (units of each constraint, usually m)."""
        return self._phi(self._args(x, qdot))

    def phi_q(self, x) -> np.ndarray:
        """Constraint Jacobian dPhi/dq, shape (n_constraints, n_q)."""
        return self._phi_q(self._args(x))

    def gamma(self, x, qdot) -> np.ndarray:
        """Right-hand side of the acceleration-level constraints Phi_q qddot = gamma."""
        return self._gamma(self._args(x, qdot))

    def applied_forces(self, x, qdot=None) -> np.ndarray:
        """Generalised applied forces Q(q, qdot) (N or N m per coordinate)."""
        return self._Q(self._args(x, qdot))

    def damping_matrix(self, x, qdot=None) -> np.ndarray:
        """-dQ/dqdot, shape (n_q, n_q) (N s/m)."""
        return -self._dQdqd(self._args(x, qdot))

    def mass(self, x) -> np.ndarray:
        """Mass matrix M(q), shape (n_q, n_q) (kg, kg m^2)."""
        return self._M(self._args(x))

    def _decompose(self, x, rtol: float = 1e-10):
        """SVD of Phi_q: (U, singular values, V^T, rank) — shared by multipliers and Z."""
        A = self.phi_q(x)
        if A.shape[0] == 0:
            return None, np.zeros(0), np.eye(A.shape[1]), 0
        U, sv, Vt = np.linalg.svd(A)
        rank = int(np.sum(sv > rtol * max(sv[0], 1e-300))) if len(sv) else 0
        return U, sv, Vt, rank

    def multipliers(self, x) -> np.ndarray:
        """Constraint reactions lambda solving Phi_q^T lambda = Q in the least-squares sense.

        With redundant constraints the minimum-norm solution is returned.
        """
        U, sv, Vt, r = self._decompose(x)
        if U is None:
            return np.zeros(0)
        Q = self.applied_forces(x)
        return U[:, :r] @ ((Vt[:r] @ Q) / sv[:r])

    def tangent_stiffness(self, x, multipliers=None) -> np.ndarray:
        """K = -dQ/dq + sum_k lambda_k Hess(Phi_k) at rest, shape (n_q, n_q)."""
        a = self._args(x)
        lam = self.multipliers(x) if multipliers is None else np.asarray(multipliers)
        return -self._dQdq(a) + np.tensordot(lam, self._phi_hess(a), axes=1)

    def allowed_motions(self, x, rtol: float = 1e-10) -> np.ndarray:
        """Orthonormal basis Z of the null space of Phi_q: the motions the joints allow."""
        _, _, Vt, r = self._decompose(x, rtol)
        return Vt[r:].T

    def stability(self, x, rtol: float = 1e-9) -> StabilityResult:
        """Physical stability of the equilibrium at ``x`` (a full variable vector).

        Reduces the tangent stiffness to the constraint tangent space, ``Kr = Z^T K Z``.
        Conservative (symmetric ``Kr``): the number of negative eigenvalues is the number
        of unstable directions. Otherwise the eigenvalues ``mu`` of
        ``(Z^T M Z)^-1 Kr`` (small oscillations ``s^2 = -mu``) are used: a direction is
        unstable when ``mu`` has a negative real part or is complex (flutter).
        Eigenvalues within ``rtol`` of the largest magnitude count as zero (neutral).
        The count is independent of the units of ``q`` (Sylvester's law of inertia).
        """
        nq, nc = len(self.coordinates), len(self.constraints)
        out = self._statics(self._args(x))
        A = out[: nc * nq].reshape(nc, nq)
        Q = out[nc * nq: nc * nq + nq]
        o = nc * nq + nq
        K = -out[o: o + nq * nq].reshape(nq, nq)
        if nc:
            U, sv, Vt = np.linalg.svd(A)
            r = int(np.sum(sv > 1e-10 * max(sv[0], 1e-300)))
            lam = U[:, :r] @ ((Vt[:r] @ Q) / sv[:r])
            K = K + (lam @ out[o + nq * nq:].reshape(nc, nq * nq)).reshape(nq, nq)
        else:
            Vt, r = np.eye(nq), 0
        Z = Vt[r:].T
        if Z.shape[1] == 0:
            return StabilityResult(0, np.zeros(0), True)
        Kr = Z.T @ K @ Z
        scale = max(np.abs(Kr).max(), 1e-300)
        if np.abs(Kr - Kr.T).max() <= 1e-9 * scale:
            ev = np.linalg.eigvalsh(0.5 * (Kr + Kr.T)) if len(Kr) > 1 else Kr[0].copy()
            return StabilityResult(int(np.sum(ev < -rtol * scale)), ev, True)
        Mr = Z.T @ self.mass(x) @ Z
        mu = np.linalg.eigvals(np.linalg.solve(Mr, Kr))
        tol = rtol * max(np.abs(mu).max(), 1e-300)
        unstable = (mu.real < -tol) | (np.abs(mu.imag) > tol)
        return StabilityResult(int(np.sum(unstable)), mu, False)
