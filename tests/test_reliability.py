"""FORM/SORM/importance sampling (``mechcont.analysis.reliability``) against closed forms, exact integrals, Monte
Carlo of the nose gear, and ``mechcont study --method form``."""

import json
from dataclasses import replace

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from scipy.integrate import quad
from scipy.stats import binomtest, norm

from mechcont.analysis.reliability import Variables, downlock_reliability, reliability, sorm_breitung
from mechcont.analysis.sensitivity import downlock_sensitivity
from mechcont.analysis.study import Distribution, StudySpec, run_chunk
from mechcont.models import load_model

run = make_runner()
NOSE = "LU=normal:1.3:0.01", "l_sp1=truncnormal:0.1:0.005:0.09:0.11"


def nose_spec(mean=1.3, n=2000, seed=1):
    """The issue's tolerance case (spring free length and attachment), the free length's mean movable."""
    return StudySpec("nose_gear", "mc", (("LU", Distribution("normal", (mean, 0.01))),
                                         ("l_sp1", Distribution("truncnormal", (0.1, 0.005, 0.09, 0.11)))), n=n, seed=seed)


def test_linear_limit_state_of_normals_is_exact():
    """g = a - 2 b + 1, a ~ N(10, 2), b ~ N(3, 1): beta = E[g]/sd[g] = 5/sqrt(8), alpha^2 = (4, 4)/8, no curvature."""
    V = Variables(["a", "b"], [Distribution("normal", (10.0, 2.0)), Distribution("normal", (3.0, 1.0))])
    r = reliability(lambda x: (x[0] - 2 * x[1] + 1, np.array([1.0, -2.0])), V,
                    evaluate=lambda X: X[:, 0] - 2 * X[:, 1] + 1, n=4000, seed=3)
    beta = 5 / np.sqrt(8)
    assert r.beta == pytest.approx(beta, rel=1e-10)
    assert r.probability == pytest.approx(norm.cdf(-beta), rel=1e-9)
    assert r.probability_sorm == pytest.approx(r.probability, rel=1e-6)
    assert r.importance == pytest.approx({"a": 0.5, "b": 0.5}, rel=1e-9)
    # the design point: the mean moved by -beta sd[g] along each variable's share of the variance
    assert r.design_point == pytest.approx({"a": 10 - 4 * 5 / 8, "b": 3 + 2 * 5 / 8}, rel=1e-9)
    s = r.sampling
    assert abs(s.probability - r.probability) < 4 * s.cov * r.probability


@pytest.mark.parametrize("dist, threshold", [(Distribution("uniform", (0.0, 2.0)), 0.02),
                                             (Distribution("truncnormal", (1.0, 0.5, 0.2, 3.0)), 0.25)])
def test_one_non_normal_variable_is_exact_through_the_transform(dist, threshold):
    """g = x - t is monotone in u = Phi^-1(F(x)): FORM gives F(t) exactly, SORM has no curvature to add."""
    V = Variables(["x"], [dist])
    r = reliability(lambda x: (x[0] - threshold, np.array([1.0])), V)
    exact = float(V.frozen[0].cdf(threshold))
    assert r.probability == pytest.approx(exact, rel=1e-8)
    assert r.design_point["x"] == pytest.approx(threshold, rel=1e-9)


def test_transform_round_trip_in_both_tails():
    V = Variables(["a", "b", "c"], [Distribution("uniform", (0.0, 1.0)), Distribution("truncnormal", (0, 1, -3, 3)),
                                    Distribution("normal", (5.0, 2.0))], shift=[1.0, 0.0, -1.0])
    U = np.array([[-6.0, 2.5, 7.0], [5.0, -2.9, -7.0], [0.3, 0.1, 0.0]])
    assert np.allclose(V.u(V.x(U)), U, atol=1e-6)
    V.shift[:] = 0.0  # a shift would cost the differences below their digits in the far tail
    h = 1e-4  # dx/du against a central difference
    for j in range(3):
        e = np.eye(3)[j] * h
        assert np.allclose((V.x(U + e) - V.x(U - e))[:, j] / (2 * h), V.dx_du(U)[:, j], rtol=1e-5, atol=1e-12)


@pytest.mark.parametrize("beta, kappa", [(3.0, 0.3), (3.5, -0.1)])
def test_sorm_improves_on_form_for_a_parabolic_limit_state(beta, kappa):
    """g = beta - u2 + kappa u1^2 / 2 in standard normals: exact P = int phi(t) Phi(-beta - kappa t^2 / 2) dt."""
    V = Variables(["u1", "u2"], [Distribution("normal", (0.0, 1.0))] * 2)
    r = reliability(lambda x: (beta - x[1] + 0.5 * kappa * x[0] ** 2, np.array([kappa * x[0], -1.0])), V,
                    u0=np.array([0.3, 0.0]))
    exact = quad(lambda t: norm.pdf(t) * norm.cdf(-beta - 0.5 * kappa * t * t), -np.inf, np.inf, epsabs=0, epsrel=1e-12)[0]
    assert r.beta == pytest.approx(beta, rel=1e-8)
    assert r.curvatures == pytest.approx([kappa], rel=1e-5)
    assert r.probability_sorm == pytest.approx(sorm_breitung(beta, [kappa]))
    assert abs(r.probability_sorm - exact) < 0.2 * abs(r.probability - exact)


def test_sorm_of_a_mean_that_fails_is_one_minus_the_safe_set():
    assert sorm_breitung(-2.0, [0.1]) == pytest.approx(1 - norm.cdf(-2.0) * (1 - 0.2) ** -0.5)
    assert np.isnan(sorm_breitung(2.0, [-0.6]))


