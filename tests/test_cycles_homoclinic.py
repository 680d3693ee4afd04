"""A family of cycles approaching a homoclinic orbit (AUTO's demo ab at B = 17): no false folds, a clear end.

Towards the homoclinic orbit the period grows without bound while D converges (it moves by 1e-9 per step
at a period of 70 s): the tangent's D component is then noise and changes sign without a fold of cycles.
A fold has a second Floquet multiplier at 1; for a planar system the non-trivial multiplier is, exactly,
``exp(integral over one period of div f)`` (Liouville), which these tests use as the truth.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from mechcont.continuation import ContinuationOptions, cycles_from_hopf

B, BETA = 17.0, 3.0


def _ab():
    from mechcont.equations import ode_model

    u1, u2, D, Bs, beta = sp.symbols("u1 u2 D B beta", real=True)
    e = sp.exp(u2)
    return ode_model("ab", {"u1": 0.0, "u2": 0.0}, {"D": 0.0, "B": B, "beta": BETA},
                     {"u1": -u1 + D * (1 - u1) * e, "u2": -u2 + D * Bs * (1 - u1) * e - beta * u2})


def _first_hopf():
    """u1 = (1 + beta) u2 / B on the equilibria; trace zero where (1 - u1)(B u1 - 1 - beta) = 1 (Routh-Hurwitz)."""
    u1 = min(r.real for r in np.roots([-B, B + 1 + BETA, -(2 + BETA)]) if 0 < r.real < 1)
    u2 = B * u1 / (1 + BETA)
    return u1 * math.exp(-u2) / (1 - u1), u1, u2


def _family(ntst):
    m = _ab()
    d, a, b = _first_hopf()
    return cycles_from_hopf(m, m.vector({"D": d, "u1": a, "u2": b}), "D", ntst=ntst, ncol=4,
                            options=ContinuationOptions(bounds={"D": (0.0, 0.2), "period": (0.0, 100.0)}))


def _liouville_multiplier(fam, i):
    """exp of the divergence's integral over row i's orbit (trapezoid on a periodic function: spectral)."""
    t, Z = fam.orbit(i, samples=4000)
    D = fam.p[i]
    e = np.exp(Z[:-1, 1])
    div = (-1 - D * e) + (-1 + D * B * (1 - Z[:-1, 0]) * e - BETA)
    return math.exp(float(np.mean(div)) * fam.period[i])


def test_family_towards_a_homoclinic_orbit_has_no_fold_and_says_so():
    fam = _family(20)
    names = [n for n, _ in fam.point_names()]
    assert "LPC1" not in names and "LPC1?" not in names, names
    assert names[0] == "HB1" and names[-1] == "EP1"
    assert "approaching a homoclinic orbit" in fam.message
    assert fam.period[-1] > 50.0  # ended on the growth of the period, well before the period bound of 100 s
    assert np.all(np.diff(fam.period) > 0)
    # the multipliers are right where they can be computed (moderate periods): Liouville's formula
    for i in range(1, len(fam)):
        if fam.period[i] < 15.0:
            # (the sampled orbit between mesh points is accurate to O(h^(NCOL+1)): ~1e-7 in the exponent, ~8 here)
            assert math.log(fam.floquet_max[i]) == pytest.approx(math.log(_liouville_multiplier(fam, i)), abs=1e-5)
    # the mesh adapts to the long orbits: the homoclinic D does not depend on the number of intervals
    fine = _family(40)
    assert "approaching a homoclinic orbit" in fine.message
    assert fine.p[-1] == pytest.approx(fam.p[-1], rel=1e-7)
