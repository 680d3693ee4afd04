"""What a drawing of a mechanism at one configuration shows, independent of how it is drawn.

Models (hand-formulated or generated) provide ``scene(x) -> Scene`` for a full variable
vector ``x``; :mod:`mechcont.outputs.drawing` turns scenes into pictures and animations.
All coordinates are in metres in the plane of the mechanism; forces in newtons; moments in
newton metres, counter-clockwise positive; or, for a description written in other units, in those
(:attr:`Scene.units`, which the drawings label).

A spatial mechanism fills the same fields with 3-vectors (x, y, z in metres; a moment is then
a 3-vector in N m) and may list its joint axes in ``joint_axes``;
:mod:`mechcont.outputs.drawing3d` draws such a scene as an orthographic three-view and a 3-D
view. :attr:`Scene.dimension` tells which kind a scene is.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..units import SI, UnitSystem

__all__ = ["Scene"]


@dataclass
class Scene:
    """Drawing primitives of one configuration.

    Attributes
    ----------
    bars:
        ``(name, points)``: a rigid body drawn as a polyline through ``points`` (k x 2).
    pins:
        Positions (2,) of revolute joints between bodies.
    grounds:
        Positions (2,) of revolute joints to the ground.
    sliders:
        ``(position, direction)``: a point sliding along a ground line of unit direction.
    springs:
        ``(name, start, end)``: a spring between two points.
    forces:
        ``(name, point, vector)``: an applied force (N) at a point.
    moments:
        ``(name, point, value)``: an applied moment (N m, counter-clockwise positive) drawn
        around ``point`` (for a moment on a body pinned to the ground: that pin); in a 3-D
        scene ``value`` is the moment vector (3,).
    anchors:
        Ground points (2,) that springs, dampers or actuators are attached to (no joint there).
    dampers:
        ``(name, start, end)``: a damper between two points.
    actuators:
        ``(name, start, end, tension)``: an actuator between two points and its load (N,
        positive in tension: pulling its ends together).
    points:
        ``(name, position)``: named points, for labels only (e.g. ``"crank.b"``,
        ``"ground.A"``); not part of :meth:`extent`.
    joint_axes:
        ``(name, position, axis)``: the axis (unit vector) of a revolute, cylindrical or
        universal joint's pin at ``position``, drawn as a short line in 3-D views (optional;
        planar scenes leave it empty: their axes are normal to the plane).
    slots:
        ``(name, start, end)``: a straight slot in a body (a pin-in-slot joint), drawn as a
        channel from ``start`` to ``end`` over the body.
    coils:
        ``(name, centre, kind)``: a rotary element at a joint, ``kind`` ``"spring"`` (a torsion
        spring, drawn as a coil around ``centre``) or ``"damper"`` (a rotary dashpot).
    units:
        The units the lengths and loads are in (SI, or a description's declared units).
    """

    bars: list[tuple[str, np.ndarray]] = field(default_factory=list)
    pins: list[np.ndarray] = field(default_factory=list)
    grounds: list[np.ndarray] = field(default_factory=list)
    sliders: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)
    springs: list[tuple[str, np.ndarray, np.ndarray]] = field(default_factory=list)
    forces: list[tuple[str, np.ndarray, np.ndarray]] = field(default_factory=list)
    moments: list[tuple[str, np.ndarray, float]] = field(default_factory=list)
    anchors: list[np.ndarray] = field(default_factory=list)
    dampers: list[tuple[str, np.ndarray, np.ndarray]] = field(default_factory=list)
    points: list[tuple[str, np.ndarray]] = field(default_factory=list)
    actuators: list[tuple[str, np.ndarray, np.ndarray, float]] = field(default_factory=list)
    joint_axes: list[tuple[str, np.ndarray, np.ndarray]] = field(default_factory=list)
    slots: list[tuple[str, np.ndarray, np.ndarray]] = field(default_factory=list)
    coils: list[tuple[str, np.ndarray, str]] = field(default_factory=list)
    units: UnitSystem = SI

    @property
    def dimension(self) -> int:
        """2 for a planar scene, 3 for a spatial one (the length of its first coordinate vector)."""
        for p in self._positions():
            return 3 if np.asarray(p).shape[-1] == 3 else 2
        return 2

    def _positions(self) -> list[np.ndarray]:
        pts = [p for _, b in self.bars for p in np.atleast_2d(b)] + list(self.pins) + list(self.grounds)
        pts += [p for p, _ in self.sliders] + [p for _, a, b in self.springs for p in (a, b)]
        pts += [p for _, a, b in self.dampers for p in (a, b)] + list(self.anchors)
        pts += [p for _, a, b, _ in self.actuators for p in (a, b)]
        pts += [p for _, p, _ in self.forces] + [p for _, p, _ in self.moments]
        pts += [p for _, a, b in self.slots for p in (a, b)] + [p for _, p, _ in self.coils]
        return pts + [p for _, p, _ in self.joint_axes]

    def extent(self) -> tuple[float, ...]:
        """Bounding box of every primitive (m): ``(xmin, xmax, ymin, ymax)``, and for a 3-D scene
        ``(xmin, xmax, ymin, ymax, zmin, zmax)``."""
        d = self.dimension
        arr = np.array(self._positions(), dtype=float).reshape(-1, d)
        return tuple(float(v) for k in range(d) for v in (arr[:, k].min(), arr[:, k].max()))
