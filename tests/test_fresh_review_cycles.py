"""A fresh user's ODE files through `cycles`: a family between two Hopf points, and bounds the start lies outside.

Truth: the Sel'kov model ``x' = -x + a y + x^2 y, y' = b - a y - x^2 y`` has its equilibrium at ``x = b``,
``y = b / (a + b^2)``, where the trace of ``df/du`` vanishes at ``b^2 = (1 - 2a -+ sqrt(1 - 8a)) / 2`` (two Hopf
points) with ``omega^2 = det = a + b^2``; both are supercritical at a = 0.08, so one family of stable cycles joins
them. Its orbit at b = 0.6 is measured on an independent long integration (SciPy, rtol 1e-12).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from mechcont.continuation import ContinuationOptions, cycles_from_hopf
from mechcont.errors import InputError
from mechcont.models import load_model

DATA = Path(__file__).parent / "data" / "fresh_user"
A = 0.08
B_LOW = math.sqrt((1 - 2 * A - math.sqrt(1 - 8 * A)) / 2)
B_HIGH = math.sqrt((1 - 2 * A + math.sqrt(1 - 8 * A)) / 2)


@pytest.fixture(scope="module")
def selkov():
    return load_model(str(DATA / "selkov.toml"))


def _hopf_vector(model, b):
    return model.vector({"b": b, "x": b, "y": b / (A + b * b)})


def _period_by_integration(b):
    def f(t, z):
        x, y = z
        return [-x + A * y + x * x * y, b - A * y - x * x * y]

    def section(t, z):
        return z[0] - b
    section.direction = 1
    sol = solve_ivp(f, (0.0, 1500.0), [0.7, 1.0], rtol=1e-12, atol=1e-12, events=section)
    t = sol.t_events[0]
    return t[-1] - t[-2]


def test_family_from_one_hopf_point_ends_at_the_other(selkov):
    # before: the family reached the low Hopf point, was labelled LPC there (its Brent location failed on the
    # near-point orbits), went back up through the high Hopf point and down again: every orbit computed twice,
    # three UZ rows at b = 0.6 and a fold of cycles that does not exist
    fam = cycles_from_hopf(selkov, _hopf_vector(selkov, B_HIGH), "b",
                           options=ContinuationOptions(bounds={"b": (0.1, 1.2)}), at=[0.6])
    names = [n for n, _ in fam.point_names()]
    assert names == ["HB1", "UZ1", "HB2"], names
    assert "LPC" not in {lab.rstrip("?") for lab in fam.labels}
    assert fam.p[0] == pytest.approx(B_HIGH, abs=1e-10)
    assert fam.period[0] == pytest.approx(2 * math.pi / math.sqrt(A + B_HIGH**2), rel=1e-10)
    end = fam.row("HB2")
    assert fam.p[end] == pytest.approx(B_LOW, abs=1e-10)
    assert fam.period[end] == pytest.approx(2 * math.pi / math.sqrt(A + B_LOW**2), rel=1e-10)
    # the parameter moves one way only: the family is not retraced
    assert np.all(np.diff(fam.p) < 0)
    uz = fam.row("UZ1")
    assert fam.period[uz] == pytest.approx(_period_by_integration(0.6), rel=1e-8)
    assert fam.stability()[uz] == "stable"


def test_start_outside_the_bounds_is_refused():
    # before: the bound B = 1:1.5 below the Hopf point at B = 2 was never crossed, and the family ran on to
    # B = 13, where its correction failed after 226 orbits
    m = load_model(str(DATA / "brusselator.toml"))
    with pytest.raises(InputError, match=r"B: start value 2 lies outside its bounds 1:1.5"):
        cycles_from_hopf(m, m.vector({"A": 1.0, "B": 2.0, "u": 1.0, "v": 2.0}), "B",
                         options=ContinuationOptions(bounds={"B": (1.0, 1.5)}))
    with pytest.raises(InputError, match=r"period: start value 6.28319 lies outside its bounds 10:100"):
        cycles_from_hopf(m, m.vector({"A": 1.0, "B": 2.0, "u": 1.0, "v": 2.0}), "B",
                         options=ContinuationOptions(bounds={"period": (10.0, 100.0)}))


def test_printed_name_of_a_detected_but_unlocated_orbit_says_so(tmp_path):
    # before: the printed table named such an orbit LPC1 while the CSV wrote LPC? (and continue prints LP1?)
    from dataclasses import replace

    from mechcont.outputs.tables import cycle_lines

    m = load_model(str(DATA / "brusselator.toml"))
    fam = cycles_from_hopf(m, m.vector({"A": 1.0, "B": 2.0, "u": 1.0, "v": 2.0}), "B",
                           options=ContinuationOptions(bounds={"B": (1.0, 2.2)}), at=[2.1])
    i = fam.row("UZ1")
    detected = replace(fam, approximate=frozenset({i}))
    assert detected.row_labels()[i] == "UZ?"
    printed = [line.split()[0] for line in cycle_lines(detected)[1:-1]]
    assert printed == ["HB1", "UZ1?", "EP1"], printed
    assert [line.split()[0] for line in cycle_lines(fam)[1:-1]] == ["HB1", "UZ1", "EP1"]
