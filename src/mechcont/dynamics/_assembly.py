"""The start of a time simulation: the mechanism assembled, its compliant joints at their loaded deflection.

A rigid mechanism is assembled kinematically: the coordinates and conditions the user holds keep their
values, the others are corrected by Gauss–Newton with minimum-kinetic-energy steps onto ``Phi = 0``.

A compliant joint (a spatial joint with a ``stiffness``) is no constraint of the dynamics but a spring
(:mod:`mechcont.mechanism.spatial._generate`): a kinematic assembly would move its deflection as freely
as any coordinate the joints leave open, and the mechanism would be released with its springs stretched
by whatever the correction gave them. Physically the user *holds* the mechanism: at rest in the pose
asked for, the held coordinates and conditions are kept there by a reaction conjugate to each (a force
``f_j grad h_j``: a moment for an angle, a pair of forces along the line for a distance) and every other
coordinate is in static equilibrium. So the pose is the solution of

    Q(q) - Phi_q^T lambda - H^T f - B^T g = 0,    Phi(q) = 0,    h(q) = h0,    B (q - q0) = 0,

(``Q`` the applied forces with the compliant joints' springs, ``Phi`` the rigid rows, ``h`` the held
coordinates and conditions) for ``q``, the joint reactions ``lambda`` and the holding forces ``f``.

The motions ``N`` that the rigid rows allow, the held states do not fix and the compliant deflections do
not change along (the mechanism's own motions, its compliant joints taken as rigid) are not held: they
start at release. They stay where the kinematic assembly ``q0`` put them (``B = N^T M``, in the
kinetic-energy metric) and the term ``B^T g = M N g`` is the d'Alembert force of the acceleration ``N g``
they start with: released at rest, ``M N g = Q - Phi_q^T lambda`` and ``Phi_q N = 0``, so the mechanism
starts with exactly that acceleration, its compliant deflections with none (no snap of its springs). ``N``
depends on the pose it is taken at: it is taken again at the pose found until the pose no longer moves (an
over-constrained closure mobile only by its geometry, Bennett's, keeps its motion only undeflected: there
``N`` changes the deflections least, by their size over the linkage's). An over-constrained rigid closure
leaves ``lambda`` indeterminate but not the pose: the Newton steps are least-squares ones.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..equations import Model
from ..errors import InputError
from ._udwadia_kalaba import ConstrainedDynamics

__all__ = ["initial_vector", "assemble"]

#: Relative rank cut of the assembly's least-squares steps (after equilibration).
_RCOND = 1e-12


def initial_vector(system: Model, x0: np.ndarray | Mapping[str, float] | Sequence[float]) -> np.ndarray:
    """Full variable vector from an array (ordered like ``system.names``) or a ``{name: value}`` mapping.

    A mapping overrides the model's default values by name.
    """
    if isinstance(x0, Mapping):
        return system.vector(x0)
    x = np.array(x0, dtype=float)
    if x.shape != (len(system.names),) or not np.all(np.isfinite(x)):
        raise InputError("x0", f"needs {len(system.names)} finite values ordered like the model's names "
                               f"({', '.join(system.names)}), or a mapping name -> value")
    return x


def assemble(system: Model, values: np.ndarray | Mapping[str, float] | Sequence[float], hold: Sequence[str] = (), *,
             kinematic: bool = False) -> np.ndarray:
    """A full variable vector whose coordinates satisfy the constraints ``Phi = 0``, at rest in static
    equilibrium where joints are compliant.

    Parameters
    ----------
    system:
        A model with ``mechanics``.
    values:
        Full vector or ``{name: value}`` overriding the defaults: parameters, and
        coordinates as a starting guess.
    hold:
        Coordinates kept at their given values (e.g. ``["theta1"]`` for a 1-DOF mechanism), or
        conditions of a description (``[conditions]``) held at their given values; the other
        coordinates are corrected by Gauss–Newton with minimum-kinetic-energy steps.
    kinematic:
        With compliant joints (a spatial joint's ``stiffness``): False (default) puts them at their
        loaded deflection, the static equilibrium of the mechanism held at the ``hold`` values by a
        reaction conjugate to each (a moment for an angle, forces along the line for a distance; motions
        nothing holds loaded by the d'Alembert force of their start: see the module); True moves them as
        freely as the rigid joints allow (for a pose that is already static, e.g. ``freefall``'s
        ``held_by``). A mechanism without compliant joints is assembled kinematically either way.

    Returns
    -------
    numpy.ndarray
        Assembled vector ordered like ``system.names`` (the reactions as given). Raises
        :class:`InputError` if the constraints cannot be met from that guess, or no static pose is found.
    """
    x = initial_vector(system, values)
    dyn = ConstrainedDynamics(system, x, baumgarte=None)
    coords = [system.names[i] for i in dyn.q_index]
    rows = list(getattr(system, "equation_names", ()))
    conditions = [h for h in hold if h not in coords and f"cond_{h}" in rows]
    for h in hold:
        if h not in coords and h not in conditions:
            raise InputError(h, f"only coordinates or conditions can be held; valid: {', '.join(coords)}"
                                + "".join(f", {r[5:]}" for r in rows if r.startswith("cond_")))
    mask = np.array([c in hold for c in coords])
    cond_rows = [rows.index(f"cond_{h}") for h in conditions]
    if conditions:
        x = _hold_conditions(system, dyn, x, cond_rows, ~mask)
    try:
        q, _ = dyn.project(0.0, x[dyn.q_index], np.zeros(dyn.nq), hold=mask)
    except InputError as exc:  # say why when no pose exists: the loop that cannot close at the held values
        from ..mechanism import held_loop_error

        why = held_loop_error(system, x, [h for h in hold if h in coords])
        if why is None:
            raise
        raise InputError(exc.field, str(why).split(": ", 1)[-1]) from None
    x[dyn.q_index] = q
    if kinematic:
        return x
    from ..mechanism import compliant_constraints

    springs = compliant_constraints(system, x)
    if not springs:  # rigid: the kinematic assembly is the pose
        return x
    return _static_pose(system, dyn, x, mask, cond_rows, springs)


def _hold_conditions(system: Model, dyn: ConstrainedDynamics, x: np.ndarray, rows: list[int], free: np.ndarray,
                     tol: float = 1e-12, max_iter: int = 30) -> np.ndarray:
    """``x`` with its ``free`` coordinates moved (Gauss–Newton, minimum-kinetic-energy steps) so that
    the joints close and the condition rows ``c(q) - NAME`` (``NAME`` at its value in ``x``) vanish."""
    x = np.array(x, float)
    qi = dyn.q_index[free]
    scale = system.scales()[dyn.q_index]
    nphi = len(dyn.mech.phi(x))

    def size(J: np.ndarray) -> np.ndarray:  # each row's size at the coordinates' scales: the tests hold in any units
        return (np.abs(np.vstack([dyn.mech.phi_q(x).reshape(-1, dyn.nq), J[rows][:, dyn.q_index]])) * scale).sum(axis=1)

    for _ in range(max_iter):
        G, J = system.residual_and_jacobian(x)
        r = np.concatenate([dyn.mech.phi(x), G[rows]])
        if np.all(np.abs(r) <= tol * size(J)):
            return x
        A = np.vstack([dyn.mech.phi_q(x).reshape(-1, dyn.nq)[:, free], J[rows][:, qi]])
        Mis = dyn.mass_inv_sqrt(x)[np.ix_(free, free)]
        x[qi] -= Mis @ (np.linalg.lstsq(A @ Mis, r, rcond=1e-12)[0])
    G, J = system.residual_and_jacobian(x)
    excess = np.abs(G[rows]) / (1e-9 * np.maximum(size(J)[nphi:], 1e-300))
    worst = float(np.max(np.abs(G[rows]), initial=0.0))
    if np.max(excess, initial=0.0) > 1:
        raise InputError("x0", f"cannot assemble the mechanism with the conditions held: residual {worst:.3g} "
                               "(is the value reachable from the start configuration?)")
    return x


def _static_pose(system: Model, dyn: ConstrainedDynamics, x: np.ndarray, held: np.ndarray, cond_rows: list[int],
                 springs: list[tuple[int, str, float]]) -> np.ndarray:
    """The kinematically assembled ``x`` (held coordinates ``held``, a mask over the coordinates; held
    condition rows ``cond_rows``) moved to the static pose with the compliant rows ``springs`` (``(row,
    reaction, -1/k)`` of the static system) at their loaded deflection (see the module)."""
    pose = _Statics(system, dyn, held, cond_rows, [row for row, _, _ in springs])
    # the rigidified mechanism first (compliant rows closed as if rigid, their reactions zero in the rows):
    # then every motion it has is held or unheld (N), and Newton only finds the deflections
    xr = np.array(x, float)
    reactions = [system.index(r) for _, r, _ in springs]
    xr[reactions] = 0.0
    try:
        xr = _hold_conditions(system, dyn, xr, cond_rows + pose.spring_rows, ~held)
    except InputError:  # the rigid rows leave a misfit the compliant joints take up
        xr = np.array(x, float)
    pose.q0 = xr[dyn.q_index].copy()
    xq, mult, count = xr, None, None
    for _ in range(_OUTER):  # the unheld motions at the deflected pose: their start is then exactly rigid
        B = pose.unheld(xq, count)
        count = len(B)
        y, mult = pose.solve(xq, B, mult)
        moved = np.max(np.abs(y - xq)[dyn.q_index] / pose.scale, initial=0.0)
        xq = y
        if not len(B) or moved <= 1e-13:
            break
    xq[reactions] = x[reactions]  # the reactions as given, as for a rigid mechanism
    return xq


#: Most solves of :class:`_Statics` with the unheld motions taken at the last pose (each a few Newton steps).
_OUTER = 6


class _Statics:
    """The static equations of the module at the pose of a full vector: the held coordinates (mask ``held``),
    the held condition rows ``cond_rows`` and the compliant rows ``spring_rows`` of ``system``'s equations;
    ``q0`` (set by the caller) is the kinematic assembly the held values and the unheld motions keep."""

    def __init__(self, system: Model, dyn: ConstrainedDynamics, held: np.ndarray, cond_rows: list[int],
                 spring_rows: list[int]) -> None:
        self.system, self.dyn, self.mech = system, dyn, dyn.mech
        self.held_idx, self.cond_rows, self.spring_rows = np.flatnonzero(held), cond_rows, spring_rows
        self.scale = np.maximum(system.scales()[dyn.q_index], 1e-300)
        self.q0 = np.zeros(dyn.nq)

    def holds(self, xq: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``h(q) - h0`` and ``H = dh/dq`` of the held coordinates and conditions at ``xq``."""
        qi, nq = self.dyn.q_index, self.dyn.nq
        G, J = self.system.residual_and_jacobian(xq)
        H = np.vstack([np.eye(nq)[self.held_idx], J[self.cond_rows][:, qi]])
        return np.concatenate([xq[qi[self.held_idx]] - self.q0[self.held_idx], G[self.cond_rows]]), H

    def unheld(self, xq: np.ndarray, count: int | None = None) -> np.ndarray:
        """``B = N^T M``: ``N`` the motions at ``xq`` that the rigid rows allow (exactly: released, the mechanism
        can start along them), the held values do not fix and the compliant rows' deflections change least
        along: as many as leave them unchanged (``count`` None: at the rigidified pose), or the ``count`` that
        change them least (at a deflected pose an over-constrained closure such as Bennett's loses its
        mobility by a little). Scaled by the coordinates' scales, so that the choice is free of units."""
        qi, nq = self.dyn.q_index, self.dyn.nq
        # in coordinates of their scale (q = scale * s), the rows' Jacobians are scaled column by column
        fixed = np.vstack([self.mech.phi_q(xq).reshape(-1, nq), self.holds(xq)[1]]) * self.scale[None, :]
        Z = _null_space(fixed)
        springs = self.system.jacobian(xq)[self.spring_rows][:, qi] * self.scale[None, :]
        _, sv, Vt = np.linalg.svd(springs @ Z)
        if count is None:
            big = max(float(np.linalg.norm(springs, 2)), 1e-300)
            count = Z.shape[1] - int(np.sum(sv > 1e-10 * big))
        N = Z @ Vt[Vt.shape[0] - count:].T
        return (N.T * self.scale[None, :]) @ self.mech.mass(xq)

    def equations(self, xq: np.ndarray, B: np.ndarray, mult: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Residual and Jacobian of the static equations at ``xq`` with the multipliers ``(lambda, f, g)``."""
        mech, qi, nq = self.mech, self.dyn.q_index, self.dyn.nq
        nr = mech.n_constraints
        hres, H = self.holds(xq)
        nh, nb = len(H), len(B)
        lam, f, g = mult[:nr], mult[nr:nr + nh], mult[nr + nh:]
        A = mech.phi_q(xq).reshape(-1, nq)
        E = np.concatenate([mech.applied_forces(xq) - A.T @ lam - H.T @ f - B.T @ g, mech.phi(xq), hres,
                            B @ (xq[qi] - self.q0)])
        # d(H^T f)/dq: the held conditions' curvature (central differences of their gradients)
        W = np.zeros((nq, nq))
        cond_f = f[len(self.held_idx):]
        for i in np.flatnonzero(np.any(H[len(self.held_idx):] != 0, axis=0)) if np.any(cond_f) else ():
            step = 1e-6 * self.scale[i]
            grads = []
            for s in (step, -step):
                y = xq.copy()
                y[qi[i]] += s
                grads.append(self.holds(y)[1].T @ f)
            W[:, i] = (grads[0] - grads[1]) / (2 * step)
        K = mech.tangent_stiffness(xq, lam) + W
        Z = np.zeros
        Jac = np.block([[-K, -A.T, -H.T, -B.T], [A, Z((nr, nr + nh + nb))], [H, Z((nh, nr + nh + nb))],
                        [B, Z((nb, nr + nh + nb))]])
        return E, Jac

    def solve(self, x: np.ndarray, B: np.ndarray, mult: np.ndarray | None,
              max_iter: int = 30) -> tuple[np.ndarray, np.ndarray]:
        """Newton from ``x`` on :meth:`equations` with the unheld motions ``B``: ``(pose, multipliers)``;
        :class:`InputError` when it finds none."""
        mech, qi, nq = self.mech, self.dyn.q_index, self.dyn.nq
        xq = np.array(x, float)
        _, H = self.holds(xq)
        if mult is None or len(mult) != mech.n_constraints + len(H) + len(B):  # linear in them: least squares
            mult = _lstsq(np.hstack([mech.phi_q(xq).reshape(-1, nq).T, H.T, B.T]), mech.applied_forces(xq))
        for _ in range(max_iter):
            E, Jac = self.equations(xq, B, mult)
            step = _lstsq(Jac, E)
            xq[qi] -= step[:nq]
            mult = mult - step[nq:]
            if (np.max(np.abs(step[:nq]) / self.scale) <= 1e-13
                    and np.max(np.abs(step[nq:]), initial=0.0) <= 1e-10 * np.max(np.abs(mult), initial=0.0)):
                break
        xq[qi[self.held_idx]] = self.q0[self.held_idx]  # exactly the values asked for
        E, Jac = self.equations(xq, B, mult)
        force = max(np.max(np.abs(mech.applied_forces(xq)), initial=0.0),
                    np.max(np.abs(Jac[:nq, nq:] @ mult), initial=0.0))
        rows = E[nq:nq + mech.n_constraints + len(H)]
        geometry = np.max(np.abs(rows), initial=0.0)
        # each joint or held row against its size at the coordinates' scales (m, rad): any units
        size = (np.abs(np.vstack([mech.phi_q(xq).reshape(-1, nq), H])) * self.scale).sum(axis=1)
        imbalance = np.max(np.abs(E[:nq]), initial=0.0)
        if not (np.all(np.abs(rows) <= 1e-9 * size) and imbalance <= 1e-8 * force):
            raise InputError("x0", f"no static pose of the compliant joints found with the held values (joint "
                                   f"residual {geometry:.3g}, force imbalance {imbalance:.3g} N): does every "
                                   "compliant direction have a stiffness?")
        return xq, mult


def _lstsq(Jac: np.ndarray, E: np.ndarray) -> np.ndarray:
    """The least-squares solution ``Jac^+ E``, rows and columns equilibrated first (forces, lengths, Euler
    parameters, reactions: units apart), so that only truly dependent rows (an over-constrained closure's)
    are cut."""
    c = _inverse_or_one(np.max(np.abs(Jac), axis=0, initial=0.0))
    rows = np.max(np.abs(Jac * c[None, :]), axis=1, initial=0.0)
    # a row of rounding-level entries (a force no row of the matrix balances yet) is not scaled up
    r = _inverse_or_one(np.maximum(rows, 1e-8 * np.max(rows, initial=0.0)))
    return c * np.linalg.lstsq(Jac * r[:, None] * c[None, :], E * r, rcond=_RCOND)[0]


def _null_space(A: np.ndarray) -> np.ndarray:
    """An orthonormal basis (columns) of the null space of ``A`` (rank cut 1e-10 of its largest singular value)."""
    if not len(A):
        return np.eye(A.shape[1])
    _, sv, Vt = np.linalg.svd(A)
    return Vt[int(np.sum(sv > 1e-10 * max(sv[0], 1e-300))):].T


def _inverse_or_one(v: np.ndarray) -> np.ndarray:
    """``1 / v`` where ``v > 0``, else 1 (an empty row or column of a matrix is left unscaled)."""
    return np.divide(1.0, v, out=np.ones_like(v), where=v > 0)
