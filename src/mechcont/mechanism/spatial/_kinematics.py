"""Symbolic kinematics of a spatial mechanism: coordinates, points, directions, rows, masses.

Body ``b`` has coordinates ``(r_b, e_b)``: frame origin (m) and Euler parameters; a point with
body coordinates ``s`` is at ``r_b + A(e_b) s`` (see :mod:`._rotation`). A force does the
virtual work ``f . dP/dq``, a moment of fixed direction ``n`` gives ``2 E^T n`` on the Euler
parameters (:meth:`SpatialKinematics.moment_work`; the loads themselves are :mod:`..loads`).
The mass matrix follows from the kinetic energy
``1/2 m |v_cg|^2 + 1/2 omega'^T J omega'`` with ``omega' = 2 G edot``, plus
``2 jbar (e . edot)^2`` (``jbar`` the mean principal inertia), which vanishes on every motion
that keeps ``|e| = 1`` and makes ``M`` positive definite.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import sympy as sp

from ...equations import gradient
from .._bodies import INERTIA_KEYS, SpatialBody, normalisation_row
from .._expr import symbol
from .._values import parameter_values
from ..elements import element_rows
from ._rotation import body_omega_matrix, cross, dot, matvec, norm, omega_matrix, perpendiculars, rotation_matrix
from .joints import SpatialRow

if TYPE_CHECKING:
    from ._description import SpatialMechanism

__all__ = ["SpatialKinematics"]


class SpatialKinematics:
    """Symbols and symbolic geometry of a :class:`SpatialMechanism`."""

    dimension = 3

    def __init__(self, mech: SpatialMechanism):
        self.mech = mech
        self.coords: list[str] = []
        self.body_r: dict[str, sp.Matrix] = {}
        self.body_e: dict[str, list[sp.Symbol]] = {}
        for b in mech.bodies:
            names = mech._coordinate_names(b.name)
            self.coords.extend(names)
            syms = [symbol(n) for n in names]
            self.body_r[b.name] = sp.Matrix(syms[:3])
            self.body_e[b.name] = syms[3:]
        self.q = [symbol(n) for n in self.coords]
        self._A = {b: rotation_matrix(e) for b, e in self.body_e.items()}
        self._points: dict[str, sp.Matrix] = {}
        defaults = parameter_values(mech, {})
        #: Parameter symbol -> default value (for structure choices that must not depend on values).
        self.defaults = {symbol(k): v for k, v in defaults.items()}

    # -- points and frames ----------------------------------------------------------------
    def local_point(self, body: str, point: str) -> sp.Matrix:
        """Body coordinates (m) of ``point`` on ``body``."""
        m, b = self.mech, self.mech.body_map[body]
        f = f"bodies.{body}"
        if point == "origin":
            return sp.zeros(3, 1)
        if point == "cg":
            return sp.Matrix([m.value(f"{f}.cg.{c}") for c in "xyz"])
        if point in b.points:
            return sp.Matrix([m.value(f"{f}.points.{point}.{c}") for c in "xyz"])
        half = m.value(f + ".length") / 2
        return sp.Matrix([-half if point == "a" else half, 0, 0])

    def rotation(self, ref: str) -> sp.Matrix:
        """Rotation matrix (body -> global) of the frame that ``ref`` belongs to (identity for ground)."""
        body = ref.split(".")[0]
        return sp.eye(3) if body == "ground" else self._A[body]

    def point(self, ref: str) -> sp.Matrix:
        """Global position (m) of the point reference ``"<body>.<point>"`` / ``"ground.<p>"``."""
        if ref not in self._points:
            body, point = ref.split(".")
            if body == "ground":
                P = sp.Matrix([self.mech.value(f"ground.{point}.{c}") for c in "xyz"])
            else:
                P = self.body_r[body] + matvec(self._A[body], self.local_point(body, point))
            self._points[ref] = P
        return self._points[ref].copy()

    def turn(self, ref: str, v: sp.Matrix) -> sp.Matrix:
        """The body vector ``v`` (design pose) of the frame ``ref`` belongs to, in global axes."""
        body = ref.split(".")[0]
        return sp.Matrix(v) if body == "ground" else matvec(self._A[body], v)

    def relative_rotation(self, a: str, b: str, axis: sp.Matrix | None = None) -> sp.Expr:
        """The rotation (rad) of the frame of ``b`` relative to that of ``a`` (point references) about
        ``axis`` (design pose), right-handed: with ``(f, g, u)`` the axis' right-handed frame
        (:func:`._rotation.perpendiculars`), ``f_a = A_a f``, ``f_b = A_b f``, ``u_a = A_a u``,
        ``atan2(u_a . (f_a x f_b), f_a . f_b)``: zero in the design pose, smooth for ``|phi| < pi``."""
        if axis is None:
            raise ValueError("a spatial relative rotation needs its axis")
        u, f, _ = perpendiculars(axis, self.defaults)
        fa, fb, ua = self.turn(a, f), self.turn(b, f), self.turn(a, u)
        return sp.atan2(dot(ua, cross(fa, fb)), dot(fa, fb))

    def cg(self, body: str) -> sp.Matrix:
        """Global position of the centre of gravity of ``body``."""
        return self.point(f"{body}.cg")

    def origin(self, body: str) -> list[sp.Symbol]:
        """The coordinates of ``body``'s frame origin: ``x``, ``y``, ``z`` (m)."""
        return list(self.body_r[body])

    def distance(self, a: str, b: str) -> sp.Expr:
        """Distance (m) between the point references ``a`` and ``b``."""
        return norm(self.point(b) - self.point(a))

    def direction(self, field: str, raw: Any = None) -> sp.Matrix:
        """The unit vector of the direction ``[x, y, z]`` at key path ``field``."""
        return _unit(sp.Matrix([self.mech.value(f"{field}.{c}") for c in "xyz"]))

    def force_work(self, P: sp.Matrix, f: sp.Matrix) -> list[sp.Expr]:
        """Generalised forces (one per coordinate) of the force ``f`` (N) at ``P``: ``f . dP/dq``."""
        dP = [gradient(P[i], self.q) for i in range(3)]
        return [dot(f, [dP[i][k] for i in range(3)]) for k in range(len(self.q))]

    def moment_work(self, body: str, n: sp.Matrix) -> list[sp.Expr]:
        """Generalised forces of a moment ``n`` (global, N m) on ``body``: ``2 E^T n`` on its Euler parameters."""
        e = self.body_e[body]
        Qe = 2 * omega_matrix(e).T * n
        index = {str(q): i for i, q in enumerate(self.q)}
        out = [sp.S.Zero] * len(self.q)
        for k, ek in enumerate(e):
            out[index[str(ek)]] = Qe[k]
        return out

    def moment_anchor(self, body: str) -> sp.Matrix:
        """Where a moment on ``body`` is drawn: its first joint to the ground, else its centre of gravity."""
        for j in self.mech.joints:
            ends = (j.a, j.b)
            if any(r.startswith("ground.") for r in ends) and any(r.split(".")[0] == body for r in ends):
                return self.point(next(r for r in ends if r.split(".")[0] == body))
        return self.cg(body)

    def body_mass(self, b: SpatialBody) -> sp.Expr:
        """Mass (kg) of body ``b``."""
        return self.mech.value(f"bodies.{b.name}.mass")

    # -- constraints ----------------------------------------------------------------------
    def constraints(self) -> list[SpatialRow]:
        """Every scalar constraint row: one normalisation row per body first (so a redundancy is
        always reported at a joint), then the joints in declaration order and the length-mode
        actuators."""
        rows: list[SpatialRow] = []
        for b in self.mech.bodies:
            e = self.body_e[b.name]
            norm_row = normalisation_row(b.name)
            rows.append(SpatialRow(norm_row, norm_row, f"mu_{b.name}", "N m",
                                   sum((c ** 2 for c in e), sp.S.Zero) - 1))
        for j in self.mech.joints:
            rows.extend(j.rows(self))
        rows += [SpatialRow(r.joint, r.equation, r.reaction, r.unit, r.expr) for r in element_rows(self)]
        return rows

    # -- inertia --------------------------------------------------------------------------
    def inertia_tensor(self, b: SpatialBody) -> sp.Matrix:
        """Inertia tensor about the CG in body axes (kg m^2): given, or the documented default."""
        m, f = self.mech, f"bodies.{b.name}"
        mass = m.value(f + ".mass")
        if b.inertia is not None:
            v = {k: m.value(f"{f}.inertia.{k}") for k in INERTIA_KEYS[:len(b.inertia)]}
            xy, xz, yz = (v.get(k, 0) for k in ("xy", "xz", "yz"))
            return sp.Matrix([[v["xx"], xy, xz], [xy, v["yy"], yz], [xz, yz, v["zz"]]])
        if b.length is not None:
            L = m.value(f + ".length")
            return sp.diag(mass * (L / 20) ** 2 / 2, mass * L ** 2 / 12, mass * L ** 2 / 12)
        # the frame origin is left out: where it is (the global origin, for hard points in aircraft
        # coordinates) must not change the body
        pts = [self.local_point(b.name, p) for p in m.point_names(b.name) if p != "origin"]
        at = self.defaults
        spread = max((float(norm(p - q).xreplace(at)) for p in pts for q in pts), default=0.0)
        radius = max(spread / 2, 1e-3)
        return sp.eye(3) * (sp.Rational(2, 5) * mass * radius ** 2)

    def mass_matrix(self) -> sp.Matrix:
        """Mass matrix (7 x 7 blocks per body) from the kinetic energy (see the module docstring)."""
        n = len(self.q)
        M = sp.zeros(n, n)
        for i, b in enumerate(self.mech.bodies):
            mass = self.mech.value(f"bodies.{b.name}.mass")
            e = self.body_e[b.name]
            c = self.local_point(b.name, "cg")
            Ac = matvec(self._A[b.name], c)
            dA = [gradient(Ac[i], e) for i in range(3)]  # d(A c)/de, 3 x 4
            Jv = [[int(i == j) for j in range(3)] + dA[i] for i in range(3)]
            J = self.inertia_tensor(b)
            G = body_omega_matrix(e)
            JG = [[sum((J[i, k] * G[k, j] for k in range(3) if J[i, k] != 0), sp.S.Zero) for j in range(4)]
                  for i in range(3)]
            jbar = (J[0, 0] + J[1, 1] + J[2, 2]) / 3
            block = sp.zeros(7, 7)
            for r in range(7):
                for col in range(r, 7):
                    v = mass * sum((Jv[i][r] * Jv[i][col] for i in range(3)), sp.S.Zero)
                    if r >= 3 and col >= 3:
                        v += 4 * sum((G[i, r - 3] * JG[i][col - 3] for i in range(3)), sp.S.Zero)
                        v += 4 * jbar * e[r - 3] * e[col - 3]
                    block[r, col] = block[col, r] = v
            M[7 * i:7 * i + 7, 7 * i:7 * i + 7] = block
        return M


def _unit(u: sp.Matrix) -> sp.Matrix:
    n = norm(u)
    return u if n == 1 else u / n
