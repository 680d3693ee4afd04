"""Symbolic applied loads of a described mechanism, planar or spatial: potential energy and other forces.

Conservative loads (gravity, springs, force-mode actuators, fixed-direction point forces and
planar pure moments whose magnitudes are parameters) enter through the potential ``V``; the generalised forces are
``Q = -dV/dq + Q_nc`` where ``Q_nc`` collects what each other load writes against the kinematics
(drag, custom loads, spatial moments: see :mod:`.loads`) and the dampers
(``-(c v + c2 v|v|) dl/dq``, ``v = dl/dt``, using the velocity symbols). Each force element
(:mod:`.elements`) and each load writes its own part.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import sympy as sp

from .loads import DRAG_SMOOTHING, Loads

if TYPE_CHECKING:
    from ._plugin import Kinematics

__all__ = ["Loads", "loads", "DRAG_SMOOTHING"]


def loads(kin: Kinematics) -> Loads:
    """Collect every load of the mechanism of ``kin`` (planar or spatial kinematics; see the module docstring)."""
    mech = kin.mech
    out = Loads(sp.S.Zero, [sp.S.Zero] * len(kin.q), [])
    if mech.gravity is not None:
        mech.gravity.apply(kin, out)
    for el in mech.force_elements():
        el.apply(kin, out)
    for ld in mech.loads:
        ld.apply(kin, out)
    return out
