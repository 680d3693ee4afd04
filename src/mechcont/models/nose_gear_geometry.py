"""Geometry and masses of the planar nose landing gear (paper Figure 6), chosen and documented.

The paper (Knowles, Krauskopf & Lowenberg 2010, Section III) publishes no dimensions or
masses. The values below describe a plausible nose gear of a 25–30 t regional aircraft and
are *tuned* so that the paper's qualitative findings have a chance to reappear. Coordinates:
origin at the main-fitting pivot O, +x aft (the airflow direction at alpha = 0), +y up,
angles from +x, counter-clockwise positive. The gear retracts forward (wheel swings forward
and up, theta3 decreasing), so drag assists extension, as on most nose gears (e.g. the A320
family's nose gear "retracts forward ... favorably assisted by aerodynamic moments during
gear extension").

Sources for the proportions
---------------------------
* N. S. Currey, *Aircraft Landing Gear Design: Principles and Practices*, AIAA 1988
  (ch. 4–5: nose-gear layout, folding drag brace with lock links acting on the brace knee,
  lock links rigged at or slightly past the aligned position and held by springs).
* J. Roskam, *Airplane Design Part IV: Layout Design of Landing Gear and Systems*, 1986
  (strut lengths and diameters; landing gear mass 2.5–5 % of the take-off mass, the nose
  gear about 15 % of that: ~150 kg at 25–30 t).

Chosen layout (downlocked: theta3 = 80 deg, i.e. the strut raked 10 deg forward at the bottom)
-------------------------------------------------------------------------------------------------
======================  =====================================================  ==========
bar                     role                                                   length
======================  =====================================================  ==========
1 drag stay upper       airframe point A = (-1.40, 0.25) m to the knee K        0.95 m
2 drag stay lower       knee K to the lug P2 on the main fitting                 0.95 m
3 main fitting          pivot O = (0, 0) to the axle, CG at mid-length           2.00 m
4 lock link (upper)     knee K to the lock-link joint J                          0.35 m
5 lock link (lower)     joint J to the lug P5 on the main fitting                0.27 m
======================  =====================================================  ==========

Main-fitting lugs are given as the paper writes them, measured from the pivot O towards
the axle, rotated by an offset angle: ``P = O - r (cos(theta3 + a), sin(theta3 + a))`` with
``(r, a) = (L32, psi1)`` for the drag stay, ``(L35, -psi2)`` for the lock links and
``(l_sp2, psi3)`` for the lock-link spring. The drag-stay knee is bent 23 deg from straight
when downlocked (the drag stay is not at its own dead centre, so the configuration is
regular). ``L35`` and ``psi2`` are *derived* (:func:`aligned_lock_lug`): P5 is placed level
with the knee at distance L4 + L5, so that with theta4 = 0 the lock links are level *and*
aligned (overcentre angle 180 deg) — the paper's downlock condition and its footnote c.

Lock-link spring: from bar 4 (at ``l_sp1`` from its centre, positive towards the knee, the
"sidestay" end) to the main fitting at ``l_sp2 = 1.69 m``, ``psi3 = -0.06 rad``: nearly
vertical, 1.30 m long, so that the paper's unstrained lengths LU = 0.8–1.3 m are meaningful
(real lock springs are shorter; this is the one concession to the paper's numbers).
``k = 20 kN/m``, ``LU = 1.3 m`` (the paper's highlighted value), ``l_sp1 = 0.1 m``.

Masses: drag stay 12 + 10 kg, main fitting with shock strut and wheels 120 kg, lock links
2.5 + 2.0 kg; bar inertias m L^2 / 12 about the centre. Drag (paper eq. 12): strut diameter
``d = 0.15 m``, ``C_D = 1.17``, ``rho = 1.225 kg/m^3``.

What this geometry implies (derived, and checked in the tests)
---------------------------------------------------------------
With the lock links aligned the mechanism sits at a *dead centre*: to first order the drag
stay and the main fitting do not move when the lock links rotate. The downlock force at
theta4 = 0 is then independent of every load on bars 1–3 (drag, gear weight) and equals

    F = (m4 + m5) g / 2 + k (s - LU) (h / s) (1/2 - l_sp1 / L4)

(``s`` the spring length, ``h`` its vertical extent): exactly linear in ``k`` and ``LU``,
nonlinear in ``l_sp1`` (see :func:`aligned_downlock_force`). The drag effect the paper
reports (1.5 N over 0–100 m/s) needs the lock links to be slightly *misaligned* when
theta4 = 0; :func:`aligned_lock_lug` takes an offset for that study.

Results with this geometry (``mechcont paper``, tested in ``tests/test_nose_gear_paper.py``):
downlock force 71.99 N at the defaults; airspeed: no effect when aligned, -2.3 N at
100 m/s (quadratic) with the lock-link lug 0.5 mm short; slopes -4239 N per m of LU and
2.50 N per kN/m of k; at LU = 1.3 m F(l_sp1) has a minimum of -16.1 N at l_sp1 = -0.104 m
and a maximum of 72.1 N at 0.096 m; the folds of F w.r.t. l_sp1 exist only above the cusp
at LU = 1.2885 m (the extrema need a nearly slack spring: LU = s^3 / (s^2 + (L4/2 - l_sp1)
dx) with s the spring length and dx its horizontal extent, minimal at the cusp).

Why the fold band is narrow (and cannot reach the paper's 0.8 m here)
----------------------------------------------------------------------
With ``a = L4/2 - l_sp1`` (attachment from the knee) and ``r = a dx / s^2`` the fold
condition gives ``|s - LU| = s |r| / |1 + r| <= (a |dx| / s) / (1 - |r|)``, and
``a |dx| / s <= L4 cos(phi)``, phi the spring's angle from horizontal
(:func:`fold_depth_bound`): folds exist only for LU within about one lock-link length of
the spring length. The paper's spring is in tension at LU = 1.3 m
(s > 1.3 m), so folds down to LU = 0.8 m need a >= 0.5 m with a nearly horizontal spring: lock
links longer than 0.5 m, i.e. not this gear. A search over the spring lug (l_sp2 <= 1.9 m,
lug at most 0.25 m off the strut axis, spring >= 1.31 m long) widens the band at best to
LU = 1.25..1.43 m (l_sp2 = 1.64 m, psi3 = +0.15 rad, a 0.245 m bracket; checked with the
model's fold continuation) — five times wider, but then the fold LU is monotone along the
lock link: one fold per LU and the cusp beyond the link's end (l_sp1 < -L4/2), i.e. the
paper's cusp and two-extrema picture is lost. The documented geometry above is kept.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from ..errors import InputError

__all__ = ["PARAMETERS", "defaults", "aligned_lock_lug", "pose", "downlocked_pose", "aligned_downlock_force",
           "fold_depth_bound", "DOWNLOCK_THETA3"]

#: Main-fitting angle at which the default geometry is downlocked (rad): 10 deg forward rake.
DOWNLOCK_THETA3 = math.radians(80.0)

#: name -> (default value, unit, typical magnitude, description). L35 and psi2 are filled
#: in by :func:`aligned_lock_lug`.
PARAMETERS: dict[str, tuple[float, str, float, str]] = {
    "Ax": (-1.40, "m", 1.0, "airframe attachment of the drag stay, x"),
    "Ay": (0.25, "m", 1.0, "airframe attachment of the drag stay, y"),
    "L1": (0.95, "m", 1.0, "drag stay upper length"),
    "L2": (0.95, "m", 1.0, "drag stay lower length"),
    "L3": (2.00, "m", 1.0, "main fitting length, pivot to axle"),
    "L4": (0.35, "m", 1.0, "lock link 1 length (paper ll1)"),
    "L5": (0.27, "m", 1.0, "lock link 2 length (paper ll2)"),
    "L32": (1.20, "m", 1.0, "pivot to drag-stay lug along the main fitting"),
    "psi1": (0.0, "rad", 1.0, "angle offset of the drag-stay lug"),
    "L35": (float("nan"), "m", 1.0, "pivot to lock-link lug along the main fitting (derived)"),
    "psi2": (float("nan"), "rad", 1.0, "angle offset of the lock-link lug (derived; enters as -psi2)"),
    "l_sp1": (0.10, "m", 0.1, "spring attachment on lock link 1 from its centre, + towards the knee"),
    "l_sp2": (1.69, "m", 1.0, "pivot to spring lug along the main fitting"),
    "psi3": (-0.06, "rad", 1.0, "angle offset of the spring lug"),
    "k": (20000.0, "N/m", 20000.0, "lock-link spring stiffness"),
    "LU": (1.30, "m", 0.1, "unstrained spring length"),
    "c": (0.0, "N s/m", 100.0, "damping along the spring (dynamic model only)"),
    "c3": (0.0, "N m s", 100.0, "rotational damping at the main-fitting pivot (dynamic model only)"),
    "m1": (12.0, "kg", 10.0, "drag stay upper mass"),
    "m2": (10.0, "kg", 10.0, "drag stay lower mass"),
    "m3": (120.0, "kg", 100.0, "main fitting, shock strut and wheels mass"),
    "m4": (2.5, "kg", 1.0, "lock link 1 mass"),
    "m5": (2.0, "kg", 1.0, "lock link 2 mass"),
    "g": (9.81, "m/s^2", 10.0, "gravitational acceleration"),
    "F": (0.0, "N", 100.0, "vertical force at the lock-link joint, + up (the unlock direction)"),
    "U": (0.0, "m/s", 100.0, "airspeed"),
    "alpha": (0.0, "rad", 1.0, "airflow direction from +x"),
    "rho": (1.225, "kg/m^3", 1.0, "air density"),
    "CD": (1.17, "", 1.0, "drag coefficient of the main fitting (cylinder)"),
    "d": (0.15, "m", 0.1, "main fitting diameter"),
}


def _e(a: float) -> np.ndarray:
    return np.array([math.cos(a), math.sin(a)])


def _circle_intersection(P: tuple[float, float] | np.ndarray, r1: float, Q: tuple[float, float] | np.ndarray, r2: float,
                         side: int) -> np.ndarray:
    """Point at distance r1 from P and r2 from Q, on the left (side=+1) of P->Q or the right."""
    dvec = np.asarray(Q, float) - np.asarray(P, float)
    dist = float(np.hypot(*dvec))
    a = (r1**2 - r2**2 + dist**2) / (2 * dist)
    h2 = r1**2 - a**2
    if h2 < -1e-12 * r1**2 or dist == 0:
        raise InputError("geometry", f"a loop cannot close: distance {dist:.6g} m with links {r1:.6g} and {r2:.6g} m")
    h = math.sqrt(max(h2, 0.0))
    u = dvec / dist
    n = np.array([-u[1], u[0]])
    return np.asarray(P, float) + a * u + side * h * n


def _knee(p: Mapping[str, float], theta3: float) -> tuple[np.ndarray, np.ndarray]:
    P2 = -p["L32"] * _e(theta3 + p["psi1"])
    K = _circle_intersection((p["Ax"], p["Ay"]), p["L1"], P2, p["L2"], +1)
    return P2, K


def aligned_lock_lug(p: Mapping[str, float], theta3: float = DOWNLOCK_THETA3, offset: float = 0.0) -> tuple[float, float]:
    """``(L35 [m], psi2 [rad])`` placing the lock-link lug P5 level with the knee at L4 + L5 + offset.

    With ``offset = 0`` the lock links are level and aligned (overcentre angle 180 deg) at
    theta4 = 0 with the main fitting at ``theta3``. A nonzero ``offset`` (m) moves the lug
    along the line of the links: theta4 = 0 then leaves them misaligned (a rigging error).
    """
    _, K = _knee(p, theta3)
    P5 = K + np.array([p["L4"] + p["L5"] + offset, 0.0])
    L35 = float(np.hypot(*P5))
    # P5 = -L35 (cos(theta3 - psi2), sin(theta3 - psi2))
    psi2 = theta3 - math.atan2(-P5[1], -P5[0])
    return L35, float(psi2)


def defaults(**overrides: float) -> dict[str, float]:
    """All parameter values (SI) with ``overrides``; L35/psi2 derived unless overridden.

    Raises :class:`InputError` for an unknown name or a non-finite value.
    """
    p = {k: v[0] for k, v in PARAMETERS.items()}
    for k, v in overrides.items():
        if k not in p:
            raise InputError(k, f"not a parameter of the nose gear; valid: {', '.join(p)}")
        v = float(v)
        if not math.isfinite(v):
            raise InputError(k, f"must be a finite number, got {v!r}")
        p[k] = v
    if "L35" not in overrides or "psi2" not in overrides:
        L35, psi2 = aligned_lock_lug(p)
        if "L35" not in overrides:
            p["L35"] = L35
        if "psi2" not in overrides:
            p["psi2"] = psi2
    return p


def pose(p: Mapping[str, float], theta3: float, lock_side: int = -1) -> dict[str, float]:
    """The 15 body coordinates in closed form for a main-fitting angle ``theta3`` (rad).

    ``lock_side = -1`` puts the lock-link joint J below the line from the knee to P5
    (overcentre angle < 180 deg), ``+1`` above. Raises :class:`InputError` when a loop
    cannot close at this ``theta3``.
    """
    P2, K = _knee(p, theta3)
    A = np.array([p["Ax"], p["Ay"]])
    O = np.zeros(2)
    P5 = -p["L35"] * _e(theta3 - p["psi2"])
    J = _circle_intersection(K, p["L4"], P5, p["L5"], -lock_side)
    out: dict[str, float] = {}
    bars = {1: (A, K), 2: (K, P2), 4: (K, J), 5: (J, P5)}  # bar 3 (through O) below
    for i, (a, b) in bars.items():
        out[f"x{i}"], out[f"y{i}"] = (0.5 * (a + b)).tolist()
        out[f"theta{i}"] = math.atan2(b[1] - a[1], b[0] - a[0])
    G3 = O - 0.5 * p["L3"] * _e(theta3)
    out["x3"], out["y3"], out["theta3"] = float(G3[0]), float(G3[1]), float(theta3)
    return out


def _gap_scan(p: Mapping[str, float], ts: np.ndarray, theta4: float) -> np.ndarray:
    """``downlocked_pose``'s closure gap |P5 - J| - L5 (m) at every main-fitting angle of ``ts`` at once
    (NaN where the knee cannot close): the same construction as :func:`_knee`, on arrays."""
    A = np.array([p["Ax"], p["Ay"]])[:, None]
    P2 = -p["L32"] * np.array([np.cos(ts + p["psi1"]), np.sin(ts + p["psi1"])])
    d = P2 - A
    dist = np.hypot(d[0], d[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        a = (p["L1"] ** 2 - p["L2"] ** 2 + dist ** 2) / (2 * dist)
        h2 = p["L1"] ** 2 - a ** 2
        u = d / dist
        K = A + a * u + np.sqrt(np.maximum(h2, 0.0)) * np.array([-u[1], u[0]])
    J = K + p["L4"] * _e(theta4)[:, None]
    P5 = -p["L35"] * np.array([np.cos(ts - p["psi2"]), np.sin(ts - p["psi2"])])
    gap = np.hypot(*(P5 - J)) - p["L5"]
    gap[(h2 < -1e-12 * p["L1"] ** 2) | (dist == 0)] = np.nan
    return gap


def downlocked_pose(p: Mapping[str, float], theta4: float = 0.0) -> dict[str, float]:
    """The 15 coordinates where the lock link 1 angle is ``theta4`` (rad), near the downlocked pose.

    Solves the one scalar closure |P5 - J| = L5 for theta3 (bracketed root search) with
    J = K + L4 (cos theta4, sin theta4). Raises :class:`InputError` if no such pose exists nearby.
    """
    from .._roots import brentq

    def gap(t3: float) -> float:
        try:
            _, K = _knee(p, t3)
        except InputError:
            return float("nan")
        J = K + p["L4"] * _e(theta4)
        P5 = -p["L35"] * _e(t3 - p["psi2"])
        return float(np.hypot(*(P5 - J)) - p["L5"])

    ts = DOWNLOCK_THETA3 + np.linspace(-0.5, 0.5, 1001)
    vals = _gap_scan(p, ts, theta4)  # brackets only: each root is found on the scalar gap
    roots = [brentq(gap, ts[i], ts[i + 1], xtol=1e-15, rtol=1e-15)
             for i in range(len(ts) - 1) if vals[i] * vals[i + 1] < 0 or vals[i] == 0]
    if not roots:
        raise InputError("theta4", f"no assembled nose-gear pose with theta4 = {theta4:g} rad near the downlocked pose")
    t3 = min(roots, key=lambda t: abs(t - DOWNLOCK_THETA3))
    P2, K = _knee(p, t3)
    J = K + p["L4"] * _e(theta4)
    P5 = -p["L35"] * _e(t3 - p["psi2"])
    out = pose(p, t3)
    mid4 = 0.5 * (K + J)
    out["x4"], out["y4"], out["theta4"] = float(mid4[0]), float(mid4[1]), float(theta4)
    out["x5"], out["y5"] = (0.5 * (J + P5)).tolist()
    out["theta5"] = math.atan2(P5[1] - J[1], P5[0] - J[0])
    return out


def aligned_downlock_force(p: Mapping[str, float]) -> float:
    """Downlock force F (N) at theta4 = 0 in closed form, for lock links aligned there (dead centre).

    Virtual work with the knee and P5 fixed to first order: only the lock links' weights,
    the spring and F work, so F = (m4 + m5) g / 2 - T u_y (1/2 - l_sp1/L4), with T = k (s - LU)
    the spring tension and u the unit vector from the bar-4 attachment to the fitting lug.
    Independent of the drag and of the masses of bars 1–3. Raises :class:`InputError` when the
    lock links are not aligned at theta4 = 0 in ``p`` (|overcentre angle - pi| > 1e-9).
    """
    q = downlocked_pose(p, 0.0)
    if abs(q["theta5"] - q["theta4"]) > 1e-9:
        raise InputError("L35", "lock links are not aligned at theta4 = 0; the closed form needs the dead centre")
    K = np.array([q["x4"], q["y4"]]) - 0.5 * p["L4"] * _e(0.0)
    S4 = K + (0.5 * p["L4"] - p["l_sp1"]) * _e(0.0)
    S3 = -p["l_sp2"] * _e(q["theta3"] + p["psi3"])
    dvec = S3 - S4
    s = float(np.hypot(*dvec))
    T = p["k"] * (s - p["LU"])
    return (p["m4"] + p["m5"]) * p["g"] / 2 - T * dvec[1] / s * (0.5 - p["l_sp1"] / p["L4"])


def fold_depth_bound(p: Mapping[str, float], n: int = 401) -> tuple[float, float]:
    """``(bound [m], s_min [m])``: how far from the spring length folds of F(l_sp1) can lie.

    At the dead centre a fold at attachment ``a = L4/2 - l_sp1`` (m from the knee) has
    ``|s - LU| = s |r| / |1 + r| <= (a |dx| / s) / (1 - |r|)`` with ``r = a dx / s^2`` (s the
    spring length, dx its horizontal extent). Returns the largest right-hand side over the
    lock link (``-L4/2 <= l_sp1 <= L4/2``; needs ``|r| < 1``) and the smallest spring length
    there: folds need ``LU >= s_min - bound``.
    """
    q = downlocked_pose(p, 0.0)
    K = np.array([q["x4"], q["y4"]]) - 0.5 * p["L4"] * _e(0.0)
    S3 = -p["l_sp2"] * _e(q["theta3"] + p["psi3"])
    a = np.linspace(0.0, p["L4"], n)
    dx = S3[0] - (K[0] + a)
    sl = np.hypot(dx, S3[1] - K[1])
    r = np.abs(a * dx) / sl**2
    return float(np.max(np.abs(a * dx) / sl / (1.0 - r))), float(np.min(sl))
