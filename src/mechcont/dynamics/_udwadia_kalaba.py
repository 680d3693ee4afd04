"""The Udwadia–Kalaba fundamental equation for any :class:`~mechcont.equations.MechanicalModel`.

For coordinates ``q`` with mass matrix ``M(q)``, generalised forces ``Q(q, qdot, t)`` and
holonomic constraints ``Phi(q) = 0``, the constrained accelerations are (paper eq. 1,
Udwadia & Kalaba 1996)

    qddot = a + M^-1/2 (A M^-1/2)^+ (b - A a),          a = M^-1 Q,

with ``A = Phi_q`` and ``b`` the right-hand side of the twice-differentiated constraints
``A qddot = b``. Exactly, ``b = gamma = -(Phi_q qdot)_q qdot``; with Baumgarte
stabilisation the constraints obey ``Phi'' + 2 alpha Phi' + beta^2 Phi = 0`` instead, i.e.

    b = gamma - 2 alpha Phi_q qdot - beta^2 Phi,

so that numerical drift decays instead of growing (alpha, beta in 1/s).

``Q`` is the applied forces plus, where ``M`` depends on ``q`` (a body frame away from its centre
of gravity, Euler parameters, a reduced form), the velocity-product inertial forces
``-(Mdot qdot - 1/2 d(qdot^T M qdot)/dq)`` of Lagrange's equations
(:meth:`~mechcont.equations.MechanicalModel.inertial_forces`): without them the motion would
depend on where a body's frame sits, and energy would not be conserved.

``(A M^-1/2)^+`` is the Moore–Penrose inverse, which makes the equation valid for
redundant constraints too. When ``B = A M^-1/2`` has full row rank, ``B^+ = B^T (B B^T)^-1``
and the equation is the same as the augmented (KKT) system ``M qddot + A^T lambda = Q,
A qddot = b``: we use a Cholesky factorisation of ``B B^T = A M^-1 A^T`` on that path (a few
microseconds) and fall back to the SVD pseudo-inverse when it is (nearly) singular.

Redundant rows (a spatial ``redundant = "drop"`` closure keeps every rigid row in its mechanics) are
dependent only up to the drift, so no cut-off decides their rank well: the number of redundant rows is
the model's (``Model.dropped_constraints``) and that many are left out of each solve, chosen by a pivoted
QR and chosen again where the kept rows lose rank (:mod:`._redundant`); the solve stays on the Cholesky
path, and the pseudo-inverse is left for a genuinely singular configuration.

On the Cholesky path the equation is solved through ``M^-1``: ``M^-1/2 (A M^-1/2)^+ r =
M^-1 A^T (A M^-1 A^T)^-1 r``. ``M^-1`` is formed once when ``M`` does not depend on the coordinates
(bars described by centre-of-gravity coordinates, as in the paper: a diagonal ``M``, kept as a vector).
Otherwise (spatial bodies in Euler parameters) ``M`` is block diagonal, one block per body, and
``M^-1`` is formed block by block at each evaluation (:class:`MassBlocks`: nine 7 x 7 inverses in one
batched call instead of one 63 x 63). Each acceleration evaluates the mechanics (``Phi_q``, ``gamma``,
``Phi``, the forces, ``M``) from one argument vector
(:meth:`~mechcont.equations.MechanicalModel.acceleration_terms`). ``M^-1/2``, the symmetric inverse
square root from the eigen-decomposition of ``M`` (block by block likewise), serves the pseudo-inverse
path and the projections.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING

import numpy as np
from scipy.linalg.lapack import dpotrf, dpotrs

from ..equations import symbol_names
from ..errors import InputError
from ._mass import MassBlocks, inverse_sqrt
from ._redundant import KeptRows

if TYPE_CHECKING:
    from ..equations import Mechanics, Model
    from ._contact import StopConstraints

__all__ = ["fundamental_equation", "inverse_sqrt", "MassBlocks", "ConstrainedDynamics"]

#: Relative cut-off of the singular values of ``A M^-1/2`` in the pseudo-inverse path, which is taken only when
#: the rows are (nearly) dependent (the Cholesky test fails): since issue 38 the redundant rows of an
#: over-constrained closure are left out before the solve (:mod:`._redundant`), so this path is left for
#: singular configurations and for the initial projection. Redundant rows are dependent only up to the
#: constraint drift (1e-9 relative on the Bennett linkage): kept at 1e-12 they were inverted, and even at
#: 1e-8 the Cholesky test let them through at times (Bricard's loop: 496 switches of path in 2 s).
_RCOND = 1e-8


def _cholesky_solve(G: np.ndarray, r: np.ndarray, spread: list[float] | None = None) -> np.ndarray | None:
    """``G^-1 r`` for a symmetric positive definite ``G`` (``B B^T`` or ``A M^-1 A^T``), or None when ``G`` is
    (nearly) singular: its Cholesky factor's diagonal spread beyond 1e6, i.e. rcond(G) below ~1e-12 (the
    rows are dependent: the callers take the pseudo-inverse). LAPACK is called directly (``dpotrf``/``dpotrs``):
    for the 5 x 6 overcentre five times cheaper than ``numpy.linalg.pinv``. ``spread``, when given, receives
    the factor's smallest over its largest diagonal entry (0 when the factorisation fails): how far the rows
    are from losing rank, at no extra cost (:class:`~._redundant.KeptRows` watches it)."""
    c, info = dpotrf(G, lower=1, clean=0)
    if info != 0:
        if spread is not None:
            spread.append(0.0)
        return None
    d = c.diagonal()  # positive: dpotrf succeeded
    lo, hi = d.min(), d.max()
    if spread is not None:
        spread.append(float(lo / hi))
    if not lo > 1e-6 * hi:
        return None
    z, _ = dpotrs(c, r, lower=1)
    return z


def _pinv_apply(B: np.ndarray, r: np.ndarray, spread: list[float] | None = None) -> np.ndarray:
    """``B^+ r`` for a wide matrix ``B``: Cholesky of ``B B^T`` if well conditioned, else SVD (``spread``: see
    :func:`_cholesky_solve`)."""
    z = _cholesky_solve(B @ B.T, r, spread)
    return B.T @ z if z is not None else np.linalg.pinv(B, rcond=_RCOND) @ r


def fundamental_equation(M_inv_sqrt: np.ndarray, Q: np.ndarray, A: np.ndarray, b: np.ndarray,
                         spread: list[float] | None = None) -> np.ndarray:
    """Constrained accelerations ``qddot = a + M^-1/2 (A M^-1/2)^+ (b - A a)``, ``a = M^-1 Q``.

    Parameters
    ----------
    M_inv_sqrt:
        ``M^-1/2`` (n x n), see :func:`inverse_sqrt`.
    Q:
        Applied generalised forces (n,), N or N m.
    A, b:
        Acceleration-level constraints ``A qddot = b``: (p x n) and (p,).
    spread:
        Optional list that receives how far the rows of ``A M^-1/2`` are from losing rank (see
        :func:`_cholesky_solve`).

    Returns
    -------
    numpy.ndarray
        ``qddot`` (n,), m/s^2 or rad/s^2.
    """
    a = M_inv_sqrt @ (M_inv_sqrt @ Q)
    if A.shape[0] == 0:
        return a
    B = A @ M_inv_sqrt
    return a + M_inv_sqrt @ _pinv_apply(B, b - A @ a, spread)


def _mass_samples(mech: Mechanics, x: np.ndarray, q_index: np.ndarray, samples: int = 3) -> tuple[np.ndarray, list[np.ndarray]]:
    """``M`` at ``x`` and at ``samples`` coordinate vectors moved at random (seeded) from it: a constant mass
    matrix is the same at all of them, and the union of their non-zero entries is ``M``'s pattern (an entry
    that is not identically zero vanishes at random points with probability 0). Numerical, so that the
    symbolic matrix (kept pickled in a cached model: seconds to load for a 63-coordinate gear) is not needed."""
    rng = np.random.default_rng(0)
    moved = []
    for _ in range(samples):
        y = np.array(x, float)
        y[q_index] += rng.uniform(-0.5, 0.5, len(q_index))
        moved.append(mech.mass(y))
    return mech.mass(x), moved


class ConstrainedDynamics:
    """The first-order ODE ``y' = f(t, y)``, ``y = (q, qdot, s)``, of a mechanism (``s``: the first-order
    states of its elements, :attr:`~mechcont.equations.MechanicalModel.element_states`, integrated with
    their rates ``r(q, qdot, s)``; none for most mechanisms).

    Parameters
    ----------
    system:
        A :class:`~mechcont.equations.Model` with ``mechanics`` set.
    x:
        Full variable vector (ordered like ``system.names``) holding the parameter values;
        its coordinate entries are ignored.
    loads:
        ``{parameter name: callable t -> value}`` for time-varying parameters (e.g. a ramp
        of the applied force ``F``). They may enter the applied forces only, not the
        constraints or the mass matrix (that would need rheonomic terms).
    baumgarte:
        ``(alpha, beta)`` in 1/s, or ``None`` for the exact ``b = gamma``.
    damping:
        Mass-proportional (Rayleigh) damping coefficient ``d`` in 1/s: the generalised
        force ``-d M qdot`` is added. Along any allowed motion it damps a mode of angular
        frequency ``omega`` with ratio ``d / (2 omega)``; its component across the
        constraints is taken up by the joint reactions, so it does no work against them.
    """

    #: ``M^-1`` when the mass matrix is constant (its diagonal when diagonal), else None (:meth:`_inverse_times`).
    _minv: np.ndarray | None = None

    def __init__(self, system: Model, x: np.ndarray, loads: Mapping[str, Callable[[float], float]] | None = None,
                 baumgarte: tuple[float, float] | None = (10.0, 10.0), damping: float = 0.0) -> None:
        mech = system.mechanics
        if mech is None:
            raise InputError(system.name, "model has no mechanics (coordinates, constraints, masses); cannot simulate")
        self.system = system
        self.mech = mech
        self.q_index = np.asarray(mech.q_index)
        self.nq = len(self.q_index)
        #: Positions in ``x`` of the element states and their number (they follow ``(q, qdot)`` in ``y``).
        self.s_index = np.asarray(getattr(mech, "s_index", np.zeros(0, np.intp)), dtype=np.intp)
        self.ns = len(self.s_index)
        self.x = np.array(x, dtype=float)
        if self.x.shape != (len(system.names),):
            raise InputError("x0", f"needs {len(system.names)} values ordered like the model's names")
        if baumgarte is not None:
            if len(baumgarte) != 2 or min(baumgarte) < 0 or not np.all(np.isfinite(baumgarte)):
                raise InputError("baumgarte", "must be (alpha, beta) with alpha, beta >= 0 (1/s), or None")
            self.alpha, self.beta = float(baumgarte[0]), float(baumgarte[1])
        else:
            self.alpha = self.beta = 0.0
        if not (np.isfinite(damping) and damping >= 0):
            raise InputError("damping", "must be a non-negative number (1/s)")
        self.damping = float(damping)
        loads = dict(loads or {})
        rigid = symbol_names([*mech.constraints, *mech.mass_matrix]) if loads else set()
        for name, fn in loads.items():
            i = system.index(name)
            if i in set(self.q_index.tolist()):
                raise InputError(name, "is a coordinate; only parameters can be prescribed as loads")
            if name in rigid:
                raise InputError(name, "enters the constraints or the mass matrix; only force parameters can vary in time")
            if not callable(fn):
                raise InputError(name, "load must be a callable t -> value")
        self._loads = [(system.index(n), fn) for n, fn in loads.items()]
        M, moved = _mass_samples(mech, self.x, self.q_index)
        self._mass_constant = all(np.array_equal(M, Mk) for Mk in moved)
        self._Mis = inverse_sqrt(M) if self._mass_constant else None
        self._M = M if self._mass_constant else None
        if self._mass_constant:  # each solve applies M^-1: formed once (a diagonal one as a vector)
            self._minv = 1.0 / np.diag(M) if not np.count_nonzero(M - np.diag(np.diag(M))) else np.linalg.inv(M)
        pattern = np.argwhere(sum((np.abs(Mk) for Mk in moved), np.abs(M)) > 0)
        self._blocks = None if self._mass_constant else MassBlocks(self.nq, pattern.tolist())
        self.nfev = 0
        #: The stops as unilateral constraints (a :class:`~._contact.StopConstraints`), or None.
        self.contacts: StopConstraints | None = None
        self._last: tuple | None = None  # the last solve with its multipliers (see recall)
        # the redundant rows the mechanics still holds (a spatial model keeps every rigid row; a planar one
        # has left its dropped rows out already): that many are left out of each solve
        names = set(mech.constraint_names or ())
        dropped = system.dropped_constraints
        n_drop = sum(r in names for r in dropped)
        #: The joint rows solved with when the model has redundant rows (:class:`~._redundant.KeptRows`), or None.
        self.kept: KeptRows | None = KeptRows(n_drop) if n_drop else None
        #: True when the model dropped redundant rows: its joint reactions are statically indeterminate (a
        #: planar model's dropped rows carry none; a spatial history reports the minimum-norm split).
        self.indeterminate = bool(dropped)

    # -- helpers -------------------------------------------------------------------------
    def full(self, t: float, q: np.ndarray, s: np.ndarray | None = None) -> np.ndarray:
        """Full variable vector at time ``t`` with coordinates ``q``, element states ``s`` (default: ``x``'s)
        and loads applied."""
        x = self.x.copy()
        x[self.q_index] = q
        if s is not None and self.ns:
            x[self.s_index] = s
        for i, fn in self._loads:
            x[i] = fn(t)
        return x

    def fulls(self, ts: np.ndarray, q: np.ndarray) -> np.ndarray:
        """:meth:`full` at each time of ``ts`` with the coordinates of each row of ``q`` (rows x n_q): array
        (rows, n_variables), the same values."""
        X = np.empty((len(ts), len(self.x)))
        X[:] = self.x
        X[:, self.q_index] = q
        for i, fn in self._loads:
            X[:, i] = [fn(float(t)) for t in ts]
        return X

    def split(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(q, qdot, s)`` of a state ``y``."""
        nq = self.nq
        return y[:nq], y[nq:2 * nq], y[2 * nq:]

    def full_of(self, t: float, y: np.ndarray) -> np.ndarray:
        """Full variable vector at time ``t`` of the state ``y`` (coordinates and element states)."""
        return self.full(t, y[:self.nq], y[2 * self.nq:])

    def mass_inv_sqrt(self, x: np.ndarray) -> np.ndarray:
        """``M^-1/2`` at ``x`` (cached when the mass matrix is constant)."""
        if self._Mis is not None:
            return self._Mis
        assert self._blocks is not None
        return self._blocks.inverse_sqrt(self.mech.mass(x))

    def mass_matrix(self, x: np.ndarray) -> np.ndarray:
        """``M`` at ``x`` (kg, kg m^2; the one of the start when it is constant)."""
        return self._M if self._M is not None else self.mech.mass(x)

    def _inverse_times(self, x: np.ndarray, R: np.ndarray, M: np.ndarray | None = None) -> np.ndarray:
        """``M^-1 R`` for ``R`` of shape (n, k): by the constant inverse, or block by block from ``M`` (default
        ``M`` at ``x``)."""
        minv = self._minv
        if minv is not None:
            return minv[:, None] * R if minv.ndim == 1 else minv @ R
        assert self._blocks is not None
        return self._blocks.inverse(self.mech.mass(x) if M is None else M) @ R

    def forces(self, x: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """Generalised forces of the equations of motion ``M qddot = forces + Phi_q^T lambda`` (N, N m):
        the applied forces, the velocity-product inertial forces (when ``M`` depends on ``q``), the
        Rayleigh damping term and the compliant stops' reactions."""
        if self.contacts is not None:  # the compliant stops' penalty reactions
            x = self.contacts.penalized(x, qd)
        Q = self.mech.applied_forces(x, qd)
        if not self._mass_constant:  # centrifugal, Coriolis and gyroscopic forces: M depends on q
            Q = Q + self.mech.inertial_forces(x, qd)
        if self.damping:
            Q = Q - self.damping * (self.mass_matrix(x) @ qd)
        return Q

    def _terms(self, x: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
        """``(A, b, forces, M)``: :meth:`joint_rows` and :meth:`forces` at ``x`` from one evaluation of the mechanics
        (:meth:`~mechcont.equations.MechanicalModel.acceleration_terms`), the same values; ``M`` None when constant."""
        stabilised = bool(self.alpha or self.beta)
        A, b, phi, Q, M = self.mech.acceleration_terms(x, qd, drift=stabilised, varying_mass=not self._mass_constant)
        if stabilised:
            assert phi is not None
            b = b - 2.0 * self.alpha * (A @ qd) - self.beta**2 * phi
        if self.contacts is not None and self.contacts.law:  # the compliant stops' reactions enter the forces
            Q = self.forces(x, qd)
        elif self.damping:
            Q = Q - self.damping * ((self._M if M is None else M) @ qd)
        return A, b, Q, M

    def joint_rows(self, x: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(A, b)``: the joints' acceleration-level constraints ``A qddot = b``, Baumgarte-stabilised."""
        A = self.mech.phi_q(x)
        b = self.mech.gamma(x, qd)
        if self.alpha or self.beta:
            b = b - 2.0 * self.alpha * (A @ qd) - self.beta**2 * self.mech.phi(x)
        return A, b

    def _solved_rows(self, x: np.ndarray, qd: np.ndarray, A: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The rows a solve uses: the joints' (those kept, with redundant rows: :attr:`kept`), then the stops'."""
        if self.kept is not None and A.shape[0]:
            keep = self.kept.select(A)
            A, b = A[keep], b[keep]
        if self.contacts is not None:  # the stops in contact are constraint rows too
            A, b = self.contacts.rows(x, qd, A, b)
        return A, b

    def _full_multipliers(self, z: np.ndarray) -> np.ndarray:
        """The multipliers of the kept rows (then of the stops in contact) spread over every joint row: a
        dropped row carries none."""
        if self.kept is None or self.kept.keep is None:
            return z
        keep = self.kept.keep
        out = np.zeros(self.mech.n_constraints + len(z) - len(keep))
        out[keep] = z[:len(keep)]
        out[self.mech.n_constraints:] = z[len(keep):]
        return out

    def acceleration(self, t: float, q: np.ndarray, qd: np.ndarray, s: np.ndarray | None = None) -> np.ndarray:
        """Constrained accelerations at time ``t`` (the fundamental equation, stabilised); ``s``: the element
        states (default ``x``'s).

        All ``nan`` when the state, a load or the forces are not finite: the integrator then
        rejects the step, shrinks it and reports where it failed.
        """
        x = self.full(t, q, s)
        # the arrays' own .all(): numpy.all's dispatch cost more than the test on these short vectors (it ran
        # five times per evaluation of the rates)
        if not (np.isfinite(x).all() and np.isfinite(qd).all()):
            return np.full(self.nq, np.nan)
        A_joints, b_joints, Q, M = self._terms(x, qd)
        A, b = self._solved_rows(x, qd, A_joints, b_joints)
        if not (np.isfinite(Q).all() and np.isfinite(A).all() and np.isfinite(b).all()):
            return np.full(self.nq, np.nan)
        qdd, z = self._solve(x, Q, A, b, M)
        # the kept rows' conditioning, read off the solve's own Cholesky factor: where they lose rank along
        # the motion they are chosen again (QR with column pivoting) and the solve repeated with them
        if self.kept is not None and self.kept.stale(t, A_joints, self._spread):
            A, b = self._solved_rows(x, qd, A_joints, b_joints)
            qdd, z = self._solve(x, Q, A, b, M)
            self.kept.rechosen(self._spread)
        self._last = (t, np.array(q), np.array(qd), self._mode(), qdd, None if z is None else self._full_multipliers(z), Q,
                      None if s is None else np.array(s))
        return qdd

    def _solve(self, x: np.ndarray, Q: np.ndarray, A: np.ndarray, b: np.ndarray,
               M: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray | None]:
        """``(qddot, z)`` of the fundamental equation with the rows ``A``, ``b`` (``z`` None on the pseudo-inverse
        path), through ``M^-1`` (``M``: the mass matrix at ``x`` when known); the Cholesky factor's diagonal
        spread left in ``self._spread``."""
        self._spread: list[float] = []
        if A.shape[0]:
            solved = self._by_inverse(x, Q, A, b, with_multipliers=True, spread=self._spread, M=M)
            if solved is not None:
                return solved[0], solved[1]
        elif self._minv is not None:  # no rows: M qddot = Q
            return self._inverse_times(x, Q[:, None])[:, 0], np.zeros(0)
        return fundamental_equation(self.mass_inv_sqrt(x), Q, A, b, self._spread), None

    def _mode(self) -> tuple[int, ...]:
        return () if self.contacts is None else tuple(self.contacts.active)

    def recall(self, t: float, q: np.ndarray, qd: np.ndarray,
               s: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray | None, np.ndarray] | None:
        """``(qddot, z, forces)`` of the last :meth:`acceleration` if it was made at exactly this state and
        contact set (the integrator's last evaluation of a step is at the step's end), else None: the
        history's reactions and energy bound reuse it instead of solving again. ``z`` (the multipliers) is
        None when that solve did not form them (the pseudo-inverse path)."""
        last = self._last
        if (last is None or last[0] != t or last[3] != self._mode() or not np.array_equal(last[1], q)
                or not np.array_equal(last[2], qd)):
            return None
        if self.ns and (last[7] is None or s is None or not np.array_equal(last[7], s)):
            return None
        return last[4], last[5], last[6]

    def _by_inverse(self, x: np.ndarray, Q: np.ndarray, A: np.ndarray, b: np.ndarray, with_multipliers: bool = False,
                    spread: list[float] | None = None,
                    M: np.ndarray | None = None) -> np.ndarray | tuple[np.ndarray, np.ndarray] | None:
        """The fundamental equation through ``M^-1`` (constant, or block by block from ``M``, default the mass
        matrix at ``x``) when ``A`` has full row rank: ``M^-1/2 (A M^-1/2)^+ r = M^-1 A^T (A M^-1 A^T)^-1 r``,
        the same matrix ``A M^-1 A^T`` and rank test as :func:`fundamental_equation`'s Cholesky path, without
        the eigen-decomposition of ``M``. None when that matrix is (nearly) singular: the caller takes the
        pseudo-inverse path. With ``with_multipliers``: ``(qddot, z)``, ``z = (A M^-1 A^T)^-1 r`` the
        multipliers (``M qddot = Q + A^T z``)."""
        R = np.empty((len(Q), A.shape[0] + 1))  # M^-1 applied to Q and A^T at once
        R[:, 0] = Q
        R[:, 1:] = A.T
        C = self._inverse_times(x, R, M)
        a, MA = C[:, 0], C[:, 1:]
        z = _cholesky_solve(A @ MA, b - A @ a, spread)
        if z is None:
            return None
        return (a + MA @ z, z) if with_multipliers else a + MA @ z

    def multipliers(self, t: float, q: np.ndarray, qd: np.ndarray,
                    s: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, bool]:
        """``(qddot, z, determinate)`` at time ``t``: the accelerations and the Lagrange multipliers ``z`` of
        the same solve, ``M qddot = forces + A^T z`` with ``A qddot = b`` (the joints' rows, then those of the
        stops in contact, :meth:`joint_rows` and :meth:`~._contact.StopConstraints.rows`).

        ``b`` is the Baumgarte-stabilised right-hand side the integrator uses, so ``qddot`` is the
        acceleration integrated and ``z`` the reactions that produce it (on the constraint manifold at
        rest the stabilisation terms vanish). ``forces`` is :meth:`forces`: applied, velocity-product
        inertial, Rayleigh and compliant-stop forces. ``z`` follows the dynamics' sign: a joint's
        reaction as the statics writes it (``Q - Phi_q^T lambda = 0``) is ``lambda = -z``; a stop's
        contact reaction is ``+z``. ``determinate`` is False when ``A M^-1/2`` is rank deficient
        (redundant constraints): ``z`` is then the minimum-norm multiplier vector, one of many that
        give the same ``qddot`` (N, N m: units of each row's reaction)."""
        known = self.recall(t, q, qd, s)
        determinate = not self.indeterminate  # redundant rows: one split of indeterminate reactions
        if known is not None and known[1] is not None:
            return known[0], known[1], determinate
        x = self.full(t, q, s)
        A_joints, b_joints, Q, M = self._terms(x, qd)
        A, b = self._solved_rows(x, qd, A_joints, b_joints)
        if A.shape[0]:  # the accelerations' own path: Cholesky of A M^-1 A^T
            solved = self._by_inverse(x, Q, A, b, with_multipliers=True, M=M)
            if solved is not None:
                return solved[0], self._full_multipliers(solved[1]), determinate
        Mis = self.mass_inv_sqrt(x)
        a = Mis @ (Mis @ Q)
        if A.shape[0] == 0:
            return a, np.zeros(0), True
        B = A @ Mis
        r = b - A @ a
        z = _cholesky_solve(B @ B.T, r)  # full row rank, as in _pinv_apply: z = (B B^T)^-1 r
        if z is not None:
            return a + Mis @ (B.T @ z), self._full_multipliers(z), determinate
        # redundant rows, from one SVD B = U S V^T cut at _RCOND as np.linalg.pinv cuts it: the step
        # w = B^+ r = V S^-1 U^T r of _pinv_apply, and the minimum-norm z with B^T z = w, z = U S^-2 U^T r
        U, sv, Vt = np.linalg.svd(B, full_matrices=False)
        rank = int(np.count_nonzero(sv > _RCOND * max(sv[0], 1e-300))) if sv.size else 0
        c = (U[:, :rank].T @ r) / sv[:rank]
        z = self._full_multipliers(U[:, :rank] @ (c / sv[:rank]))
        return a + Mis @ (Vt[:rank].T @ c), z, rank == A.shape[0] and determinate

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        """Right-hand side ``(qdot, qddot, sdot)`` of the first-order system."""
        self.nfev += 1
        if not self.ns:
            q, qd = y[: self.nq], y[self.nq:]
            return np.concatenate([qd, self.acceleration(t, q, qd)])
        q, qd, s = self.split(y)
        qdd = self.acceleration(t, q, qd, s)
        return np.concatenate([qd, qdd, self.mech.element_state_rates(self.full(t, q, s), qd)])

    # -- projection onto the constraint manifold (M-metric, like the fundamental equation) --
    def project(self, t: float, q: np.ndarray, qd: np.ndarray, tol: float = 1e-12,
                max_iter: int = 20, hold: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Nearest consistent state: ``Phi(q) = 0`` and ``Phi_q qdot = 0``.

        Corrections are the minimum-kinetic-energy ones, ``dq = -M^-1/2 (A M^-1/2)^+ Phi``
        (Gauss–Newton) and ``qdot -= M^-1/2 (A M^-1/2)^+ A qdot``. ``hold`` is an optional
        boolean mask of coordinates kept fixed. Raises :class:`InputError` (field ``x0``)
        if the constraints cannot be satisfied.
        """
        q = np.array(q, float)
        qd = np.array(qd, float)
        free = np.ones(self.nq, bool) if hold is None else ~np.asarray(hold, bool)
        phi = self.mech.phi(self.full(t, q))
        for _ in range(max_iter):
            if phi.size == 0 or np.max(np.abs(phi)) <= tol:
                break
            x = self.full(t, q)
            Mis = self.mass_inv_sqrt(x)[np.ix_(free, free)]
            A = self.mech.phi_q(x)[:, free]
            q[free] -= Mis @ (np.linalg.pinv(A @ Mis, rcond=_RCOND) @ phi)
            phi = self.mech.phi(self.full(t, q))
        if phi.size and np.max(np.abs(phi)) > 1e3 * tol + 1e-9:
            raise InputError("x0", f"cannot assemble the mechanism: constraint residual {np.max(np.abs(phi)):.3g} "
                                   "(start values of the coordinates are too far from a valid configuration)")
        x = self.full(t, q)
        A = self.mech.phi_q(x)
        if A.shape[0]:
            Mis = self.mass_inv_sqrt(x)
            qd = qd - Mis @ (np.linalg.pinv(A @ Mis, rcond=_RCOND) @ (A @ qd))
        return q, qd
