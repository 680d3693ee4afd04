"""Stops: one-sided limits of conditions, their contact reactions, and continuation through contact changes.

Truth: a pendulum resting on a stop (planar angle stop, spatial distance stop), closed forms for the
contact reaction, the release load and the fold after release; the generated stop force against
finite differences of the condition.
"""

import math
import pickle
from pathlib import Path

import numpy as np
import pytest

from mechcont.analysis import continuation_with_stops, equilibrium_on_stops, stops_in_contact
from mechcont.continuation import ContinuationOptions, find_equilibrium
from mechcont.errors import InputError
from mechcont.mechanism import load_description, parse_description

DATA = Path(__file__).parent / "data"
M, L, G, THETA0 = 2.0, 1.0, 9.81, -1.2


@pytest.fixture(scope="module")
def pendulum():
    return load_description(DATA / "pendulum_stop.toml").build()


def test_reaction_is_a_parameter_with_its_unit(pendulum):
    v = pendulum.variable("R_rest")
    assert v.kind == "parameter" and v.value == 0.0 and v.unit == "N m"
    (stop,) = pendulum.stops
    assert (stop.condition, stop.side, stop.limit, stop.reaction) == ("angle", 1, -1.2, "R_rest")
    assert stop.gap(-1.0) == pytest.approx(0.2)


def test_contact_reaction_closed_form(pendulum):
    x, contact = equilibrium_on_stops(pendulum, pendulum.defaults())
    assert contact == ["rest"]
    d = pendulum.as_dict(x)
    # moment balance about the pin: R = m g (L/2) cos(theta0)
    assert d["R_rest"] == pytest.approx(M * G * L / 2 * math.cos(THETA0), rel=1e-12)
    assert d["angle"] == THETA0
    assert stops_in_contact(pendulum, x) == ["rest"]


def test_free_equilibrium_leaves_the_stop_alone(pendulum):
    # a large lifting moment: the bar stands off the stop, reaction 0
    x0 = find_equilibrium(pendulum, values={"T": 8.0}, guess={"theta_bar": -0.5, "angle": -0.5})
    x, contact = equilibrium_on_stops(pendulum, x0)
    d = pendulum.as_dict(x)
    assert contact == [] and d["R_rest"] == 0.0
    assert math.cos(d["theta_bar"]) == pytest.approx(8.0 / (M * G * L / 2), rel=1e-10)


def test_generated_stop_force_is_the_condition_gradient(pendulum):
    # the Jacobian column of R_rest in the moment row is d(angle)/d(theta_bar) = 1
    x, _ = equilibrium_on_stops(pendulum, pendulum.defaults())
    J = pendulum.jacobian(x)
    row = pendulum.equation_names.index("M_bar")
    assert J[row, pendulum.index("R_rest")] == pytest.approx(1.0, abs=1e-14)


def test_release_then_fold(pendulum):
    x, _ = equilibrium_on_stops(pendulum, pendulum.defaults())
    run = continuation_with_stops(pendulum, x, "T", direction=1, stop_at_fold=True,
                                  options=ContinuationOptions(bounds={"T": (-20, 20)}))
    assert [s[:2] for s in run.switches] == [("SR", "rest")]
    assert run.contact == [("rest",), ()]
    sr = run.branch[run.branch.special_points[0].label + "1"]
    assert sr.label == "SR" and sr.stop == "rest" and sr.info["stop"] == "rest"
    assert sr["T"] == pytest.approx(M * G * L / 2 * math.cos(THETA0), rel=1e-9)
    assert abs(sr["R_rest"]) < 1e-9
    lp = run.first_fold()
    # lifted off the stop the bar balances T = m g (L/2) cos(theta): the largest T it carries is at theta = 0
    assert lp["T"] == pytest.approx(M * G * L / 2, rel=1e-9)
    assert abs(lp["theta_bar"]) < 1e-6
    # the contact piece is stable, the free piece stable up to the fold
    b = run.branch
    assert np.all(b.n_unstable[: lp.index] == 0)
    # on the contact piece the reaction carries the rest: R + T = m g (L/2) cos(theta0)
    on = b.values[: run.switches[0][2] + 1]
    np.testing.assert_allclose(on[:, b.names.index("R_rest")] + on[:, b.names.index("T")],
                               M * G * L / 2 * math.cos(THETA0), rtol=1e-10)


