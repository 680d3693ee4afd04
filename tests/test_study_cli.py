"""`mechcont study`: one-line errors, a study killed half way and resumed, a real local Dask cluster,
and the grid study against the design map of `mechcont design`."""

import signal
import subprocess
import sys

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from numeric_text import assert_frames_close

from mechcont.analysis.study import Distribution, GridAxis, StudySpec, read_results, run_study

pytest.importorskip("pyarrow")
run = make_runner()

TOLERANCES = ("--dist", "k=normal:20000:1500", "--dist", "LU=normal:0.6:0.005")


@pytest.mark.parametrize("args, words", [
    (("--dist", "LU=gauss:1:2", "--n", "5"), ["--dist LU", "unknown distribution 'gauss'"]),
    (("--dist", "LU=normal:1.3:0.01"), ["--n", "number of samples"]),
    (("--dist", "LU=normal:1.3:0.01", "--grid", "k=1:2:3", "--n", "3"), ["--grid", "not both"]),
    (("--grid", "LU=1.2:1.4"), ["--grid LU", "LO:HI:N"]),
    (("--dist", "LUX=normal:1.3:0.01", "--n", "3"), ["LUX", "unknown variable"]),
    (("--dist", "LU=normal:1.3:0.01", "--n", "0"), ["--n", "positive"]),
    (("--dist", "LU=normal:1.3:0.01", "--n", "3", "--plot", "x.gif"), ["--plot", "unknown file type"]),
])
def test_bad_input_is_one_line(tmp_path, args, words):
    r = run("study", "nose_gear", *args, "--out", tmp_path / "s", "--scheduler", "serial")
    one_line_error(r, *words)
    assert not (tmp_path / "s").exists()


def test_study_prints_probability_and_ranking(tmp_path):
    r = run("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--dist", "U=uniform:0:100", "--n", "300",
            "--out", tmp_path / "s", "--scheduler", "serial", "--plot", tmp_path / "s.png")
    assert r.exit_code == 0, r.output
    df = read_results(tmp_path / "s" / "results.parquet")
    k = int((df["downlock_force"] <= 0).sum())
    assert f"P(not locking unaided) = {k / 300:.4g} ({k} of 300 samples)" in r.output
    ranking = [ln.split()[0] for ln in r.output.splitlines() if " SRC " in ln]
    assert ranking == ["LU", "U"]
    slopes = {ln.split()[0]: ln.split("slope ")[1].split("  ")[0].split()[1] for ln in r.output.splitlines() if " SRC " in ln}
    assert slopes == {"LU": "N/m", "U": "N/(m/s)"}  # the slope's unit, N per the parameter's unit
    assert (tmp_path / "s.png").stat().st_size > 10_000
    again = run("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--dist", "U=uniform:0:100", "--n", "300",
                "--out", tmp_path / "s", "--scheduler", "serial")
    one_line_error(again, "--out", "--resume")


def test_slope_units_read_as_units():
    from mechcont.cli.study import per_unit

    assert [per_unit("N", u) for u in ("m", "N/m", "N m", "")] == ["N/m", "N/(N/m)", "N/(N m)", "N"]


