"""Studies: specs parsed from a whitelist, deterministic samples, Parquet written chunk by chunk, resume."""

import json

import numpy as np
import pytest
from scipy import stats

from mechcont.analysis.study import (
    Distribution,
    GridAxis,
    StudySpec,
    failure_probability,
    parse_axis,
    parse_distribution,
    read_results,
    run_study,
    sensitivity,
)
from mechcont.errors import InputError

pytest.importorskip("pyarrow")


def mc_spec(**kw):
    params = (("LU", Distribution("normal", (1.3, 0.01))), ("l_sp1", Distribution("truncnormal", (0.1, 0.01, 0.085, 0.115))),
              ("U", Distribution("uniform", (0.0, 100.0))))
    return StudySpec("nose_gear", "mc", params, **{"n": 600, "seed": 4, "chunk": 100, **kw})


def test_distributions_parse_from_a_whitelist():
    assert parse_distribution("normal:1.3:0.005", "LU") == Distribution("normal", (1.3, 0.005))
    assert parse_distribution("truncnormal:0:1:-2:2", "x").fields == {"mean": 0, "sd": 1, "low": -2, "high": 2}
    assert parse_axis("1.25:1.35:11", "LU") == GridAxis(1.25, 1.35, 11)
    for text, words in [("gauss:1:2", "unknown distribution"), ("normal:1", "needs 2 numbers"),
                        ("normal:1:-1", "positive"), ("uniform:2:1", "inverted"), ("normal:__import__('os'):1", "not a number"),
                        ("normal:1e999:1", "not a finite")]:
        with pytest.raises(InputError, match=words) as e:
            parse_distribution(text, "LU")
        assert str(e.value).startswith("LU") and "\n" not in str(e.value)
    with pytest.raises(InputError, match="LO:HI:N"):
        parse_axis("1:2", "LU")


def test_spec_round_trips_and_refuses_unknown_keys():
    spec = mc_spec()
    assert StudySpec.from_mapping(json.loads(json.dumps(spec.to_mapping()))) == spec
    with pytest.raises(InputError, match="study.sed: unknown key"):
        StudySpec.from_mapping({**spec.to_mapping(), "sed": 3})
    with pytest.raises(InputError, match="a grid study needs a grid axis"):
        StudySpec("nose_gear", "grid", (("LU", Distribution("normal", (1.3, 0.01))),))
    table = {"model": "nose_gear", "sampling": "lhs", "n": 10, "parameters": {"LU": {"distribution": "normal", "mean": 1.3,
                                                                                     "sd": 0.01}}}
    assert StudySpec.from_mapping(table).parameters == (("LU", Distribution("normal", (1.3, 0.01))),)


def test_samples_follow_their_distributions():
    """Monte Carlo: the same seed gives the same samples; truncated normals stay inside their cut and
    match the truncated CDF (Kolmogorov-Smirnov). Latin hypercube: exactly one sample per stratum."""
    spec = mc_spec(n=4000)
    S = spec.samples()
    assert np.array_equal(S, spec.samples())
    assert not np.array_equal(S, mc_spec(n=4000, seed=5).samples())
    lo, hi = 0.085, 0.115
    assert (S[:, 1] >= lo).all() and (S[:, 1] <= hi).all()
    a, b = (lo - 0.1) / 0.01, (hi - 0.1) / 0.01
    assert stats.kstest(S[:, 1], stats.truncnorm(a, b, loc=0.1, scale=0.01).cdf).pvalue > 1e-3
    assert stats.kstest(S[:, 0], stats.norm(1.3, 0.01).cdf).pvalue > 1e-3
    lhs = StudySpec("nose_gear", "lhs", mc_spec().parameters, n=50, seed=1).samples()
    strata = np.floor(stats.norm(1.3, 0.01).cdf(lhs[:, 0]) * 50).astype(int)
    assert sorted(strata) == list(range(50))
    grid = StudySpec("nose_gear", "grid", (("LU", GridAxis(1.2, 1.4, 3)), ("k", GridAxis(1e4, 3e4, 2)))).samples()
    assert np.allclose(grid, [[1.2, 1e4], [1.2, 3e4], [1.3, 1e4], [1.3, 3e4], [1.4, 1e4], [1.4, 3e4]], rtol=1e-15)


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    folder = tmp_path_factory.mktemp("study") / "mc"
    return run_study(mc_spec(), folder), folder


