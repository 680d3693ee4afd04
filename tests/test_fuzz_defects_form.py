"""Defects of the third fuzz campaign (issue 33), FORM and studies: FORM says when it is outside its domain
(a mean design that fails, no root along the search, an importance sampling that sees no failure), checked
against closed forms and seeded Monte Carlo; a study spec's model_hash is checked; a study's cost is
estimated and bounded before it starts; a fake Dask scheduler cannot hang or crash a study."""

import json
import socket
import struct
import threading
import time

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from scipy.stats import norm

from mechcont.analysis.reliability import Variables, reliability
from mechcont.analysis.study import Distribution
from mechcont.errors import ConvergenceError

run = make_runner()
pytest.importorskip("pyarrow")


def _linear(mean_b):
    """g = a - 2 b + 1, a ~ N(10, 2), b ~ N(mean_b, 1): g ~ N(11 - 2 mean_b, sqrt 8), P(g <= 0) = Phi(-beta)."""
    V = Variables(["a", "b"], [Distribution("normal", (10.0, 2.0)), Distribution("normal", (mean_b, 1.0))])
    return V, (lambda x: (x[0] - 2 * x[1] + 1, np.array([1.0, -2.0]))), (lambda X: X[:, 0] - 2 * X[:, 1] + 1)


def _own_monte_carlo(mean_b, n=400_000, seed=12345):
    rng = np.random.default_rng(seed)
    a, b = rng.normal(10.0, 2.0, n), rng.normal(mean_b, 1.0, n)
    return float(np.mean(a - 2 * b + 1 <= 0))


def test_a_mean_design_that_fails_is_said_and_the_sampling_checks_the_safe_side():
    V, limit, evaluate = _linear(8.0)  # E[g] = -5: the mean fails, beta = -5/sqrt(8)
    beta = -5 / np.sqrt(8)
    truth = norm.cdf(-beta)
    assert _own_monte_carlo(8.0) == pytest.approx(truth, abs=4 * np.sqrt(truth * (1 - truth) / 400_000))
    r = reliability(limit, V, evaluate=evaluate, n=4000, seed=3)
    assert r.beta == pytest.approx(beta, rel=1e-10) and r.probability == pytest.approx(truth, rel=1e-12)
    s = r.sampling
    assert s.event == "safe" and s.hits > 1000
    assert abs(s.probability - truth) < 4 * s.cov * s.probability  # was 1e-3-ish: failures weighed by ~0 weights
    m = r.monte_carlo  # 4000 samples see ~150 safe ones: cheap, so made
    assert m is not None and m.n == 4000 and abs(m.probability - truth) < 4 * np.sqrt(truth * (1 - truth) / m.n)
    assert any("mean design already fails" in f and "1 - P" in f for f in r.findings)
    doc = r.to_dict()
    assert doc["importance_sampling"]["event"] == "safe" and doc["monte_carlo"]["n"] == 4000 and doc["findings"]


def test_a_mean_design_that_holds_has_no_finding():
    V, limit, evaluate = _linear(3.0)
    r = reliability(limit, V, evaluate=evaluate, n=2000, seed=3)
    assert r.findings == [] and r.monte_carlo is None and r.sampling.event == "failure"
    assert abs(r.sampling.probability - r.probability) < 4 * r.sampling.cov * r.probability


def test_an_importance_sampling_that_sees_no_failure_says_so_and_monte_carlo_shows_form_wrong():
    """g = (u - 3)^2 - 1e-12: FORM stops at u = 3 - 1e-6 and says Phi(-3) = 1.3e-3; the failure domain is an
    interval 2e-6 wide (P = 2e-6 phi(3) = 8.9e-9), which no importance sample hits; 10,000 Monte Carlo samples
    (13 failures expected if FORM were right) see none."""
    V = Variables(["u"], [Distribution("normal", (0.0, 1.0))])
    r = reliability(lambda x: ((x[0] - 3) ** 2 - 1e-12, np.array([2 * (x[0] - 3)])), V,
                    evaluate=lambda X: (X[:, 0] - 3) ** 2 - 1e-12, n=10_000, seed=1)
    assert r.probability == pytest.approx(norm.cdf(-3), rel=1e-4)
    assert r.sampling.hits == 0 and r.sampling.probability == 0
    assert any("saw no failure" in f and "checks nothing" in f for f in r.findings), r.findings
    assert r.monte_carlo is not None and r.monte_carlo.failures == 0