# -- killed half way, resumed -----------------------------------------------------------------
KILLED = ("lockstay.toml", *TOLERANCES, "--n", "40", "--analysis", "unlock", "--chunk", "2")


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory):
    folder = tmp_path_factory.mktemp("whole")
    spec = StudySpec("lockstay.toml", "mc", (("k", Distribution("normal", (20000.0, 1500.0))),
                                             ("LU", Distribution("normal", (0.6, 0.005)))),
                     n=40, analyses=("unlock",), chunk=2)
    run_study(spec, folder / "s")
    return spec, read_results(folder / "s" / "results.parquet")


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_killed_study_resumes_losing_and_recomputing_nothing(tmp_path, uninterrupted, sig):
    """A real `mechcont study` process is killed after its second chunk is written; every part on
    disk then is kept as it is (not recomputed), the rest is computed by --resume, and the results
    equal an uninterrupted run (to rounding: the killed run is another process, which may sit on another
    BLAS kernel; solves converge to 1e-10 relative or better, rtol 1e-9 leaves room for that)."""
    spec, whole = uninterrupted
    out = tmp_path / "s"
    code = "import sys; from mechcont.cli import main; main(sys.argv[1:])"
    proc = subprocess.Popen([sys.executable, "-c", code, "study", *KILLED, "--out", str(out), "--scheduler", "serial",
                             "--verbose"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        written = 0
        while written < 2:
            line = proc.stdout.readline()
            assert line, proc.communicate()[1]
            written += line.startswith("chunk ")
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == (-9 if sig == signal.SIGKILL else 143), err
    if sig == signal.SIGTERM:
        assert [ln for ln in err.splitlines() if ln.strip()] == ["error: terminated"]
    parts = {p.name: p.stat().st_mtime_ns for p in (out / "parts").glob("chunk-*.parquet")}
    assert 2 <= len(parts) < spec.n_chunks
    assert not (out / "results.parquet").exists()
    r = run("study", *KILLED, "--out", out, "--scheduler", "serial", "--resume")
    assert r.exit_code == 0, r.output
    assert f"{spec.n_chunks - len(parts)} chunk(s) computed in this process, {len(parts)} resumed" in r.output
    assert {p.name: p.stat().st_mtime_ns for p in (out / "parts").glob("chunk-*.parquet")}.items() >= parts.items()
    assert not list((out / "parts").glob(".chunk-*"))
    assert_frames_close(read_results(out / "results.parquet"), whole, rtol=1e-9, atol=1e-9)
    assert whole["unlock_force"].notna().all() and (whole["unlock_margin"] > 0).all()


# -- a real local cluster ---------------------------------------------------------------------
CLUSTER_SPEC = StudySpec("nose_gear", "mc", (("L4", Distribution("uniform", (0.26, 0.44))),
                                             ("LU", Distribution("normal", (1.3, 0.01))),
                                             ("k", Distribution("uniform", (-2000.0, 40000.0)))), n=240, seed=2, chunk=30)


@pytest.fixture(scope="module")
def serial_run(tmp_path_factory):
    """The cluster tests' reference: the study in this process, with batched rows, stragglers and failed samples."""
    serial = run_study(CLUSTER_SPEC, tmp_path_factory.mktemp("serial") / "s")
    a = serial.frame()
    assert {"batched", "single"} <= set(a["path"]) and (a["status"] == "failed").any()
    return serial, a


def test_auto_in_this_process_equals_serial(tmp_path, serial_run):
    """A study too small for a cluster: ``scheduler="auto"`` runs every chunk here, in order, and gives the serial
    run's table (rtol 1e-9: the solves converge to 1e-10 relative or better)."""
    serial, a = serial_run
    auto = run_study(CLUSTER_SPEC, tmp_path / "auto", scheduler="auto", workers=2)
    assert auto.computed == serial.computed == list(range(CLUSTER_SPEC.n_chunks))
    assert auto.ran_on.startswith("this process (auto: 210 samples left") and serial.ran_on == "this process"
    assert_frames_close(auto.frame(), a, rtol=1e-9, atol=1e-9)


@pytest.mark.slow
def test_local_cluster_equals_serial(tmp_path, serial_run):
    """Two worker processes of a dask.distributed LocalCluster give the serial run's results (to the
    solves' rounding), batched rows, stragglers solved alone and failed samples alike."""
    pytest.importorskip("dask.distributed")
    serial, a = serial_run
    cluster = run_study(CLUSTER_SPEC, tmp_path / "cluster", scheduler="local", workers=2)
    assert cluster.computed and sorted(cluster.computed) == serial.computed
    assert_frames_close(cluster.frame(), a, rtol=1e-9, atol=1e-9)


@pytest.mark.slow
def test_auto_on_a_local_cluster_equals_serial(tmp_path, serial_run, monkeypatch):
    """``scheduler="auto"`` when the cluster pays off (its start taken as free): the first chunk in this process,
    the others on two worker processes, the serial run's results (to the solves' rounding)."""
    pytest.importorskip("dask.distributed")
    from mechcont.analysis.study import _schedule

    monkeypatch.setattr(_schedule, "CLUSTER_START_SECONDS", 0.0)
    serial, a = serial_run
    auto = run_study(CLUSTER_SPEC, tmp_path / "auto", scheduler="auto", workers=2)
    assert auto.computed[0] == 0 and sorted(auto.computed) == serial.computed
    assert auto.ran_on.startswith("this process, then a local cluster of 2 worker processes (auto: 210 samples left")
    assert_frames_close(auto.frame(), a, rtol=1e-9, atol=1e-9)


# -- the design map ---------------------------------------------------------------------------
def test_grid_study_reproduces_the_design_map():
    """A grid study over (l_sp1, LU) against analysis.design.design_region on the same plane: the
    force at the design l_sp1 on every level equals the design table's (an exact solve) to 1e-9,
    and every grid point locks unaided exactly where the design table's F > 0 intervals (their ends
    solved exactly) say so; the continued F = 0 boundary separates the grid's signs."""
    from mechcont.analysis.design import design_region
    from mechcont.analysis.study import grid_values, run_chunk
    from mechcont.models import load_model

    s = load_model("nose_gear")
    levels = np.linspace(1.25, 1.35, 6)
    region = design_region(s, "l_sp1", "LU", x_bounds=(-0.175, 0.175), y_levels=levels, n_x=41)
    x0 = region.design[0]
    spec = StudySpec("nose_gear", "grid", (("l_sp1", GridAxis(-0.175, 0.175, 36)), ("LU", GridAxis(1.25, 1.35, 6))))
    cols = run_chunk(s, spec, 0)
    import pandas as pd

    df = pd.DataFrame(cols)
    df.attrs["grid_shape"] = spec.grid_shape
    F = grid_values(df, "downlock_force")
    at_design = run_chunk(s, StudySpec("nose_gear", "grid", (("l_sp1", GridAxis(x0, x0, 1)),
                                                             ("LU", GridAxis(1.25, 1.35, 6)))), 0)
    for row, f in zip(region.rows, at_design["downlock_force"]):
        assert f == pytest.approx(row.force_at_design, rel=1e-9, abs=1e-9)
    x = spec.parameters[0][1].values()
    for j, row in enumerate(region.rows):
        assert row.level == pytest.approx(levels[j], abs=1e-15)
        inside = np.array([any(a < v < b for a, b in row.locking_intervals) for v in x])
        near = np.array([min((abs(v - e) for iv in row.locking_intervals for e in iv), default=1.0) < 1e-9 for v in x])
        assert np.array_equal((F[:, j] > 0)[~near], inside[~near]), row
    assert region.boundary is not None
    # the design map's F = 0 curve: LU on it, at each crossing l_sp1, sits between grid levels of opposite sign
    from scipy.interpolate import RegularGridInterpolator

    interp = RegularGridInterpolator((x, levels), F)
    b = region.boundary
    on = np.column_stack([b["l_sp1"], b["LU"]])
    assert np.max(np.abs(interp(on))) < 0.02 * np.max(np.abs(F))


def test_spec_file_is_data_with_whitelisted_keys(tmp_path):
    """A TOML study file gives the same study as the options; unknown keys and non-numbers are one line."""
    spec = tmp_path / "study.toml"
    spec.write_text('sampling = "lhs"\nn = 40\nseed = 2\n[parameters]\nLU = "normal:1.3:0.01"\n'
                    'l_sp1 = { distribution = "uniform", low = 0.05, high = 0.15 }\n[set]\nk = 25000\n')
    r = run("study", "nose_gear", "--spec", spec, "--out", tmp_path / "a", "--scheduler", "serial")
    assert r.exit_code == 0, r.output
    r2 = run("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--dist", "l_sp1=uniform:0.05:0.15", "--sample", "lhs",
             "--n", "40", "--seed", "2", "--set", "k=25000", "--out", tmp_path / "b", "--scheduler", "serial")
    assert r2.exit_code == 0, r2.output
    assert read_results(tmp_path / "a" / "results.parquet").equals(read_results(tmp_path / "b" / "results.parquet"))
    for text, words in [('sampling = "mc"\nn = 4\nimport = "os"\n[parameters]\nLU = "normal:1.3:0.01"\n',
                         ["study.toml.import", "unknown key"]),
                        ('sampling = "mc"\nn = 4\n[parameters]\nLU = "normal:__import__(\'os\'):0.01"\n',
                         ["study.toml.parameters.LU", "not a number"]),
                        ('sampling = "mc"\nn = 4\n[parameters]\nLU = { distribution = "normal", mean = 1.3 }\n',
                         ["study.toml.parameters.LU.sd", "not a number"])]:
        spec.write_text(text)
        one_line_error(run("study", "nose_gear", "--spec", spec, "--out", tmp_path / "c", "--scheduler", "serial"), *words)
    assert not (tmp_path / "c").exists()
    one_line_error(run("study", "nose_gear", "--grid", "LU=1.2:1.4:2", "--grid", "k=1e4:2e4:2", "--grid", "L4=0.3:0.4:2",
                       "--plot", tmp_path / "p.png", "--out", tmp_path / "d"), "--plot", "no figure")
    assert not (tmp_path / "d").exists()
