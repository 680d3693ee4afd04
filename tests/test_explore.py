"""The branch explorer page (mechcont explore): the poses it embeds, its special points, no network, bad input."""

from __future__ import annotations

import html
import json
import re
import sys

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.continuation import Branch
from mechcont.models import load_model
from mechcont.outputs.explore import explore_page, page_data

run = make_runner()

OVERCENTRE = ("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
              "--bounds", "F=-100:120")
FOLDS = ("folds", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--along", "LU",
         "--bounds", "F=-200:200", "--bounds", "LU=0.1:2")
DOWNLOCK = ("downlock", "nose_gear", "--vary", "l_sp1", "--bounds", "l_sp1=-0.175:0.175")
RETRACTION = ("continue", "dual_sidestay_kinematics", "--vary", "theta", "--bounds", "theta=0:1.5")
SWEEP = ("sweep", "overcentre", "--set", "LU=0.4", "--set", "c=50", "--start", "theta1=1.2", "--ramp", "F=-65:-90:1",
         "--ramp", "F=-90:110:4", "--watch", "theta1", "--no-progress")


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    """The four branches the explorer must show and a time history, as CSV files."""
    d = tmp_path_factory.mktemp("explore")
    out = {}
    for key, args in (("overcentre", OVERCENTRE), ("folds", FOLDS), ("downlock", DOWNLOCK),
                      ("retraction", RETRACTION), ("sweep", SWEEP)):
        path = d / f"{key}.csv"
        result = run(*args, "--out", path)
        assert result.exit_code == 0, result.output
        out[key] = path
    return out


def _embedded(page: str) -> dict:
    m = re.search(r'<script type="application/json" class="mcx-data">(.*?)</script>', page, re.S)
    assert m is not None
    return json.loads(m.group(1))


def _same(a, b) -> None:
    """Pose items as embedded (nested lists) equal the scene's arrays to 1e-12 m (N, N m)."""
    np.testing.assert_allclose(np.asarray(a, float), np.asarray(b, float), rtol=0, atol=1e-12)


def _check_poses(system, branch: Branch, doc: dict, bodies: list[dict]) -> None:
    """Every embedded row's pose is the scene of the model at that table row, item by item."""
    names = [b["name"] for b in bodies]
    assert len(doc["poses"]) == len(doc["rows"])
    for pose, row in zip(doc["poses"], doc["rows"]):
        scene = system.scene(branch.values[row])
        assert [names[k] for k, _ in pose["bars"]] == [n for n, _ in scene.bars]
        for (_, got), (_, want) in zip(pose["bars"], scene.bars):
            _same(got, want)
        for key, items in (("pins", scene.pins), ("grounds", scene.grounds), ("anchors", scene.anchors)):
            assert len(pose[key]) == len(items)
            for got, want in zip(pose[key], items):
                _same(got, want)
        for key, items in (("springs", scene.springs), ("dampers", scene.dampers), ("slots", scene.slots),
                           ("forces", scene.forces),
                           ("actuators", scene.actuators), ("moments", scene.moments), ("axes", scene.joint_axes)):
            assert [it[0] for it in pose[key]] == [it[0] for it in items]
            for got, want in zip(pose[key], items):
                for g, w in zip(got[1:], want[1:]):
                    _same(g, w)


def test_overcentre_poses_are_the_model_points(tables):
    system = load_model("overcentre")
    branch = Branch.read_csv(tables["overcentre"])
    page = explore_page(system, [tables["overcentre"]])
    data = _embedded(page)
    doc = data["branches"][0]
    assert data["dim"] == 2 and doc["rows"] == list(range(len(branch)))
    _check_poses(system, branch, doc, data["bodies"])
    # independently of the scene code: each bar runs from centre - L/2 e to centre + L/2 e (the table's columns)
    for pose, row in zip(doc["poses"], doc["rows"]):
        v = dict(zip(branch.names, branch.values[row]))
        for k, (_, pts) in enumerate(pose["bars"], start=1):
            c, e = np.array([v[f"x{k}"], v[f"y{k}"]]), np.array([np.cos(v[f"theta{k}"]), np.sin(v[f"theta{k}"])])
            _same(pts, [c - v[f"L{k}"] / 2 * e, c + v[f"L{k}"] / 2 * e])
        _same(pose["forces"][0][2], [0.0, v["F"]])
    # colours are the PNG drawings' (drawing.body_colours)
    from mechcont.outputs.drawing import body_colours

    assert {b["name"]: b["colour"] for b in data["bodies"]} == body_colours([system.scene(branch.values[0])])


