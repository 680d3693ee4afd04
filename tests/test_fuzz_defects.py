"""Defects a fuzz campaign found (issue 20): each silently wrong result, traceback or hang is now a
one-line error (exit 2), a reported finding, or a verified recomputation."""

import shutil
import time
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.mechanism import find_description

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


# -- description values that were accepted and gave wrong results -------------------------------
DATA = Path(__file__).parent / "data"
PENDULUM_STOP_3D = (DATA / "spatial" / "pendulum_stop_3d.toml").read_text()
PENDULUM_STOP = (DATA / "pendulum_stop.toml").read_text()


def _file(tmp_path, text, name="m.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("normal", ["[nan, 0, 0]", "[inf, 0, 0]", "[1e308, 1e308, 0]", "[1e-320, 0, 0]",
                                    "[-inf, 1, 0]"])
def test_spatial_collinear_normal_must_be_finite_and_normalisable(tmp_path, normal):
    cond = f'col = {{ type = "collinear", points = ["ground.O", "bar.a", "bar.b"], normal = {normal} }}\n'
    text = PENDULUM_STOP_3D.replace("[conditions]\n", "[conditions]\n" + cond, 1)
    clean_failure(run("equations", _file(tmp_path, text)), "conditions.col.normal", "finite direction")


def test_spatial_collinear_normal_of_ordinary_length_is_accepted(tmp_path):
    cond = 'col = { type = "collinear", points = ["ground.O", "bar.a", "bar.b"], normal = [0, 1e-3, 0] }\n'
    text = PENDULUM_STOP_3D.replace("[conditions]\n", "[conditions]\n" + cond, 1)
    r = run("equations", _file(tmp_path, text))
    assert r.exit_code == 0, r.output


def test_a_held_coordinate_is_the_value_solved_or_refused(tmp_path):
    """`hold = { x_crank = 50 }` of a crank 0.2 m long pinned at the origin: refused (it used to be
    moved to 0.07 m by the placement of the crank and reported as held)."""
    text = find_description("slidercrank").read_text().replace("hold = { theta_crank = 0.8 }", "hold = { x_crank = 50 }")
    clean_failure(run("check", _file(tmp_path, text)), "cannot close", "x_crank = 50")
    # a reachable held x: assembled with x_crank at that value (r cos(theta) = 0.1 with r = 0.2)
    text = text.replace("x_crank = 50", "x_crank = 0.1")
    from mechcont.mechanism import load_description

    system = load_description(_file(tmp_path, text, "ok.toml")).build()
    assert system.vector()[system.index("x_crank")] == pytest.approx(0.1, abs=1e-12)


def test_min_stop_above_max_stop_is_refused(tmp_path):
    text = PENDULUM_STOP + '\n[stops.top]\ncondition = "angle"\nmax = -1.3\n'
    clean_failure(run("equations", _file(tmp_path, text)), "stops.top.max", "-1.3 is below min = -1.2", "rest")
    ok = PENDULUM_STOP + '\n[stops.top]\ncondition = "angle"\nmax = 1.3\n'
    assert run("equations", _file(tmp_path, ok, "ok.toml")).exit_code == 0


@pytest.mark.parametrize("inertia, words", [
    ("[1, 1, 1, 10, 0, 0]", ("not positive definite",)),
    ("[1, 1, 100]", ("triangle inequality",)),
    ("[1, 2, 3.5, 0.1, 0, 0]", ("triangle inequality",)),
])
def test_spatial_inertia_must_be_a_real_bodys(tmp_path, inertia, words):
    text = PENDULUM_STOP_3D.replace("inertia = [0.01, 0.1, 0.1]", f"inertia = {inertia}", 1)
    clean_failure(run("equations", _file(tmp_path, text)), "bodies.bar.inertia", *words)


@pytest.mark.parametrize("inertia", ["[1, 1, 2]", "[2, 3, 4, 0.5, -0.2, 0.1]", "[0.01, 0.1, 0.1]"])
def test_spatial_inertia_of_real_bodies_is_accepted(tmp_path, inertia):
    text = PENDULUM_STOP_3D.replace("inertia = [0.01, 0.1, 0.1]", f"inertia = {inertia}", 1)
    assert run("equations", _file(tmp_path, text)).exit_code == 0


@pytest.mark.parametrize("value, name", [("fwd_L1=-1.15", "fwd_L1"), ("aft_L5=0", "aft_L5"), ("fwd_L2=-0.9", "fwd_L2")])
def test_dual_sidestay_kinematics_refuses_non_physical_lengths(tmp_path, value, name):
    clean_failure(run("draw", "dual_sidestay_kinematics", "--set", value, "--out", tmp_path / "d.png"),
                  name, "length (m) must be positive")
    assert list(tmp_path.iterdir()) == []


