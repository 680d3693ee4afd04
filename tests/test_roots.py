"""mechcont's own Brent root finder returns SciPy's ``brentq`` bits (it replaces it to keep
``scipy.optimize`` out of light imports)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq as scipy_brentq

from mechcont._roots import brentq


def _functions(rng):
    for _ in range(100):
        c, k, p = rng.uniform(-2, 2), rng.uniform(0.1, 20), rng.integers(1, 8)
        yield (lambda x, c=c, k=k: math.tanh(k * (x - c)) + 0.1 * (x - c)), -3.0, 3.0
        yield (lambda x, c=c, p=p: (x - c) ** p * (1 if p % 2 else np.sign(x - c))), c - rng.uniform(0.1, 3), c + 1.0
        yield (lambda x, c=c: math.cos(x) - c / 4), 0.0, math.pi
        yield (lambda x, c=c, k=k: math.exp(k * x) - math.exp(k * c)), c - 1.5, c + 0.5


@pytest.mark.parametrize(("xtol", "rtol"), [(2e-12, 8.881784197001252e-16), (1e-14, 8.9e-16), (1e-15, 1e-15), (1e-4, 1e-6)])
def test_brentq_matches_scipy_bit_for_bit(xtol, rtol):
    rng = np.random.default_rng(7)
    n = 0
    for f, a, b in _functions(rng):
        if (f(a) < 0) == (f(b) < 0):
            continue
        try:
            expected = scipy_brentq(f, a, b, xtol=xtol, rtol=rtol)
        except RuntimeError:  # not converged in 100 iterations (flat high powers): so must ours
            with pytest.raises(RuntimeError):
                brentq(f, a, b, xtol=xtol, rtol=rtol)
            continue
        assert brentq(f, a, b, xtol=xtol, rtol=rtol) == expected
        n += 1
    assert n > 250


def test_brentq_errors_as_scipy():
    with pytest.raises(ValueError, match="different signs"):
        brentq(lambda x: x * x + 1, -1.0, 1.0)
    with pytest.raises(ValueError, match="NaN"):
        brentq(lambda x: math.nan if x > 0 else -1.0, -1.0, 1.0)
    with pytest.raises(RuntimeError, match="converge"):
        brentq(lambda x: math.tanh(10 * (x - 0.3)), 0.0, 1.0, maxiter=3)
    with pytest.raises(ValueError, match="rtol"):
        brentq(lambda x: x, -1.0, 1.0, rtol=1e-17)
    assert brentq(lambda x: x, 0.0, 1.0) == 0.0


def test_known_end_values_are_not_evaluated_again_and_change_nothing():
    rng = np.random.default_rng(5)
    n = 0
    for f, a, b in _functions(rng):
        fa, fb = f(a), f(b)
        if (fa < 0) == (fb < 0):
            continue
        calls = []

        def g(x, f=f, calls=calls):
            calls.append(x)
            return f(x)

        try:
            expected = brentq(f, a, b, xtol=1e-14, rtol=8.9e-16)
        except RuntimeError:
            continue
        assert brentq(g, a, b, xtol=1e-14, rtol=8.9e-16, fa=fa, fb=fb) == expected
        assert a not in calls and b not in calls
        n += 1
    assert n > 250
    with pytest.raises(ValueError, match="NaN"):
        brentq(lambda x: x, -1.0, 1.0, fa=math.nan)
