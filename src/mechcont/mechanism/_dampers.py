"""Hydraulic dampers: the tension of a damper between two points and its generalised forces.

A damper of length ``l`` (m) between its points ``a`` and ``b`` carries the tension (N, positive
pulling its ends together, as springs and actuators)

    T = c v + c2 v |v|,     v = dl/dt (m/s),

``c`` (N s/m) the linear (laminar) term and ``c2`` (N s^2/m^2) the quadratic one of a restrictor
orifice. Its generalised force is ``-T dl/dq``. The tension depends on the velocity symbols only,
so it vanishes at rest: every continuation (an equilibrium is at rest) sees no damper; the time
simulation does.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

__all__ = ["damper_tension", "damper_forces"]


def damper_tension(c, c2, rate) -> sp.Expr:
    """Tension ``c v + c2 v |v|`` (N) of a damper stroking at ``rate`` = ``v`` (m/s)."""
    return c * rate + c2 * rate * sp.Abs(rate)


def damper_forces(mech, kin, length_of, q: Sequence, qd: Sequence) -> list[sp.Expr]:
    """Generalised forces (one per coordinate ``q``, velocity symbols ``qd``) of every damper of ``mech``.

    ``length_of(a, b)`` is the distance (m) between two point references in the coordinates of ``kin``.
    """
    Q = [sp.S.Zero] * len(q)
    for d in mech.dampers:
        f = f"dampers.{d.name}"
        length = length_of(d.a, d.b)
        grad = [sp.diff(length, qi) for qi in q]
        rate = sum((gi * vi for gi, vi in zip(grad, qd)), sp.S.Zero)
        T = damper_tension(mech.value(f + ".c"), mech.value(f + ".c2"), rate)
        Q = [Qi - T * gi for Qi, gi in zip(Q, grad)]
    return Q
