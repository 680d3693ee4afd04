"""A gear nobody tuned: folds located whatever the units, checked by an independent scan.

``examples/main_gear.toml`` is a five-bar main gear written as a user would (30 kN/m lock
spring, a lock force of a few hundred newtons to a few kilonewtons, no ``scale =`` keys).
Its folds must be located to machine precision, identical when the force unit changes by
1e+-3, and agree with a computation that does not use the fold machinery: hold the lock
link angle, solve for the force, and find the extrema of F(theta4) by root finding on its
derivative.
"""

from pathlib import Path

import pytest
from scipy.optimize import brentq

from mechcont.continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium
from mechcont.mechanism import load_description, parse_description

GEAR = Path(__file__).resolve().parent.parent / "examples" / "main_gear.toml"
BOUNDS = {"theta4": (-0.8, 0.8), "F": (-5e4, 5e4)}
FORCES = ("k", "m1", "m2", "m3", "m4", "m5")  # with F: every force of the model scales with these


@pytest.fixture(scope="module")
def gear():
    return load_description(GEAR).build()


def folds_of(system, factor=1.0):
    """Folds (theta4, F) of the branch through theta4 = 0.08, F in the file's units."""
    x0 = find_equilibrium(system, hold={"theta4": 0.08}, free=["F"])
    bounds = {"theta4": BOUNDS["theta4"], "F": (BOUNDS["F"][0] * factor, BOUNDS["F"][1] * factor)}
    b = continuation(system, x0, "F", options=ContinuationOptions(bounds=bounds))
    return b, sorted((p["theta4"], p["F"]) for p in b.special("LP"))


def force_at(system, theta4, guess):
    """F (N) that holds the lock link at ``theta4``: a square solve, no fold machinery."""
    x = find_equilibrium(system, hold={"theta4": theta4}, free=["F"], guess=guess)
    return x[system.index("F")], x


def scan_extremum(system, theta_guess, guess, h=1e-5):
    """theta4 and F where dF/dtheta4 = 0 near ``theta_guess`` (central differences + Brent)."""
    def slope(t):
        return (force_at(system, t + h, guess)[0] - force_at(system, t - h, guess)[0]) / (2 * h)

    lo, hi = theta_guess - 0.02, theta_guess + 0.02
    t = brentq(slope, lo, hi, xtol=1e-13)
    return t, force_at(system, t, guess)[0]


def test_folds_are_located_and_agree_with_an_independent_scan(gear):
    b, folds = folds_of(gear)
    assert len(folds) == 2 and folds[0][1] < 0 < folds[1][1]
    for p in b.special("LP"):
        assert p.status == "located"
        assert p.info["residual"] < 1e-12 and p.info["singular_value"] < 1e-10
    for p in b.special("LP"):
        theta, F = p["theta4"], p["F"]
        t_scan, F_scan = scan_extremum(gear, theta, p.x)  # the fold's assembly mode as the guess
        assert F == pytest.approx(F_scan, rel=1e-9)
        assert theta == pytest.approx(t_scan, abs=1e-5)  # the scan's derivative is only O(h^2) accurate


@pytest.mark.parametrize("factor", [1e-3, 1e3])
def test_changing_the_force_unit_leaves_the_folds_unchanged(gear, factor):
    # every force scaled (spring, weights, the applied force): the gear in another force unit
    scaled = load_description(GEAR).build(**{n: gear.variable(n).value * factor for n in FORCES})
    _, ref = folds_of(gear)
    _, got = folds_of(scaled, factor)
    assert len(got) == len(ref)
    for (t0, F0), (t1, F1) in zip(ref, got):
        assert t1 == pytest.approx(t0, rel=1e-9, abs=1e-12)
        assert F1 / factor == pytest.approx(F0, rel=1e-9)


def test_stale_scales_do_not_move_the_folds(gear):
    # the same forces a thousand times smaller while the continuation keeps the scales of the
    # original build (F's scale now a thousand times too large): only the steps change
    scaled = gear.with_values({n: gear.variable(n).value * 1e-3 for n in FORCES})
    _, ref = folds_of(gear)
    _, got = folds_of(scaled, 1e-3)
    assert len(got) == len(ref)
    for (t0, F0), (t1, F1) in zip(ref, got):
        assert t1 == pytest.approx(t0, rel=1e-9, abs=1e-12)
        assert F1 * 1e3 == pytest.approx(F0, rel=1e-9)


def test_the_lock_force_in_kilonewtons_gives_the_same_folds(gear):
    # only F changes unit: its inferred scale is now unrelated to the spring's
    text = GEAR.read_text().replace('magnitude = "F"', 'magnitude = "1000*F"')
    text = text.replace('F = { value = 0.0, unit = "N",', 'F = { value = 0.0, unit = "kN",')
    kn = parse_description(text, "main_gear_kN.toml").build()
    _, ref = folds_of(gear)
    _, got = folds_of(kn, 1e-3)
    for (t0, F0), (t1, F1) in zip(ref, got):
        assert t1 == pytest.approx(t0, rel=1e-9, abs=1e-12)
        assert 1000 * F1 == pytest.approx(F0, rel=1e-9)


def test_fold_curve_has_a_cusp_where_the_force_has_an_inflection(gear):
    b, _ = folds_of(gear)
    lp = max(b.special("LP"), key=lambda p: p["F"])
    curve = continue_folds(gear, lp, "F", "LU", options=ContinuationOptions(bounds={"LU": (1.0, 2.0), **BOUNDS}))
    assert curve.success, curve.message
    cps = curve.special("CP")
    assert len(cps) == 1 and cps[0].status == "located"
    # independent check, by held-angle solves: F(theta4) has a degenerate critical point at
    # the cusp (first and second derivatives vanish, the third does not), while at the
    # regular fold the curve started from the second derivative is far from zero
    def derivatives(point, h=1e-4):
        at = gear.with_values({"LU": point["LU"]})
        t = point["theta4"]
        F = [force_at(at, t + k * h, point.x)[0] for k in (-2, -1, 0, 1, 2)]
        return ((F[3] - F[1]) / (2 * h), (F[3] - 2 * F[2] + F[1]) / h**2,
                (F[4] - 2 * F[3] + 2 * F[1] - F[0]) / (2 * h**3))

    d1, d2, d3 = derivatives(cps[0])
    assert abs(d1) < 1e-7 * abs(d3) and abs(d2) < 1e-5 * abs(d3)
    f1, f2, f3 = derivatives(lp)
    assert abs(f1) < 1e-7 * abs(f3) and abs(f2) > 0.1 * abs(f3)


def test_folds_command_runs_on_the_unscaled_gear(tmp_path):
    from cli_helpers import make_runner

    out = tmp_path / "folds.csv"
    r = make_runner()("folds", GEAR, "--start", "theta4=0.08", "--vary", "F", "--along", "LU", "--fold", "1",
                      "--bounds", "theta4=-0.8:0.8", "--bounds", "LU=1.0:2.0", "--out", out)
    assert r.exit_code == 0, r.output
    assert "CP1" in r.output and out.exists()