def test_no_monte_carlo_when_it_would_see_nothing():
    V = Variables(["u"], [Distribution("normal", (0.0, 1.0))])
    r = reliability(lambda x: ((x[0] - 3) ** 2 - 1e-12, np.array([2 * (x[0] - 3)])), V,
                    evaluate=lambda X: (X[:, 0] - 3) ** 2 - 1e-12, n=500, seed=1)
    assert r.monte_carlo is None
    assert any("no Monte Carlo check" in f and "7.4e+03" in f for f in r.findings), r.findings


@pytest.mark.parametrize("g, words", [
    (lambda x: (np.exp(x[0] / 10), np.array([np.exp(x[0] / 10) / 10])), "stays positive (safe)"),
    (lambda x: (-np.exp(-x[0] / 10), np.array([np.exp(-x[0] / 10) / 10])), "stays not positive (failing)"),
])
def test_a_limit_state_with_no_root_along_the_search(g, words):
    V = Variables(["x"], [Distribution("normal", (0.0, 1.0))])
    t0 = time.perf_counter()
    with pytest.raises(ConvergenceError) as info:
        reliability(g, V)
    assert time.perf_counter() - t0 < 10
    text = str(info.value)
    assert "no root along the search" in text and words in text and "\n" not in text


# -- the command line: the campaign's cases -------------------------------------------------------
def test_study_form_of_the_nose_gear_whose_mean_fails(tmp_path):
    """LU ~ N(1.35 m, 10 mm) with the root LU* = 1.31698 m below the mean: the downlock force falls with LU
    (one variable, monotone), so P(F <= 0) = Phi((1.35 - LU*) / 0.01) exactly; the importance sampling
    (of the safe side) and a seeded Monte Carlo agree with it; the campaign saw IS 0.39."""
    from mechcont.analysis.sensitivity import downlock_sensitivity
    from mechcont.models import load_model

    r = run("study", "nose_gear", "--method", "form", "--dist", "LU=normal:1.35:0.01", "--n", "400", "--scheduler",
            "serial", "--dir", tmp_path / "f")
    assert r.exit_code == 0, r.output
    doc = json.loads((tmp_path / "f" / "reliability.json").read_text())
    lu = doc["design_point"]["LU"]
    s = downlock_sensitivity(load_model("nose_gear"), ["LU"], {"LU": lu})
    assert abs(s.value) < 1e-6 * abs(s["LU"]) * 0.01  # the design point is the force's root
    truth = norm.cdf((1.35 - lu) / 0.01)
    assert doc["probability"] == pytest.approx(truth, rel=1e-9)
    is_ = doc["importance_sampling"]
    assert is_["event"] == "safe" and abs(is_["probability"] - truth) < 4 * is_["cov"] * truth
    assert "mean design already fails" in r.stderr and "warning:" in r.stderr
    assert "Traceback" not in r.output


def test_study_form_whose_mean_fails_by_133_standard_deviations(tmp_path):
    r = run("study", "nose_gear", "--method", "form", "--dist", "LU=normal:1.45:0.001", "--n", "200", "--scheduler",
            "serial", "--dir", tmp_path / "f")
    assert r.exit_code == 0, r.output
    doc = json.loads((tmp_path / "f" / "reliability.json").read_text())
    assert doc["probability"] == 1.0 and doc["importance_sampling"]["probability"] == 1.0  # was P = 0, cov nan
    assert doc["importance_sampling"]["event"] == "safe"
    assert any("mean design already fails" in f for f in doc["findings"])
    assert "mean design already fails" in r.stderr


# -- model_hash -----------------------------------------------------------------------------------
SPEC = 'sampling = "mc"\nn = 5\nchunk = 5\n[hold]\ntheta4 = 0.0\n[parameters]\nLU = "normal:1.3:0.01"\n'


def _description(tmp_path):
    import shutil

    from mechcont.mechanism import find_description

    return shutil.copy(find_description("nose_gear.toml"), tmp_path / "ng.toml")


