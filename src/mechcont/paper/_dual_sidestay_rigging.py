"""The dual-sidestay section's rigging analyses (:mod:`mechcont.paper.dual_sidestay`): how far each lock-link
pair is from aligned at gear down (:func:`lock_misfit`, :func:`alignment_angle`, :func:`rigging_scan`) and the
loads a misrigged pair carries when both are forced to lock (:func:`downlock_loads`)."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from ..models.dual_sidestay import geometry_values
from ..models.dual_sidestay_geometry import DEFAULT_GEOMETRY, GearGeometry

__all__ = ["lock_misfit", "alignment_angle", "rigging_scan", "downlock_loads", "DownlockLoads", "STAY_STIFFNESS",
           "SIDE_LOAD"]


def _knee(A: np.ndarray, n: np.ndarray, L1: float, B: np.ndarray, L2: float, hint: np.ndarray) -> np.ndarray | None:
    """Knee (m): on the circle of radius L1 about A in the plane through A normal to n, at L2 from B; of the
    two solutions the one nearer ``hint``. ``None`` when the arms cannot reach."""
    h = float((B - A) @ n)
    Bp = B - h * n
    r2 = L2**2 - h * h
    d = float(np.linalg.norm(Bp - A))
    if r2 < 0 or d == 0:
        return None
    a = (L1**2 - r2 + d * d) / (2 * d)
    q = L1**2 - a * a
    if q < 0:
        return None
    e = (Bp - A) / d
    f = np.cross(n, e)
    cands = [A + a * e + sgn * math.sqrt(q) * f for sgn in (1, -1)]
    return min(cands, key=lambda k: float(np.linalg.norm(k - hint)))


def lock_misfit(values: dict, side: str, geo: GearGeometry = DEFAULT_GEOMETRY,
                knee_hint: np.ndarray | None = None) -> float:
    """How far (m) the ``side`` lock links are from alignment at the parameter ``values`` (``theta`` ...):
    |K - P'| - (L4 + sqrt(L5^2 - d^2)), with the knee K solved in closed form, P' the lug P projected onto
    the fold plane and d its distance from it. Negative: slack (the links can fold); zero: aligned;
    positive: a rigid link pair would have to stretch by this much. Of the two knee positions the one nearer
    ``knee_hint`` (m; default: the gear-down knee) is taken."""
    from ..models.dual_sidestay_geometry import rotation, trunnion_axis

    R = rotation(trunnion_axis(values["delta"]), values["theta"])

    def vec(name: str) -> np.ndarray:
        return np.array([values[f"{side}_{name}_{c}"] for c in "xyz"])

    A, n = vec("A"), vec("n")
    B, P = R @ vec("B0"), R @ vec("P0")
    st = geo.forward if side == "fwd" else geo.aft
    K = _knee(A, n, values[f"{side}_L1"], B, values[f"{side}_L2"], st.K if knee_hint is None else knee_hint)
    if K is None:
        return float("nan")
    d = float((P - A) @ n)
    reach = values[f"{side}_L4"] + math.sqrt(max(values[f"{side}_L5"] ** 2 - d * d, 0.0))
    return float(np.linalg.norm(K - (P - d * n)) - reach)


def alignment_angle(values: dict, side: str, geo: GearGeometry = DEFAULT_GEOMETRY,
                    window: tuple[float, float] = (-0.0087, 0.0175)) -> float:
    """Retraction angle (rad) near gear down at which the ``side`` lock links are aligned (misfit 0): the
    sign change nearest gear down on a 0.01 deg grid over ``window`` (rad; default -0.5 to 1 deg), polished by Brent's method.

    Raises
    ------
    ValueError
        When the links do not align in ``window`` (or the knee cannot reach there).
    """
    from scipy.optimize import brentq

    def g(t: float) -> float:
        return lock_misfit({**values, "theta": t}, side, geo)

    grid = np.arange(window[0], window[1], math.radians(0.01))
    vals = np.array([g(t) for t in grid])
    pairs = [k for k in range(len(grid) - 1) if np.isfinite(vals[k]) and np.isfinite(vals[k + 1])
             and vals[k] * vals[k + 1] <= 0]
    if not pairs:
        raise ValueError(f"the {side} lock links do not align between {math.degrees(window[0]):.2f} and "
                         f"{math.degrees(window[1]):.2f} deg")
    k = min(pairs, key=lambda k: abs(grid[k]))
    return float(brentq(g, grid[k], grid[k + 1], xtol=1e-15))


def rigging_scan(offsets: Iterable[float],
                 geo: GearGeometry = DEFAULT_GEOMETRY) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rigging tolerance of the rigid downlock: the aft airframe attachment moved by each of ``offsets`` (m)
    along its stay line (towards the fitting positive), all lengths unchanged.

    Returns arrays (rad, rad, m): the aft and forward lock links' alignment angles, and the aft links'
    misfit at the forward links' alignment angle (what a rigid aft link pair would have to stretch, or
    leave slack, for both pairs to be aligned at once).
    """
    values = geometry_values(geo)
    theta_f = alignment_angle(values, "fwd", geo)
    aft, misfit = [], []
    for delta in offsets:
        moved = {**values, **{f"aft_A_{c}": float(a + delta * uc) for c, a, uc in zip("xyz", geo.aft.A, geo.aft.u)}}
        aft.append(alignment_angle(moved, "aft", geo))
        misfit.append(lock_misfit({**moved, "theta": theta_f}, "aft", geo))
    return np.array(aft), np.full(len(aft), theta_f), np.array(misfit)


#: Representative axial stiffness of a sidestay with its airframe attachment (N/m): a steel stay of about
#: 2.1 m and 1e-3 m^2 section (E A / L ~ 1e8 N/m) in series with a wing attachment of ~5e7 N/m.
STAY_STIFFNESS = 3.0e7


