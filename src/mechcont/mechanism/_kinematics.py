"""Symbolic kinematics of a described mechanism: coordinates, points, constraints, masses.

Body ``b`` has coordinates ``q_b = (x_b, y_b, theta_b)``; a point with body coordinates
``p`` is at ``(x_b, y_b) + R(theta_b) p``. Constraints are written as "side a minus side b"
so that the multiplier of a joint is the force the body of ``a`` exerts on the body of
``b`` (see the joint classes).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import TYPE_CHECKING, Any

import sympy as sp

from ._bodies import Body, Polar, SpatialBody, coordinate_names
from ._expr import evaluate, symbol
from ._plugin import Kinematics
from .elements import element_rows
from .joints import ConstraintRow

if TYPE_CHECKING:
    from ._description import JointT, Mechanism

__all__ = ["PlanarKinematics", "ConstraintRow", "pin_chain", "place_along_joints"]


def _rot(theta: sp.Expr, p: sp.Matrix) -> sp.Matrix:
    c, s = sp.cos(theta), sp.sin(theta)
    return sp.Matrix([c * p[0] - s * p[1], s * p[0] + c * p[1]])


class PlanarKinematics:
    """Symbols and symbolic geometry of a planar ``mech`` (built once per :meth:`Mechanism.build`): the
    planar strategy of the :class:`~._plugin.Kinematics` protocol."""

    dimension = 2

    def __init__(self, mech: Mechanism):
        self.mech = mech
        self.coords: list[str] = []
        self.body_q: dict[str, tuple[sp.Symbol, sp.Symbol, sp.Symbol]] = {}
        for b in mech.bodies:
            names = coordinate_names(b.name)
            self.coords.extend(names)
            self.body_q[b.name] = tuple(symbol(n) for n in names)
        self.q = [symbol(n) for n in self.coords]

    # -- points --------------------------------------------------------------------
    def local_point(self, body: str, point: str) -> sp.Matrix:
        """Body coordinates (m) of ``point`` on ``body``."""
        m, b = self.mech, self.mech.body_map[body]
        f = f"bodies.{body}"
        if point == "origin":
            return sp.Matrix([0, 0])
        if point == "cg":
            return sp.Matrix([m.value(f + ".cg.x"), m.value(f + ".cg.y")])
        if point in b.points:
            spec = b.points[point]
            if isinstance(spec, Polar):
                r, a = m.value(f"{f}.points.{point}.r"), m.value(f"{f}.points.{point}.angle")
                return sp.Matrix([r * sp.cos(a), r * sp.sin(a)])
            return sp.Matrix([m.value(f"{f}.points.{point}.x"), m.value(f"{f}.points.{point}.y")])
        half = m.value(f + ".length") / 2
        return sp.Matrix([-half if point == "a" else half, 0])

    def point(self, ref: str) -> sp.Matrix:
        """Global position (m) of the point reference ``"<body>.<point>"`` / ``"ground.<p>"``."""
        body, point = ref.split(".")
        if body == "ground":
            return sp.Matrix([self.mech.value(f"ground.{point}.x"), self.mech.value(f"ground.{point}.y")])
        x, y, th = self.body_q[body]
        return sp.Matrix([x, y]) + _rot(th, self.local_point(body, point))

    def angle(self, ref: str) -> sp.Expr:
        """Orientation (rad) of the frame that the point reference belongs to (0 for ground)."""
        body = ref.split(".")[0]
        return sp.S.Zero if body == "ground" else self.body_q[body][2]

    def turn(self, ref: str, v: sp.Matrix) -> sp.Matrix:
        """The body vector ``v`` of the frame ``ref`` belongs to, in global axes."""
        return _rot(self.angle(ref), sp.Matrix(v))

    def relative_rotation(self, a: str, b: str, axis: sp.Matrix | None = None) -> sp.Expr:
        """The rotation (rad) of the frame of ``b`` relative to that of ``a``: ``theta_b - theta_a``
        (``axis`` is the plane's normal, not needed)."""
        return self.angle(b) - self.angle(a)

    def cg(self, body: str) -> sp.Matrix:
        """Global position of the centre of gravity of ``body``."""
        return self.point(f"{body}.cg")

    def moment_anchor(self, body: str) -> sp.Matrix:
        """Where a moment on ``body`` is drawn: its first pin or weld to the ground, else its frame origin."""
        for j in self.mech.joints:
            if j.COINCIDENT:
                for here, there in ((j.a, j.b), (j.b, j.a)):
                    if here.split(".")[0] == "ground" and there.split(".")[0] == body:
                        return self.point(there)
        return self.point(f"{body}.origin")

    def origin(self, body: str) -> list[sp.Symbol]:
        """The coordinates of ``body``'s frame origin: ``x``, ``y`` (m)."""
        return list(self.body_q[body][:2])

    def distance(self, a: str, b: str) -> sp.Expr:
        """Distance (m) between the point references ``a`` and ``b``."""
        d = self.point(b) - self.point(a)
        return sp.sqrt(d[0] ** 2 + d[1] ** 2)

    def direction(self, field: str, raw: Any) -> sp.Matrix:
        """The unit vector of the direction at key path ``field``: its ``[x, y]`` normalised, or
        ``(cos, sin)`` of an angle (rad) (``raw``, the value as described, tells which)."""
        m = self.mech
        if isinstance(raw, (tuple, list)):
            u = sp.Matrix([m.value(f"{field}.x"), m.value(f"{field}.y")])
            return u / sp.sqrt(u[0] ** 2 + u[1] ** 2)
        a = m.value(field)
        return sp.Matrix([sp.cos(a), sp.sin(a)])

    def force_work(self, P: sp.Matrix, f: sp.Matrix, theta: sp.Expr = sp.S.Zero, moment: sp.Expr = 0) -> list[sp.Expr]:
        """Generalised forces (one per coordinate) of the force ``f`` (N) at ``P`` and the moment
        ``moment`` (N m) on the frame at angle ``theta``: ``f . dP/dq + moment dtheta/dq``."""
        return [f[0] * sp.diff(P[0], qi) + f[1] * sp.diff(P[1], qi) + moment * sp.diff(theta, qi) for qi in self.q]

    # -- constraints ---------------------------------------------------------------
    def constraints(self) -> list[ConstraintRow]:
        """Every scalar constraint, joint by joint in declaration order, then the force elements' (length-mode actuators)."""
        rows = [row for j in self.mech.joints for row in j.rows(self)]
        return rows + element_rows(self)

    # -- inertia -------------------------------------------------------------------
    def mass_matrix(self) -> sp.Matrix:
        """Mass matrix (kg, kg m, kg m^2) from the kinetic energy of every body about its CG."""
        n = len(self.q)
        M = sp.zeros(n, n)
        for i, b in enumerate(self.mech.bodies):
            m, inertia = self.body_mass(b), self.body_inertia(b)
            c = self.local_point(b.name, "cg")
            rc = _rot(self.body_q[b.name][2], c)
            block = sp.Matrix([[m, 0, -m * rc[1]], [0, m, m * rc[0]],
                               [-m * rc[1], m * rc[0], inertia + m * (c[0] ** 2 + c[1] ** 2)]])
            M[3 * i:3 * i + 3, 3 * i:3 * i + 3] = block
        return M

    def body_mass(self, b: Body | SpatialBody) -> sp.Expr:
        """Mass (kg) of body ``b``."""
        return self.mech.value(f"bodies.{b.name}.mass")

    def body_inertia(self, b: Body | SpatialBody) -> sp.Expr:
        """Moment of inertia about the CG (kg m^2): given, or ``m L^2/12`` for a bar."""
        f = f"bodies.{b.name}"
        if b.inertia is not None:
            return self.mech.value(f + ".inertia")
        return self.body_mass(b) * self.mech.value(f + ".length") ** 2 / 12


def pin_chain(mech: Mechanism[JointT, Any], placed: set[str]) -> Iterator[tuple[JointT, str, str, str]]:
    """Walk coincident joints (pins, welds) outward from the ``placed`` bodies (``"ground"`` included).

    Yields ``(joint, known_ref, new_ref, new_body)`` for each joint that places a new body
    from one already placed, in declaration order, repeating until nothing changes. The
    joints yielded form a spanning tree; ``placed`` itself is not modified.
    """
    placed = set(placed)
    changed = True
    while changed:
        changed = False
        for j in mech.joints:
            if not j.COINCIDENT:
                continue
            ba, bb = j.a.split(".")[0], j.b.split(".")[0]
            if (ba in placed) == (bb in placed):
                continue
            known, new = (j.a, j.b) if ba in placed else (j.b, j.a)
            body = new.split(".")[0]
            yield j, known, new, body
            placed.add(body)
            changed = True


def place_along_joints(kin: Kinematics, placed: set[str], guess: dict[str, float], values: Mapping[str, float]) -> None:
    """Move the frame origin of each body reached from the ``placed`` ones through coincident
    joints (:func:`pin_chain`) so that the joint's two points meet, its orientation in ``guess``
    kept: updates ``guess`` (coordinate name -> value) for the kinematics ``kin``, planar or spatial.
    The held coordinates (``[assembly] hold``, at the parameter ``values``) are set first and keep
    their values: placing a body by a joint must not move them."""
    mech = kin.mech
    held = {k: evaluate(mech.value(f"assembly.hold.{k}"), values, f"assembly.hold.{k}") for k in mech.hold}
    guess.update(held)
    num = {symbol(k): v for k, v in values.items()}
    for _, known, new, body in pin_chain(kin.mech, placed):
        origin = kin.origin(body)
        at = {**num, **{symbol(k): v for k, v in guess.items()}}
        P = [float(c) for c in kin.point(known).xreplace(at)]
        local = [float(c) for c in kin.point(new).xreplace({**at, **{s: 0 for s in origin}})]
        for s, p, q in zip(origin, P, local):
            guess[str(s)] = p - q
    guess.update(held)
