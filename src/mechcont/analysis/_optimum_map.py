"""An optimum over two design parameters drawn on their design map (:func:`optimum_map`), with the boundaries
of its active constraints traced through it; see :mod:`mechcont.analysis.optimize` for the optimum."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..equations import Model
from ..errors import ConvergenceError, InputError
from .optimize import BETA, NOT_LOCKING, Constraint, OptimumResult, _Quantities, _reliability_constraints

if TYPE_CHECKING:
    from .design import DesignRegion
    from .study._spec import Distribution

__all__ = ["OptimumMap", "optimum_map"]


@dataclass(frozen=True)
class OptimumMap:
    """An optimum over two design parameters drawn on their design map.

    Attributes
    ----------
    region:
        The design map (:class:`~mechcont.analysis.design.DesignRegion`) over the design bounds.
    optimum:
        ``(x, y)``: the optimum in the map's parameters (SI).
    boundaries:
        ``[(constraint, x, y)]``: each active constraint's boundary as a curve in the plane (SI).
        ``downlock_force`` is continued exactly through the optimum (the force held at its bound,
        the second parameter solved for); a design bound is a line; any other quantity is traced
        through the optimum by Newton on its exact gradient, level by level.
    notes:
        What could not be drawn, and why.
    """

    region: DesignRegion
    optimum: tuple[float, float]
    boundaries: list[tuple[str, np.ndarray, np.ndarray]]
    notes: list[str] = field(default_factory=list)


def optimum_map(system: Model, result: OptimumResult, bounds: Mapping[str, tuple[float, float]], *,
                constraints: Sequence[Constraint] = (), values: Mapping[str, float] | None = None,
                random: Mapping[str, Distribution] | None = None, levels: int = 11, n_x: int = 121,
                grid: int = 11) -> OptimumMap:
    """The design map over the two design parameters of ``result`` with the optimum and its active boundaries.

    ``bounds`` are the design's (the map's extent); ``constraints``, ``values`` and ``random`` those
    given to :func:`optimize`. The map is :func:`~mechcont.analysis.design.design_region` with
    ``levels`` levels of the second parameter and ``n_x`` points in the first; a quantity other
    than the downlock force or a design bound is traced through the optimum by Newton on its
    exact gradient at ``grid`` levels each way. Raises :class:`InputError` unless there are exactly two design parameters.
    """
    from ..continuation import ContinuationOptions, continuation, find_equilibrium
    from .design import design_region
    from .downlock import downlock_condition, downlock_point

    design = list(result.design)
    if len(design) != 2:
        raise InputError("plot", f"a design map needs exactly two design parameters, got {len(design)}")
    xn, yn = design
    values = dict(values or {})
    region = design_region(system, xn, yn, x_bounds=bounds[xn], y_levels=np.linspace(*bounds[yn], levels),
                           values=values, n_x=n_x)
    opt = (result.design[xn], result.design[yn])
    h, f = downlock_condition(system)
    by_text = {str(c): c for c in _reliability_constraints(system, constraints, random)}
    curves: list[tuple[str, np.ndarray, np.ndarray]] = []
    notes: list[str] = []
    for what, _ in result.active:
        c = by_text.get(what)
        if c is None:  # a design bound, "NAME >= EDGE"
            name, _, edge = what.split(" ")
            e = float(edge)
            line = np.array([e, e])
            curves.append((what, line, np.array(bounds[yn])) if name == xn else (what, np.array(bounds[xn]), line))
        elif c.quantity == "downlock_force":
            at = {**values, xn: opt[0], f: c.bound}
            try:
                start = find_equilibrium(system, values=at, hold=h, free=[yn],
                                         guess=downlock_point(system, {**values, xn: opt[0], yn: opt[1]}, hold=h,
                                                              force=f))
                br = continuation(system, start, xn, hold=list(h), free=[yn], options=ContinuationOptions(
                    ds=0.02, dsmin=1e-9, dsmax=0.5, bounds={xn: bounds[xn], yn: bounds[yn]}, max_steps=2000))
            except (ConvergenceError, InputError) as exc:
                notes.append(f"the boundary {what} is not drawn: {exc}")
                continue
            order = np.argsort(br.s)
            curves.append((what, br[xn][order], br[yn][order]))
        else:
            if c.quantity == BETA:  # shown as the probability it stands for
                from scipy.stats import norm

                what = f"{NOT_LOCKING} {'<=' if c.sense == '>=' else '>='} {float(norm.sf(c.bound)):.3g}"
            curves += _traced_boundary(system, c, what, design, bounds, values, random, opt, grid, notes)
    return OptimumMap(region, opt, curves, notes)


def _traced_boundary(system: Model, c: Constraint, what: str, design: Sequence[str],
                     bounds: Mapping[str, tuple[float, float]], values: Mapping[str, float],
                     random: Mapping[str, Distribution] | None, opt: tuple[float, float], n: int,
                     notes: list[str]) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The curve ``c.quantity = c.bound`` through the optimum ``opt``, traced on the exact gradients.

    One design parameter is solved for (the one the quantity changes most across its range, at
    the optimum) by Newton at ``n`` levels of the other, marching out from the optimum both ways
    (each level starts from the last); a level where it fails or leaves the bounds ends that way.
    Returns ``[(what, x, y)]`` in the design's order.
    """
    q = _Quantities(system, design, values, None, random)
    lo = np.array([bounds[d][0] for d in design], dtype=float)
    hi = np.array([bounds[d][1] for d in design], dtype=float)
    z0 = np.array(opt, dtype=float)
    _, g0 = q.at(z0, [c.quantity])[c.quantity]
    i = int(np.argmax(np.abs(g0) * (hi - lo)))  # solved for
    j = 1 - i
    scale = max(abs(c.bound), 1e-12)
    points = {float(z0[j]): z0.copy()}
    for way in (-1, 1):
        z = z0.copy()
        for level in np.linspace(z0[j], hi[j] if way > 0 else lo[j], n)[1:]:
            z = z.copy()
            z[j] = level
            try:
                for _ in range(30):
                    v, g = q.at(z, [c.quantity])[c.quantity]
                    if abs(v - c.bound) <= 1e-9 * scale:
                        break
                    z[i] -= (v - c.bound) / g[i]
                    if not lo[i] <= z[i] <= hi[i]:
                        raise ConvergenceError(f"{design[i]} leaves its bounds")
                else:
                    raise ConvergenceError("Newton did not converge")
            except (ConvergenceError, InputError, ZeroDivisionError, FloatingPointError) as exc:
                notes.append(f"the boundary {what} is not drawn past {design[j]} = {z[j]:g}: {exc}")
                break
            points[float(level)] = z.copy()
    pts = np.array([points[k] for k in sorted(points)])
    return [(what, pts[:, 0], pts[:, 1])]