def test_contact_made_on_the_way_down(pendulum):
    x0 = find_equilibrium(pendulum, values={"T": 5.0}, guess={"theta_bar": -1.0, "angle": -1.0})
    x, contact = equilibrium_on_stops(pendulum, x0)
    assert contact == []
    run = continuation_with_stops(pendulum, x, "T", direction=-1,
                                  options=ContinuationOptions(bounds={"T": (-10, 10)}))
    assert [s[:2] for s in run.switches] == [("SC", "rest")]
    sc = run.branch.special_points[0]
    assert sc.label == "SC" and sc["T"] == pytest.approx(M * G * L / 2 * math.cos(THETA0), rel=1e-9)
    end = run.branch.values[-1]
    d = dict(zip(run.branch.names, end))
    assert d["T"] == pytest.approx(-10.0)
    assert d["R_rest"] == pytest.approx(M * G * L / 2 * math.cos(THETA0) + 10.0, rel=1e-10)
    assert d["angle"] == pytest.approx(THETA0, abs=1e-12)


def test_contact_stability_holds_the_stop():
    # a pendulum pushed by gravity against a stop above the horizontal: free it would be unstable
    # there (it hangs below), held by the stop it is not
    text = (DATA / "pendulum_stop.toml").read_text().replace("min = -1.2", "max = 0.3").replace(
        "initial = { theta = -1.2 }", "initial = { theta = 0.3 }")
    m = parse_description(text, "p.toml").build()
    x, contact = equilibrium_on_stops(m, m.defaults(), values={"T": 15.0})
    assert contact == ["rest"]
    assert m.as_dict(x)["R_rest"] == pytest.approx(15.0 - M * G * L / 2 * math.cos(0.3), rel=1e-12)
    run = continuation_with_stops(m, x, "T", direction=-1, options=ContinuationOptions(bounds={"T": (10, 15)}))
    assert m.mechanics.stability(x).n_unstable == 1   # free, the bar would fall from there
    assert np.all(run.branch.n_unstable == 0)          # held by the stop it is stable


def test_spatial_distance_stop_closed_form():
    m = load_description(DATA / "spatial" / "pendulum_stop_3d.toml").build()
    assert m.variable("R_floor").unit == "N"
    x, contact = equilibrium_on_stops(m, m.defaults())
    assert contact == ["floor"]
    d = m.as_dict(x)
    # virtual work: R = m g d_min / (2 L)
    assert d["R_floor"] == pytest.approx(2.0 * 9.81 * 0.72 / (2 * 0.8), rel=1e-10)
    assert d["gap"] == 0.72


def test_stops_pickle_with_the_model(pendulum):
    back = pickle.loads(pickle.dumps(pendulum))
    assert back.stops == pendulum.stops
    assert back.with_values({"T": 1.0}).stops == pendulum.stops


@pytest.mark.parametrize("table, field, words", [
    ('[stops.rest]\ncondition = "nope"\nmin = 0', "stops.rest.condition", "unknown condition 'nope'"),
    ('[stops.rest]\ncondition = "angle"\nmin = 0\nmax = 1', "stops.rest", "exactly one of min"),
    ('[stops.rest]\ncondition = "angle"', "stops.rest", "exactly one of min"),
    ('[stops.rest]\ncondition = "angle"\nmin = 0\nlimit = 3', "stops.rest.limit", "valid keys"),
    ('[stops.rest]\ncondition = "angle"\nmin = true', "stops.rest.min", "number or an expression"),
    ('[stops.rest]\ncondition = "angle"\nmin = "Q + 1"', "stops.rest.min", "Q"),
])
def test_bad_stop_tables(table, field, words):
    text = (DATA / "pendulum_stop.toml").read_text().split("[stops.rest]")[0] + table + "\n"
    with pytest.raises(InputError) as err:
        parse_description(text, "p.toml")
    assert field in str(err.value) and words in str(err.value)


def test_reaction_name_clash_is_named():
    text = (DATA / "pendulum_stop.toml").read_text().replace(
        'T = { value', 'R_rest = 1.0\nT = { value')
    with pytest.raises(InputError, match="contact reaction R_rest of a stop"):
        parse_description(text, "p.toml")


