"""The library work the commands used to do themselves (issue 34, item 4: a thin CLI), tested directly against truth,
and the one parser of each repeated command-line pattern (``cli/_parse.py``).

Truth: the statics of a pendulum on a stop (tests/data/pendulum_stop.toml: m = 2 kg, L = 1 m, a = m g L / 2 the
largest gravity moment; on the stop at -1.2 rad the reaction is a cos(1.2) - T, lifted off it by T the bar hangs where
a cos(theta) = T, stable for theta < 0); central differences of re-solved downlock forces; a branch continued at another
parameter value than the model's."""

import math
import sys
import types
from pathlib import Path

import numpy as np
import pytest

from mechcont.errors import InputError

DATA = Path(__file__).parent / "data"
A = 2.0 * 9.81 * 1.0 / 2


@pytest.fixture(scope="module")
def pendulum():
    from mechcont.mechanism import load_description

    return load_description(DATA / "pendulum_stop.toml").build()


def test_stops_at_rest_on_the_stop(pendulum):
    from mechcont.analysis.rest_on_stops import stops_at_rest

    rest = stops_at_rest(pendulum, pendulum.defaults())
    assert rest.failure == "" and rest.contact == ("rest",) and rest.stable
    (stop,) = rest.stops
    assert stop.in_contact and stop.key == "min" and stop.limit == pytest.approx(-1.2)
    assert stop.value == pytest.approx(A * math.cos(1.2), rel=1e-10) and stop.unit == "N m"
    assert rest.x is not None and rest.x[pendulum.index("angle")] == pytest.approx(-1.2, abs=1e-12)
    assert "in contact, reaction R_rest = 3.55473 N m" in rest.lines()[1]


def test_stops_at_rest_lifted_off_the_stop(pendulum):
    from mechcont.analysis.rest_on_stops import stops_at_rest

    lifted = pendulum.with_values({"T": 8.0})
    rest = stops_at_rest(lifted, lifted.defaults())
    theta = -math.acos(8.0 / A)  # a cos(theta) = T on the stable side
    (stop,) = rest.stops
    assert not stop.in_contact and rest.contact == () and rest.stable
    assert stop.value == pytest.approx(theta, rel=1e-9) and stop.gap == pytest.approx(theta + 1.2, rel=1e-9)
    assert "free, angle = " in rest.lines()[1]


def test_stops_at_rest_without_an_equilibrium_is_a_finding(pendulum):
    """T above a: no angle balances gravity (a cos(theta) < T), and on the stop the reaction would pull."""
    from mechcont.analysis.rest_on_stops import stops_at_rest

    torn = pendulum.with_values({"T": 1.2 * A})
    rest = stops_at_rest(torn, torn.defaults())
    assert rest.failure.startswith("no equilibrium with a consistent set of stops in contact")
    assert rest.x is None and rest.stops == () and not rest.stable
    assert rest.lines()[1:] == [f"  {rest.failure}"]


def test_start_on_stops_rests_on_the_stop(pendulum):
    from mechcont.analysis.rest_on_stops import start_on_stops

    for T in (0.0, 1.0):
        start = start_on_stops(pendulum, "T", values={"T": T})
        x = pendulum.as_dict(start.x)
        assert start.contact == ("rest",)
        assert x["angle"] == pytest.approx(-1.2, abs=1e-12)
        assert x["R_rest"] == pytest.approx(A * math.cos(1.2) - T, rel=1e-10)


def test_design_sensitivity_against_central_differences():
    """The force's derivative per level against central differences of re-solved downlock forces; the lock
    margin's against the library's margin sensitivity at that level; a level without a fold has None there."""
    from mechcont.analysis import design_region
    from mechcont.analysis.design_sensitivity import check_design_parameters, design_sensitivity
    from mechcont.analysis.downlock import downlock_condition, downlock_point
    from mechcont.analysis.sensitivity import margin_sensitivity
    from mechcont.models import load_model

    model = load_model("nose_gear")
    hold, force = downlock_condition(model)
    region = design_region(model, "l_sp1", "LU", x_bounds=(-0.175, 0.175), y_levels=np.linspace(1.3, 1.35, 2),
                           force=force)
    params = check_design_parameters(model, ["LU", "k"], hold, force)
    sens = design_sensitivity(model, region, params, hold=hold, force=force)
    x0 = region.design[0]
    assert len(sens.rows) == 2 and sens.columns[0] == f"d{force}/dLU at l_sp1={x0:g} (N/m)"
    for row, got in zip(region.rows, sens.rows):
        for p, unit in (("LU", "N/m"), ("k", "N/(N/m)")):
            v = model.variable(p).value if p != "LU" else row.level
            h = 1e-6 * abs(v)

            def F(value, p=p, level=row.level):
                x = downlock_point(model, {"LU": level, "l_sp1": x0, p: value})
                return x[model.index(force)]

            fd = (F(v + h) - F(v - h)) / (2 * h)
            assert got[f"d{force}/d{p} at l_sp1={x0:g} ({unit})"] == pytest.approx(fd, rel=1e-5), (row.level, p)
        lock = margin_sensitivity(model, "l_sp1", ["LU"], {"LU": row.level}, kind="lock", bounds=(-0.175, 0.175))
        assert got["d(lock margin)/dLU (1)"] == pytest.approx(lock["LU"], rel=1e-9)
    assert sens.rows[0]["d(margin to fold)/dLU (1)"] is not None and sens.rows[1]["d(margin to fold)/dLU (1)"] is None
    with pytest.raises(InputError, match="params"):
        check_design_parameters(model, ["theta1"], hold, force)


