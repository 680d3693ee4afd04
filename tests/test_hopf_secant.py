"""The Hopf event's secant guess (``secant_fraction``): the zero of the product of the pair sums, not of the
scale-tamed test function, so that it errs by the square of the step as a fold's secant does."""

from __future__ import annotations

import numpy as np

from mechcont.continuation._hopf_point import bialternate_test, secant_fraction

SIGMA_HOPF = 0.37  # where the critical pair crosses the imaginary axis
OMEGA = 2.0


def _eigenvalues(sigma: float) -> np.ndarray:
    """A pair ``mu +- i omega`` crossing at SIGMA_HOPF (``mu`` curved) beside three stable real eigenvalues that
    move too: 10 pair sums, whose product changes with every one of them."""
    d = sigma - SIGMA_HOPF
    mu = 0.3 * d + 0.2 * d * d
    return np.array([mu + 1j * OMEGA, mu - 1j * OMEGA, -1.0 - 0.5 * d, -2.5 + d, -4.0])


def _error(ds: float, before: float, fraction) -> float:
    """|guess - SIGMA_HOPF| for the bracket [SIGMA_HOPF - before ds, SIGMA_HOPF + (1 - before) ds]."""
    s0 = SIGMA_HOPF - before * ds
    v0, v1 = bialternate_test(_eigenvalues(s0)), bialternate_test(_eigenvalues(s0 + ds))
    assert v0 * v1 < 0
    return abs(s0 + fraction(v0, v1) * ds - SIGMA_HOPF)


def test_secant_fraction_errs_by_the_square_of_the_step():
    pairs = 5 * 4 // 2
    for before in (0.1, 0.35, 0.5, 0.8):
        errors = [_error(ds, before, lambda v0, v1: secant_fraction(v0, v1, pairs)) for ds in (0.1, 0.05, 0.025)]
        # second order: halving the step quarters the error
        assert errors[1] / errors[0] < 0.3 and errors[2] / errors[1] < 0.3, errors
        assert errors[0] < 0.01 * 0.1, errors  # within 1 % of the step at ds = 0.1
        if before != 0.5:
            # the test function's own secant is first order (|v| ~ |g|^(1/10) is all curvature near the zero):
            # halving the step only halves its error, which is a tenth of the step or more here; it is right
            # only where the bracket is symmetric (|v0| = |v1| to first order, the midpoint)
            plain = [_error(ds, before, lambda v0, v1: v0 / (v0 - v1)) for ds in (0.1, 0.05, 0.025)]
            assert all(p > 10 * e for p, e in zip(plain, errors)), (plain, errors)


def test_secant_fraction_at_the_edges():
    assert secant_fraction(0.0, -1.0, 10) == 0.0  # the first point is the zero
    assert secant_fraction(2.0, 0.0, 10) == 1.0
    assert secant_fraction(1.0, -1.0, 10) == 0.5  # symmetric values: midway, whatever m
    # a ratio whose m-th power overflows: the zero is at the first point to rounding
    assert 0.0 <= secant_fraction(1e-30, -1e30, 45) < 1e-300
    assert secant_fraction(1e30, -1e-30, 45) == 1.0