def test_no_consistent_contact_set_is_reported(pendulum):
    # a stop that would have to pull: forcing contact with a large lifting moment releases it
    x0 = find_equilibrium(pendulum, values={"T": 8.0}, guess={"theta_bar": -0.5, "angle": -0.5})
    x, contact = equilibrium_on_stops(pendulum, x0, contact=["rest"])
    assert contact == []
    with pytest.raises(InputError, match="unknown stop"):
        equilibrium_on_stops(pendulum, x0, stops=["other"])


def test_an_inconsistent_start_is_refused_with_the_way_out(pendulum):
    # at T = 8 the bar stands off the stop; a start that claims contact there would pull
    x0 = find_equilibrium(pendulum, values={"T": 8.0}, hold={"angle": THETA0}, free=["R_rest"],
                          guess={"theta_bar": THETA0})
    assert pendulum.as_dict(x0)["R_rest"] < 0
    with pytest.raises(InputError, match="stop rest is not consistently.*equilibrium_on_stops"):
        continuation_with_stops(pendulum, x0, "T")


def test_check_reports_the_stops_in_contact():
    from tests.cli_helpers import make_runner

    run = make_runner()

    r = run("check", DATA / "pendulum_stop.toml")
    assert r.exit_code == 0, r.output
    assert "rest  min of angle = -1.2 rad: in contact, reaction R_rest = 3.55473 N m" in r.output
    assert "stability there (a stop in contact holds its condition): stable" in r.output
    lifted = run("check", DATA / "pendulum_stop.toml", "--set", "T=8")
    assert "rest  min of angle = -1.2 rad: free, angle = " in lifted.output


def test_continue_with_stops_on_the_command_line(tmp_path):
    from mechcont.continuation import read_branch_table
    from tests.cli_helpers import make_runner, one_line_error

    run = make_runner()
    out = tmp_path / "b.csv"
    r = run("continue", DATA / "pendulum_stop.toml", "--vary", "T", "--bounds", "T=-5:12", "--stops", "--out", out)
    assert r.exit_code == 0, r.output
    assert "SR1" in r.output and "LP1" in r.output
    # without --start the table shows the stop's condition (not the first coordinate, x_bar, 0 throughout)
    assert "angle (deg)" in r.output.splitlines()[1] and "x_bar" not in r.output
    rows, units = read_branch_table(out)
    T = np.array([float(r["T"]) for r in rows])
    R = np.array([float(r["R_rest"]) for r in rows])
    assert units["R_rest"] == "N m" and T[0] == pytest.approx(-5.0)
    assert R[0] == pytest.approx(M * G * L / 2 * math.cos(THETA0) + 5.0, rel=1e-10)   # on the stop
    assert [r["label"] for r in rows if r.get("label")][:2] == ["EP", "SR"]
    # without --stops the stops are free and the user is told how to let them act
    r = run("continue", DATA / "pendulum_stop.toml", "--vary", "T", "--bounds", "T=-5:12")
    assert "note: pendulum_stop has stops (rest)" in r.output and "--stops" in r.output
    one_line_error(run("continue", "overcentre", "--vary", "F", "--stops"), "--stops", "has no stops")


@pytest.mark.parametrize("path", [DATA / "pendulum_stop.toml", DATA / "spatial" / "pendulum_stop_3d.toml"])
def test_derivatives_with_a_stop_reaction_match_differences(path):
    from tests.derivative_checks import check_derivatives

    m = load_description(path).build()
    check_derivatives(m.with_values({m.stops[0].reaction: 3.0}))


def test_reduced_form_carries_the_stop():
    m = load_description(DATA / "pendulum_stop.toml").build_reduced()
    x, contact = equilibrium_on_stops(m, m.defaults())
    assert contact == ["rest"] and "x_bar" not in m.names
    assert m.as_dict(x)["R_rest"] == pytest.approx(M * G * L / 2 * math.cos(THETA0), rel=1e-12)