def test_a_pin_in_slot_joint_is_drawn_as_its_slot():
    """The quick-return mechanism's slot (tests/data/quick_return.toml, a pin-in-slot joint): embedded at
    every row where the model's scene puts it (the page's script draws each as a line of kind "slot")."""
    from pathlib import Path

    from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium

    system = load_model(Path(__file__).parent / "data" / "quick_return.toml")
    x0 = find_equilibrium(system, hold={"theta_crank": 0.5}, free=["Mc"])
    scales = {n: 10.0 for n in ("Mc", "R_O_x", "R_O_y", "R_C_x", "R_C_y", "R_slot")}
    branch = continuation(system, x0, "Mc", options=ContinuationOptions(bounds={"theta_crank": (0.0, 1.0)},
                                                                      scales=scales))
    page = explore_page(system, [branch])
    data = _embedded(page)
    doc = data["branches"][0]
    _check_poses(system, branch, doc, data["bodies"])
    assert all(len(pose["slots"]) == 1 for pose in doc["poses"])


def test_every_special_point_is_listed(tables):
    for key, model in (("overcentre", "overcentre"), ("folds", "overcentre"), ("downlock", "nose_gear"),
                       ("retraction", "dual_sidestay_kinematics")):
        branch = Branch.read_csv(tables[key])
        doc = page_data(model, [tables[key]])["branches"][0]
        assert [s["name"] for s in doc["special"]] == branch.point_names()
        assert [doc["rows"][s["row"]] for s in doc["special"]] == [p.index for p in branch.special_points]
        assert branch.point_names(), key
    labels = [s["name"] for s in page_data("overcentre", [tables["folds"]])["branches"][0]["special"]]
    assert "CP1" in labels


def test_spatial_and_planar_gears(tables):
    for key, model, dim in (("retraction", "dual_sidestay_kinematics", 3), ("downlock", "nose_gear", 2)):
        system = load_model(model)
        branch = Branch.read_csv(tables[key])
        data = page_data(system, [tables[key]])
        assert data["dim"] == dim
        assert set(data["views"]) == ({"front", "side", "top"} if dim == 3 else {"plane"})
        _check_poses(system, branch, data["branches"][0], data["bodies"])


def test_fold_curve_and_history_in_one_page(tables):
    system = load_model("overcentre")
    data = page_data(system, [tables["overcentre"], tables["sweep"]], max_rows=200)
    curve, history = data["branches"]
    assert "t" in history["columns"] and "theta1_dot" in history["columns"]
    sweep = Branch.read_csv(tables["sweep"])
    assert len(sweep) > 200 and len(history["rows"]) <= 200 + len(sweep.special_points) + 1
    assert "rows shown" in history["note"] and history["rows"][-1] == len(sweep) - 1
    assert {doc["rows"][s["row"]] for doc in (history,) for s in doc["special"]} == \
        {p.index for p in sweep.special_points}
    X = np.array([[sweep.column(n)[r] for n in system.names] for r in history["rows"]])
    for pose, x in zip(history["poses"], X):
        for (_, got), (_, want) in zip(pose["bars"], system.scene(x).bars):
            _same(got, want)
    folds = page_data(system, [tables["folds"]])["branches"][0]
    assert set(folds["n_unstable"]) == {-1}
    assert curve["n_unstable"].count(0) > 0 and max(curve["n_unstable"]) > 0


def test_page_is_offline_and_safe(tables):
    page = explore_page("overcentre", [tables["overcentre"], tables["folds"]], title="</script><b>x")
    assert not re.search(r"""(src|href)\s*=\s*["']?\s*(https?:)?//""", page, re.I)
    assert not re.search(r"url\(\s*['\"]?\s*(https?:)?//|@import|<link\b", page, re.I)
    assert "</script><b>" not in page
    assert page.count("</script>") == 2


