"""Figures of a family of cycles (issue 35, item 6): the amplitude diagram, phase portraits, the orbit as full vectors."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from mechcont.continuation import ContinuationOptions, cycles_from_hopf
from mechcont.equations import dynamics_of, ode_model
from mechcont.errors import InputError
from mechcont.outputs.cycle_plots import amplitude_figure, phase_portrait

x, y, mu = sp.symbols("x y mu", real=True)
R2 = x**2 + y**2


@pytest.fixture(scope="module")
def family():
    g = mu + 2 * R2 - R2**2  # subcritical: unstable cycles from mu = 0 down to the fold at mu = -1, stable beyond
    m = ode_model("sub", {"x": 0.0, "y": 0.0}, {"mu": 0.0}, {"x": x * g - y, "y": y * g + x})
    return m, cycles_from_hopf(m, m.defaults(), "mu", options=ContinuationOptions(ds=0.02, dsmax=0.3,
                                                                                bounds={"mu": (-2.0, 0.2)}))


def test_amplitude_diagram_draws_stable_solid_unstable_dashed_and_marks_the_fold(family):
    _, fam = family
    ax = amplitude_figure(fam, "x").axes[0]
    styles = {(ln.get_linestyle(), ln.get_label()) for ln in ax.get_lines() if len(ln.get_xdata()) > 1}
    assert ("--", "cycles, unstable") in styles and ("-", "cycles, stable") in styles
    k = fam.row("LPC1")
    marked = [ln for ln in ax.get_lines() if len(ln.get_xdata()) == 1 and ln.get_marker() == "o"]
    assert {round(float(ln.get_ydata()[0]), 6) for ln in marked} == {round(fam.maximum[k, 0], 6),
                                                                     round(fam.minimum[k, 0], 6)}
    assert any(t.get_text() == "LPC1" for t in ax.texts)
    with pytest.raises(InputError, match="state"):
        amplitude_figure(fam, "z")


def test_phase_portrait_closes_each_orbit_and_full_vectors_carry_the_parameter(family):
    m, fam = family
    ax = phase_portrait(fam, rows=[1, fam.row("LPC1"), len(fam) - 1])
    lines = ax.get_lines()
    assert len(lines) == 3
    for ln in lines:  # closed over one period
        assert ln.get_xdata()[0] == pytest.approx(ln.get_xdata()[-1], abs=1e-12)
    k = fam.row("LPC1")
    t, rows = fam.full_vectors(dynamics_of(m), k, samples=40)
    assert t[-1] == pytest.approx(fam.period[k]) and rows.shape == (41, len(m.names))
    assert np.all(rows[:, m.index("mu")] == fam.p[k])
    np.testing.assert_allclose(np.hypot(rows[:, 0], rows[:, 1]), 1.0, atol=1e-4)  # the fold's orbit: r = 1


def test_animate_cycle_draws_one_period_of_full_vectors(family, overcentre, tmp_path):
    # the plumbing of the animation: one frame per instant of the period, each drawn from dynamics.full_vectors.
    # A stand-in dynamics turns the orbit into poses of the overcentre (its bars' angles follow the orbit's x, y)
    from mechcont.outputs.cycle_plots import animate_cycle

    _, fam = family
    base = overcentre.defaults()
    seen = []

    class Poses:
        def full_vector(self, z, x):
            seen.append(z.copy())
            v = base.copy()
            v[overcentre.index("theta1")] += 0.2 * z[0]
            v[overcentre.index("theta2")] -= 0.2 * z[1]
            return v

        def full_vectors(self, Z, x):
            return np.array([self.full_vector(z, x) for z in Z])

    k = fam.row("LPC1")
    n = animate_cycle(overcentre, Poses(), fam, k, tmp_path / "cycle.gif", frames=6, fps=6)
    assert n == 6 and (tmp_path / "cycle.gif").stat().st_size > 1000
    t, Z = fam.orbit(k, 6)
    np.testing.assert_allclose(np.array(seen), Z, atol=1e-12)  # one period: the first instant again at the end
    with pytest.raises(InputError, match="row"):
        animate_cycle(overcentre, Poses(), fam, len(fam), tmp_path / "x.gif")
