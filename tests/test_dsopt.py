"""The dual-sidestay gear's lock springs with the least unlock load, each overcentre stop preloaded at rest (issue 24).

Checked against truth: the new quantities' exact gradients against central differences, and the optimum
re-solved without any gradient (the preload bound solved by Brent's method on the locked state, the unlock
load from its own release run) and against a small grid of designs.
"""

from __future__ import annotations

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from scipy.optimize import brentq

from mechcont.analysis._stop_quantities import preload_sensitivity, stop_unlock_sensitivity
from mechcont.analysis.optimize import Constraint, optimize
from mechcont.analysis.stop_lock import locked_on_stops, stop_unlock
from mechcont.errors import InputError
from mechcont.paper.design_optimum import DS_BOUNDS, DS_FORCE, DS_MARGIN, dual_sidestay_optimum
from mechcont.paper.dual_sidestay import generated_gear

DESIGN = list(DS_BOUNDS)
# the generated gear's first build in the session's fresh cache takes ~40 s
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def gear():
    return generated_gear()


@pytest.fixture(scope="module")
def optimum():
    return dual_sidestay_optimum()


def _reactions(gear, k, stretch):
    """The stop reactions (N m) of the locked state, no gradient involved, with that state and its stops in contact
    (the release run of :func:`_at_rest` is not made: a root search on a reaction needs none)."""
    x, contact = locked_on_stops(gear, {"k_lock": k, "stretch": stretch})
    R_fwd, R_aft = (float(x[gear.index(f"R_{s}")]) if s in contact else 0.0 for s in ("fwd_stop", "aft_stop"))
    return R_fwd, R_aft, x, contact


def _at_rest(gear, k, stretch):
    """Reactions (N m) and unlock load (N) from the locked state and its release run, no gradient involved."""
    R_fwd, R_aft, x, contact = _reactions(gear, k, stretch)
    if len(contact) < 2:  # a pair off its stop: not locked on both, no unlock load to compare
        return R_fwd, R_aft, float("nan")
    return R_fwd, R_aft, float(stop_unlock(gear, x, DS_FORCE, stability=False, both=False).unlock_force)


@pytest.mark.parametrize("of", ["R_fwd_stop", "R_aft_stop", "unlock"])
def test_gradients_match_central_differences(gear, of):
    at = {"k_lock": 5000.0, "stretch": 0.62}

    def value(v):
        return (stop_unlock_sensitivity(gear, v, DS_FORCE, DESIGN) if of == "unlock"
                else preload_sensitivity(gear, v, of, DESIGN))

    s = value(at)
    for name, h in (("k_lock", 1.0), ("stretch", 1e-5)):
        fd = (value({**at, name: at[name] + h}).value - value({**at, name: at[name] - h}).value) / (2 * h)
        # central differences: truncation ~h^2 f''' and round-off ~1e-12 |f| / h, both far below 1e-5 relative here
        assert s[name] == pytest.approx(fd, rel=1e-5), name


def test_optimum_is_on_the_preload_bound_and_the_stretch_bound(optimum):
    res, nominal = optimum
    assert res.success
    R_fwd, R_aft = res.quantities["R_fwd_stop"], res.quantities["R_aft_stop"]
    assert min(R_fwd, R_aft) == pytest.approx(DS_MARGIN, rel=1e-6)
    assert max(R_fwd, R_aft) > DS_MARGIN
    assert res.design["stretch"] == pytest.approx(DS_BOUNDS["stretch"][0], abs=1e-9)
    assert res.value < nominal["unlock_force"]
    assert all(m > 0 for _, m in res.active)  # KKT: the active constraints push the right way


def test_kkt_with_independent_gradients(gear, optimum):
    """grad f = mu_R grad R + mu_s e_stretch with both multipliers positive (the vertex is a KKT point)."""
    res, _ = optimum
    u = stop_unlock_sensitivity(gear, res.design, DS_FORCE, DESIGN)
    r = preload_sensitivity(gear, res.design, "R_fwd_stop", DESIGN)
    gf = np.array([u[n] for n in DESIGN])
    A = np.column_stack([[r[n] for n in DESIGN], [0.0, 1.0]])
    mu = np.linalg.solve(A, gf)
    assert mu[0] > 0 and mu[1] > 0
    # along the active preload constraint, raising stretch off its bound raises the unlock load
    tangent = np.array([-r["stretch"], r["k_lock"]])  # d(R) = 0, stretch increasing
    assert float(gf @ tangent) > 0


def test_optimum_resolved_without_gradients(gear, optimum):
    res, _ = optimum
    lo = DS_BOUNDS["stretch"][0]

    def fwd_excess(k):
        return _reactions(gear, k, lo)[0] - DS_MARGIN

    k = brentq(fwd_excess, 1500.0, 3000.0, xtol=1e-9, rtol=1e-13)
    assert res.design["k_lock"] == pytest.approx(k, rel=1e-6)
    assert res.value == pytest.approx(_at_rest(gear, k, lo)[2], rel=1e-6)
    # further along the preload bound (more stretch, solved for k) the unlock load is higher
    for st in (0.55, 0.65):
        kk = brentq(lambda v, st=st: _reactions(gear, v, st)[0] - DS_MARGIN, 1000.0, 8000.0, xtol=1e-6)
        assert _at_rest(gear, kk, st)[2] > res.value