@dataclass(frozen=True)
class DownlockLoads:
    """Gear down, both lock-link pairs held at alignment or slack, under gravity (fitting and wheels).

    Attributes: ``theta`` (rad) the settled retraction angle; ``tension`` ``{side: N}`` the axial load in
    each lock-link pair (0 when slack); ``stretch`` ``{side: m}`` each sidestay's elastic extension
    (0 when rigid); ``misfit`` ``{side: m}`` each pair's distance from alignment (<= 0).
    """

    theta: float
    tension: dict
    stretch: dict
    misfit: dict


def _g(values: dict[str, float], side: str, theta: float, stretch: float, geo: GearGeometry) -> float:
    return lock_misfit({**values, "theta": theta, f"{side}_L1": values[f"{side}_L1"] + stretch}, side, geo)


#: Representative outboard side load at the axle (N) for the downlock study: about 0.2 of a main gear's
#: static reaction at 78 t.
SIDE_LOAD = 30.0e3


def downlock_loads(offset: float = 0.0, stiffness: float | None = STAY_STIFFNESS, side_load: float = SIDE_LOAD,
                   geo: GearGeometry = DEFAULT_GEOMETRY, h: float = 1e-6) -> DownlockLoads:
    """Lock-link loads of the locked gear under gravity and an outboard ``side_load`` (N, +y at the axle) with
    the aft attachment moved ``offset`` (m) along its stay, each sidestay an axial spring of ``stiffness``
    (N/m; ``None``: rigid).

    The gear settles where gravity's potential is least subject to misfit <= 0 for both pairs; the
    multiplier of an active misfit constraint is that pair's tension (N). Solved as KKT conditions with
    an active set (a pair with negative tension is slack); derivatives of the closed-form misfit by
    central differences of step ``h``. A rigid gear settles where the first pair aligns: both pairs
    carry load only at the one exact rigging.

    Raises
    ------
    ValueError
        When no active set gives a converged equilibrium.
    """
    from scipy.optimize import fsolve

    from ..models.dual_sidestay_geometry import trunnion_axis

    values = geometry_values(geo)
    values.update({f"aft_A_{c}": float(a + offset * uc) for c, a, uc in zip("xyz", geo.aft.A, geo.aft.u)})
    e = trunnion_axis(geo.delta)
    sides = ("fwd", "aft")

    def dV(theta: float) -> float:  # J/rad: the weight of the fitting and wheels and the side load, about the trunnion axis
        from ..models.dual_sidestay_geometry import rotation

        R = rotation(e, theta)
        return (geo.fitting_mass * geo.g * float(np.cross(e, R @ geo.cg)[2])
                - side_load * float(np.cross(e, R @ geo.axle)[1]))

    def d(f: Callable[[float], float], k: int, z: Sequence[float]) -> float:
        zp, zm = list(z), list(z)
        zp[k] += h
        zm[k] -= h
        return (f(*zp) - f(*zm)) / (2 * h)

    for active in (sides, ("fwd",), ("aft",)):
        if stiffness is None:  # rigid
            if len(active) == 2:
                continue   # a rigid gear settles where the first pair aligns; both only by exact rigging
            side = active[0]
            theta = alignment_angle(values, side, geo)
            tension = -dV(theta) / d(functools.partial(_g, values, side, stretch=0.0, geo=geo), 0, [theta])
            other = [s for s in sides if s != side][0]
            slack = _g(values, other, theta, 0.0, geo)
            if tension >= 0 and slack <= 1e-12:
                return DownlockLoads(theta, {side: tension, other: 0.0}, {s: 0.0 for s in sides},
                                     {side: 0.0, other: slack})
            continue

        def kkt(z: np.ndarray, active: tuple[str, ...] = active) -> list[float]:
            theta, st = z[0], dict(zip(sides, z[1:3]))
            lam = dict(zip(active, z[3:]))
            rows = [dV(theta) + sum(lam[s] * d(functools.partial(_g, values, s, stretch=st[s], geo=geo), 0, [theta])
                                    for s in active)]
            for s in sides:
                grad = d(functools.partial(_g, values, s, theta, geo=geo), 0, [st[s]]) if s in active else 0.0
                rows.append(st[s] * stiffness + lam.get(s, 0.0) * grad)
            rows += [_g(values, s, theta, st[s], geo) * 1e3 for s in active]
            return rows

        lam0 = abs(dV(0.0)) / 4.0 / len(active)   # the misfit changes about 4 m per rad of retraction
        z0 = [alignment_angle(values, active[0], geo), lam0 / stiffness, lam0 / stiffness] + [lam0] * len(active)
        z = fsolve(kkt, z0, xtol=1e-13, full_output=True)[0]   # judged by its residual below
        res = np.abs(kkt(z))
        # converged: the moment and spring rows to 1e-7 of the load moment, the misfits to 1e-9 m
        if not (np.all(res[:3] < 1e-7 * abs(dV(0.0)) + 1e-9) and np.all(res[3:] < 1e-6)):
            continue
        theta, st = z[0], dict(zip(sides, z[1:3]))
        lam = dict(zip(active, z[3:]))
        mis = {s: _g(values, s, theta, st[s], geo) for s in sides}
        if all(v >= 0 for v in lam.values()) and all(mis[s] <= 1e-9 for s in sides if s not in active):
            return DownlockLoads(float(theta), {s: float(lam.get(s, 0.0)) for s in sides},
                                 {s: float(st[s]) for s in sides}, mis)
    raise ValueError(f"no locked equilibrium found for the aft attachment offset {offset} m")
