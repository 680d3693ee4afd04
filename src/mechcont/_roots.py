"""Brent's method for a root in a bracket, without importing ``scipy.optimize``.

``scipy.optimize`` takes 0.3-0.5 s to import (it pulls in ``scipy.sparse``, ``scipy.spatial``
and ``scipy.special``), more than a whole continuation run, for the one bracketing root
finder mechcont uses. This is the same algorithm as SciPy's ``brentq`` (Brent 1973 as
written in SciPy's ``brentq.c``: inverse quadratic extrapolation, secant, bisection), step
for step in the same IEEE double arithmetic, so it returns the same bits (tested against
SciPy); its errors are the same types with the same meaning.
"""

from __future__ import annotations

import math
from collections.abc import Callable

__all__ = ["brentq"]

#: SciPy's defaults (``xtol``; ``rtol`` = 4 machine epsilons, its smallest allowed value).
XTOL = 2e-12
RTOL = 4 * 2.220446049250313e-16


def _value(f: Callable[[float], float], x: float) -> float:
    fx = float(f(x))
    if math.isnan(fx):
        raise ValueError(f"The function value at x={x:f} is NaN; solver cannot guarantee convergence.")
    return fx


def brentq(f: Callable[[float], float], a: float, b: float, xtol: float = XTOL, rtol: float = RTOL,
           maxiter: int = 100, fa: float | None = None, fb: float | None = None) -> float:
    """A zero of the scalar function ``f`` between ``a`` and ``b`` (where ``f`` changes sign).

    Converged when the bracket's half width is below ``(xtol + rtol * |x|) / 2`` or ``f``
    is exactly zero. Returns the abscissa (same units as ``a``, ``b``). ``fa`` / ``fb``:
    the values at ``a`` / ``b`` when the caller knows them (``f`` is then not called there;
    with ``f(a)``, ``f(b)`` themselves the iterates are the same).

    Raises
    ------
    ValueError
        ``f(a)`` and ``f(b)`` have the same sign, ``f`` returned NaN, or a tolerance is invalid.
    RuntimeError
        Not converged in ``maxiter`` iterations.
    """
    if xtol <= 0:
        raise ValueError(f"xtol too small ({xtol:g} <= 0)")
    if rtol < RTOL:
        raise ValueError(f"rtol too small ({rtol:g} < {RTOL:g})")
    if maxiter < 0:
        raise ValueError("maxiter should be > 0")
    xpre, xcur = float(a), float(b)
    fpre = _value(f, xpre) if fa is None else float(fa)
    fcur = _value(f, xcur) if fb is None else float(fb)
    if math.isnan(fpre) or math.isnan(fcur):
        raise ValueError("The function value at an end of the bracket is NaN; solver cannot guarantee convergence.")
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    if (fpre < 0) == (fcur < 0):
        raise ValueError("f(a) and f(b) must have different signs")
    xblk = fblk = spre = scur = 0.0
    for _ in range(maxiter):
        if fpre != 0 and fcur != 0 and (fpre < 0) != (fcur < 0):
            xblk, fblk = xpre, fpre  # the bracket's other end
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):  # keep the best point as xcur
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # secant
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # inverse quadratic extrapolation
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre = scur = sbis
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        xcur += scur if abs(scur) > delta else (delta if sbis > 0 else -delta)
        fcur = _value(f, xcur)
    raise RuntimeError(f"Failed to converge after {maxiter} iterations, value is {xcur}.")