def test_dual_sidestay_kinematics_refuses_a_zero_plane_normal(tmp_path):
    args = [a for c in "xyz" for a in ("--set", f"fwd_n_{c}=0")]
    clean_failure(run("draw", "dual_sidestay_kinematics", *args, "--out", tmp_path / "d.png"), "fwd_n", "positive")


SWEEP = ("sweep", "overcentre", "--set", "LU=0.4", "--set", "c=50", "--start", "theta1=1.2", "--watch", "theta1",
         "--no-progress", "--ramp", "F=-65:-90:0.5")


@pytest.mark.parametrize("rtol", ["1e300", "1", "0.5", "1e-20"])
def test_sweep_rtol_outside_a_sensible_range(tmp_path, rtol):
    clean_failure(run(*SWEEP, "--rtol", rtol, "--out", tmp_path / "s.csv"), "rtol", "between 1e-13 and 0.1")
    assert list(tmp_path.iterdir()) == []


def test_max_steps_is_capped_with_the_valid_range(tmp_path):
    t0 = time.perf_counter()
    clean_failure(run("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--max-steps",
                      "999999999999", "--out", tmp_path / "b.csv"), "--max-steps", "1..100000")
    assert time.perf_counter() - t0 < 20 and list(tmp_path.iterdir()) == []


def test_check_without_an_equilibrium_has_a_finding_and_exit_1(tmp_path):
    """A moment of 100 N m on a pendulum whose gravity moment is at most m g L / 2 = 9.81 N m: no equilibrium."""
    text = PENDULUM_STOP.split("[conditions]")[0]  # no stops: the free mechanism
    r = run("check", _file(tmp_path, text), "--set", "T=100")
    assert r.exit_code == 1, r.output
    assert "findings: none" not in r.output and "no equilibrium found at these parameter values" in r.output
    assert run("check", _file(tmp_path, text, "ok.toml"), "--set", "T=5").exit_code == 0  # 5 < 9.81: one exists


def test_check_without_a_consistent_stop_set_has_a_finding(tmp_path):
    path = _file(tmp_path, PENDULUM_STOP)
    r = run("check", path, "--set", "T=100", "--quiet")
    assert r.exit_code == 1 and "finding: no equilibrium with a consistent set of stops in contact" in r.stderr
    # pushed onto its stop (clockwise), the pendulum rests there: no free equilibrium, but one on the stop
    r = run("check", path, "--set", "T=-100")
    assert r.exit_code == 0 and "findings: none" in r.output and "in contact" in r.output, r.output


@pytest.mark.parametrize("text, words", [
    (PENDULUM_STOP.replace("[conditions]\n", '[conditions]\nd = { type = "distance", points = ["ground.O", "bar.a"] }\n'),
     ("conditions.d", "ground.O and bar.a coincide")),
    (PENDULUM_STOP_3D.replace("[conditions]\n", '[conditions]\nd = { type = "distance", points = ["ground.O", "bar.a"] }\n'),
     ("conditions.d", "ground.O and bar.a coincide")),
])
def test_distance_between_two_pinned_points(tmp_path, text, words):
    clean_failure(run("check", _file(tmp_path, text)), *words)


# -- tracebacks ---------------------------------------------------------------------------------
BIG = "1" + "0" * 4400  # Python refuses to convert integers of more than 4300 digits
OVERCENTRE = find_description("overcentre").read_text()


def test_a_4401_digit_integer_in_a_description(tmp_path):
    path = _file(tmp_path, OVERCENTRE.replace("k = { value = 127.0", "k = { value = " + BIG, 1))
    clean_failure(run("equations", path), "m.toml", "4401 digits")


