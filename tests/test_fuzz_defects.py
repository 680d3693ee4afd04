"""Defects a fuzz campaign found (issue 20): each silently wrong result, traceback or hang is now a
one-line error (exit 2), a reported finding, or a verified recomputation."""

import shutil

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error

run = make_runner()


def clean_failure(result, *words):
    one_line_error(result, *words)
    assert "Traceback" not in result.output and "Traceback" not in result.stderr


# -- study --resume verifies every part ----------------------------------------------------------
pytest.importorskip("pyarrow")
STUDY = ("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--n", "30", "--chunk", "10", "--scheduler", "serial",
         "--quiet")


@pytest.fixture(scope="module")
def studies(tmp_path_factory):
    """The study (seed 0), the same with seed 1, and the same with chunks of 5: three folders."""
    root = tmp_path_factory.mktemp("studies")
    for name, extra in (("a", ()), ("seed1", ("--seed", "1")), ("chunk5", ()), ):
        args = list(STUDY)
        if name == "chunk5":
            args[args.index("--chunk") + 1] = "5"
        r = run(*args, *extra, "--out", root / name)
        assert r.exit_code == 0, r.output
    return root


def _results(folder):
    from mechcont.analysis.study import read_results

    return read_results(folder / "results.parquet")


def _copy_study(studies, tmp_path):
    out = tmp_path / "s"
    shutil.copytree(studies / "a", out)
    (out / "results.parquet").unlink()
    return out


@pytest.mark.parametrize("spoil, why", [
    (lambda p, st: shutil.copy(st / "seed1" / "parts" / p.name, p), "other settings"),
    (lambda p, st: shutil.copy(st / "chunk5" / "parts" / p.name, p), "other settings"),
    (lambda p, st: p.write_bytes(p.read_bytes()[: len(p.read_bytes()) // 2]), "cannot be read"),
    (lambda p, st: p.write_bytes(b""), "cannot be read"),
    (lambda p, st: p.write_bytes(b"PAR1 garbage \x00\x01" * 50), "cannot be read"),
])
def test_resume_recomputes_a_part_that_is_not_this_studys(tmp_path, studies, spoil, why):
    out = _copy_study(studies, tmp_path)
    part = out / "parts" / "chunk-000001.parquet"
    spoil(part, studies)
    r = run(*STUDY, "--out", out, "--resume")
    assert r.exit_code == 0, r.output
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "chunk-000001.parquet" in lines[0] and why in lines[0], r.stderr
    assert "computing it again" in lines[0]
    a, b = _results(studies / "a"), _results(out)
    assert list(b["sample"]) == list(range(30))
    np.testing.assert_allclose(b["LU"], a["LU"], rtol=0, atol=0)  # the samples are a pure function of the spec
    np.testing.assert_allclose(b["downlock_force"], a["downlock_force"], rtol=1e-9)


def test_resume_with_a_part_from_a_study_with_other_columns(tmp_path, studies):
    out = _copy_study(studies, tmp_path)
    other = tmp_path / "other"
    r = run(*STUDY, "--dist", "U=uniform:0:100", "--out", other)
    assert r.exit_code == 0, r.output
    shutil.copy(other / "parts" / "chunk-000002.parquet", out / "parts" / "chunk-000002.parquet")
    r = run(*STUDY, "--out", out, "--resume")
    assert r.exit_code == 0 and "chunk-000002.parquet" in r.stderr, r.output
    assert list(_results(out).columns) == list(_results(studies / "a").columns)


def test_resume_with_a_folder_for_a_part_is_one_line(tmp_path, studies):
    out = _copy_study(studies, tmp_path)
    part = out / "parts" / "chunk-000000.parquet"
    part.unlink()
    part.mkdir()
    clean_failure(run(*STUDY, "--out", out, "--resume"), "--resume", "is a folder")
    assert part.is_dir() and not (out / "results.parquet").exists()


def test_resume_keeps_verified_parts(tmp_path, studies):
    out = _copy_study(studies, tmp_path)
    r = run(*STUDY, "--out", out, "--resume")
    assert r.exit_code == 0 and r.stderr.strip() == "", r.output
    assert len(_results(out)) == 30


def test_branch_summary_bound_is_a_status_and_a_fold_is_not_unstable():
    """The release run's own force bound (F0 - 50 scales) is no force of the mechanism: nan and a note;
    the fold where the run stops has a zero eigenvalue: it is a fold, not an unstable point."""
    from mechcont.analysis.study import Distribution, StudySpec
    from mechcont.analysis.study._kernels import run_chunk
    from mechcont.analysis.unlock import RELEASE_FORCE_SPAN
    from mechcont.models import load_model

    system = load_model("lockstay.toml")
    spec = StudySpec("lockstay.toml", "mc", (("LU", Distribution("normal", (0.6, 0.005))),), n=2, seed=3,
                     analyses=("branch",))
    c = run_chunk(system, spec, 0)
    F = c["downlock_force"]
    bound = F - RELEASE_FORCE_SPAN * system.variable("F").scale
    assert np.isnan(c["branch_force_low"]).all()
    for note, b in zip(c["branch_note"], bound):
        assert note == f"decreasing: the release run ended at its bound {b:.6g} N, no fold"
    assert (c["branch_folds"] == 1).all() and (c["branch_force_high"] > F).all()
    assert (c["branch_unstable_points"] == 0).all()
