"""Branch tables carry units (CSV headers, JSON map, DataFrame attrs), folds are 'fold', and the
special points are numbered alike in every output."""

import csv
import json
import math

import numpy as np
import pytest

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium, read_branch_table
from mechcont.continuation._branch import read_csv_header, unit_header
from mechcont.errors import InputError
from mechcont.models import build_overcentre
from mechcont.outputs.animation import branch_frames


@pytest.fixture(scope="module")
def overcentre():
    return build_overcentre(LU=0.4)


@pytest.fixture(scope="module")
def branch(overcentre):
    x0 = find_equilibrium(overcentre, hold={"theta1": 0.3}, free=["F"])
    return continuation(overcentre, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}))


def test_csv_headers_carry_units_and_read_back(tmp_path, overcentre, branch):
    path = branch.to_csv(tmp_path / "b.csv")
    header = path.read_text().splitlines()[0].split(",")
    assert header[:3] == ["x1 [m]", "y1 [m]", "theta1 [rad]"]
    assert "F [N]" in header and "k [N/m]" in header and "m1 [kg]" in header
    assert header[-5:] == ["s", "stability", "n_unstable", "label", "vary"]  # dimensionless: bare names
    rows, units = read_branch_table(path)
    assert units == {n: u for n, u in branch.units.items() if u}
    assert [float(r["F"]) for r in rows] == branch["F"].tolist()  # full precision, SI values
    frames = branch_frames(overcentre, path)  # the reader of draw/animate
    np.testing.assert_array_equal(frames.values, branch.values)
    assert frames.vary == "F"


def test_old_tables_without_units_still_read(tmp_path, overcentre, branch):
    path = tmp_path / "old.csv"
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([*branch.names, "s", "stability", "label"])
        for row, st, lab in zip(branch.values, branch.stability_labels(), branch.labels):
            w.writerow([*map(repr, row.tolist()), 0.0, "stable" if st == "fold" else st, lab])
    frames = branch_frames(overcentre, path)
    np.testing.assert_array_equal(frames.values, branch.values)
    rows, units = read_branch_table(path)
    assert units == {} and float(rows[0]["F"]) == branch["F"][0]


