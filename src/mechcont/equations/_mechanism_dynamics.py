"""The dynamics of a mechanism: its equations of motion as a first-order system, and their linearisation.

The equations of motion of a :class:`~._mechanics.MechanicalModel` are

    M(q) qddot = Q(q, qdot, s) + h(q, qdot) - d M qdot + Phi_q^T mu,    Phi(q) = 0,    sdot = r(q, qdot, s)

(``h`` the velocity-product inertial forces, ``d`` an optional mass-proportional damping in 1/s,
``s`` the first-order element states; at rest ``mu = -lambda``, the statics' reactions).

**Linearisation** (:meth:`MechanismDynamics.linearise`) about an equilibrium ``x``: with ``N`` an
orthonormal basis of the null space of ``Phi_q`` (the allowed motions) and ``dq = N eta``,

    Mr eta'' + Cr eta' + Kr eta = Br ds,     ds' = Rq N eta + Rv N eta' + Rs ds,

``Mr = N^T M N``, ``Cr = N^T C N`` (``C = -dQ/dqdot + d M``), ``Kr = N^T K N`` with the exact tangent
stiffness ``K = -dQ/dq + sum_k lambda_k Hess(Phi_k)`` (non-symmetric for non-conservative loads; the
curvature term is the second derivative of ``Q`` along the curved constraint manifold:
differentiating ``Phi(q(eta)) = 0`` twice gives ``Phi_q q'' = -Hess(Phi)[N, N]``, and ``Q = Phi_q^T
lambda`` at the equilibrium), ``Br = N^T dQ/ds`` and ``R* = dr/d*``. The state ``(eta, eta', ds)``
gives the explicit ``A`` (``E`` None: ``Mr`` is symmetric positive definite and as small as the
number of degrees of freedom, so inverting it costs nothing and loses nothing; a descriptor form
would only add infinite eigenvalues to filter). Only where an allowed motion has no mass (the statics
allows massless bodies) is ``Mr`` singular: then ``E = diag(I, Mr, I)`` with the undivided blocks, and
the massless motions' infinite eigenvalues are left out by :meth:`~._dynamics.LinearDynamics.eigenvalues`.
The velocity-product forces are quadratic in ``qdot`` and drop out.

**Rates** (:meth:`MechanismDynamics.rates`): an explicit ODE in minimal coordinates by generalised
coordinate partitioning at a reference equilibrium (the first ``x`` the dynamics is asked about, or
``reference``): the dependent coordinates are the pivot columns of a column-pivoted QR of ``Phi_q``
with its columns scaled by the coordinates' typical magnitudes (unit-free), the rest independent;
``z = (q_i, v_i, s)``. The dependent coordinates follow from ``Phi = 0`` by Newton, their velocities
from ``Phi_q qdot = 0``, the accelerations from the constrained equations of motion (the KKT system).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, cast

import numpy as np
import scipy.linalg
from scipy.linalg.lapack import dgesv as _dgesv
from scipy.linalg.lapack import dgetrf as _dgetrf
from scipy.linalg.lapack import dgetrs as _dgetrs

from ..errors import ConvergenceError, InputError
from ._linear_dynamics import LinearDynamics
from ._mechanics import MechanicalModel, constraint_rank
from ._stacked_linear import Reduced, motions_and_reactions, reduced_blocks, state_matrices
from ._velocity_names import velocity_name

if TYPE_CHECKING:
    from ._model import Model

__all__ = ["MechanismDynamics"]


#: Below this relative Newton step the factors of the previous iterate's constraint Jacobian are reused (a
#: chord step): that Jacobian differs from the current one by about the relative step, so each chord step
#: still contracts the error by that factor (three digits or more), and the loop's tests stop at rounding as
#: before; it saves a compiled call and a factorisation per call of the rates (a time simulation's inner loop).
_CHORD = 1e-3
#: A Newton step of at most this many ulps (relative) has converged to rounding.
_ULPS = 4 * float(np.finfo(float).eps)


def _solve(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``A^-1 b`` by LAPACK's ``dgesv`` (``np.linalg.solve`` costs three times as much on these small
    systems, the rates' inner loop); raises ``numpy.linalg.LinAlgError`` when ``A`` is singular."""
    _, _, sol, info = _dgesv(A, b)
    if info:
        raise np.linalg.LinAlgError("singular matrix")
    return sol