def test_unlock_through_a_stop_equals_the_downlock_release_fold():
    # the shipped lock stay with a knee stop 0.05 (sine) over centre: pushed open from rest, its first fold
    # is the unlock load that `mechcont downlock` finds by releasing the aligned (downlocked) point
    from mechcont.analysis import downlock_point, unlock_folds
    from mechcont.mechanism import find_description

    base = find_description("lockstay").read_text()
    stopped = base.replace("[assembly]", '[stops.overcentre]\ncondition = "aligned"\nmax = 0.05\n\n[assembly]')
    m = parse_description(stopped, "lockstay_stop.toml").build()
    x, contact = equilibrium_on_stops(m, m.defaults())
    run = continuation_with_stops(m, x, "F", stop_at_fold=True, options=ContinuationOptions(bounds={"F": (-2e3, 2e3)}))
    lp = run.first_fold()
    plain = parse_description(base, "lockstay.toml").build()
    down = downlock_point(plain)
    folds = unlock_folds(plain, down, "F", ["aligned"])
    assert lp is not None and lp.located
    assert lp["F"] == pytest.approx(folds.unlock_force, rel=1e-9)
    assert lp["R_overcentre"] == 0.0 and lp["aligned"] < 0.05


@pytest.mark.parametrize("args, field", [(["--vary", "R_rest"], "vary: R_rest"), (["--vary", "angle"], "vary: angle"),
                                         (["--vary", "T", "--hold", "angle"], "hold: angle"),
                                         (["--vary", "T", "--free", "R_rest"], "free: R_rest")])
def test_continue_with_stops_refuses_a_lens_on_the_stops(args, field):
    from tests.cli_helpers import make_runner, one_line_error

    one_line_error(make_runner()("continue", DATA / "pendulum_stop.toml", *args, "--stops"), field,
                   "is switched by the stop rest")


def test_a_stop_on_a_condition_without_coordinates_is_refused():
    text = (DATA / "pendulum_stop.toml").read_text().replace(
        'angle = { type = "angle", bodies = ["ground", "bar"] }', 'angle = { type = "angle", bodies = ["ground", "bar"] }\n'
        'size = "2*L"')
    text = text.replace('condition = "angle"', 'condition = "size"')
    with pytest.raises(InputError, match="stops.rest.condition.*does not depend on the coordinates"):
        parse_description(text, "p.toml").build()


def test_a_bad_stop_table_is_one_line_on_the_command_line(tmp_path):
    from tests.cli_helpers import make_runner, one_line_error

    bad = tmp_path / "bad.toml"
    bad.write_text((DATA / "pendulum_stop.toml").read_text().replace("min = -1.2", "min = -1.2\nmax = 0.5"))
    one_line_error(make_runner()("check", bad), "stops.rest", "exactly one of min")
    bad.write_text((DATA / "pendulum_stop.toml").read_text().replace('condition = "angle"\nmin', 'condition = "gap"\nmin'))
    one_line_error(make_runner()("continue", bad, "--vary", "T", "--stops"), "stops.rest.condition",
                   "unknown condition 'gap'")


def test_a_limit_in_parameters_follows_with_values():
    # the stop angle as a parameter: with_values moves the stop (and a condition's target) as a
    # fresh build at those values does, and the contact reaction follows the closed form
    text = (DATA / "pendulum_stop.toml").read_text().replace(
        'T = { value = 0.0', 'stop = { value = -1.2, unit = "rad" }\nT = { value = 0.0').replace(
        "min = -1.2", 'min = "stop"').replace(
        'angle = { type = "angle", bodies = ["ground", "bar"] }',
        'angle = { type = "angle", bodies = ["ground", "bar"] }\nlevel = { type = "angle", bodies = ["ground", "bar"], '
        'target = "stop + 0.2" }')
    m = parse_description(text, "p.toml").build()
    assert m.stops[0].limit == -1.2 and m.conditions["level"] == pytest.approx(-1.0)
    moved = m.with_values({"stop": -0.9})
    fresh = parse_description(text.replace("value = -1.2", "value = -0.9"), "p.toml").build()
    assert moved.stops == fresh.stops and moved.stops[0].limit == -0.9
    assert moved.conditions == fresh.conditions and moved.conditions["level"] == pytest.approx(-0.7)
    assert m.stops[0].limit == -1.2  # the original is unchanged
    x, contact = equilibrium_on_stops(moved, moved.defaults())
    assert contact == ["rest"] and x[moved.index("angle")] == pytest.approx(-0.9, abs=1e-12)
    assert x[moved.index("R_rest")] == pytest.approx(M * G * L / 2 * math.cos(-0.9), rel=1e-10)
    assert pickle.loads(pickle.dumps(moved)).with_values({"stop": -1.0}).stops[0].limit == -1.0
