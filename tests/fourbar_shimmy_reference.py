"""An independent model of tests/data/fourbar_shimmy.toml: the caster wheel steered through a four-bar, in its one
angle ``psi`` (the wheel's), Lagrange's equation written by hand, with the tyre's deflection ``y``.

Geometry (m): the wheel swivels about the ground pin O = 0; its arm point R = 0.2 (-sin psi, cos psi); the crank
(length a = 0.25, pivot B = (0.4, 0), angle alpha) and the coupler (length b = 0.4 from R to the crank pin P, angle
beta) close the loop ``R + b e(beta) = B + a e(alpha)`` (``e(t) = (cos t, sin t)``). P is the intersection of the
circles |P - B| = a, |P - R| = b on the upper side. Differentiating the loop once and twice gives the velocity ratios
``alpha', beta'`` and their derivatives (a 2 x 2 solve each):

    [a e+(alpha), -b e+(beta)] [alpha', beta']   = R',
    [a e+(alpha), -b e+(beta)] [alpha'', beta''] = R'' - b beta'^2 e(beta) + a alpha'^2 e(alpha)     (e+ = e turned +90 deg)

Kinetic energy ``J(psi) psi_dot^2 / 2`` with ``J = I_w + (m_c a^2/4 + I_c) alpha'^2 + m_k |R' + (b/2) beta' e+(beta)|^2
+ I_k beta'^2`` (bars: ``I = m L^2 / 12`` about their centres); Lagrange: ``J psi'' + J'/2 psi_dot^2 = Q`` with

    Q = -k (alpha - alpha_0) alpha' - c (beta' - alpha')^2 psi_dot - (e + t) F(y),   F = F_max tanh(C y / (sigma F_max)),
    y' = e psi_dot + V sin psi - (V / sigma) y                    (tests/test_tyre.py: the caster's tyre).

The linearisation at an equilibrium (psi*, 0, y* = sigma sin psi*) has the characteristic cubic
``s^3 + (c_ + r) s^2 + (k_ + c_ r - q e) s + r (k_ - q sigma cos psi*)`` (``r = V / sigma``, ``k_ = -dQ/dpsi / J``,
``c_ = -dQ/dpsi_dot / J``, ``q = dQ/dy / J``): by Routh-Hurwitz its Hopf speeds solve the quadratic
``c_ r^2 + (c_^2 - q e + q sigma cos psi*) r + c_ (k_ - q e) = 0``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

K, C_D, E, SIGMA, C_T, F_MAX, T_P, ALPHA0 = 20.0, 4.0, 0.1, 0.3, 1800.0, 50.0, 0.02, 1.5
RA, A, B, BX = 0.2, 0.25, 0.4, 0.4
I_W, M_C, M_K = 0.5, 1.0, 1.0
I_C, I_K = M_C * A * A / 12, M_K * B * B / 12


def kinematics(psi: float) -> tuple[float, ...]:
    """``(alpha, beta, alpha', beta', alpha'', beta'')`` (rad, per rad of psi) of the loop at the wheel angle psi."""
    s, c = math.sin(psi), math.cos(psi)
    rx, ry = -RA * s, RA * c
    dx, dy = BX - rx, -ry
    d = math.hypot(dx, dy)
    ux, uy = dx / d, dy / d
    along = (B * B - A * A + d * d) / (2 * d)
    h = math.sqrt(B * B - along * along)
    px, py = rx + along * ux - h * uy, ry + along * uy + h * ux
    al, be = math.atan2(py, px - BX), math.atan2(py - ry, px - rx)
    # the 2 x 2 loop matrix [a e+(alpha), -b e+(beta)] and its solves (Cramer)
    m11, m21, m12, m22 = -A * math.sin(al), A * math.cos(al), B * math.sin(be), -B * math.cos(be)
    det = m11 * m22 - m12 * m21

    def solve(f1, f2):
        return (f1 * m22 - m12 * f2) / det, (m11 * f2 - m21 * f1) / det

    da, db = solve(-RA * c, -RA * s)  # R' = RA (-cos psi, -sin psi)
    g1 = RA * s - B * db * db * math.cos(be) + A * da * da * math.cos(al)  # R'' = RA (sin psi, -cos psi)
    g2 = -RA * c - B * db * db * math.sin(be) + A * da * da * math.sin(al)
    dda, ddb = solve(g1, g2)
    return al, be, da, db, dda, ddb


def inertia(psi: float) -> tuple[float, float]:
    """``(J, dJ/dpsi)`` (kg m^2, kg m^2/rad) of the linkage at psi."""
    s, c = math.sin(psi), math.cos(psi)
    al, be, da, db, dda, ddb = kinematics(psi)
    # the coupler's centre's velocity ratio v = R' + (b/2) beta' e+(beta) and its derivative
    vx = -RA * c - 0.5 * B * db * math.sin(be)
    vy = -RA * s + 0.5 * B * db * math.cos(be)
    ax = RA * s - 0.5 * B * (ddb * math.sin(be) + db * db * math.cos(be))
    ay = -RA * c + 0.5 * B * (ddb * math.cos(be) - db * db * math.sin(be))
    crank = M_C * A * A / 4 + I_C
    J = I_W + crank * da * da + M_K * (vx * vx + vy * vy) + I_K * db * db
    dJ = 2 * (crank * da * dda + M_K * (vx * ax + vy * ay) + I_K * db * ddb)
    return J, dJ


def tyre_force(y: float) -> float:
    """The saturating side force (N) at the deflection y (m)."""
    return F_MAX * math.tanh(C_T * y / (SIGMA * F_MAX))


def rates(z, V: float) -> list[float]:
    """``d(psi, psi_dot, y)/dt`` at the speed V (m/s)."""
    psi, w, y = z
    al, be, da, db, _, _ = kinematics(psi)
    J, dJ = inertia(psi)
    Q = -K * (al - ALPHA0) * da - C_D * (db - da) ** 2 * w - (E + T_P) * tyre_force(y)
    return [w, (Q - 0.5 * dJ * w * w) / J, E * w + V * math.sin(psi) - V / SIGMA * y]


def equilibrium() -> float:
    """psi* (rad): the steered equilibrium, the spring's moment balancing the steady tyre force through the loop
    (independent of V: the steady deflection is sigma sin psi)."""
    def moment(psi):
        al, _, da, _, _, _ = kinematics(psi)
        return -K * (al - ALPHA0) * da - (E + T_P) * tyre_force(SIGMA * math.sin(psi))
    return brentq(moment, -0.2, 0.2, xtol=1e-300, rtol=4 * np.finfo(float).eps)


def hopf_speeds() -> np.ndarray:
    """The two Hopf speeds (m/s), roots of the Routh-Hurwitz quadratic (module docstring), ascending; and their
    frequencies (rad/s), ``omega^2 = k_ + c_ r - q e`` (the cubic's middle coefficient at a Hopf point)."""
    psi = equilibrium()
    al, _, da, db, dda, _ = kinematics(psi)
    J, _ = inertia(psi)
    y = SIGMA * math.sin(psi)
    dF = C_T / SIGMA / math.cosh(C_T * y / (SIGMA * F_MAX)) ** 2
    k_ = K * (da * da + (al - ALPHA0) * dda) / J  # -dQ/dpsi / J (the tyre's force does not depend on psi)
    c_ = C_D * (db - da) ** 2 / J
    q = -(E + T_P) * dF / J
    r = np.sort(np.roots([c_, c_ * c_ - q * E + q * SIGMA * math.cos(psi), c_ * (k_ - q * E)]).real)
    V = SIGMA * r
    return V, np.sqrt(k_ + c_ * r - q * E)


def cycle(V: float, t_end: float = 30.0, rtol: float = 1e-11):
    """The limit cycle at V by a long integration (DOP853) from psi* + 0.1 rad at rest: ``(period (s), min psi,
    max psi (rad), z)`` of its last two periods, ``z`` the state at the last maximum of psi (a point on the cycle)."""
    psi0 = equilibrium()
    z0 = [psi0 + 0.1, 0.0, SIGMA * math.sin(psi0)]
    sol = solve_ivp(lambda _t, z: rates(z, V), (0.0, t_end), z0, method="DOP853", rtol=rtol, atol=1e-13,
                    dense_output=True)
    t = np.linspace(t_end - 3.0, t_end, 3001)
    w = sol.sol(t)[1]
    # extrema of psi: where psi_dot changes sign, refined on the dense output
    ups = [brentq(lambda s: sol.sol(s)[1], t[i], t[i + 1], xtol=1e-14) for i in range(len(t) - 1)
           if w[i] < 0 <= w[i + 1]]
    downs = [brentq(lambda s: sol.sol(s)[1], t[i], t[i + 1], xtol=1e-14) for i in range(len(t) - 1)
             if w[i] > 0 >= w[i + 1]]
    period = downs[-1] - downs[-2]
    return period, float(sol.sol(ups[-1])[0]), float(sol.sol(downs[-1])[0]), sol.sol(downs[-1])


def monodromy(V: float, z: np.ndarray, period: float, h: float = 1e-6) -> np.ndarray:
    """The monodromy matrix (3 x 3) of the cycle through z by central differences of the flow over one period."""
    M = np.zeros((3, 3))
    for j in range(3):
        ends = []
        for sgn in (1, -1):
            z0 = np.array(z, float)
            z0[j] += sgn * h
            ends.append(solve_ivp(lambda _t, zz: rates(zz, V), (0.0, period), z0, method="DOP853", rtol=1e-13,
                                  atol=1e-15).y[:, -1])
        M[:, j] = (ends[0] - ends[1]) / (2 * h)
    return M