STUDY_FILES = {
    "4401-digit integer": (f'sampling = "mc"\nn = {BIG}\n[parameters]\nLU = "normal:1.3:0.01"\n', ("4401 digits",)),
    "5000-deep array": ('sampling = "mc"\nn = 5\nanalyses = ' + "[" * 5000 + "]" * 5000
                        + '\n[parameters]\nLU = "normal:1.3:0.01"\n', ("nested too deeply",)),
    "binary file": (bytes(range(256)) * 10, ("not a text file",)),
    "10 GiB chunk": ('sampling = "mc"\nn = 10000000\nchunk = 1000000\n[parameters]\nLU = "normal:1.3:0.01"\n',
                     ("chunk", "GiB", "give at most")),
    "10^10-point grid": ('sampling = "grid"\n[parameters]\nLU = "1.2:1.4:100000"\nU = "0:100:100000"\n',
                         ("grid", "10000000000 points", "at most 10000000")),
    "20-axis grid (int64 overflow)": ('sampling = "grid"\n[parameters]\n' + "".join(f'p{i} = "0:1:100000"\n' for i in range(20)),
                                      ("grid", "at most 10000000")),
    "n = inf": ('sampling = "mc"\nn = inf\n[parameters]\nLU = "normal:1.3:0.01"\n', ("n", "whole number")),
    "chunk = nan": ('sampling = "mc"\nn = 5\nchunk = nan\n[parameters]\nLU = "normal:1.3:0.01"\n', ("chunk", "whole number")),
}


@pytest.mark.parametrize("case", list(STUDY_FILES))
def test_bad_study_spec_files(tmp_path, case):
    text, words = STUDY_FILES[case]
    spec = tmp_path / "spec.toml"
    spec.write_bytes(text) if isinstance(text, bytes) else spec.write_text(text)
    t0 = time.perf_counter()
    clean_failure(run("study", "nose_gear", "--spec", spec, "--out", tmp_path / "s", "--scheduler", "serial"), *words)
    assert time.perf_counter() - t0 < 30  # decided from the sizes, before any work
    assert not (tmp_path / "s").exists()


def test_a_huge_grid_on_the_command_line_is_refused_at_once(tmp_path):
    t0 = time.perf_counter()
    clean_failure(run("study", "nose_gear", "--grid", "LU=1.2:1.4:100000", "--grid", "U=0:100:100000", "--out",
                      tmp_path / "s", "--scheduler", "serial"), "10000000000 points")
    assert time.perf_counter() - t0 < 30 and not (tmp_path / "s").exists()


def test_rotation_vector_beyond_a_turn(tmp_path):
    text = (DATA / "spatial" / "pendulum_3d.toml").read_text()
    text = text.replace("rotation = [0, 0.8, 0]", "rotation = [0, 0, 1e308]", 1)
    clean_failure(run("check", _file(tmp_path, text)), "bodies.bar.initial.rotation", "at most 2 pi")


@pytest.fixture(scope="module")
def overcentre_branch(tmp_path_factory):
    out = tmp_path_factory.mktemp("branch") / "b.csv"
    r = run("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--bounds", "theta1=-1.2:1.2", "--out", out,
            "--quiet")
    assert r.exit_code == 0, r.output
    return out


def _edited_csv(src, tmp_path, row, column, value, name="e.csv"):
    import csv

    rows = list(csv.reader(src.open()))
    rows[row + 1][rows[0].index(column)] = value
    path = tmp_path / name
    with path.open("w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    return path


def test_draw_a_branch_cell_of_1e308(tmp_path, overcentre_branch):
    csv_path = _edited_csv(overcentre_branch, tmp_path, 2, "y1 [m]", "1e308")
    r = run("draw", "overcentre", "--point", f"{csv_path}:2", "--out", tmp_path / "p.png")
    clean_failure(r, "configuration", "beyond any mechanism")
    assert "RuntimeWarning" not in r.stderr and not (tmp_path / "p.png").exists()


@pytest.mark.parametrize("address", ["tls://127.0.0.1:1", "ucx://127.0.0.1:1", "inproc://x", "nonsense"])
def test_scheduler_addresses_other_than_tcp(tmp_path, address):
    clean_failure(run(*STUDY, "--scheduler", address, "--out", tmp_path / "s"), "--scheduler")
    assert not (tmp_path / "s").exists()


def test_a_scheduler_that_accepts_and_never_answers(tmp_path, monkeypatch):
    """A loopback listener that accepts the connection and says nothing: the timeout fires."""
    import socket
    import threading

    from mechcont.analysis.study import _dask

    monkeypatch.setattr(_dask, "SCHEDULER_TIMEOUT", 2.0)
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)
    server.settimeout(60)
    accepted = []

    def accept():
        try:
            accepted.append(server.accept()[0])
        except OSError:
            pass

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    try:
        t0 = time.perf_counter()
        r = run("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--n", "30", "--chunk", "10", "--quiet",
                "--scheduler", f"tcp://127.0.0.1:{server.getsockname()[1]}", "--out", tmp_path / "s")
        elapsed = time.perf_counter() - t0
    finally:
        server.close()
        for c in accepted:
            c.close()
        thread.join(5)
    clean_failure(r, "--scheduler", "did not answer within 2 s")
    assert accepted and elapsed < 30
    assert not (tmp_path / "s").exists()