def test_a_branch_in_jupyter_is_the_compact_page(tables, monkeypatch):
    """``import mechcont`` in IPython registers the page as every Branch's HTML view, by name."""
    import types

    import mechcont

    registered = {}

    class Formatter:
        def for_type_by_name(self, module, name, func):
            registered[(module, name)] = func

    shell = types.SimpleNamespace(display_formatter=types.SimpleNamespace(formatters={"text/html": Formatter()}))
    monkeypatch.setitem(sys.modules, "IPython", types.SimpleNamespace(get_ipython=lambda: shell))
    assert mechcont._register_notebook_view()
    view = registered[("mechcont.continuation._branch", "Branch")]
    assert (Branch.__module__, Branch.__name__) == ("mechcont.continuation._branch", "Branch")  # what it names
    branch = Branch.read_csv(tables["overcentre"], model="overcentre")
    text = view(branch)
    assert text.startswith("<iframe srcdoc=")
    inner = html.unescape(text.split('srcdoc="', 1)[1].split('" style=', 1)[0])
    data = _embedded(inner)
    assert data["compact"] is True and data["bodies"]  # the model loaded: the mechanism is drawn
    assert view(Branch.read_csv(tables["overcentre"])).startswith("<iframe")  # no model: the diagram alone
    monkeypatch.delitem(sys.modules, "IPython")
    assert not mechcont._register_notebook_view()  # outside IPython: nothing to register with


def test_cli_writes_the_page(tables, tmp_path):
    out = tmp_path / "page.html"
    result = run("explore", "nose_gear", "--branch", tables["downlock"], "--out", out)
    assert result.exit_code == 0, result.output
    assert _embedded(out.read_text())["branches"][0]["special"]


@pytest.mark.parametrize("args, words", [
    (("overcentre", "--branch", "missing.csv"), ("branch", "missing.csv")),
    (("nose_gear", "--branch", "{overcentre}"), ("lacks the column", "--set")),
    (("overcentre", "--branch", "{overcentre}", "--set", "nonsense=1"), ("nonsense",)),
    (("overcentre", "--branch", "{overcentre}", "--set", "F"), ("NAME=VALUE",)),
    (("no_such_model", "--branch", "{overcentre}"), ("model",)),
    (("overcentre", "--branch", "{overcentre}", "--max-rows", "1"), ("--max-rows",)),
])
def test_cli_bad_input_is_one_line_and_writes_nothing(tables, tmp_path, args, words):
    out = tmp_path / "page.html"
    args = [str(a).format(overcentre=tables["overcentre"]) for a in args]
    one_line_error(run("explore", *args, "--out", out), *words)
    assert not out.exists()
    one_line_error(run("explore", "overcentre", "--branch", tables["overcentre"], "--out", tmp_path / "p.png"), ".html")


def test_set_gives_a_column_the_table_lacks(tables, tmp_path):
    text = tables["overcentre"].read_text().splitlines()
    header = text[0].split(",")
    drop = header.index("c [N s/m]")
    (tmp_path / "no_c.csv").write_text("\n".join(",".join(c for k, c in enumerate(line.split(",")) if k != drop)
                                                 for line in text) + "\n")
    one_line_error(run("explore", "overcentre", "--branch", tmp_path / "no_c.csv", "--out", tmp_path / "a.html"),
                   "lacks the column(s) c ", "--set")
    result = run("explore", "overcentre", "--branch", tmp_path / "no_c.csv", "--set", "c=0", "--out", tmp_path / "a.html")
    assert result.exit_code == 0, result.output
    data = _embedded((tmp_path / "a.html").read_text())
    system, branch = load_model("overcentre"), Branch.read_csv(tables["overcentre"])
    _check_poses(system, branch, data["branches"][0], data["bodies"])


def test_bad_tables_and_outputs(tables, tmp_path):
    text = tables["sweep"].read_text().splitlines()
    cells = text[5].split(",")
    cells[0] = "nan"  # the time column: not a model variable, still refused
    (tmp_path / "nan.csv").write_text("\n".join([*text[:5], ",".join(cells), *text[6:]]) + "\n")
    one_line_error(run("explore", "overcentre", "--branch", tmp_path / "nan.csv", "--out", tmp_path / "a.html"),
                   "column t", "finite")
    cells[0] = "zero"
    (tmp_path / "text.csv").write_text("\n".join([*text[:5], ",".join(cells), *text[6:]]) + "\n")
    one_line_error(run("explore", "overcentre", "--branch", tmp_path / "text.csv", "--out", tmp_path / "a.html"),
                   "not a number")
    one_line_error(run("explore", "overcentre", "--branch", tables["overcentre"], "--out", tmp_path), "--out")
    assert not (tmp_path / "a.html").exists()


