"""The command line: continue, folds, models; bad input -> one line on stderr, exit 2, nothing written."""

import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.continuation import read_branch_table
from mechcont.models.overcentre import symmetric_folds


@pytest.fixture(scope="module")
def run():
    return make_runner()


def test_continue_writes_csv_with_labels_and_stability(tmp_path, run):
    out, fig = tmp_path / "b.csv", tmp_path / "b.png"
    r = run("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
            "--bounds", "theta1=-1.2:1.2", "--out", out, "--plot", fig)
    assert r.exit_code == 0, r.output
    rows, units = read_branch_table(out)
    assert {"theta1", "F", "s", "stability", "label"} <= set(rows[0])
    assert units["theta1"] == "rad" and units["F"] == "N" and "s" not in units
    assert out.read_text().startswith("x1 [m],y1 [m],theta1 [rad],")
    # a fold is neutral: its row says "fold", every other row stable or unstable
    assert {r["stability"] for r in rows if r["label"] != "LP"} == {"stable", "unstable"}
    assert [r["stability"] for r in rows if r["label"] == "LP"] == ["fold", "fold"]
    lps = sorted((float(r["theta1"]), float(r["F"])) for r in rows if r["label"] == "LP")
    for (th, F), (th0, F0) in zip(lps, symmetric_folds(1.5, 1, 1, 9.81, 127, 0.4)):
        assert th == pytest.approx(th0, rel=1e-10) and F == pytest.approx(F0, rel=1e-10)
    assert [r["label"] for r in rows].count("EP") == 2
    assert fig.read_bytes().startswith(b"\x89PNG")
    assert "LP1" in r.output


def test_continue_json(tmp_path, run):
    import json

    out = tmp_path / "b.json"
    r = run("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--bounds", "theta1=-1:1", "--out", out,
            "--quiet")
    assert r.exit_code == 0 and r.output == ""
    doc = json.loads(out.read_text())
    assert doc["vary"] == "F" and len(doc["columns"]["F"]) == len(doc["labels"])


def test_folds_command_finds_the_cusp(tmp_path, run):
    out = tmp_path / "f.csv"
    r = run("folds", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--along", "LU",
            "--bounds", "LU=0.1:2", "--out", out)
    assert r.exit_code == 0, r.output
    rows = read_branch_table(out)[0]
    (cp,) = [r for r in rows if r["label"] == "CP"]
    assert float(cp["LU"]) == pytest.approx(1.5, rel=1e-9)


def test_folds_command_names_a_runaway_first_branch(tmp_path, run):
    # no bounds on the branch in F: it runs to max_steps, and the command says which variable ran away
    r = run("folds", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--along", "LU",
            "--bounds", "LU=0.1:2", "--max-steps", "400", "--out", tmp_path / "f.csv")
    assert r.exit_code == 0, r.output
    (line,) = [ln for ln in r.output.splitlines() if ln.startswith("ends of the branch in F:")]
    assert "max_steps=400" in line and "may grow without bound" in line and "--bounds" in line


def test_models_lists_parameters(run):
    r = run("models", "overcentre")
    assert r.exit_code == 0
    assert "LU" in r.output and "unstrained spring length" in r.output


def test_models_says_each_size_once_and_describes_every_parameter(run):
    r = run("models", "overcentre", "nose_gear", "dual_sidestay_kinematics")
    assert r.exit_code == 0, r.output
    heads = [ln for ln in r.output.splitlines() if not ln.startswith(" ")]
    assert len(heads) == 3
    for head in heads:  # "overcentre: ... (6 equations)": the size once, not also in the description
        assert head.count("equations") == 1 and head.count("states") == 0, head
    params = [ln.split() for ln in r.output.splitlines() if ln.startswith("    ")]
    geometry = [p for p in params if p[0].startswith(("fwd_", "aft_"))]
    assert len(geometry) == 32  # 2 sidestays x (A, n, B0, P0 vectors + 4 lengths)
    for p in geometry:
        text = " ".join(p)
        assert ("forward sidestay:" in text) == p[0].startswith("fwd_") and "sidestay:" in text, text
        assert "geometry" not in text, text


@pytest.mark.parametrize("args, words", [
    (("continue", "overcentre", "--set", "LU=abc", "--start", "theta1=0.3", "--vary", "F"), ("LU", "not a number")),
    (("continue", "overcentre", "--set", "LU", "--start", "theta1=0.3", "--vary", "F"), ("--set", "NAME=VALUE")),
    (("continue", "overcentre", "--start", "theta1=0.3", "--vary", "Q"), ("Q", "unknown variable")),
    (("continue", "overcentre", "--set", "ZZ=1", "--start", "theta1=0.3", "--vary", "F"), ("ZZ", "unknown variable")),
    (("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--bounds", "F=3:1"), ("inverted",)),
    (("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--bounds", "F=2:2"), ("inverted",)),
    (("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--bounds", "F"), ("NAME=LO:HI",)),
    (("continue", "overcentre", "--start", "theta1=7", "--set", "L2=0.5", "--vary", "F"), ("did not converge",)),
    (("continue", "overcentre", "--start", "theta1=0.3"), ("--vary",)),
    (("continue", "nomodel", "--vary", "F"), ("unknown model",)),
    (("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--ds", "-1"), ("ds",)),
    (("folds", "overcentre", "--set", "LU=2", "--start", "theta1=0.3", "--vary", "F", "--along", "LU",
      "--bounds", "theta1=-1:1"), ("no fold",)),
])
def test_bad_input_one_line_exit_2(tmp_path, run, args, words):
    out = tmp_path / "x.csv"
    one_line_error(run(*args, "--out", out), *words)
    assert not out.exists()


def test_bad_output_suffix_writes_nothing(tmp_path, run):
    r = run("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--bounds", "theta1=-1:1",
            "--out", tmp_path / "b.csv", "--plot", tmp_path / "b.bmp")
    one_line_error(r, "--plot", ".png")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, words", [
    (("continue", "fourbar.toml", "--set", "a=-0.3", "--start", "theta_crank=1.0", "--vary", "T"),
     ("bodies.crank.length", "positive")),
    (("downlock", "nose_gear.toml", "--hold", "theta4=0", "--vary", "U", "--bounds", "U=0:100", "--set", "m4=-1"),
     ("mass", "positive")),
])
def test_impossible_values_of_a_described_mechanism_are_refused(tmp_path, run, args, words):
    out = tmp_path / "x.csv"
    one_line_error(run(*args, "--out", out), *words)
    assert not out.exists()


def test_branch_csv_records_the_continuation_parameter(tmp_path, run):
    # vary a state (theta1) and solve for a parameter (F): the CSV must say which was continued
    out = tmp_path / "b.csv"
    r = run("continue", "overcentre", "--set", "LU=0.4", "--vary", "theta1", "--free", "F",
            "--bounds", "theta1=-1:1", "--out", out)
    assert r.exit_code == 0, r.output
    rows = read_branch_table(out)[0]
    assert {row["vary"] for row in rows} == {"theta1"}
    from mechcont.models import load_model
    from mechcont.outputs.animation import branch_frames

    assert branch_frames(load_model("overcentre"), out).vary == "theta1"