def test_sweep_ramp_to_1e308_is_refused_at_once(tmp_path):
    t0 = time.perf_counter()
    r = run("sweep", "overcentre", "--set", "LU=0.4", "--set", "c=50", "--start", "theta1=1.2", "--watch", "theta1",
            "--no-progress", "--ramp", "F=0:1e308:1e308", "--out", tmp_path / "s.csv")
    clean_failure(r, "ramp", "F: 0 -> 1e+308", "times its scale")
    assert time.perf_counter() - t0 < 20 and list(tmp_path.iterdir()) == []


# -- minor ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("args", [
    ("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--free", "theta2", "--quiet"),
    ("draw", "overcentre", "--start", "theta1=0.3", "--free", "theta2"),
])
def test_free_a_state_is_refused(tmp_path, args):
    clean_failure(run(*args, "--out", tmp_path / ("b.csv" if args[0] == "continue" else "p.png")),
                  "--free", "theta2 is a state", "free a parameter")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("only", [",", " , ,", ""])
def test_paper_only_naming_no_section(tmp_path, only):
    clean_failure(run("paper", "--only", only, "--out", tmp_path / "p"), "--only", "names no section", "overcentre")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["lambda", "if", "None", "class"])
def test_parameter_named_by_a_python_keyword(tmp_path, name):
    path = _file(tmp_path, OVERCENTRE.replace("[parameters]\n", f"[parameters]\n{name} = 1.0\n", 1))
    clean_failure(run("equations", path), f"parameters.{name}", "Python keyword")


def test_text_from_a_description_cannot_forge_lines_or_drive_the_terminal(tmp_path):
    text = OVERCENTRE.replace('name = "overcentre_generated"', 'name = "evil\\nfindings: none\\u001b[2J"', 1)
    text = text.replace('description = "Overcentre mechanism generated from its description (paper Fig. 2)"',
                        'description = "a\\u001b]0;pwned\\u0007b\\rc"', 1)
    text = text.replace("[parameters]\n", '[parameters]\nzz = { value = 1.0, description = "x\\nforged: yes\\u001b[31m" }\n', 1)
    r = run("check", _file(tmp_path, text))
    assert r.exit_code == 0, r.output
    assert "\x1b" not in r.output and "\x07" not in r.output and "\r" not in r.output
    lines = r.output.splitlines()
    assert lines[0].startswith("mechanism evil\\nfindings: none\\x1b[2J")
    assert lines[1] == "  a\\x1b]0;pwned\\x07b\\rc"
    assert not any(ln.startswith(("forged", "findings: none\\")) for ln in lines)
    assert [ln for ln in lines if ln.startswith("findings")] == ["findings: none"]


@pytest.mark.parametrize("column, value, words", [
    ("n_unstable", "-5", ("column n_unstable", "'-5'")),
    ("n_unstable", "1.5", ("column n_unstable",)),
    ("s", "nan", ("column s", "not a finite number")),
    ("s", "inf", ("column s",)),
])
def test_animate_refuses_a_bad_branch_cell(tmp_path, overcentre_branch, column, value, words):
    csv_path = _edited_csv(overcentre_branch, tmp_path, 1, column, value)
    clean_failure(run("animate", "overcentre", "--branch", csv_path, "--out", tmp_path / "a.gif", "--no-progress"),
                  "branch", "line 3", *words)
    assert not (tmp_path / "a.gif").exists()


def test_animate_refuses_duplicated_columns(tmp_path, overcentre_branch):
    lines = overcentre_branch.read_text().splitlines()
    lines = [ln + "," + ln.split(",")[2] for ln in lines]  # theta1 [rad] once more, other values or not
    path = tmp_path / "d.csv"
    path.write_text("\n".join(lines) + "\n")
    clean_failure(run("animate", "overcentre", "--branch", path, "--out", tmp_path / "a.gif", "--no-progress"),
                  "branch", "more than once", "theta1 [rad]")
    assert not (tmp_path / "a.gif").exists()


def test_the_scheduler_probe_accepts_a_real_dask_scheduler():
    """The handshake probe that bounds the wait must let a real scheduler through at once."""
    distributed = pytest.importorskip("dask.distributed")
    from mechcont.analysis.study._dask import _probe_scheduler

    with distributed.LocalCluster(n_workers=0, processes=True, dashboard_address=None, silence_logs=50) as cluster:
        assert cluster.scheduler_address.startswith("tcp://")
        t0 = time.perf_counter()
        _probe_scheduler(cluster.scheduler_address)
        assert time.perf_counter() - t0 < 5