@pytest.mark.parametrize("model, hash_, words", [
    ("nose_gear", "0" * 64, ("model_hash", "built-in model")),
    ("nose_gear", "not a hash", ("model_hash", "not a SHA-256")),
    ("FILE", "1" * 64, ("model_hash", "is not the hash of", "description changed")),
])
def test_a_study_specs_model_hash_is_checked(tmp_path, model, hash_, words):
    if model == "FILE":
        model = _description(tmp_path)
    spec = tmp_path / "spec.toml"
    spec.write_text(f'model_hash = "{hash_}"\n' + SPEC)
    r = run("study", model, "--spec", spec, "--scheduler", "serial", "--dir", tmp_path / "s")
    one_line_error(r, *words)
    assert not (tmp_path / "s").exists()


def test_a_study_spec_with_the_right_model_hash_runs(tmp_path):
    import hashlib

    path = _description(tmp_path)
    spec = tmp_path / "spec.toml"
    spec.write_text(f'model_hash = "{hashlib.sha256(path.read_bytes()).hexdigest()}"\n' + SPEC)
    r = run("study", str(path), "--spec", spec, "--scheduler", "serial", "--dir", tmp_path / "s", "--quiet")
    assert r.exit_code == 0, r.output


# -- a study's cost -------------------------------------------------------------------------------
def test_ten_million_samples_are_estimated_and_refused_before_anything_is_written(tmp_path):
    t0 = time.perf_counter()
    r = run("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--n", "10000000", "--scheduler", "serial",
            "--dir", tmp_path / "s", "--max-hours", "0.05")
    one_line_error(r, "--max-hours", "10000000 samples", "timed on", "above the limit of 3 min")
    assert time.perf_counter() - t0 < 60 and not (tmp_path / "s").exists()


def test_the_estimate_is_said_and_a_raised_limit_lets_the_study_run(tmp_path):
    from mechcont.analysis.study import StudySpec
    from mechcont.analysis.study._estimate import estimate_study
    from mechcont.models import load_model

    spec = StudySpec("nose_gear", "mc", (("LU", Distribution("normal", (1.3, 0.01))),), n=400, seed=0, chunk=200)
    est = estimate_study(load_model("nose_gear"), spec, spec.samples(), np.arange(400))
    assert est is not None and est.samples == 400 and 4 <= est.timed <= 64 and 0 < est.per_sample < 0.1
    assert est.seconds == pytest.approx(400 * est.per_sample)
    r = run("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--n", "400", "--scheduler", "serial", "--dir",
            tmp_path / "s", "--max-hours", "1e-9")
    one_line_error(r, "--max-hours", "400 samples")
    r = run("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--n", "400", "--scheduler", "serial", "--dir",
            tmp_path / "s", "--quiet")
    assert r.exit_code == 0, r.output


@pytest.mark.parametrize("hours", ["0", "-1", "nan", "inf"])
def test_max_hours_must_be_a_positive_number(tmp_path, hours):
    one_line_error(run("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--n", "10", "--dir", tmp_path / "s",
                       "--max-hours", hours), "--max-hours")


# -- a fake Dask scheduler ------------------------------------------------------------------------
@pytest.mark.parametrize("announced", [2**62, 2**30])
def test_a_fake_scheduler_announcing_a_huge_frame(tmp_path, monkeypatch, announced):
    """It accepts, sends a frame length of 2^62 bytes (MemoryError in Dask's read) or 1 GiB (then nothing:
    Dask waited for it forever): one line, at once."""
    from mechcont.analysis.study import _dask

    monkeypatch.setattr(_dask, "SCHEDULER_TIMEOUT", 2.0)
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    server.settimeout(60)
    conns = []

    def serve():
        while True:
            try:
                c = server.accept()[0]
            except OSError:
                return
            conns.append(c)
            c.sendall(struct.pack("Q", announced) + b"\0" * 64)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        t0 = time.perf_counter()
        r = run("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--n", "30", "--chunk", "10", "--quiet",
                "--scheduler", f"tcp://127.0.0.1:{server.getsockname()[1]}", "--dir", tmp_path / "s")
        elapsed = time.perf_counter() - t0
    finally:
        # close() alone does not wake the thread blocked in accept() (it waited out join's 5 s);
        # shutdown() makes that accept() fail at once
        try:
            server.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        server.close()
        for c in conns:
            c.close()
        thread.join(5)
    one_line_error(r, "--scheduler", "not a Dask scheduler")
    assert elapsed < 30 and not (tmp_path / "s").exists()
