"""The shimmy section of ``mechcont paper`` (issue 36, item 3) against truth.

* The Hopf speed found on the equilibrium branch against an independent bisection of the leading
  eigenvalue (``onset_speed``: one linearisation per speed, no Hopf system): agree to the bisection's
  tolerance.
* The caster reduction: with the strut's lateral bending made rigid (``k_lat`` = 1e14 N/m, against the
  tyre's lateral stiffness C/sigma = 6e5 N/m: the swivel moves by about 1e-9 of the tyre's deflection)
  the gear is the caster wheel of tests/test_shimmy_dynamics.py with the side force acting at the
  pneumatic trail t behind the contact point: ``I psi'' = -k psi - c psi' - (e + t) F``,
  ``y' = e psi' + V psi - (V/sigma) y`` (linearised), whose cubic has

      a2 = c/I + V/sigma,  a1 = (k + (c V + e (e + t) C)/sigma)/I,  a0 = V (k + (e + t) C)/(I sigma)

  (the same expansion as there, the moment arm of F being e + t). Each point of the Hopf curve in
  (V, c_psi) must satisfy Routh-Hurwitz's ``a2 a1 = a0``: relative residual below 1e-6 (the neglected
  compliance contributes about (C/sigma)/k_lat = 6e-9 and m_lat omega^2/k_lat = 1e-7).
* The brute-force grid (``stability_grid``, one eigenvalue evaluation per point) on either side of
  the example's Hopf curve points: stable on the side the curve's hatching says, shimmy on the other.
* The summary paragraph: a design limit only where the grid confirms its stable side (stand-in results).
* Slow: the cycles born at HB1 against a long time simulation at 60 m/s from a small disturbance
  (amplitude and period; the tolerances are in the test).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechcont.continuation import ContinuationOptions, continue_hopf
from mechcont.paper import _shimmy_analysis as an
from mechcont.paper.shimmy import gear_at, onset_speed, shimmy_mechanism, stability_grid


@pytest.fixture(scope="module")
def gear():
    """The example gear at 1 m/s, its branch in speed and the branch's Hopf point."""
    model, x = gear_at(1.0)
    branch = an.equilibria(model, x)
    hopf = [p for p in branch.special_points if p.label == "HB"]
    return model, branch, hopf


def test_one_hopf_point_in_speed_at_the_bisected_onset(gear):
    _, _, hopf = gear
    assert len(hopf) == 1
    v_bisect = onset_speed(shimmy_mechanism(), tol=1e-10)
    assert v_bisect is not None
    assert hopf[0]["V"] == pytest.approx(v_bisect, rel=1e-8)


def test_hopf_curve_of_the_rigid_strut_is_routh_hurwitz():
    mech = shimmy_mechanism()
    model, x = gear_at(1.0, mech, k_lat=1e14)
    branch = an.equilibria(model, x)
    hopf = next(p for p in branch.special_points if p.label == "HB")
    curve = continue_hopf(model, hopf, "V", "c_psi", options=ContinuationOptions(
        ds=0.1, dsmax=1.0, max_steps=3, bounds={"V": (1.0, 100.0), "c_psi": (0.0, 100.0)},
        scales={"V": 10.0, "c_psi": 10.0}))
    assert len(curve) >= 5
    p = {n: curve.column(n) for n in ("V", "c_psi", "e", "k_psi", "I_z", "sigma", "C_tyre", "t_p")}
    V, c, e, k, inertia, sigma, C, t = (p[n] for n in ("V", "c_psi", "e", "k_psi", "I_z", "sigma", "C_tyre", "t_p"))
    a2 = c / inertia + V / sigma
    a1 = (k + (c * V + e * (e + t) * C) / sigma) / inertia
    a0 = V * (k + (e + t) * C) / (inertia * sigma)
    assert np.ptp(c) > 1.0                       # the curve moved in the damper rate
    np.testing.assert_array_less(np.abs(a2 * a1 - a0) / (a2 * a1), 1e-6)
    # and its frequency is the cubic's sqrt(a1)
    np.testing.assert_allclose(curve.column("omega"), np.sqrt(a1), rtol=1e-6)


def test_brute_force_grid_either_side_of_the_hopf_curve(gear):
    model, _, hopf = gear
    curve = continue_hopf(model, hopf[0], "V", "c_psi", options=ContinuationOptions(
        ds=0.1, dsmax=1.0, max_steps=3, bounds={"V": (1.0, 100.0), "c_psi": (0.0, 100.0)},
        scales={"V": 10.0, "c_psi": 10.0}))
    mech = shimmy_mechanism()
    for i in range(0, len(curve), 2):
        V, c = curve.values[i][model.index("V")], curve.values[i][model.index("c_psi")]
        side = np.array([curve.column("stable_V")[i], curve.column("stable_c_psi")[i]])
        side /= np.hypot(side[0] / 10.0, side[1] / 10.0)   # a step of about 1 % of the chart's spans
        step = 0.1 * side
        re_stable = stability_grid([V + step[0]], "c_psi", [c + step[1]], mech)[0, 0]
        re_shimmy = stability_grid([V - step[0]], "c_psi", [c - step[1]], mech)[0, 0]
        assert re_stable < 0 < re_shimmy, (V, c, re_stable, re_shimmy)


