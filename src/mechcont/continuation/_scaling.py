"""Scales read off the equations themselves, so results do not depend on the user's units.

A fold is where the Jacobian with respect to the states is singular. Which of its singular
values is "small" depends on the units: with angles in radians and forces in newtons next
to a 30 kN/m spring, the null vector of the unscaled matrix is all reaction components and
the smallest singular value need not belong to the fold. Equilibrating the matrix first
(``R J C`` with every row and column of largest entry 1, Ruiz's algorithm) removes that
dependence: changing the unit of any variable or equation rescales ``R`` and ``C`` and
leaves the equilibrated matrix as it was.
"""

from __future__ import annotations

import numpy as np

__all__ = ["equilibrate"]


def equilibrate(A: np.ndarray, reference: np.ndarray | None = None, iterations: int = 40,
                tol: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    """Row and column scales ``(r, c)`` such that ``diag(r) A diag(c)`` is equilibrated.

    Ruiz's iteration: divide every row and column by the square root of its largest
    magnitude until all are within ``tol`` of 1. Zero rows or columns keep the scale 1.

    The equilibrated matrix fixes ``r`` and ``c`` only up to a common factor
    (``r / s``, ``c * s``). It is chosen so that the geometric mean of ``c`` over the
    ``reference`` columns (e.g. the angles, in radians) is 1: ``c[j]`` is then the change of
    variable ``j`` (in its own unit) that weighs as much in the equations as one radian of
    motion, a physical, unit-independent typical magnitude.

    Parameters
    ----------
    A:
        Matrix (m, n), e.g. a Jacobian in SI units.
    reference:
        Boolean mask of length n (columns in radians); all columns when None or empty.

    Returns
    -------
    (r, c):
        Positive arrays of length m and n.
    """
    B = np.abs(np.asarray(A, dtype=float))
    m, n = B.shape
    # rows then columns in one array each (scales, and the largest entries of a pass), so one
    # operation updates both: the same arithmetic as two, with half the calls
    rc, big = np.ones(m + n), np.empty(m + n)
    r, c, r_col, rbig, cbig = rc[:m], rc[m:], rc[:m, None], big[:m], big[m:]
    top, low = np.maximum.reduce, np.minimum.reduce  # ndarray.max/min without their Python wrappers
    S = np.empty_like(B)
    zero = not (top(B, axis=1, initial=0.0).all() and top(B, axis=0, initial=0.0).all())
    for _ in range(iterations):
        np.multiply(B, r_col, out=S)
        S *= c
        top(S, axis=1, initial=0.0, out=rbig)
        top(S, axis=0, initial=0.0, out=cbig)
        if zero:  # a zero row or column keeps its scale
            big[big == 0] = 1.0
        rc /= np.sqrt(big)
        # max |big - 1| < tol, from the extremes (the same comparison: rounding is monotonic)
        if top(big) - 1 < tol and 1 - low(big) < tol:
            break
    ref = np.ones(n, dtype=bool) if reference is None or not np.any(reference) else np.asarray(reference, bool)
    factor = float(np.exp(np.mean(np.log(c[ref]))))
    return r * factor, c / factor
