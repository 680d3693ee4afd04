"""Design answers from the downlock analysis: where the gear locks unaided, and how far the folds are.

Questions an engineer asks, answered by continuation on the downlock condition (lock links
held aligned, the force ``F`` solved for; see :mod:`mechcont.analysis.downlock`):

* "For which (l_sp1, LU) is the downlock force positive?" — the gear then locks with no
  help. The boundary ``F = 0`` is itself continued (F held at 0, LU freed, l_sp1 varied).
* "What is the margin to the fold?" — folds of the downlock force with respect to the
  design parameter (extrema of F(l_sp1), the paper's Figure 11 limit points) bound the
  region where moving the attachment has the counter-intuitive effect; the margin is the
  distance of the design value to the nearest one, and the fold locus in the second
  parameter ends at a cusp.

Every run the answers rest on is checked: one that failed or stopped short of its bounds
is named, with where and why, in :attr:`DesignRegion.warnings`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..continuation import Branch, ContinuationOptions, SpecialPoint, continuation, continue_folds
from ..equations import Model, units_of
from ..errors import ConvergenceError, InputError
from ..units import derivative_unit
from ._runs import early_stops
from .downlock import downlock, downlock_condition, downlock_point, downlocked_pose

__all__ = ["FoldLocus", "DesignRow", "DesignRegion", "fold_locus", "design_region"]


@dataclass(frozen=True)
class FoldLocus:
    """Folds of the downlock force with respect to a design parameter.

    Attributes
    ----------
    branch:
        Continuation in the force with the design parameter solved for (lock links held);
        its ``LP`` points are the extrema of F(design).
    curve:
        The fold curve continued in the second parameter (``None`` when the branch has no
        fold); ``CP`` marks cusps.
    """

    branch: Branch
    curve: Branch | None
    warnings: list[str] = field(default_factory=list)

    @property
    def cusps(self) -> list[SpecialPoint]:
        """Cusp points (``CP``) of the fold curve."""
        return [] if self.curve is None else self.curve.special("CP")


@dataclass(frozen=True)
class DesignRow:
    """One level of the second parameter in the design table (SI units).

    Attributes
    ----------
    level:
        Value of the second parameter (its unit, e.g. m for ``LU``).
    force_at_design:
        Downlock force (N) at the design value of the first parameter.
    slope_at_design:
        dF/dx (N per unit of x) there: how sensitive the lock is to the design parameter.
    locking_intervals:
        Intervals of x where F > 0 (the gear locks unaided).
    folds:
        Values of x where F(x) has an extremum (folds of the force branch).
    margin_to_fold:
        Distance (unit of x) from the design value to the nearest fold; nan if none.
    margin_to_zero:
        Distance (unit of x) from the design value to the nearest F = 0 crossing; nan if none.
        Unsigned: see :attr:`locks_unaided` and :attr:`lock_margin`.
    """

    level: float
    force_at_design: float
    locking_intervals: tuple[tuple[float, float], ...]
    folds: tuple[float, ...]
    margin_to_fold: float
    margin_to_zero: float = float("nan")
    slope_at_design: float = float("nan")

    @property
    def locks_unaided(self) -> bool:
        """True when the downlock force at the design value is positive (the gear locks with no help)."""
        return bool(self.force_at_design > 0)

    @property
    def lock_margin(self) -> float:
        """:attr:`margin_to_zero` signed: positive when the design locks unaided (by that much of x
        before it stops doing so), negative when it does not (that much of x to go); nan when F does
        not change sign in the range."""
        return self.margin_to_zero if self.locks_unaided else -self.margin_to_zero


@dataclass(frozen=True)
class DesignRegion:
    """Downlock force over a plane of two design parameters, the F = 0 boundary and the folds.

    Attributes
    ----------
    x_name, y_name:
        The design parameters (e.g. ``"l_sp1"``, ``"LU"``).
    x, y:
        Grid vectors; ``force[i, j]`` is the downlock force (N) at ``(x[j], y[i])``.
    boundary:
        Branch along ``F = 0`` (``None`` if it does not cross the plane).
    folds:
        :class:`FoldLocus` (``None`` if no fold in the plane).
    rows:
        :class:`DesignRow` per level of ``y``.
    design:
        The design point ``(x0, y0)``.
    """

    x_name: str
    y_name: str
    x: np.ndarray
    y: np.ndarray
    force: np.ndarray
    boundary: Branch | None
    folds: FoldLocus | None
    rows: list[DesignRow] = field(default_factory=list)
    design: tuple[float, float] = (np.nan, np.nan)
    units: tuple[str, str, str] = ("", "", "N")  # of x, y and the force
    warnings: list[str] = field(default_factory=list)  # runs that stopped short: where and why

    def table(self) -> list[dict[str, float | str]]:
        """The design table as records (one per level), numbers in SI units named in the headings.

        Columns: the level of y; the force at the design x and its slope dF/dx; whether the
        design locks unaided (F > 0 there: "yes"/"no"); the x intervals where F > 0; the folds
        (extrema of F in x); the distance from the design x to the nearest fold; the signed
        margin to the nearest F = 0 crossing (positive: locks unaided with that margin,
        negative: does not, by that much). "none" when there is none in the range.
        """
        ux, uy, uf = (f" ({u})" if u else "" for u in self.units)
        x = self.x_name
        x0 = f"{self.design[0]:g} {self.units[0]}".strip()
        slope_unit = f" ({derivative_unit(self.units[2], self.units[0])})" if self.units[0] else ""

        def dist(v: float) -> str | float:
            return "none" if not np.isfinite(v) else float(v)

        out = []
        for r in self.rows:
            out.append({
                f"{self.y_name}{uy}": r.level,
                f"F at {x}={x0}{uf}": r.force_at_design,
                f"dF/d{x} at {x}={x0}{slope_unit}": r.slope_at_design,
                f"locks unaided at {x}={x0}": "yes" if r.locks_unaided else "no",
                f"{x} where F>0 (locks unaided){ux}": "; ".join(f"{a:.4g}..{b:.4g}" for a, b in r.locking_intervals)
                or "none",
                f"folds (extrema of F) at {x}{ux}": "; ".join(f"{f:.4g}" for f in r.folds) or "none",
                f"margin to fold{ux}": dist(r.margin_to_fold),
                f"lock margin to F=0 (+ locks, - does not){ux}": dist(r.lock_margin),
            })
        return out


def _options(bounds: Mapping[str, tuple[float, float]], scale_span: float,
             max_steps: int = 2000) -> ContinuationOptions:
    return ContinuationOptions(ds=0.02, dsmin=1e-9, dsmax=max(0.02, min(0.5, scale_span)), bounds=bounds,
                               max_steps=max_steps)


def fold_locus(system: Model, design: str, second: str, bounds: Mapping[str, tuple[float, float]], *,
               values: Mapping[str, float] | None = None, hold: Mapping[str, float] | None = None,
               force: str | None = None, force_bounds: tuple[float, float] | None = None,
               condition: str | None = None, max_steps: int = 2000) -> FoldLocus:
    """Extrema of the downlock force in ``design`` (folds) and their locus in ``second``.

    Parameters
    ----------
    system:
        The model.
    design:
        Parameter solved for along the force branch (e.g. ``"l_sp1"``).
    second:
        Parameter in which the folds are continued (e.g. ``"LU"``).
    bounds:
        ``{name: (low, high)}`` for ``design`` and ``second`` (the curve ends at them).
    values, hold, force, condition:
        Start parameter values and the downlock condition (see :func:`downlock`).
    force_bounds:
        Range of the force along the branch; default +-1e4 N (N m for a moment) in the description's units.
    max_steps:
        Most continuation steps each way, for both runs.

    Returns
    -------
    FoldLocus
        The force branch and the fold curve (None when there is no fold).
    """
    h, f = downlock_condition(system, hold, force, condition=condition)
    for n in (design, second):
        system.variable(n)
        if n not in bounds:
            raise InputError("bounds", f"give a range for {n}")
    x0 = downlock_point(system, values, hold=h, force=f)
    if force_bounds is None:
        big = 1e4 * units_of(system).from_si(system.variable(f).unit)
        force_bounds = (-big, big)
    opts = _options({design: bounds[design], f: force_bounds}, 0.5, max_steps)
    br = continuation(system, x0, f, hold=list(h), free=[design], options=opts)
    warnings = early_stops(br, f"force branch in {f} ({design} solved for)", show=(design,))
    lps = br.special("LP")
    if not lps:
        return FoldLocus(br, None, warnings)
    curve_opts = _options({design: bounds[design], second: bounds[second], f: force_bounds}, 0.2, max_steps)
    curve = continue_folds(system, lps[0], vary=f, free=second, options=curve_opts)
    warnings += early_stops(curve, f"fold curve in {second}", show=(design, f))
    return FoldLocus(br, curve, warnings)


def _slope(system: Model, vals: Mapping[str, float], x_name: str, x0: float, xb: tuple[float, float],
           h: Mapping[str, float], f: str) -> float:
    """dF/dx (N per unit of x) at x0 by a central difference of two downlock solves (step 1e-6 x scale)."""
    step = 1e-6 * system.variable(x_name).scale
    a, b = max(x0 - step, xb[0]), min(x0 + step, xb[1])
    try:
        Fa, Fb = (downlock_point(system, {**vals, x_name: v}, hold=h, force=f)[system.index(f)] for v in (a, b))
    except ConvergenceError:
        return float("nan")
    return float((Fb - Fa) / (b - a))


def _refined(system: Model, intervals: Iterable[tuple[float, float]], vals: Mapping[str, float], x_name: str,
             xb: tuple[float, float], h: Mapping[str, float], f: str) -> tuple[tuple[float, float], ...]:
    """The interior ends of ``intervals`` (F = 0 crossings) solved exactly: F held at 0, x freed."""
    from ..continuation import find_equilibrium

    base = downlocked_pose(system)

    edge = 1e-9 * (xb[1] - xb[0])  # a branch's end at its bound, to rounding (1499.9999999999998 of 1500), is no crossing

    def crossing(xc: float) -> float:
        if not xb[0] + edge < xc < xb[1] - edge:
            return xc
        v = {**vals, x_name: xc, f: 0.0}
        try:
            x = find_equilibrium(system, values={k: w for k, w in v.items() if k != x_name}, hold=h, free=[x_name],
                                 guess=system.vector(v, base=base) if base is not None else v)
        except ConvergenceError:
            return xc
        return float(x[system.index(x_name)])

    return tuple((crossing(a), crossing(b)) for a, b in intervals)


def _intervals(x: np.ndarray, F: np.ndarray) -> tuple[tuple[float, float], ...]:
    """Intervals of x where F > 0 (linear interpolation of the crossings)."""
    pos = F > 0
    out, start = [], (x[0] if pos[0] else None)
    for i in range(1, len(x)):
        if pos[i] != pos[i - 1]:
            xc = x[i - 1] - F[i - 1] * (x[i] - x[i - 1]) / (F[i] - F[i - 1])
            if pos[i]:
                start = xc
            else:
                assert start is not None  # F > 0 at x[i - 1]: its interval began there or before
                out.append((float(start), float(xc)))
                start = None
    if start is not None:
        out.append((float(start), float(x[-1])))
    return tuple(out)


def design_region(system: Model, x_name: str, y_name: str, *,
                  x_bounds: tuple[float, float], y_levels: Sequence[float] | np.ndarray,
                  values: Mapping[str, float] | None = None, hold: Mapping[str, float] | None = None,
                  force: str | None = None, n_x: int = 121, condition: str | None = None,
                  max_steps: int = 2000, progress: Callable[[], object] | None = None) -> DesignRegion:
    """Downlock force over the (x, y) design plane, the F = 0 boundary, folds and margins.

    Parameters
    ----------
    system:
        The model.
    x_name, y_name:
        Design parameters: ``x`` is continued for each level of ``y``.
    x_bounds:
        Range of ``x`` (SI).
    y_levels:
        Levels of ``y`` (SI), at least two, increasing.
    values, hold, force, condition:
        Other parameter values and the downlock condition (see :func:`downlock_condition`).
    n_x:
        Number of grid points in ``x`` for the force map.
    max_steps:
        Most continuation steps each way, for every run.
    progress:
        Called with no argument after each level of ``y`` and after the boundary and the fold
        locus (``len(y_levels) + 2`` calls; progress bars).

    Returns
    -------
    DesignRegion
        Force map, boundary branch, fold locus, one :class:`DesignRow` per level, and the
        warnings of every run that stopped short of its bounds.
    """
    h, f = downlock_condition(system, hold, force, condition=condition)
    y_levels = np.asarray(sorted(float(v) for v in y_levels))
    if len(y_levels) < 2:
        raise InputError(y_name, "give at least two levels")
    lo, hi = map(float, x_bounds)
    if not lo < hi:
        raise InputError(x_name, f"empty range {lo:g}:{hi:g}")
    values = dict(values or {})
    x0 = float(values.get(x_name, system.variable(x_name).value))
    x0 = min(max(x0, lo), hi)
    grid = np.linspace(lo, hi, n_x)
    force_map = np.full((len(y_levels), n_x), np.nan)
    rows, warnings = [], []
    big = 1e6 * units_of(system).from_si(system.variable(f).unit)  # 1e6 N (N m) in the file's units
    for i, yv in enumerate(y_levels):
        vals = {**values, y_name: float(yv), x_name: x0}
        # the model at this level: a hold target (or a stop's limit) written in the level's parameter follows it
        level = system.with_values({y_name: float(yv)})
        hl = h if hold else downlock_condition(level, None, force, condition=condition)[0]
        run = downlock(level, x_name, {x_name: (lo, hi)}, values=vals, hold=hl, force=f, unlock=False,
                       max_steps=max_steps)
        warnings += [f"{y_name} = {yv:g}: {w}" for w in run.warnings]
        br = run.branch
        order = np.argsort(br[x_name])
        xs, Fs = br[x_name][order], br[f][order]
        force_map[i] = np.interp(grid, xs, Fs)
        # extrema of F(x): folds of the force branch with x solved for
        try:
            fl = continuation(level, downlock_point(level, vals, hold=hl, force=f), f, hold=list(hl), free=[x_name],
                              options=_options({x_name: (lo, hi), f: (-big, big)}, 0.5, max_steps))
            folds = tuple(sorted(p[x_name] for p in fl.special("LP")))
            warnings += [f"{y_name} = {yv:g}: {w}" for w in early_stops(fl, f"force branch in {f} ({x_name} solved "
                                                                            f"for, to find the folds)", show=(x_name,))]
        except ConvergenceError as exc:
            folds = ()
            warnings.append(f"{y_name} = {yv:g}: the folds of {f} in {x_name} are unknown: {exc}")
        try:
            F0 = float(downlock_point(level, {**vals}, hold=hl, force=f)[system.index(f)])
        except ConvergenceError:
            F0 = float(np.interp(x0, xs, Fs))
        slope = _slope(level, vals, x_name, x0, (lo, hi), hl, f)
        margin = min((abs(x0 - v) for v in folds), default=float("nan"))
        intervals = _refined(level, _intervals(xs, Fs), vals, x_name, (lo, hi), hl, f)
        edge = 1e-9 * (hi - lo)  # an interval's end at a bound, to rounding, is no crossing of F = 0
        crossings = [e for iv in intervals for e in iv if lo + edge < e < hi - edge]
        to_zero = min((abs(x0 - c) for c in crossings), default=float("nan"))
        rows.append(DesignRow(float(yv), F0, intervals, folds, margin, to_zero, slope))
        if progress is not None:
            progress()
    boundary, why = _zero_force_boundary(system, x_name, y_name, (lo, hi), (y_levels[0], y_levels[-1]), grid,
                                         y_levels, force_map, values, h, f, max_steps)
    warnings += why
    if progress is not None:
        progress()
    y_mid = float(values.get(y_name, system.variable(y_name).value))
    locus: FoldLocus | None
    try:
        locus = fold_locus(system, x_name, y_name, {x_name: (lo, hi), y_name: (y_levels[0], y_levels[-1])},
                           values={**values, y_name: y_mid}, hold=h, force=f, max_steps=max_steps)
        warnings += locus.warnings
    except (ConvergenceError, InputError) as exc:
        locus = None
        warnings.append(f"the fold locus from {y_name} = {y_mid:g} is unknown: {exc}")
    if progress is not None:
        progress()
    units = (system.variable(x_name).unit, system.variable(y_name).unit,
             system.variable(f).unit or units_of(system).label("N"))
    return DesignRegion(x_name, y_name, grid, y_levels, force_map, boundary, locus, rows, (x0, y_mid), units,
                        warnings)


def _zero_force_boundary(system: Model, x_name: str, y_name: str, xb: tuple[float, float], yb: tuple[float, float],
                         grid: np.ndarray, levels: np.ndarray, fmap: np.ndarray, values: Mapping[str, float],
                         h: Mapping[str, float], f: str, max_steps: int = 2000) -> tuple[Branch | None, list[str]]:
    """Continue the curve F = 0 in the (x, y) plane from a sign change of the force map.

    The start is solved on the level where the map changes sign (y held there, x solved
    for), so it lies inside the y range whatever the spacing of the levels. Returns
    ``(branch or None, warnings)``.
    """
    from ..continuation import find_equilibrium

    for i in range(len(levels)):
        row = fmap[i]
        idx = np.nonzero(np.sign(row[:-1]) * np.sign(row[1:]) < 0)[0]
        if len(idx):
            j = idx[0]
            xs = grid[j] - row[j] * (grid[j + 1] - grid[j]) / (row[j + 1] - row[j])
            vals = {**values, y_name: float(levels[i]), x_name: float(xs), f: 0.0}
            base = downlocked_pose(system)
            guess = system.vector(vals, base=base) if base is not None else None
            try:
                x0 = find_equilibrium(system, values={k: v for k, v in vals.items() if k != x_name}, hold=h,
                                      free=[x_name], guess=system.vector(vals, base=guess))
                br = continuation(system, x0, x_name, hold=list(h), free=[y_name],
                                  options=_options({x_name: xb, y_name: yb}, 0.5, max_steps))
            except (ConvergenceError, InputError) as exc:
                return None, [f"the {f} = 0 boundary from {y_name} = {levels[i]:g}, {x_name} = {xs:.6g} is unknown: "
                              f"{exc}"]
            return br, early_stops(br, f"{f} = 0 boundary in {x_name} ({y_name} solved for)", show=(y_name,))
    return None, []