def test_a_long_table_is_thinned_to_the_size_budget_keeping_every_event(tables):
    """The page's embedded data stays within its byte budget: the sweep (a time history with its JUMP events)
    thinned evenly, every special point and the last row kept, the note saying why; the full table without one."""
    system, sweep = load_model("overcentre"), Branch.read_csv(tables["sweep"])
    full = explore_page(system, [tables["sweep"]])
    budget = 60_000
    page = explore_page(system, [tables["sweep"]], budget=budget)
    data = json.dumps(_embedded(page)["branches"], separators=(",", ":"))
    assert len(data) <= budget < len(json.dumps(_embedded(full)["branches"], separators=(",", ":")))
    doc = _embedded(page)["branches"][0]
    assert {doc["rows"][s["row"]] for s in doc["special"]} == {p.index for p in sweep.special_points}
    assert doc["rows"][0] == 0 and doc["rows"][-1] == len(sweep) - 1
    plain = sorted(set(doc["rows"]) - {p.index for p in sweep.special_points} - {len(sweep) - 1})
    assert len(set(np.diff(plain))) == 1  # every k-th row
    assert "rows shown" in doc["note"] and "0.06 MB" in doc["note"]
    assert _embedded(full)["branches"][0]["rows"] == list(range(len(sweep)))
    with pytest.raises(Exception, match="budget"):
        page_data(system, [tables["sweep"]], budget=0)


def test_event_labels_are_their_own_text_and_codes_are_numbered(tables, tmp_path):
    """A time history's events keep their text (a repeated one numbered once, in brackets), the diagram gets
    them without their numbers; codes (LP, JUMP) are numbered as the branch names them."""
    sweep = Branch.read_csv(tables["sweep"])
    doc = page_data("overcentre", [tables["sweep"]])["branches"][0]
    assert [s["tag"] for s in doc["special"]] == [s["name"] for s in doc["special"]] == sweep.point_names()
    text = tables["sweep"].read_text().splitlines()
    header = text[0].split(",")
    k = header.index("label")
    rows = [line.split(",") for line in text[1:]]
    events = ["impact fwd_stop 75.3032 1/s; contact fwd_stop", "release aft_stop", "release aft_stop",
              "impact aft_stop 41.6839 1/s", "EVENT"]
    for r, label in zip((3, 7, 9, 12, 15), events):
        rows[r][k] = label
    for r in range(len(rows)):
        if r not in (3, 7, 9, 12, 15):
            rows[r][k] = ""
    path = tmp_path / "events.csv"
    path.write_text("\n".join([text[0], *(",".join(r) for r in rows)]) + "\n")
    special = page_data("overcentre", [path])["branches"][0]["special"]
    assert [s["tag"] for s in special] == ["impact fwd_stop 75.3032 1/s; contact fwd_stop", "release aft_stop (1)",
                                           "release aft_stop (2)", "impact aft_stop 41.6839 1/s", "EVENT1"]
    assert [s["short"] for s in special] == ["impact + contact fwd_stop", "release aft_stop", "release aft_stop",
                                             "impact aft_stop", "EVENT1"]
    assert [s["name"] for s in special] == Branch.read_csv(path).point_names()


def test_the_default_axes_of_a_spatial_gear_show_what_moves_most(tables):
    """The dual-sidestay kinematics has no angle among its states: y is the coordinate that travels furthest
    along the retraction (read from the table here), not the table's last column; planar, the first angle."""
    branch = Branch.read_csv(tables["retraction"])
    system = load_model("dual_sidestay_kinematics")
    states = [v.name for v in system.variables if v.kind == "state" and v.unit == "m"]
    travel = {n: float(np.ptp(branch.column(n))) for n in states}
    assert page_data(system, [tables["retraction"]])["axes"] == ["theta", max(travel, key=travel.get)]
    assert page_data("overcentre", [tables["overcentre"]])["axes"] == ["F", "theta1"]
    assert page_data("nose_gear", [tables["downlock"]])["axes"][0] == "l_sp1"
