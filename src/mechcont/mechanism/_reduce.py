"""The reduced form: eliminate the coordinates that a tree of pins determines explicitly.

Starting at the ground, every revolute (or weld) joint that connects an already placed body
(or the ground) to a new body fixes the new body's frame origin explicitly:
``(x_b, y_b) = P_a - R(theta_b) p_b`` (a weld also fixes ``theta_b = theta_a + angle``).
Those coordinates are substituted everywhere, the joint's constraint rows vanish
identically, and so do its reactions: with ``q = q(r)`` and ``J = dq/dr``,

    J^T (Q - Phi_q^T lambda) = Q_r - Phi_r,r^T lambda_rest,   Q_r = -dV(q(r))/dr + J^T Q_nc,

because ``Phi_tree(q(r)) = 0`` identically gives ``Phi_tree,q J = 0``. The remaining
unknowns are the independent angles (and the coordinates of bodies reached only through
sliders), the loop-closing constraints and their reactions. Solutions are the same as the
full form's (the eliminated reactions follow from the full equations by a linear solve);
for the overcentre it leaves ``theta1, theta2, R_slider`` and three equations. For the
dynamic model the mass matrix becomes ``J^T M J``; its velocity-product terms (zero at rest)
come, like every model's, from that matrix's Christoffel symbols
(:meth:`~mechcont.equations.MechanicalModel.inertial_forces`), so a time simulation of the
reduced form is the same motion as the full form's.
"""

from __future__ import annotations

from collections.abc import Mapping

import sympy as sp

from ..equations import velocity_symbol
from ._kinematics import ConstraintRow, PlanarKinematics, pin_chain

__all__ = ["tree_elimination", "reduce_form", "velocity_map"]


def tree_elimination(kin: PlanarKinematics) -> tuple[dict[sp.Symbol, sp.Expr], set[str]]:
    """Coordinates fixed by a spanning tree of pins from the ground.

    Returns ``(substitution, tree_joints)``: each eliminated coordinate symbol mapped to its
    expression in the kept coordinates, and the names of the joints used.
    """
    mech = kin.mech
    subs: dict[sp.Symbol, sp.Expr] = {}
    tree = set()
    for j, known, new, body in pin_chain(mech, {"ground"}):
        x, y, th = kin.body_q[body]
        rel = j.locked_angle(kin)
        if rel is not None:
            th_known = kin.angle(known).xreplace(subs)
            subs[th] = th_known + rel if new == j.b else th_known - rel
        p_known = kin.point(known).xreplace(subs)
        p_new_local = kin.point(new).xreplace({x: 0, y: 0}).xreplace(subs)
        subs[x] = p_known[0] - p_new_local[0]
        subs[y] = p_known[1] - p_new_local[1]
        tree.add(j.name)
    return subs, tree


def velocity_map(kin: PlanarKinematics, subs: Mapping[sp.Symbol, sp.Expr]
                 ) -> tuple[list[tuple[str, sp.Symbol]], sp.Matrix, dict[sp.Symbol, sp.Expr]]:
    """``(kept, J, vel)`` of the substitution ``subs`` of the eliminated coordinates: the kept ``(name,
    symbol)`` pairs, ``J = dq/dr`` (every coordinate by the kept ones) and the velocity symbols of every
    coordinate written in the kept ones' (``qdot = J rdot``)."""
    kept = [(n, s) for n, s in zip(kin.coords, kin.q) if s not in subs]
    r = [s for _, s in kept]
    q_of_r = [subs.get(s, s) for s in kin.q]
    J = sp.Matrix([[sp.diff(qi, rj) for rj in r] for qi in q_of_r])
    qd_full = [velocity_symbol(n) for n in kin.coords]
    qd_r = [velocity_symbol(n) for n, _ in kept]
    vel = {qd_full[i]: sum((J[i, j] * qd_r[j] for j in range(len(r))), sp.S.Zero) for i in range(len(kin.q))}
    return kept, J, vel


def reduce_form(kin: PlanarKinematics, rows: list[ConstraintRow], V: sp.Expr, Q_nc: list[sp.Expr], M: sp.Matrix
                ) -> tuple[list[str], list[ConstraintRow], list[sp.Expr], sp.Matrix, dict[sp.Symbol, sp.Expr]]:
    """Apply :func:`tree_elimination`.

    Returns ``(coords, rows, forces, mass, subs)``: kept coordinate names, remaining
    constraint rows, generalised applied forces ``Q_r`` (with the kept coordinates' velocity
    symbols), the reduced mass matrix and the substitution of the eliminated coordinates.
    """
    subs, tree = tree_elimination(kin)
    kept, J, vel = velocity_map(kin, subs)
    r = [s for _, s in kept]
    V_r = V.xreplace(subs)
    Qnc_full = [e.xreplace(subs).xreplace(vel) for e in Q_nc]
    M_sub = M.xreplace(subs)
    forces = []
    for j, rj in enumerate(r):
        nc = sum((J[i, j] * Qnc_full[i] for i in range(len(kin.q)) if J[i, j] != 0 and Qnc_full[i] != 0), sp.S.Zero)
        forces.append(-sp.diff(V_r, rj) + nc)
    rest = [ConstraintRow(row.joint, row.equation, row.reaction, row.unit, row.expr.xreplace(subs))
            for row in rows if row.joint not in tree]
    mass = J.T * M_sub * J
    return [n for n, _ in kept], rest, forces, mass, subs