def test_angles_in_degrees_are_converted_and_wrong_units_refused(tmp_path, overcentre, branch):
    names = list(branch.names)
    i = names.index("theta1")
    deg = tmp_path / "deg.csv"
    with open(deg, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([unit_header(n, "deg" if n == "theta1" else branch.units[n]) for n in names])
        for row in branch.values:
            row = row.copy()
            row[i] = math.degrees(row[i])
            w.writerow(map(repr, row.tolist()))
    np.testing.assert_allclose(branch_frames(overcentre, deg).values, branch.values, rtol=1e-14, atol=1e-15)
    bad = tmp_path / "bad.csv"
    bad.write_text(deg.read_text().replace("F [N]", "F [kN]", 1))
    with pytest.raises(InputError, match=r"unit of F .* 'N', not 'kN'"):
        branch_frames(overcentre, bad)


def test_header_parsing():
    assert read_csv_header("F [N]") == ("F", "N")
    assert read_csv_header("c [N s/m]") == ("c", "N s/m")
    assert read_csv_header("label") == ("label", "")
    assert unit_header("s", "") == "s"


def test_a_fold_is_neither_stable_nor_unstable(branch):
    words = branch.stability_labels()
    assert [w for w, lab in zip(words, branch.labels) if lab == "LP"] == ["fold", "fold"]
    assert {w for w, lab in zip(words, branch.labels) if lab != "LP"} == {"stable", "unstable"}


def test_json_has_units_and_point_names(tmp_path, branch):
    doc = json.loads(branch.to_json(tmp_path / "b.json").read_text())
    assert doc["units"]["F"] == "N" and doc["units"]["theta1"] == "rad"
    assert [p["name"] for p in doc["special_points"]] == branch.point_names() == ["EP1", "LP1", "LP2", "EP2"]
    assert [p["values"]["F"] for p in doc["special_points"] if p["label"] == "LP"] == [
        branch["LP1"]["F"], branch["LP2"]["F"]]


def test_numbering_runs_along_the_arclength(branch):
    idx = [p.index for p in branch.special_points]
    assert idx == sorted(idx) and np.all(np.diff(branch.s) > 0)
    # LP1 is the first fold met from the first row, in the CSV row order too
    lp_rows = [i for i, lab in enumerate(branch.labels) if lab == "LP"]
    assert [branch["LP1"].index, branch["LP2"].index] == lp_rows


def test_frame_has_units(branch):
    pd = pytest.importorskip("pandas")
    frame = branch.to_frame()
    assert isinstance(frame, pd.DataFrame) and len(frame) == len(branch)
    assert frame.attrs["units"]["F"] == "N" and frame.attrs["units"]["theta1"] == "rad"
    assert frame.attrs["vary"] == "F"
    assert frame.attrs["special_points"] == {"EP1": 0, "LP1": branch["LP1"].index, "LP2": branch["LP2"].index,
                                             "EP2": len(branch) - 1}
    assert frame["stability"][branch["LP1"].index] == "fold"


def test_a_written_branch_reads_back(tmp_path, branch):
    from mechcont.continuation import Branch

    b = Branch.read_csv(branch.to_csv(tmp_path / "b.csv"))
    np.testing.assert_array_equal(b.values, branch.values)
    np.testing.assert_array_equal(b.s, branch.s)
    assert b.names == branch.names and b.vary == "F" and b.units == {n: u for n, u in branch.units.items() if u}
    assert b.point_names() == branch.point_names() and b["LP2"]["F"] == branch["LP2"]["F"]
    assert b.stability_labels() == branch.stability_labels()


def test_one_numbering_in_every_output(tmp_path):
    """LP2 is the same fold in the CLI table, the CSV rows, the JSON, the plot labels and `folds --fold 2`;
    the table shows angles in degrees with the unit in the heading."""
    from cli_helpers import make_runner

    from mechcont.continuation import Branch
    from mechcont.outputs.plotting import new_figure, plot_branch

    run = make_runner()
    args = ("overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--bounds", "theta1=-1.2:1.2")
    r = run("continue", *args, "--out", tmp_path / "b.csv")
    assert r.exit_code == 0, r.output
    assert run("continue", *args, "--out", tmp_path / "b.json", "--quiet").exit_code == 0
    head, *rows = [ln.split() for ln in r.output.splitlines()[1:5]]
    assert head == ["point", "F", "(N)", "theta1", "(deg)", "stability"]
    table = {row[0]: (float(row[1]), float(row[2]), row[3]) for row in rows}
    b = Branch.read_csv(tmp_path / "b.csv")
    doc = json.loads((tmp_path / "b.json").read_text())
    from_json = {p["name"]: p["values"] for p in doc["special_points"]}
    lp_rows = [i for i, lab in enumerate(b.labels) if lab == "LP"]
    for k, name in enumerate(("LP1", "LP2")):
        F, th = b[name]["F"], b[name]["theta1"]
        assert b[name].index == lp_rows[k]
        assert table[name] == (pytest.approx(F, rel=1e-9), pytest.approx(math.degrees(th), rel=1e-9), "fold")
        assert from_json[name]["F"] == F
    _, ax = new_figure()
    plot_branch(b, "F", "theta1", ax=ax)
    labels = {t.get_text(): t.xy for t in ax.texts}
    assert set(labels) == {"LP1", "LP2"}
    for name in ("LP1", "LP2"):
        assert labels[name] == pytest.approx((b[name]["F"], math.degrees(b[name]["theta1"])))
    # `folds --fold 2` continues that same LP2 (the curve starts there, at LU = 0.4 m)
    r = run("folds", *args[:-2], "--along", "LU", "--bounds", "LU=0.1:2", "--fold", "2", "--out", tmp_path / "f.csv")
    assert r.exit_code == 0, r.output
    assert "continuing LP2 (--fold 2)" in r.output
    curve = Branch.read_csv(tmp_path / "f.csv")
    i0 = int(np.argmin(np.abs(curve.s)))
    assert curve["F"][i0] == pytest.approx(b["LP2"]["F"], rel=1e-9) and curve["LU"][i0] == pytest.approx(0.4)
    bad = run("folds", *args[:-2], "--along", "LU", "--bounds", "LU=0.1:2", "--fold", "3")
    assert bad.exit_code == 2 and "LP1 at F = " in bad.stderr and "LP2 at F = " in bad.stderr


def test_special_point_repr_is_readable():
    """``folds["CP1"]`` at the prompt: label, row, status and named values, not raw arrays."""
    from mechcont.continuation import SpecialPoint

    p = SpecialPoint("CP", 35, np.array([1.5, 9.81, -1.2e-13]), ("LU", "F", "theta1"), tangent=np.ones(3),
                     info={"null_vector": np.ones(3)})
    text = repr(p)
    assert text == "SpecialPoint(CP at row 35, located: LU=1.5, F=9.81, theta1=-1.2e-13)"
    big = SpecialPoint("LP", 2, np.arange(100.0), tuple(f"q{i}" for i in range(100)), info={"status": "approximate"})
    text = repr(big)
    assert text.startswith("SpecialPoint(LP? at row 2, approximate: q0=0, q1=1,") and "q59=59, ... (40 more" in text
    assert "array" not in text