@pytest.mark.slow
def test_simulation_from_a_small_disturbance_lands_on_the_continued_cycle(gear):
    """At 60 m/s the cycle's largest Floquet multiplier is about 0.96: a simulation of 2 s (104 periods)
    reaches it to within the transient it still has, which the simulation estimates from its last three
    crests (a geometric series). The amplitude must agree to twice that estimate plus 1e-5 rad (the
    collocation with 10 intervals of degree 4 and the crest's parabola are far finer); the period to
    1e-4 relative (along the family it changes by 0.017 ms per degree of amplitude: the transient moves it
    by about 1e-5 relative)."""
    model, _, hopf = gear
    from mechcont.continuation import cycles_from_hopf

    cycles = cycles_from_hopf(model, hopf[0].x, "V", options=ContinuationOptions(
        ds=0.1, dsmax=20.0, max_steps=60, bounds={"V": (1.0, 61.0)}, scales={"V": 10.0}), ntst=10, ncol=4, at=(60.0,))
    row = [i for i, lab in enumerate(cycles.labels) if lab == "UZ"]
    assert len(row) == 1
    row = row[0]
    assert cycles.p[row] == pytest.approx(60.0, abs=1e-9)
    assert cycles.stable[row]
    k = cycles.state_names.index(an.TORSION)
    sim = an.simulate_onto(60.0, shimmy_mechanism())
    assert sim.remaining < math.radians(0.05)
    assert abs(sim.amplitude - cycles.maximum[row, k]) < 2 * sim.remaining + 1e-5
    assert sim.period == pytest.approx(cycles.period[row], rel=1e-4)
    # the cycle is no small-amplitude approximation: tens of degrees, saturated by the tyre
    assert math.degrees(cycles.maximum[row, k]) > 20.0


def test_hopf_curve_computes_the_lyapunov_coefficient_once_per_point(gear, monkeypatch):
    """On a mechanism ``l1`` costs two dependent batches of rates (third differences along directions): the GH event
    and the table's column must share it, not compute it twice per point."""
    from mechcont.continuation import _hopf

    model, _, hopf = gear
    calls = []
    original = _hopf.first_lyapunov

    def counting(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(_hopf, "first_lyapunov", counting)
    curve = continue_hopf(model, hopf[0], "V", "c_psi", options=ContinuationOptions(
        ds=0.1, dsmax=1.0, max_steps=2, bounds={"V": (1.0, 100.0), "c_psi": (0.0, 100.0)},
        scales={"V": 10.0, "c_psi": 10.0}))
    assert len(calls) <= len(curve)


def test_the_finding_states_a_design_limit_only_where_the_grid_confirms_the_stable_side():
    """The paragraph is written from the numbers: stand-in results (a straight Hopf curve from
    (1 m/s, 1) to (100 m/s, 30)) give the limit read off the curve at 100 m/s; when the brute-force grid
    shows shimmy above that limit too, no limit is claimed."""
    import types

    from mechcont.paper import _shimmy_figures as fg

    hopf = types.SimpleNamespace(extra={"hopf": types.SimpleNamespace(lyapunov=-1.0, frequency=300.0)})
    cols = {"V": np.array([1.0, 100.0]), "c_psi": np.array([1.0, 30.0]), "e": np.array([0.0, 0.25])}
    curve = types.SimpleNamespace(column=cols.__getitem__)
    cycles = types.SimpleNamespace(state_names=(an.TORSION,), stable=np.array([True, True]),
                                   maximum=np.array([[0.0], [0.5]]), labels=["HB", ""], p=np.array([14.0, 20.0]))
    design = {"V": 14.0, "c_psi": 10.0, "e": 0.1}
    values = np.array([0.0, 50.0])
    for above, claimed in ((-1.0, True), (1.0, False)):
        grid = (np.array([1.0, 100.0]), values, np.array([[1.0, 1.0], [above, above]]))
        text = " ".join(fg.finding(hopf, {"c_psi": curve, "e": curve}, {"c_psi": grid, "e": grid}, cycles, [], 100.0,
                                   design))
        assert ("at least 30.0 N m s/rad keeps the gear shimmy-free up to 100 m/s" in text) is claimed
        assert "supercritical" in text and "no hysteresis" in text