def test_nose_gear_form_within_the_monte_carlo_interval():
    """FORM against 10,000 Monte Carlo downlock solves (the issue's study), and against the linear-slope
    check: the force is nearly linear in LU, so beta ~ F(mean) / (|dF/dLU| sd)."""
    spec = nose_spec(n=10_000, seed=1)
    system = load_model("nose_gear")
    cols = run_chunk(system, replace(spec, chunk=10_000), 0)
    ok = cols["status"] == "converged"
    k, n = int((cols["downlock_force"][ok] <= 0).sum()), int(ok.sum())
    ci = binomtest(k, n).proportion_ci(0.95, method="exact")
    r = downlock_reliability(spec, n=0)
    assert ci.low < r.probability < ci.high
    assert ci.low < r.probability_sorm < ci.high
    s = downlock_sensitivity(system, ["LU"], {"LU": 1.3, "l_sp1": 0.1})
    assert r.beta == pytest.approx(s.value / (-s["LU"] * 0.01), rel=0.01)
    assert r.importance["LU"] > 0.95  # the attachment hardly matters near its maximum


def test_nose_gear_one_in_a_million_agrees_with_importance_sampling():
    """The free length's mean moved 30 mm shorter: P ~ 1e-6, out of reach of Monte Carlo; FORM and SORM
    within 10 % of importance sampling around the design point (its own CoV ~ 2 %)."""
    r = downlock_reliability(nose_spec(mean=1.2696), n=10_000, seed=5)
    assert 3e-7 < r.probability < 3e-6
    s = r.sampling
    assert s.failed == 0 and s.cov < 0.03
    assert r.probability == pytest.approx(s.probability, rel=0.1)
    assert r.probability_sorm == pytest.approx(s.probability, rel=0.1)
    assert r.seconds < 30


def test_linear_model_form_exact_at_one_in_a_million():
    """A description with a downlock moment linear in normal M0 and m (tests/data/pendulum_downlock.toml)."""
    c = 9.81 * 0.5 * np.cos(0.3)
    beta = 4.75
    sd0, mean_m, sd_m = 0.5, 2.0, 0.1
    mean0 = c * mean_m + beta * np.hypot(sd0, c * sd_m)
    spec = StudySpec("tests/data/pendulum_downlock.toml", "mc",
                     (("M0", Distribution("normal", (mean0, sd0))), ("m", Distribution("normal", (mean_m, sd_m)))), n=1)
    r = downlock_reliability(spec, n=4000)
    assert r.beta == pytest.approx(beta, rel=1e-8)
    assert r.probability == pytest.approx(norm.cdf(-beta), rel=1e-7)
    assert r.sampling.probability == pytest.approx(r.probability, rel=4 * r.sampling.cov)


# -- the command line ----------------------------------------------------------------------------
def test_study_method_form_writes_and_prints(tmp_path):
    r = run("study", "nose_gear", "--dist", NOSE[0], "--dist", NOSE[1], "--method", "form", "--n", "1000",
            "--out", tmp_path / "f", "--scheduler", "serial")
    assert r.exit_code == 0, r.output
    doc = json.loads((tmp_path / "f" / "reliability.json").read_text())
    assert {"beta", "probability", "probability_sorm", "design_point", "importance"} <= set(doc)
    assert set(doc["design_point"]) == set(doc["importance"]) == {"LU", "l_sp1"}
    assert sum(doc["importance"].values()) == pytest.approx(1.0, rel=1e-12)
    assert doc["probability"] == pytest.approx(norm.cdf(-doc["beta"]), rel=1e-12)
    assert doc["importance_sampling"]["n"] == 1000
    assert f"beta = {doc['beta']:.6g}" in r.output and f"LU = {doc['design_point']['LU']:.10g} m" in r.output


@pytest.mark.parametrize("args, words", [
    (("--dist", NOSE[0], "--method", "sorm"), ["--method", "unknown method 'sorm'", "form"]),
    (("--grid", "LU=1.2:1.4:3", "--method", "form"), ["--grid", "--method form"]),
    (("--dist", NOSE[0], "--method", "form", "--sample", "lhs"), ["--sample", "--method form"]),
    (("--dist", NOSE[0], "--method", "form", "--n", "-1"), ["--n", "non-negative"]),
    (("--dist", "LUX=normal:1:0.1", "--method", "form"), ["LUX"]),
    # every free length in 1.2..1.25 m locks: no failure point within the bounded distribution
    (("--dist", "LU=uniform:1.2:1.25", "--method", "form"), ["FORM", "no failure point", "LU = 1.25"]),
])
def test_study_method_form_bad_input_is_one_line(tmp_path, args, words):
    r = run("study", "nose_gear", *args, "--out", tmp_path / "f", "--scheduler", "serial")
    one_line_error(r, *words)
    assert not (tmp_path / "f").exists()


@pytest.mark.slow
def test_importance_sampling_on_a_local_cluster_equals_in_process():
    """The importance samples solved on a local Dask cluster (two chunks) give the same forces as in this process."""
    pytest.importorskip("distributed")
    spec = replace(nose_spec(mean=1.2696), chunk=500)
    here = downlock_reliability(spec, n=1000, seed=4)
    there = downlock_reliability(spec, n=1000, seed=4, scheduler="local", workers=2)
    assert "local cluster" in there.sampling.ran_on and here.sampling.ran_on == "this process"
    assert there.sampling.probability == pytest.approx(here.sampling.probability, rel=1e-9)
    assert there.sampling.cov == pytest.approx(here.sampling.cov, rel=1e-9)