def test_held_branch_differences(overcentre):
    from mechcont.continuation import continuation, find_equilibrium, run_options
    from mechcont.dynamics import held_branch_differences

    x0 = find_equilibrium(overcentre, values={"LU": 0.4}, hold={"theta1": 0.3}, free=["F"])
    branch = continuation(overcentre, x0, "F", options=run_options({"F": (-100.0, 100.0)}))
    at_04 = overcentre.with_values({"LU": 0.4})
    assert held_branch_differences(at_04, branch, ["F"]) == []
    at_05 = overcentre.with_values({"LU": 0.5})
    (diff,) = held_branch_differences(at_05, branch, ["F"])
    assert diff[0] == "LU" and diff[1] == pytest.approx(0.4) and diff[2] == pytest.approx(0.5)
    # F moves along the branch: solved for there, never a difference, even when not named as ramped
    assert [d[0] for d in held_branch_differences(at_05.with_values({"F": 7.0}), branch)] == ["LU"]


def test_paper_run_writes_the_summary_of_its_sections(tmp_path, monkeypatch):
    from mechcont.paper.sections import chosen_sections, run_sections, summary_header

    ran = []
    for name, text in (("overcentre", "## one"), ("dual_sidestay", "## two")):
        def run(out, quiet, timings, name=name, text=text):
            ran.append(name)
            timings[f"{name} step"] = 0.5
            (out / f"{name}.png").write_bytes(b"")
            return [text, ""]
        monkeypatch.setitem(sys.modules, f"mechcont.paper.{name}", types.SimpleNamespace(run=run))
    result = run_sections(tmp_path, ["dual_sidestay", "overcentre"])
    assert ran == ["overcentre", "dual_sidestay"]  # the sections' order, not the order named
    assert result.summary.read_text() == "\n".join([*summary_header(), "## one", "", "## two"]) + "\n"
    assert list(result.timings) == ["overcentre step", "section overcentre (total)", "dual_sidestay step",
                                    "section dual_sidestay (total)"]
    assert result.timings_file.read_text().splitlines()[1:] == result.timings_table().splitlines()
    assert chosen_sections(None) == ["overcentre", "dynamics", "nose_gear", "design_optimum", "freefall", "shimmy"]
    assert chosen_sections(" shimmy, dual_sidestay") == ["shimmy", "dual_sidestay"]
    for bad in ("", "nope"):
        with pytest.raises(InputError, match="only"):
            chosen_sections(bad)


def test_one_parser_per_pattern():
    from mechcont.cli._parse import assignments, at_values, bounds, branch_row, named_item, span

    assert named_item(" k = 3", "--set", "NAME=VALUE") == ("k", " 3")
    assert assignments(["k=3", "LU=0.4"], "set") == {"k": 3.0, "LU": 0.4}
    assert bounds(["F=:1", "x=-2:"]) == {"F": (-math.inf, 1.0), "x": (-2.0, math.inf)}
    assert span("U=20:80", "--critical") == ("U", 20.0, 80.0)
    assert at_values(["D=0.1,0.2", "D=0.3"], "D") == (0.1, 0.2, 0.3)
    assert branch_row("dir:with:colon/b.csv:LP1") == ("dir:with:colon/b.csv", "LP1")
    for call, field in ((lambda: named_item("=3", "--set", "NAME=VALUE"), "--set"),
                        (lambda: span("U=20:", "--critical"), "--critical U"),  # a range that must be finite
                        (lambda: span("U=80:20", "--critical"), "--critical U"),
                        (lambda: bounds(["k=1:2"], "--design") and bounds(["k=2:1"], "--design"), "--design k"),
                        (lambda: at_values(["F=1"], "D"), "--at"),
                        (lambda: at_values(["D="], "D"), "--at"),
                        (lambda: at_values(["D=1,x"], "D"), "--at D"),
                        (lambda: branch_row("b.csv"), "--point"),
                        (lambda: branch_row("b.csv:"), "--point")):
        with pytest.raises(InputError) as info:
            call()
        assert info.value.field == field, (info.value.field, field)


def test_read_branch_row_is_the_run_s_point(overcentre, tmp_path):
    """A row read back from a written table is the run's point (the fold LP1 at the run's fold load, the unknowns the
    run solved for) and passes its own check; a row that claims to be a fold and is not fails it; a table whose vary
    column names no variable of the model is refused naming the point."""
    from mechcont.continuation import continuation, find_equilibrium, run_options
    from mechcont.continuation.branch_rows import read_branch_row

    x0 = find_equilibrium(overcentre, values={"LU": 0.4}, hold={"theta1": 0.3}, free=["F"])
    branch = continuation(overcentre, x0, "F", options=run_options({"F": (-100.0, 100.0)}))
    path = tmp_path / "b.csv"
    branch.to_csv(path)
    row = read_branch_row(overcentre, path, "LP1")
    fold = branch.special("LP")[0]
    assert row.vary == "F" and row.point.label == "LP" and row.name == f"{path}:LP1"
    assert row.point["F"] == pytest.approx(fold["F"], rel=1e-9)
    assert set(row.unknowns) == set(overcentre.state_names)
    row.check(overcentre)
    with pytest.raises(InputError):
        read_branch_row(overcentre, path, "1").check(overcentre, "LP")  # the second row is no fold
    text = path.read_text().replace(",F\n", ",nope\n").replace(",F\r\n", ",nope\r\n")
    other = tmp_path / "other.csv"
    other.write_text(text)
    with pytest.raises(InputError) as info:
        read_branch_row(overcentre, other, "LP1")
    assert info.value.field == "point" and "nope" in str(info.value)
