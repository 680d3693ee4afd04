"""Physical stability: changes exactly at folds and branch points, from the mechanics."""

import numpy as np
import pytest
import sympy as sp

from mechcont import MechanicalModel, Model, Variable
from mechcont.continuation import ContinuationOptions, continuation, switch_branch


def buckling_column():
    """Rigid inverted pendulum on a torsional spring: V = k th^2 / 2 + m g L cos(th).

    Equilibrium -k th + m g L sin(th) = 0. The upright branch th = 0 loses stability at
    the pitchfork m g L = k; the bent branches th != 0 exist for m g L > k and are stable.
    """
    vs = [Variable("th", "state", 0.0, "rad"), Variable("k", "parameter", 100.0, "N m/rad"),
          Variable("m", "parameter", 5.0, "kg"), Variable("g", "parameter", 9.81, "m/s^2"),
          Variable("L", "parameter", 1.0, "m")]
    th, k, m, g, L = (v.symbol for v in vs)
    V = k * th ** 2 / 2 + m * g * L * sp.cos(th)
    Q = -sp.diff(V, th)
    mech = MechanicalModel([v.name for v in vs], ["th"], [], [Q], sp.Matrix([[m * L ** 2]]))
    return Model("column", vs, [Q], mechanics=mech).compile()


def test_stability_changes_exactly_at_the_branch_point():
    s = buckling_column()
    # vary the mass: critical m = k / (g L)
    m_crit = 100.0 / 9.81
    opts = ContinuationOptions(bounds={"m": (1.0, 20.0), "th": (-2.5, 2.5)}, max_steps=400)
    b = continuation(s, s.vector({"m": 1.0}), "m", direction=1, options=opts)
    (bp,) = b.special("BP")
    assert bp["m"] == pytest.approx(m_crit, rel=1e-10)
    before, after = b["m"] < m_crit * (1 - 1e-9), b["m"] > m_crit * (1 + 1e-9)
    assert b.stable[before].all() and (~b.stable[after]).all()
    # the bent branches: stable, V'' = k - m g L cos(th) > 0 there
    nb = switch_branch(s, bp, options=opts)
    bent = np.abs(nb["th"]) > 1e-6
    assert bent.sum() > 10
    expected = 100.0 - nb["m"] * 9.81 * np.cos(nb["th"]) > 0
    assert np.array_equal(nb.stable[bent], expected[bent])
    assert nb.stable[bent].all()
    assert np.allclose(-100.0 * nb["th"] + nb["m"] * 9.81 * np.sin(nb["th"]), 0, atol=1e-9)


def test_reduced_stiffness_equals_second_derivative_of_potential():
    s = buckling_column()
    for th, m in [(0.3, 10.5), (1.2, 13.0), (0.0, 5.0)]:
        x = s.vector({"th": th, "m": m})
        res = s.mechanics.stability(x)
        Vpp = 100.0 - m * 9.81 * 1.0 * np.cos(th)
        # one coordinate, no constraints: Z = [1], Kr = V''
        assert res.eigenvalues[0] == pytest.approx(Vpp, rel=1e-12)