def test_serial_study_writes_labelled_parquet(serial):
    result, folder = serial
    assert result.computed == list(range(6)) and result.reused == []
    df = read_results(folder / "results.parquet")
    assert df["sample"].tolist() == list(range(600))
    assert df.attrs["units"]["downlock_force"] == "N" and df.attrs["units"]["LU"] == "m"
    assert df.attrs["study"] == json.loads((folder / "study.json").read_text())
    assert np.array_equal(df[["LU", "l_sp1", "U"]].to_numpy(), mc_spec().samples())
    assert (df["status"] == "converged").all()
    assert (df["locks_unaided"] == (df["downlock_force"] > 0)).all()


def test_resume_recomputes_nothing_done(serial, tmp_path):
    import shutil

    result, folder = serial
    copy = tmp_path / "copy"
    shutil.copytree(folder, copy)
    parts = {p.name: p.stat().st_mtime_ns for p in (copy / "parts").iterdir()}
    with pytest.raises(InputError, match="already holds a study; add --resume"):
        run_study(mc_spec(), copy)
    again = run_study(mc_spec(), copy, resume=True)
    assert again.computed == [] and again.reused == list(range(6))
    assert {p.name: p.stat().st_mtime_ns for p in (copy / "parts").iterdir()} == parts
    (copy / "parts" / "chunk-000003.parquet").unlink()
    (copy / "parts" / ".chunk-000004-abc.parquet").write_bytes(b"half a part")  # a killed run's temporary
    third = run_study(mc_spec(), copy, resume=True)
    assert third.computed == [3]
    assert not list((copy / "parts").glob(".chunk-*"))
    assert read_results(copy / "results.parquet").equals(read_results(folder / "results.parquet"))
    with pytest.raises(InputError, match=r"other settings \(seed differ"):
        run_study(mc_spec(seed=9), copy, resume=True)


def test_unknown_or_wrong_names_refused_before_anything_is_written(tmp_path):
    for params, words in [((("LUX", Distribution("normal", (1.3, 0.01))),), "LUX: unknown variable"),
                          ((("F", Distribution("normal", (1.3, 0.01))),), "F: is the downlock force"),
                          ((("theta1", Distribution("normal", (1.3, 0.01))),), "theta1: is a state")]:
        with pytest.raises(InputError, match=words):
            run_study(StudySpec("nose_gear", "mc", params, n=5), tmp_path / "x")
        assert not (tmp_path / "x").exists()


def test_probability_and_sensitivity(serial):
    """The probability is the count over the converged samples with the exact Clopper-Pearson
    interval (beta quantiles); the airspeed, which cannot move the force of aligned lock links
    (a dead centre), ranks last with no effect beyond the sampling noise."""
    result, folder = serial
    df = read_results(folder / "results.parquet")
    fp = failure_probability(df)
    k, n = int((df["downlock_force"] <= 0).sum()), len(df)
    assert (fp.failures, fp.samples, fp.probability) == (k, n, k / n)
    assert 0 < k < n
    assert fp.low == pytest.approx(stats.beta.ppf(0.025, k, n - k + 1), rel=1e-9)
    assert fp.high == pytest.approx(stats.beta.ppf(0.975, k + 1, n - k), rel=1e-9)
    ranking, r2 = sensitivity(df)
    assert [s.name for s in ranking][0] == "LU" and ranking[-1].name == "U"
    # no effect: its coefficient is within the regression's sampling noise, 4 standard errors
    assert abs(ranking[-1].src) < 4 * np.sqrt((1 - r2) / len(df))
    assert ranking[0].spearman < -0.9  # more spring free length, less pull over centre


def test_the_sampled_sensitivity_has_its_own_name():
    """Two classes were named ``Sensitivity`` (the engine's exact derivatives, a study's regression): the study's
    is ``SampledSensitivity`` (its old name kept as an alias), and the slope it reports is the regression's."""
    import numpy as np
    import pandas as pd

    from mechcont.analysis.study import SampledSensitivity, Sensitivity, sensitivity
    from mechcont.continuation import Sensitivity as Exact

    assert SampledSensitivity.__name__ != Exact.__name__ and Sensitivity is SampledSensitivity
    rng = np.random.default_rng(1)
    a = rng.normal(size=200)
    df = pd.DataFrame({"a": a, "downlock_force": 3.0 * a + 0.01 * rng.normal(size=200), "status": "converged"})
    (only,), r2 = sensitivity(df, ["a"])
    assert isinstance(only, SampledSensitivity) and only.slope == pytest.approx(3.0, rel=1e-2) and r2 > 0.99
