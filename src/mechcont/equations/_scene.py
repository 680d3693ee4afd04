"""What a drawing of a mechanism at one configuration shows, independent of how it is drawn.

Models (hand-formulated or generated) provide ``scene(x) -> Scene`` for a full variable
vector ``x``; :mod:`mechcont.outputs.drawing` turns scenes into pictures and animations.
All coordinates are in metres in the plane of the mechanism; forces in newtons; moments in
newton metres, counter-clockwise positive.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

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
        around ``point`` (for a moment on a body pinned to the ground: that pin).
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

    def extent(self) -> tuple[float, float, float, float]:
        """Bounding box ``(xmin, xmax, ymin, ymax)`` of every primitive (m)."""
        pts = [p for _, b in self.bars for p in np.atleast_2d(b)] + list(self.pins) + list(self.grounds)
        pts += [p for p, _ in self.sliders] + [p for _, a, b in self.springs for p in (a, b)]
        pts += [p for _, a, b in self.dampers for p in (a, b)] + list(self.anchors)
        pts += [p for _, a, b, _ in self.actuators for p in (a, b)]
        pts += [p for _, p, _ in self.forces] + [p for _, p, _ in self.moments]
        arr = np.array(pts, dtype=float).reshape(-1, 2)
        return float(arr[:, 0].min()), float(arr[:, 0].max()), float(arr[:, 1].min()), float(arr[:, 1].max())