def _factor(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """LU factors of ``A`` (``dgetrf``) for :func:`_lu_solve`; raises ``LinAlgError`` when singular."""
    lu, piv, info = _dgetrf(A)
    if info:
        raise np.linalg.LinAlgError("singular matrix")
    return lu, piv


def _lu_solve(lu: tuple[np.ndarray, np.ndarray], b: np.ndarray) -> np.ndarray:
    """``A^-1 b`` from :func:`_factor`'s factors."""
    return _dgetrs(lu[0], lu[1], b)[0]


#: Relative step of the central differences: ``eps^(1/3)`` balances their truncation error
#: (``h^2 f'''/6``) against rounding (``eps f / h``), leaving about ``eps^(2/3)`` ~ 4e-11 relative.
FD_STEP = float(np.finfo(float).eps) ** (1 / 3)


class MechanismDynamics:
    """The :class:`~._dynamics.Dynamics` of a mechanism model (``model.mechanics`` set).

    ``damping``: mass-proportional (Rayleigh) damping ``d`` (1/s), the force ``-d M qdot`` the time
    simulation adds with its ``damping`` option. ``reference``: the full vector whose configuration
    chooses the coordinate partition of :meth:`rates` (default: the first ``x`` asked about).
    """

    def __init__(self, model: Model, damping: float = 0.0, reference: np.ndarray | None = None) -> None:
        if model.mechanics is None:
            raise InputError(model.name, "has no mechanics: no equations of motion")
        if not (np.isfinite(damping) and damping >= 0):
            raise InputError("damping", "must be a non-negative number (1/s)")
        # the equations of motion need the compiled model itself (its batches, motion terms, statics layout), more
        # than the Mechanics protocol offers: a model's mechanics is a MechanicalModel
        mech = cast(MechanicalModel, model.mechanics)
        self.model, self.mech, self.damping = model, mech, float(damping)
        self._q = np.asarray(mech.q_index, dtype=np.intp)
        self._s = np.asarray(getattr(mech, "s_index", np.zeros(0, np.intp)), dtype=np.intp)
        scales = model.scales()
        self._qscale = np.asarray(scales[self._q], dtype=float)
        self._sscale = np.asarray(scales[self._s], dtype=float)
        self._part: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self._cols: tuple[np.ndarray, np.ndarray] = (np.zeros(0, np.intp), np.zeros(0, np.intp))
        # the full vectors last linearised (the first row of each of the last few _reduced) and their allowed
        # motions N, for linearisation_basis: a Hopf point's l1 takes the critical pair's linearisation there
        # instead of differencing the rates again
        self._bases: dict[bytes, np.ndarray] = {}
        self._names: dict[int, tuple[str, ...]] = {}  # linearise's state names, by size
        if reference is not None:
            self._partition(np.asarray(reference, dtype=float))

    # -- the partition ---------------------------------------------------------------------
    def _partition(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(independent, dependent, kept rows)``: coordinate positions (into ``q``) and constraint rows."""
        if self._part is None:
            nq = len(self._q)
            A = self.mech.phi_q(x)
            if A.shape[0] == 0:
                self._part = (np.arange(nq), np.zeros(0, np.intp), np.zeros(0, np.intp))
            else:
                B = A * self._qscale[None, :]
                r = constraint_rank(B, np.linalg.svd(B, compute_uv=False))
                _, _, piv = scipy.linalg.qr(B, mode="economic", pivoting=True)
                dep = np.sort(piv[:r])
                _, _, rows = scipy.linalg.qr(B[:, dep].T, mode="economic", pivoting=True)
                self._part = (np.setdiff1d(np.arange(nq), dep), dep, np.sort(rows[:r]))
            # the independent and dependent coordinates' positions in the full vector
            self._cols = (self._q[self._part[0]], self._q[self._part[1]])
        return self._part

    @property
    def state_names(self) -> tuple[str, ...]:
        """``z``'s names: the independent coordinates, their velocities (``_dot``), the element states."""
        indep, _, _ = self._partition(self.model.defaults())
        coords = [self.mech.coordinates[i] for i in indep]
        return (*coords, *(velocity_name(c) for c in coords), *self.mech.element_states)

    def _split(self, z: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        indep, _, _ = self._partition(x)
        n = len(indep)
        z = np.asarray(z, dtype=float)
        if z.shape != (2 * n + len(self._s),):
            raise InputError("z", f"needs {2 * n + len(self._s)} values ({', '.join(self.state_names)})")
        return z[:n], z[n:2 * n], z[2 * n:]

    def _configuration(self, qi: np.ndarray, s: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``x`` with the independent coordinates ``qi``, the dependent ones solved from ``Phi = 0`` (Newton
        from ``x``'s own), and the states ``s``. Raises :class:`ConvergenceError` when Newton fails."""
        indep, dep, rows = self._partition(x)
        icols, cols = self._cols
        out = np.array(x, dtype=float)
        out[icols] = qi
        out[self._s] = s
        if len(dep) == 0:
            return out
        size = np.maximum(np.abs(out[cols]), self._qscale[dep])
        last, lu = np.inf, None
        for _ in range(30):
            res = self.mech.phi(out)[rows]
            if not res.any():  # closed exactly (linear constraints after one step): the step would be zero
                return out
            if lu is None or last > _CHORD:
                lu = _factor(self.mech.phi_q(out)[rows][:, dep])
            step = _lu_solve(lu, -res)
            out[cols] += step
            change = float(np.max(np.abs(step) / size))
            # converged to rounding: a step of a few ulps, or one that no longer halves once below 1e-10
            if change <= _ULPS or (change < 1e-10 and change > 0.5 * last):
                return out
            last = change
        raise ConvergenceError(f"the dependent coordinates did not close the constraints at {qi}")

    def _velocities(self, x: np.ndarray, vi: np.ndarray, A: np.ndarray | None = None) -> np.ndarray:
        """All coordinate velocities from the independent ones: ``Phi_q qdot = 0`` (``A``: the kept rows of
        ``Phi_q`` at ``x`` when already evaluated)."""
        indep, dep, rows = self._partition(x)
        qd = np.zeros(len(self._q))
        qd[indep] = vi
        if len(dep):
            if A is None:
                A = self.mech.phi_q(x)[rows]
            qd[dep] = _solve(A[:, dep], -A[:, indep] @ vi)
        return qd

    def accelerations(self, x: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """Constrained accelerations ``qddot`` (all coordinates) at the configuration ``x`` with velocities
        ``qd``, from the KKT system ``[M A^T; A 0] [qddot; -mu] = [F; gamma]`` (``F``: applied, inertial
        and mass-proportional damping forces; ``A`` the kept rows of ``Phi_q``)."""
        _, _, rows = self._partition(x)
        M, F, gamma, _ = self.mech.motion_terms(x, qd)
        return self._solve_kkt(M, F, gamma, self.mech.phi_q(x)[rows] if len(rows) else None, qd)

    def _solve_kkt(self, M: np.ndarray, F: np.ndarray, gamma: np.ndarray, A: np.ndarray | None,
                   qd: np.ndarray) -> np.ndarray:
        """``qddot`` from the KKT system (``A`` the kept rows of ``Phi_q``, None without constraints)."""
        if self.damping:
            F = F - self.damping * (M @ qd)
        if A is None:
            return _solve(M, F)
        _, _, rows = self._part  # type: ignore[misc]
        n, m = M.shape[0], len(rows)
        K = np.zeros((n + m, n + m))
        K[:n, :n], K[:n, n:], K[n:, :n] = M, A.T, A
        return _solve(K, np.concatenate([F, gamma[rows]]))[:n]

    # -- the Dynamics protocol --------------------------------------------------------------
    def state_at(self, x: np.ndarray) -> np.ndarray:
        """``z`` of the equilibrium ``x``: its independent coordinates, zero velocities, its element states."""
        x = np.asarray(x, dtype=float)
        indep, _, _ = self._partition(x)
        return np.concatenate([x[self._q[indep]], np.zeros(len(indep)), x[self._s]])

    def full_vector(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``x`` with every coordinate (the dependent ones solved) and element state of ``z``; the
        reactions and condition values are left at ``x``'s."""
        qi, _, s = self._split(z, x)
        return self._configuration(qi, s, x)

    def coordinate_velocities(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """Every coordinate's velocity at the state ``z`` (``Phi_q qdot = 0``), ordered like the coordinates."""
        qi, vi, s = self._split(z, x)
        return self._velocities(self._configuration(qi, s, x), vi)

    def rates(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``dz/dt = (v_i, qddot_i, r)`` (coordinate units per second, per second squared, state units per second).
        Raises :class:`~mechcont.errors.ConvergenceError` where the dependent coordinates cannot close the
        constraints (``z`` too far from the reference configuration for this partition)."""
        qi, vi, s = self._split(z, x)
        indep, _, rows = self._partition(x)
        xx = self._configuration(qi, s, x)
        A = self.mech.phi_q(xx)[rows] if len(rows) else None  # once, for the velocities and the KKT system
        qd = self._velocities(xx, vi, A)
        M, F, gamma, r = self.mech.motion_terms(xx, qd)
        qdd = self._solve_kkt(M, F, gamma, A, qd)
        return np.concatenate([vi, qdd[indep], r])

    def _steps(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        indep, _, _ = self._partition(x)
        typical = np.concatenate([self._qscale[indep], self._qscale[indep], self._sscale])  # velocities: per 1 s
        return FD_STEP * np.maximum(np.abs(z), typical)

    def rates_jacobian(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``df/dz``: the kinematic rows ``d v_i/dz`` exact, the others by central differences (step
        :data:`FD_STEP` times each component's magnitude or typical scale), all ``2 len(z)`` rates in one
        :meth:`rates_batch`."""
        self._split(z, x)
        return self.rates_jacobian_batch(np.asarray(z, dtype=float)[None, :], x)[0]

    def parameter_rates(self, z: np.ndarray, x: np.ndarray, names: Sequence[str]) -> np.ndarray:
        """``df/dp`` for the named parameters by central differences (step :data:`FD_STEP` times the
        parameter's magnitude or scale); the dependent coordinates re-solved at each."""
        self._split(z, x)
        return self.parameter_rates_batch(np.asarray(z, dtype=float)[None, :], x, names)[0]

    # -- many states at once (the periodic orbits' collocation points, the Jacobians' differences) --
    def _configuration_batch(self, QI: np.ndarray, S: np.ndarray, x: np.ndarray) -> np.ndarray:
        """:meth:`_configuration` at every row of ``QI``, ``S``: the full vectors (m, n_variables). The same
        Newton iteration row by row (a row leaves the loop when its own test passes), each iteration one
        compiled call and one stacked solve for the rows still iterating."""
        indep, dep, rows = self._partition(x)
        out = np.repeat(np.asarray(x, dtype=float)[None, :], len(QI), axis=0)
        out[:, self._q[indep]] = QI
        out[:, self._s] = S
        if len(dep) == 0 or len(out) == 0:
            return out
        mech, cols = self.mech, self._q[dep]
        size = np.maximum(np.abs(out[:, cols]), self._qscale[dep])
        last = np.full(len(out), np.inf)
        active = np.arange(len(out))
        for _ in range(30):
            res = mech.phi_batch(out[active])[:, rows]
            active = active[res.any(axis=1)]  # closed exactly: the step would be zero (as in _configuration)
            if len(active) == 0:
                return out
            Xa = out[active]
            A = mech.phi_q_batch(Xa)[:, rows][:, :, dep]
            step = np.linalg.solve(A, -res[res.any(axis=1)][:, :, None])[:, :, 0]
            out[active[:, None], cols[None, :]] += step
            change = np.max(np.abs(step) / size[active], axis=1)
            done = (change <= _ULPS) | ((change < 1e-10) & (change > 0.5 * last[active]))
            last[active] = change
            active = active[~done]
            if len(active) == 0:
                return out
        raise ConvergenceError(f"the dependent coordinates did not close the constraints at {QI[active[0]]}")

    def full_vectors(self, Z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """:meth:`full_vector` at every row of ``Z`` ((m, len(state_names))): array (m, n_variables), every
        coordinate (the dependent ones solved, one stacked Newton iteration for all rows) and element state."""
        Z = np.asarray(Z, dtype=float)
        indep, _, _ = self._partition(x)
        n, ns = len(indep), len(self._s)
        if Z.ndim != 2 or Z.shape[1] != 2 * n + ns:
            raise InputError("Z", f"needs rows of {2 * n + ns} values ({', '.join(self.state_names)})")
        return self._configuration_batch(Z[:, :n], Z[:, 2 * n:], x)

    def rates_batch(self, Z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """:meth:`rates` at every row of ``Z`` ((m, len(state_names))): array (m, len(state_names)), equal to
        the point-by-point rates to rounding; a few compiled calls and stacked solves for all rows."""
        Z = np.asarray(Z, dtype=float)
        indep, dep, rows = self._partition(x)
        n, ns = len(indep), len(self._s)
        if Z.ndim != 2 or Z.shape[1] != 2 * n + ns:
            raise InputError("Z", f"needs rows of {2 * n + ns} values ({', '.join(self.state_names)})")
        mech = self.mech
        VI = Z[:, n:2 * n]
        XX = self._configuration_batch(Z[:, :n], Z[:, 2 * n:], x)
        QD = np.zeros((len(Z), len(self._q)))
        QD[:, indep] = VI
        A = mech.phi_q_batch(XX)[:, rows] if len(rows) else None
        if A is not None and len(dep):
            QD[:, dep] = np.linalg.solve(A[:, :, dep], -(A[:, :, indep] @ VI[:, :, None]))[:, :, 0]
        M, F, G, R = mech.motion_terms_batch(XX, QD)
        if self.damping:
            F = F - self.damping * (M @ QD[:, :, None])[:, :, 0]
        if A is None:
            QDD = np.linalg.solve(M, F[:, :, None])[:, :, 0]
        else:
            nq, m = M.shape[1], len(rows)
            K = np.zeros((len(Z), nq + m, nq + m))
            K[:, :nq, :nq], K[:, :nq, nq:], K[:, nq:, :nq] = M, A.transpose(0, 2, 1), A
            rhs = np.concatenate([F, G[:, rows]], axis=1)
            QDD = np.linalg.solve(K, rhs[:, :, None])[:, :nq, 0]
        return np.concatenate([VI, QDD[:, indep], R], axis=1)

    def rates_jacobian_batch(self, Z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """:meth:`rates_jacobian` at every row of ``Z``: array (m, n_z, n_z); the ``2 m n_z`` differenced
        rates in one :meth:`rates_batch`."""
        Z = np.asarray(Z, dtype=float)
        n = len(self._partition(x)[0])
        m, nz = Z.shape
        H = np.array([self._steps(z, x) for z in Z]).reshape(m, nz)
        Zp = np.repeat(Z[:, None, :], nz, axis=1)
        Zm = Zp.copy()
        j = np.arange(nz)
        Zp[:, j, j] += H
        Zm[:, j, j] -= H
        R = self.rates_batch(np.concatenate([Zp.reshape(-1, nz), Zm.reshape(-1, nz)]), x).reshape(2, m, nz, nz)
        J = np.zeros((m, nz, nz))
        J[:, :n, n:2 * n] = np.eye(n)
        # J[k, :, j] = (f(zp_j) - f(zm_j)) / (zp_j - zm_j): R[., k, j, :] holds f at the j-th shifted state
        J[:, n:, :] = ((R[0] - R[1]) / (Zp[:, j, j] - Zm[:, j, j])[:, :, None]).transpose(0, 2, 1)[:, n:, :]
        return J

    def parameter_rates_batch(self, Z: np.ndarray, x: np.ndarray, names: Sequence[str]) -> np.ndarray:
        """:meth:`parameter_rates` at every row of ``Z``: array (m, n_z, len(names)); two :meth:`rates_batch`
        per parameter."""
        x = np.asarray(x, dtype=float)
        Z = np.asarray(Z, dtype=float)
        scales = self.model.scales()
        out = np.zeros((*Z.shape, len(names)))
        for k, name in enumerate(names):
            i = self.model.index(name)
            h = FD_STEP * max(abs(x[i]), scales[i])
            xp, xm = x.copy(), x.copy()
            xp[i] += h
            xm[i] -= h
            out[:, :, k] = (self.rates_batch(Z, xp) - self.rates_batch(Z, xm)) / (xp[i] - xm[i])
        return out

    def linearise(self, x: np.ndarray) -> LinearDynamics:
        """``A`` of the small motions ``(eta, eta', ds)`` about the equilibrium ``x`` (see the module
        docstring), ``E`` None (a descriptor ``E`` where a motion has no mass); the names ``eta1..``,
        ``eta1_dot..``, then the element states."""
        A, E = state_matrices(self._reduced(np.asarray(x, dtype=float)[None, :]), None)
        return LinearDynamics(A[0], None if E is None else E[0], self._linear_names(A.shape[1]))

    def linearise_near(self, x: np.ndarray, X: np.ndarray,
                       descriptor: bool | None = None) -> tuple[np.ndarray, np.ndarray | None]:
        """``(A, E)`` of the small motions about each row of ``X`` (full vectors near the equilibrium ``x``,
        shape (m, n_variables)): arrays (m, n, n), ``E`` None unless ``descriptor`` (then the undivided
        blocks, as :meth:`linearise` makes them where a motion has no mass; None: as :meth:`linearise` decides,
        the descriptor form for all rows where any row's reduced mass is singular).

        The allowed motions at each row are ``x``'s (the basis :meth:`linearise` uses there) projected onto
        the row's null space of ``Phi_q``: a basis that moves smoothly with the row, so that differences of
        these matrices are derivatives of ``x``'s linearisation (each row's own singular vectors need not be
        continuous where the null space has more than one dimension). All rows in a few compiled calls and
        stacked factorisations (the Hopf system's directional derivatives)."""
        X = np.asarray(X, dtype=float)
        x = np.asarray(x, dtype=float)
        if len(X) and X[0].tobytes() == x.tobytes():
            # x's own linearisation asked for too (a Hopf polish's): its row is the reference as it stands, the
            # same matrices as with x stacked before it once more
            return state_matrices(self._reduced(X, project=True), descriptor)
        both = self._reduced(np.vstack([x[None, :], X]), project=True)
        return state_matrices(both.rows(1), descriptor)

    def linearisation_basis(self, x: np.ndarray) -> np.ndarray | None:
        """``T`` with ``dz = T (eta, eta', ds)``: the state ``z`` (:attr:`state_names`) of the small motions
        that :meth:`linearise` describes in ``(eta, eta', ds)`` about the equilibrium ``x``, so that ``df/dz =
        T A T^-1`` (``A`` its explicit matrix). Known only for the last few ``x`` linearised (:meth:`linearise`,
        or the first row of :meth:`linearise_near`), bit for bit: None for any other (the allowed motions' basis
        is not unique where there are several, so it is never recomputed to go with a matrix made earlier)."""
        x = np.asarray(x, dtype=float)
        N = self._bases.get(x.tobytes())
        if N is None:
            return None
        indep, _, _ = self._partition(x)
        NI = N[indep]
        d, ns = NI.shape[1], len(self._s)
        if NI.shape[0] != d:
            return None
        T = np.zeros((2 * d + ns, 2 * d + ns))
        T[:d, :d] = T[d:2 * d, d:2 * d] = NI
        T[2 * d:, 2 * d:] = np.eye(ns)
        return T

    def _linear_names(self, n: int) -> tuple[str, ...]:
        names = self._names.get(n)
        if names is None:
            d = (n - len(self._s)) // 2
            names = self._names[n] = (*(f"eta{i + 1}" for i in range(d)),
                                      *(velocity_name(f"eta{i + 1}") for i in range(d)), *self.mech.element_states)
        return names

    def reduced_matrices(self, x: np.ndarray) -> tuple[np.ndarray, ...]:
        """``(Mr, Cr, Kr, Br, Rq N, Rv N, Rs)`` at the equilibrium ``x`` (see the module docstring): reduced
        mass (kg, kg m^2), damping (N s/m ...), tangent stiffness (N/m ...), state forces, and the states' rates'
        derivatives along the allowed motions."""
        return tuple(part[0] for part in self._reduced(np.asarray(x, dtype=float)[None, :]).matrices())

    def _reduced(self, X: np.ndarray, project: bool = False) -> Reduced:
        """:meth:`reduced_matrices` at every row of ``X`` (m, n_variables), stacked: one compiled call per
        group of terms (the statics' ``Phi_q``, ``Q``, ``dQ/dq`` and constraint Hessians in one). ``project``:
        every row's allowed motions are the first row's projected onto its own (:meth:`linearise_near`)."""
        mech = self.mech
        m, nq = len(X), len(self._q)
        args = mech._batch_args(X)
        layout = mech._statics_layout
        vals = np.asarray(mech._statics.batch(args), dtype=float).reshape(m, -1)
        N, lam = motions_and_reactions(layout.constraint_jacobians(vals), vals[:, layout.q_slice],
                                       len(self._partition(X[0])[2]), project)
        if len(self._bases) >= 4:
            del self._bases[next(iter(self._bases))]
        self._bases[X[0].tobytes()] = N[0]
        M = mech._M.batch(args)
        negC = mech._dQdqd.batch(args)  # -C = dQ/dqdot - d M
        if self.damping:
            negC = negC - self.damping * M
        ns = len(self._s)
        if ns:
            J = mech._rates_jac.batch(args).reshape(m, ns, 2 * nq + ns)
            dQs = mech._dQds.batch(args).reshape(m, nq, ns)
        else:
            J, dQs = np.zeros((m, 0, 2 * nq)), np.zeros((m, nq, 0))
        return reduced_blocks(N, M, negC, -layout.stiffnesses(vals, lam), dQs, J)
