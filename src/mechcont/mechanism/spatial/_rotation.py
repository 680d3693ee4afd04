"""Orientation by Euler parameters (unit quaternions), written as polynomials.

A body's orientation is ``e = (e0, e1, e2, e3)`` with ``|e| = 1`` (one normalisation row per
body). Euler parameters have no singular orientation, unlike any three angles, and every
quantity below is a polynomial of degree at most two in ``e``: exact derivatives stay short.

* rotation matrix (body -> global), homogeneous of degree 2 (equal to the usual form when
  ``|e| = 1``): ``A = (e0^2 - eps.eps) I + 2 eps eps^T + 2 e0 [eps x]``, ``eps = (e1, e2, e3)``;
* angular velocity, global ``omega = 2 E edot`` and body ``omega' = 2 G edot`` with
  ``E = [-eps, e0 I + [eps x]]``, ``G = [-eps, e0 I - [eps x]]`` (3 x 4);
* the virtual work of a moment ``n`` (global, N m) is ``n . 2 E de``: generalised force
  ``2 E^T n`` on the four parameters.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import sympy as sp

__all__ = ["rotation_matrix", "omega_matrix", "body_omega_matrix", "skew", "quaternion_from_rotation_vector",
           "perpendiculars", "cross", "dot", "norm", "matvec"]


def skew(v: Sequence) -> sp.Matrix:
    """The matrix ``[v x]`` with ``[v x] w = v x w``."""
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def rotation_matrix(e: Sequence) -> sp.Matrix:
    """Rotation matrix (body -> global) of the Euler parameters ``e`` (homogeneous, degree 2)."""
    e0, eps = e[0], sp.Matrix(e[1:])
    return (e0 ** 2 - eps.dot(eps)) * sp.eye(3) + 2 * eps * eps.T + 2 * e0 * skew(eps)


def omega_matrix(e: Sequence) -> sp.Matrix:
    """``E`` (3 x 4): global angular velocity ``omega = 2 E edot``."""
    eps = sp.Matrix(e[1:])
    return sp.Matrix.hstack(-eps, e[0] * sp.eye(3) + skew(eps))


def body_omega_matrix(e: Sequence) -> sp.Matrix:
    """``G`` (3 x 4): body-frame angular velocity ``omega' = 2 G edot``."""
    eps = sp.Matrix(e[1:])
    return sp.Matrix.hstack(-eps, e[0] * sp.eye(3) - skew(eps))


def quaternion_from_rotation_vector(r: Sequence[float] | np.ndarray) -> np.ndarray:
    """Euler parameters (4,) of the rotation by ``|r|`` radians about ``r / |r|``."""
    r = np.asarray(r, dtype=float)
    angle = float(np.linalg.norm(r))
    if angle == 0.0:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * r / angle])


def matvec(A: sp.Matrix, v: Sequence) -> sp.Matrix:
    """``A v`` of a 3 x 3 matrix and a 3-vector, term by term (SymPy's matrix product goes through
    its polynomial domains, far slower on these small symbolic products)."""
    return sp.Matrix([sum((A[i, k] * v[k] for k in range(3) if v[k] != 0), sp.S.Zero) for i in range(3)])


def cross(u: Sequence, v: Sequence) -> sp.Matrix:
    """``u x v`` of two 3-vectors."""
    return sp.Matrix([u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]])


def dot(u: Sequence, v: Sequence) -> sp.Expr:
    """``u . v`` of two 3-vectors."""
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def norm(u: Sequence) -> sp.Expr:
    """``|u|`` of a 3-vector."""
    return sp.sqrt(dot(u, u))


def perpendiculars(u: sp.Matrix, at: dict) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """Unit ``u`` and two unit vectors ``f``, ``g`` completing a right-handed frame ``(f, g, u)``.

    With ``i`` the global axis along which ``u`` has its largest component (at the parameter
    values ``at``, symbol -> value, so the choice does not move with the values), ``f`` is the
    next global axis ``h = e_(i+1 mod 3)`` made perpendicular to ``u``:
    ``f = (h - (h.u) u) / |...|``, and ``g = u x f``. For the global axes themselves:
    ``u = x``: ``f = y, g = z``; ``u = y``: ``f = z, g = x``; ``u = z``: ``f = x, g = y``.
    """
    n = norm(u)
    unit = sp.Matrix([c / n for c in u]) if n != 1 else sp.Matrix(u)
    num = [abs(float(sp.sympify(c).xreplace(at))) for c in u]
    h = sp.Matrix([0, 0, 0])
    h[(int(np.argmax(num)) + 1) % 3] = 1
    f = h - dot(h, unit) * unit
    nf = norm(f)
    f = f if nf == 1 else sp.Matrix([c / nf for c in f])
    return unit, f, cross(unit, f)
