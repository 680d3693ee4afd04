"""Symbolic applied loads of a described mechanism: potential energy and other forces.

Conservative loads (gravity, springs, force-mode actuators, fixed-direction point forces and
pure moments whose magnitudes are parameters) enter through the potential ``V``; the generalised forces are
``Q = -dV/dq + Q_nc`` where ``Q_nc`` collects drag, custom loads (virtual work
``f . dP/dq + M dtheta/dq``) and dampers (``-(c v + c2 v|v|) dl/dq``, ``v = dl/dt``, using the velocity symbols).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import sympy as sp

from ..equations import velocity_symbol
from ._actuators import actuator_potential
from ._dampers import damper_forces
from ._description import CustomLoad, Drag, Moment, PointForce
from ._kinematics import Kinematics

__all__ = ["Loads", "loads", "DRAG_SMOOTHING"]

#: Velocity (m/s) below which the drag's |u_n| is smoothed: sqrt(u_n^2 + DRAG_SMOOTHING^2).
DRAG_SMOOTHING = 1e-6


@dataclass
class Loads:
    """Potential ``V`` (J), non-conservative generalised forces ``Q_nc`` (per coordinate) and
    the force vectors to draw ``(name, point expr, vector expr)``."""

    V: sp.Expr
    Q_nc: list[sp.Expr]
    arrows: list[tuple[str, sp.Matrix, sp.Matrix]]


def _length(kin: Kinematics, a: str, b: str) -> sp.Expr:
    d = kin.point(b) - kin.point(a)
    return sp.sqrt(d[0] ** 2 + d[1] ** 2)


def _virtual_work(kin: Kinematics, P: sp.Matrix, f: sp.Matrix, theta, moment) -> list[sp.Expr]:
    out = []
    for qi in kin.q:
        out.append(f[0] * sp.diff(P[0], qi) + f[1] * sp.diff(P[1], qi) + moment * sp.diff(theta, qi))
    return out


def loads(kin: Kinematics) -> Loads:
    """Collect every load of the mechanism of ``kin`` (see the module docstring)."""
    mech = kin.mech
    V = sp.S.Zero
    Q_nc = [sp.S.Zero] * len(kin.q)
    arrows: list[tuple[str, sp.Matrix, sp.Matrix]] = []
    if mech.gravity is not None:
        g, ang = mech.value("gravity.g"), mech.value("gravity.angle")
        gvec = sp.Matrix([g * sp.cos(ang), g * sp.sin(ang)])
        for b in mech.bodies:
            V -= kin.body_mass(b) * gvec.dot(kin.cg(b.name))
    for s in mech.springs:
        f = f"springs.{s.name}"
        k, l0, pre = mech.value(f + ".k"), mech.value(f + ".free_length"), mech.value(f + ".preload")
        length = _length(kin, s.a, s.b)
        V += pre * length + k / 2 * (length - l0) ** 2
    V += actuator_potential(kin)
    qd = [velocity_symbol(n) for n in kin.coords]
    Q_nc = [a + b for a, b in zip(Q_nc, damper_forces(mech, kin, partial(_length, kin), kin.q, qd))]
    for ld in mech.loads:
        f = f"loads.{ld.name}"
        if isinstance(ld, PointForce):
            F = mech.value(f + ".magnitude")
            if isinstance(ld.direction, (tuple, list)):
                u = sp.Matrix([mech.value(f + ".direction.x"), mech.value(f + ".direction.y")])
                u = u / sp.sqrt(u[0] ** 2 + u[1] ** 2)
            else:
                a = mech.value(f + ".direction")
                u = sp.Matrix([sp.cos(a), sp.sin(a)])
            P = kin.point(ld.at)
            V -= F * u.dot(P)
            arrows.append((ld.name, P, F * u))
        elif isinstance(ld, Moment):
            V -= mech.value(f + ".magnitude") * kin.body_q[ld.body][2]
        elif isinstance(ld, Drag):
            Q_drag, P, force = _drag(kin, ld)
            Q_nc = [a + b for a, b in zip(Q_nc, Q_drag)]
            arrows.append((ld.name, P, force))
        elif isinstance(ld, CustomLoad):
            P = kin.point(ld.at)
            force = sp.Matrix([mech.value(f + ".fx"), mech.value(f + ".fy")])
            theta = kin.angle(ld.at)
            Q_c = _virtual_work(kin, P, force, theta, mech.value(f + ".moment"))
            Q_nc = [a + b for a, b in zip(Q_nc, Q_c)]
            arrows.append((ld.name, P, force))
    return Loads(V, Q_nc, arrows)


def _drag(kin: Kinematics, ld: Drag):
    mech, f = kin.mech, f"loads.{ld.name}"
    rho, U, alpha, d, CD = (mech.value(f"{f}.{a}") for a in ("rho", "U", "alpha", "d", "CD"))
    A, B = kin.point(f"{ld.body}.{ld.start}"), kin.point(f"{ld.body}.{ld.end}")
    pa, pb = kin.local_point(ld.body, ld.start), kin.local_point(ld.body, ld.end)
    L2 = (pb[0] - pa[0]) ** 2 + (pb[1] - pa[1]) ** 2  # squared segment length (no sqrt: stays smooth)
    perp = sp.Matrix([-(B - A)[1], (B - A)[0]])  # L times the unit normal n
    s = U * (sp.cos(alpha) * perp[0] + sp.sin(alpha) * perp[1])  # L u_n
    # 1/2 rho C_D d L u_n |u_n| n  with |u_n| -> sqrt(u_n^2 + eps^2), written without L itself
    force = rho * CD * d / 2 * s * sp.sqrt(s ** 2 + DRAG_SMOOTHING ** 2 * L2) / L2 * perp
    P = (A + B) / 2
    return _virtual_work(kin, P, force, sp.S.Zero, 0), P, force
