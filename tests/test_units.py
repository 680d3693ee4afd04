"""The one display rule: angles (rad) shown in degrees, every other unit unchanged."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechcont.units import derivative_unit, display, display_scale, display_unit, shown


def test_an_angle_is_shown_in_degrees_and_nothing_else_is_converted():
    v, u = display(math.pi / 2, "rad")
    assert u == "deg" and v == pytest.approx(90.0, rel=1e-15)
    assert display(2.5, "N") == (2.5, "N")
    assert display(2.5, "") == (2.5, "")
    arr, u = display(np.array([0.0, math.pi, -math.pi / 4]), "rad")
    assert u == "deg" and np.allclose(arr, [0.0, 180.0, -45.0], rtol=1e-15, atol=0.0)
    assert display_unit("rad") == "deg" and display_unit("m") == "m"
    assert display_scale("rad") * math.pi == pytest.approx(180.0, rel=1e-15) and display_scale("N") == 1.0


def test_shown_writes_the_value_with_its_display_unit():
    assert shown(math.pi, "rad") == "180 deg"
    assert shown(12.5, "N") == "12.5 N"
    assert shown(0.5, "") == "0.5"


def test_the_unit_of_a_derivative():
    assert [derivative_unit("N", u) for u in ("m", "N/m", "N m", "", "N")] == ["N/m", "N/(N/m)", "N/(N m)", "N", "1"]
    assert derivative_unit("", "m") == "1/m"


def test_a_derivative_of_a_quotient_reads_back_as_its_unit():
    """A force in g mm/s^2 per mm keeps one '/', per a stiffness both are grouped; dimension() reads them
    (by hand: (1,1,-2) - (1,0,0) = (0,1,-2); (1,1,-2) - (0,1,-2) = (1,0,0)), and a grouped denominator too."""
    from mechcont.units import dimension

    assert derivative_unit("g mm/s^2", "mm") == "g mm/(s^2 mm)"
    assert derivative_unit("g mm/s^2", "g/s^2") == "(g mm/s^2)/(g/s^2)"
    assert dimension("g mm/(s^2 mm)") == (0, 1, -2)
    assert dimension("(g mm/s^2)/(g/s^2)") == (1, 0, 0)
    assert dimension("N/(N/m)") == (1, 0, 0) and dimension("N m/(N/m)") == (2, 0, 0)
    assert dimension("N/(m") is None and dimension("N)/m(") is None