def test_optimum_beats_a_grid(gear, optimum):
    res, _ = optimum
    feasible = 0
    for k in (1000.0, 2500.0, 4000.0, 8000.0):
        for st in (0.5, 0.6, 0.75):
            R_fwd, R_aft, x, contact = _reactions(gear, k, st)
            if min(R_fwd, R_aft) >= DS_MARGIN:  # both reactions positive: both pairs on their stops
                feasible += 1
                assert float(stop_unlock(gear, x, DS_FORCE, stability=False, both=False).unlock_force) >= res.value
    assert feasible >= 4


def test_stop_preload_needs_stops():
    from mechcont.models import load_model

    with pytest.raises(InputError, match="has no stops"):
        optimize(load_model("nose_gear"), "unlock_force", {"k": (1000.0, 8000.0)},
                 constraints=[Constraint.parse("stop_preload >= 10")])


def test_stop_preload_is_not_an_objective(gear):
    with pytest.raises(InputError, match="R_fwd_stop"):
        optimize(gear, "stop_preload", DS_BOUNDS, force=DS_FORCE)


def test_cli_optimizes_the_lock_springs(tmp_path, optimum):
    """``mechcont optimize ... --force F_lock --constraint 'stop_preload >= 20'``: the same optimum as the API."""
    import json
    from pathlib import Path

    res, _ = optimum
    example = Path(__file__).resolve().parents[1] / "examples" / "dual_sidestay.toml"
    run = make_runner()
    args = [example, "--minimize", "unlock_force", "--design", "k_lock=1000:16000", "--design", "stretch=0.5:0.85",
            "--constraint", f"stop_preload >= {DS_MARGIN:g}"]
    r = run("optimize", *args, "--force", DS_FORCE, "--out", tmp_path / "opt.json")
    assert r.exit_code == 0, r.output
    got = json.loads((tmp_path / "opt.json").read_text())
    assert got["value"] == pytest.approx(res.value, rel=1e-9)
    assert got["design"]["k_lock"] == pytest.approx(res.design["k_lock"], rel=1e-9)
    one_line_error(run("optimize", *args, "--force", "F_nope"), "--force", "F_lock")


TOL = {"k_lock": (200.0, "N/m"), "stretch": (0.005, "")}  # standard deviations, normal, centred on the design


@pytest.fixture(scope="module")
def reliable(gear, optimum):
    """Least unlock load locking unaided at P(not locking) <= 1e-6, started from the deterministic optimum."""
    from mechcont.analysis.study import Distribution

    random = {n: Distribution("normal", (gear.variable(n).value, sd)) for n, (sd, _) in TOL.items()}
    res = optimize(gear, "unlock_force", DS_BOUNDS, constraints=[Constraint.parse("P(not locking) <= 1e-6")],
                   random=random, force=DS_FORCE, values=optimum[0].design)
    return res, random


def test_reliable_optimum_is_a_kkt_point_on_the_probability_bound(gear, reliable):
    from scipy.stats import norm

    from mechcont.analysis.optimize import BETA, _Quantities

    res, random = reliable
    assert res.success
    assert res.quantities[BETA] == pytest.approx(norm.isf(1e-6), rel=1e-6)
    assert [c for c, _ in res.active] == [f"{BETA} >= {norm.isf(1e-6):g}"]  # interior in both design parameters
    q = _Quantities(gear, DESIGN, {}, None, random, DS_FORCE)
    at = q.at(np.array([res.design[n] for n in DESIGN]), ["unlock_force", BETA])
    span = np.array([DS_BOUNDS[n][1] - DS_BOUNDS[n][0] for n in DESIGN])
    gf, gb = at["unlock_force"][1] * span, at[BETA][1] * span  # on the optimiser's scaled variables
    tangent = np.array([-gb[1], gb[0]]) / np.linalg.norm(gb)
    assert abs(gf @ tangent) <= 1e-4 * np.linalg.norm(gf)


def test_reliable_optimum_beta_without_form(gear, reliable):
    """The reliability index at the optimum as the distance to the nearest failure point in standard normal space,
    found by a polar search (Brent along each ray, Brent over the ray's angle): no FORM, no gradient."""
    from scipy.optimize import minimize_scalar

    from mechcont.continuation import find_equilibrium

    res, _ = reliable
    stops = gear.stops
    hold = {s.condition: float(s.limit) for s in stops}
    free = [s.reaction for s in stops]
    guess = locked_on_stops(gear, res.design)[0]

    def weakest(u):
        v = {n: res.design[n] + TOL[n][0] * ui for n, ui in zip(DESIGN, u)}
        x = find_equilibrium(gear, values=v, hold=hold, free=free, guess=guess)
        return min(float(x[gear.index(r)]) for r in free)

    def radius(theta):
        d = np.array([np.cos(theta), np.sin(theta)])
        return brentq(lambda r: weakest(r * d), 0.0, 10.0, xtol=1e-12)

    # failure lies towards a softer spring (u_k < 0) and a longer free length (u_stretch > 0)
    coarse = np.linspace(np.pi / 2 + 0.05, np.pi - 0.05, 7)
    t0 = coarse[int(np.argmin([radius(t) for t in coarse]))]
    best = minimize_scalar(radius, bounds=(t0 - 0.25, t0 + 0.25), method="bounded", options={"xatol": 1e-7})
    assert best.fun == pytest.approx(res.quantities["beta(not locking)"], rel=1e-6)
