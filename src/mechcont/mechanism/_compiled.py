"""The compiled callables a generated model carries (its coordinates, dropped rows' residual, scenes,
value checks).

Picklable, and apart from the generators (which import SymPy), so that a model loaded from the
disk cache finds their classes without importing SymPy.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..equations import Apart, Scene
from ..units import SI, UnitSystem

__all__ = ["DroppedResidual", "CoordinatesOf", "GeneratedScene", "SpatialScene", "ValueCheck", "SCREEN_MARGIN"]


@dataclass(frozen=True)
class DroppedResidual:
    """``f(x) -> max |Phi_dropped(x)|`` (m or rad): 0 while the dropped rows stay implied."""

    fn: Callable[[np.ndarray], np.ndarray] | None

    def __call__(self, x: np.ndarray) -> float:
        """Largest residual of the dropped redundant constraint rows at ``x`` (0.0 if none dropped)."""
        if self.fn is None:
            return 0.0
        return float(np.max(np.abs(self.fn(np.asarray(x, dtype=float)))))


@dataclass(frozen=True)
class CoordinatesOf:
    """``f(x) -> {coordinate: value}`` for every body coordinate, eliminated ones included."""

    coordinates: tuple[str, ...]
    fn: Callable[[np.ndarray], np.ndarray]

    def __call__(self, x: np.ndarray) -> dict[str, float]:
        """All body coordinates (m, rad) at the full variable vector ``x``."""
        return dict(zip(self.coordinates, (float(v) for v in self.fn(np.asarray(x, dtype=float)))))


@dataclass(frozen=True)
class GeneratedScene:
    """``scene(x) -> Scene`` of a generated mechanism (see :func:`scene_function`); picklable.

    ``items`` lists ``(kind, name, (number of points, extra))`` in the order of the compiled
    function ``fn``'s output pairs; ``units`` the description's (the scenes' lengths and loads are in them).
    """

    items: tuple
    fn: Callable[[np.ndarray], np.ndarray]
    units: UnitSystem = SI

    def __call__(self, x: np.ndarray) -> Scene:
        """Drawing primitives at the full variable vector ``x`` (m, N)."""
        flat = np.asarray(self.fn(np.asarray(x, dtype=float)), dtype=float).reshape(-1, 2)
        out, i = Scene(units=self.units), 0
        for kind, name, (n, _) in self.items:
            pts = flat[i:i + n]
            i += n
            if kind == "bar":
                out.bars.append((name, pts.copy()))
            elif kind == "pin":
                out.pins.append(pts[0].copy())
            elif kind == "ground":
                out.grounds.append(pts[0].copy())
            elif kind == "slider":
                out.sliders.append((pts[0].copy(), pts[1].copy()))
            elif kind == "spring":
                out.springs.append((name, pts[0].copy(), pts[1].copy()))
            elif kind == "damper":
                out.dampers.append((name, pts[0].copy(), pts[1].copy()))
            elif kind == "anchor":
                out.anchors.append(pts[0].copy())
            elif kind == "actuator":
                out.actuators.append((name, pts[0].copy(), pts[1].copy(), float(pts[2][0])))
            elif kind == "moment":
                out.moments.append((name, pts[0].copy(), float(pts[1][0])))
            elif kind == "point":
                out.points.append((name, pts[0].copy()))
            elif kind == "slot":
                out.slots.append((name, pts[0].copy(), pts[1].copy()))
            elif kind in ("torsion_spring", "torsion_damper"):
                out.coils.append((name, pts[0].copy(), kind.removeprefix("torsion_")))
            else:
                out.forces.append((name, pts[0].copy(), pts[1].copy()))
        return out


@dataclass(frozen=True)
class SpatialScene:
    """``scene(x) -> Scene`` (3-D) of a generated spatial mechanism; picklable.

    ``items`` lists ``(kind, name, number of points)`` in the order of the compiled function
    ``fn``'s output triples (see :func:`spatial_scene_function`); ``units`` the description's."""

    items: tuple
    fn: Callable[[np.ndarray], np.ndarray]
    units: UnitSystem = SI

    def __call__(self, x: np.ndarray) -> Scene:
        """Drawing primitives (3-D) at the full variable vector ``x``."""
        flat = np.asarray(self.fn(np.asarray(x, dtype=float)), dtype=float).reshape(-1, 3)
        out, i = Scene(units=self.units), 0
        for kind, name, n in self.items:
            pts = flat[i:i + n].copy()
            i += n
            if kind == "bar":
                out.bars.append((name, pts))
            elif kind == "pin":
                out.pins.append(pts[0])
            elif kind == "ground":
                out.grounds.append(pts[0])
            elif kind == "axis":
                out.joint_axes.append((name, pts[0], pts[1]))
            elif kind == "spring":
                out.springs.append((name, pts[0], pts[1]))
            elif kind == "damper":
                out.dampers.append((name, pts[0], pts[1]))
            elif kind == "actuator":
                out.actuators.append((name, pts[0], pts[1], float(pts[2][0])))
            elif kind == "anchor":
                out.anchors.append(pts[0])
            elif kind == "moment":
                out.moments.append((name, pts[0], pts[1]))
            elif kind == "force":
                out.forces.append((name, pts[0], pts[1]))
            elif kind in ("torsion_spring", "torsion_damper"):
                out.coils.append((name, pts[0], kind.removeprefix("torsion_")))
            else:
                out.points.append((name, pts[0]))
        return out


#: A screened quantity clears its bound only by more than this (SI units); nearer, the exact check decides.
SCREEN_MARGIN = 1e-9


class ValueCheck(Apart):
    """``check(values)``: a description's physical checks at parameter ``values`` (the defaults where not given).

    The exact check (``exact(values)``: SymPy's correctly rounded values, the one-line
    :class:`~mechcont.errors.InputError`) runs only when a compiled screen of the same
    quantities cannot clear the values: a quantity that is not finite, a limit or a vector
    within :data:`SCREEN_MARGIN` of its bound, or no screen (a check it cannot express). Solves
    call this at every start, so values that are clearly valid pass without SymPy; ``exact`` is
    pickled apart and unpickled (importing SymPy) only when it is needed.

    ``groups`` lists ``(kind, n)`` for the screen's consecutive outputs: ``finite`` (each
    finite), ``positive``/``nonnegative`` (one limit), ``nonzero`` (a vector of ``n``) and
    ``perpendicular`` (two 3-vectors, their cosine within 1e-9 of zero). ``screen`` is a compiled
    function of the parameter values, their values when there are no parameters, or None.
    """

    _APART = ("exact",)

    def __init__(self, names: Sequence[str], defaults: Sequence[float],
                 screen: Callable[[np.ndarray], np.ndarray] | np.ndarray | None, groups: Sequence[tuple[str, int]],
                 exact: Callable[[dict[str, float]], None]) -> None:
        self.names, self.defaults = tuple(names), tuple(float(d) for d in defaults)
        self.screen, self.groups = screen, tuple(groups)
        self.exact = exact

    def __call__(self, values: Mapping[str, float]) -> None:
        """Raise :class:`~mechcont.errors.InputError` for physically impossible ``values`` ({name: SI value})."""
        full = {n: float(values.get(n, d)) for n, d in zip(self.names, self.defaults)}
        if not self.clears(full):
            self.exact(full)

    def clears(self, full: Mapping[str, float]) -> bool:
        """True when the screen shows every check passing at ``full`` (all parameters) by a clear margin."""
        if self.screen is None:
            return False
        x = np.array([full[n] for n in self.names], dtype=float)
        if not np.isfinite(x).all():
            return False
        v = self.screen if isinstance(self.screen, np.ndarray) else np.asarray(self.screen(x), dtype=float)
        if not np.isfinite(v).all():
            return False
        i = 0
        for kind, n in self.groups:
            g, i = v[i:i + n], i + n
            if kind == "positive" and not g[0] > SCREEN_MARGIN:
                return False
            if kind == "nonnegative" and not (g[0] == 0.0 or g[0] > SCREEN_MARGIN):
                return False
            if kind == "nonzero" and not np.abs(g).max() > SCREEN_MARGIN:
                return False
            if kind == "perpendicular":
                a, b = g[:3], g[3:]
                na, nb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
                if not (na > SCREEN_MARGIN and nb > SCREEN_MARGIN and abs(float(a @ b)) / (na * nb) < 1e-10):
                    return False
        return True

