"""Symbolic applied loads of a described mechanism, planar or spatial: potential energy and other forces.

Conservative loads (gravity, springs, force-mode actuators, fixed-direction point forces and
planar pure moments whose magnitudes are parameters) enter through the potential ``V``; the generalised forces are
``Q = -dV/dq + Q_nc`` where ``Q_nc`` collects what each other load writes against the kinematics
(drag, custom loads, spatial moments: see :mod:`.loads`) and the dampers
(``-(c v + c2 v|v|) dl/dq``, ``v = dl/dt``, using the velocity symbols).
"""

from __future__ import annotations

import sympy as sp

from ..equations import velocity_symbol
from ._actuators import actuator_potential
from ._dampers import damper_forces
from .loads import DRAG_SMOOTHING, Loads

__all__ = ["Loads", "loads", "DRAG_SMOOTHING"]


def loads(kin) -> Loads:
    """Collect every load of the mechanism of ``kin`` (planar or spatial kinematics; see the module docstring)."""
    mech = kin.mech
    out = Loads(sp.S.Zero, [sp.S.Zero] * len(kin.q), [])
    if mech.gravity is not None:
        mech.gravity.apply(kin, out)
    for s in mech.springs:
        f = f"springs.{s.name}"
        k, l0, pre = mech.value(f + ".k"), mech.value(f + ".free_length"), mech.value(f + ".preload")
        length = kin.distance(s.a, s.b)
        out.V += pre * length + k / 2 * (length - l0) ** 2
    out.V += actuator_potential(kin)
    qd = [velocity_symbol(n) for n in kin.coords]
    out.add(damper_forces(mech, kin, kin.distance, kin.q, qd))
    for ld in mech.loads:
        ld.apply(kin, out)
    return out
