"""Sensitivities of a stop's release load, of the design map's margins and of a cusp's location, against
closed forms and central differences of re-solved quantities (issue 24, item 1).

Closed forms (statics of a pendulum, a = m g L / 2 its largest gravity moment):
- pendulum_lock.toml: on its max stop at 0.3 rad, R = M0 - F - a cos(0.3): released at F = M0 - a cos(0.3).
- pendulum_snap.toml: on the same stop held by T, R = T - a cos(0.3): released at T = a cos(0.3).
- pendulum_stop.toml: on a min stop at -1.2 rad, R = a cos(1.2) - T: released at T = a cos(1.2).
- toggle_clamp_stop.toml: released where the hand force alone holds the handle at the stop's angle,
  F = k (0.8 - x_p - l0) x_p' / (2 Lh cos(theta)) (tests/test_toggle_clamp.py), so dF/dl0 = -k x_p' / (2 Lh cos)
  and dF/dk = F / k (the stop's angle depends on neither).
- the overcentre's cusp: its folds W +- k L (1 - (LU/L)^{2/3})^{3/2} meet at LU = L, F = W = (m1 + m2) g / 2.
"""

import math
from pathlib import Path

import numpy as np
import pytest
from test_sensitivity import central, relative_error

from mechcont.analysis._cusp import _Cusp
from mechcont.analysis.sensitivity import cusp_sensitivity, margin_sensitivity, release_sensitivity
from mechcont.analysis.stop_lock import locked_on_stops
from mechcont.continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium
from mechcont.errors import InputError
from mechcont.models import load_model

DATA = Path(__file__).parent / "data"
G = 9.81


def released(model, stop, vary, values):
    """The release load re-solved from scratch: the stop's condition at its limit, its reaction 0, vary freed."""
    s = {st.name: st for st in model.stops}[stop]
    x = find_equilibrium(model, values={**values, s.reaction: 0.0}, hold={s.condition: s.limit}, free=[vary])
    return x[model.index(vary)]


def check_against_resolved(model, sens, stop, vary, params):
    for p in params:
        def load(y):
            return released(model, stop, vary, {q: y[model.index(q)] for q in params})

        fd = central(load, model, sens.x, p)
        assert relative_error(sens[p], fd) < 1e-6, (p, sens[p], fd)


def test_pendulum_release_loads_match_closed_forms():
    lock = load_model(str(DATA / "pendulum_lock.toml"))
    x, contact = locked_on_stops(lock)
    assert contact == ["top"]
    sens = release_sensitivity(lock, x, "top", "F", ["M0", "m", "L", "g"])
    c = math.cos(0.3)
    assert sens.kind == "release" and sens.value == pytest.approx(15.0 - G * c, rel=1e-12)
    assert sens["M0"] == pytest.approx(1.0, rel=1e-12)
    assert sens["m"] == pytest.approx(-G / 2 * c, rel=1e-10)
    assert sens["L"] == pytest.approx(-2.0 * G / 2 * c, rel=1e-10)
    assert sens["g"] == pytest.approx(-2.0 / 2 * c, rel=1e-10)
    assert sens.units["m"] == "N m/kg"
    check_against_resolved(lock, sens, "top", "F", ["M0", "m", "L"])

    snap = load_model(str(DATA / "pendulum_snap.toml"))
    x, _ = locked_on_stops(snap)
    sens = release_sensitivity(snap, x, "top", "T", ["m", "L"])
    assert sens.value == pytest.approx(G * c, rel=1e-12)
    assert sens["m"] == pytest.approx(G / 2 * c, rel=1e-10) and sens["L"] == pytest.approx(G * c, rel=1e-10)


def test_release_point_of_a_run_with_stops():
    """The SR point of a continuation with stops (pendulum_stop lifted off its rest by T) gives its release load's
    derivatives through Branch.sensitivity, as the closed form a cos(1.2) differentiated."""
    from mechcont.analysis.stops import continuation_with_stops

    model = load_model(str(DATA / "pendulum_stop.toml"))
    x, _ = locked_on_stops(model)
    run = continuation_with_stops(model, x, "T", options=ContinuationOptions(bounds={"T": (-1.0, 15.0)}, max_steps=200))
    (sr,) = run.branch.special("SR")
    sens = run.branch.sensitivity(model, "SR1", ["m", "L", "g"])
    c = math.cos(1.2)
    assert sens.kind == "release" and sens.quantity == "T"
    assert sens.value == pytest.approx(G * c, rel=1e-12) and sr["T"] == pytest.approx(G * c, rel=1e-6)
    assert sens["m"] == pytest.approx(G / 2 * c, rel=1e-10)
    assert sens["L"] == pytest.approx(G * c, rel=1e-10)
    assert sens["g"] == pytest.approx(c, rel=1e-10)
    with pytest.raises(InputError, match="unknown stop"):
        release_sensitivity(model, x, "nope", "T", ["m"])


def test_clamp_release_load_matches_closed_form_and_resolves():
    from test_toggle_clamp import Lh, Ll, force_to_hold

    model = load_model(str(DATA / "toggle_clamp_stop.toml"))
    x, _ = locked_on_stops(model)
    params = ["l0", "k", "Lh", "Ll"]
    sens = release_sensitivity(model, x, "over", "F", params)
    theta = sens.x[model.index("theta_handle")]
    k = 50000.0
    assert sens.value == pytest.approx(force_to_hold(theta, 0.6), rel=1e-9)
    root = np.sqrt(Ll**2 - Lh**2 * np.sin(theta) ** 2)
    dxp = -Lh * np.sin(theta) - Lh**2 * np.sin(theta) * np.cos(theta) / root
    assert sens["l0"] == pytest.approx(-k * dxp / (2 * Lh * np.cos(theta)), rel=1e-9)
    assert sens["k"] == pytest.approx(sens.value / k, rel=1e-9)
    check_against_resolved(model, sens, "over", "F", params)


@pytest.fixture(scope="module")
def overcentre_cusp(overcentre):
    x0 = find_equilibrium(overcentre, values={"LU": 0.4}, hold={"theta1": 0.3}, free=["F"])
    b = continuation(overcentre, x0, "F", options=ContinuationOptions(bounds={"F": (-200.0, 200.0)}))
    curve = continue_folds(overcentre, b.special("LP")[0], vary="F", free="LU",
                           options=ContinuationOptions(bounds={"F": (-200.0, 200.0), "LU": (0.1, 2.0)}))
    return curve


def test_overcentre_cusp_location_matches_closed_form(overcentre, overcentre_cusp):
    """LU_c = L (both bars together: dL1 + dL2 = 1), F_c = W: its location is exact (second derivatives); the
    cusp's load, a state, from the bordered cusp system (third derivatives as differences of exact second ones)."""
    sens = overcentre_cusp.sensitivity(overcentre, "CP1", ["L1", "L2", "k", "m1", "g"])
    assert sens.kind == "cusp" and sens.quantity == "LU"
    assert sens.value == pytest.approx(1.5, rel=1e-12)
    assert sens["L1"] + sens["L2"] == pytest.approx(1.0, rel=1e-9)
    for p in ("k", "m1", "g"):
        assert abs(sens[p]) < 1e-12, p
    assert sens.states["m1"]["F"] == pytest.approx(G / 2, rel=1e-8)
    assert sens.states["g"]["F"] == pytest.approx(1.0, rel=1e-8)
    assert abs(sens.states["k"]["F"]) < 1e-8
    for p in ("L1", "L2"):  # the bordered system's LU row is the exact formula
        assert sens.states[p]["LU"] == pytest.approx(sens[p], rel=1e-7)


def test_nose_gear_cusp_matches_relocated_cusps():
    """The design map's fold locus (folds of F in l_sp1, continued in LU) ends at a cusp: its location and
    coordinates against central differences of cusps re-located at p +- h."""
    from mechcont.analysis.design import fold_locus

    model = load_model("nose_gear")
    fl = fold_locus(model, "l_sp1", "LU", {"l_sp1": (-0.175, 0.175), "LU": (1.25, 1.35)})
    (cp,) = fl.cusps
    states, vary = list(cp.info["unknowns"][:-1]), cp.info["unknowns"][-1]
    params = ["L4", "psi3"]
    sens = cusp_sensitivity(model, cp.x, states, vary, "LU", params)
    assert sens.value == pytest.approx(cp["LU"], rel=1e-6)
    idx = [model.index(n) for n in ("LU", "l_sp1", "F")]

    def relocated(y):
        return _Cusp(model, y, states, vary, "LU").locate()[0][idx]

    for p in params:
        fd = central(relocated, model, sens.x, p)
        assert relative_error(sens[p], fd[0]) < 1e-6, (p, sens[p], fd[0])
        exact = [sens.states[p][n] for n in ("LU", "l_sp1", "F")]
        for e, d in zip(exact, fd):
            assert relative_error(e, d) < 1e-6, (p, exact, fd)


@pytest.mark.parametrize("kind", ["fold", "lock"])
def test_nose_gear_margins_match_resolved_margins(kind):
    """The design map's margins along l_sp1 (to the nearest fold, and the signed one to F = 0) at the model's
    design, against central differences of the fold re-polished / the crossing re-solved at p +- h."""
    from mechcont.analysis.design import fold_locus
    from mechcont.analysis.downlock import downlock_point
    from mechcont.continuation._fold_point import polish_fold

    model = load_model("nose_gear")
    params = ["l_sp1", "LU", "L4", "k"]
    sens = margin_sensitivity(model, "l_sp1", params, kind=kind, bounds=(-0.175, 0.175))
    x0 = model.variable("l_sp1").value
    lens = [n for n in model.state_names if n != "theta4"] + ["l_sp1"]
    i = model.index("l_sp1")
    if kind == "fold":
        folds = [p["l_sp1"] for p in fold_locus(model, "l_sp1", "LU", {"l_sp1": (-0.175, 0.175),
                                                                        "LU": (1.25, 1.35)}).branch.special("LP")]
        assert sens.value == pytest.approx(min(abs(x0 - f) for f in folds), rel=1e-6)

        def where(y):
            return polish_fold(model, y, lens, "F").x[i]
    else:
        assert downlock_point(model)[model.index("F")] > 0 and sens.value > 0  # locks unaided: a positive margin

        def where(y):
            return find_equilibrium(model, values={"F": 0.0, **{p: y[model.index(p)] for p in params[1:]}},
                                    hold={"theta4": 0.0}, free=["l_sp1"], guess=y, tol=1e-15)[i]
    side = 1.0 if x0 > sens.x[i] else -1.0
    assert sens["l_sp1"] == side
    for p in params[1:]:
        # the crossing bends fast in LU (a 1e-4 step is off by 1e-3 even extrapolated): steps of 1e-6
        fd = -side * central(where, model, sens.x, p, rel=1e-6 if kind == "lock" else 1e-4)
        if p == "k" and kind == "fold":  # the fold's place does not depend on the spring's stiffness
            assert abs(sens[p]) < 1e-12 and abs(fd) < 1e-9
            continue
        assert relative_error(sens[p], fd) < 1e-6, (p, sens[p], fd)


def test_design_table_sensitivity_columns(tmp_path):
    """`design --sensitivity`: per level the force's derivatives at the design l_sp1 against central differences
    of re-solved downlock forces, and the margins' against the library's sensitivities at that level; a name
    that is solved for is a one-line error."""
    import csv

    from cli_helpers import make_runner, one_line_error

    from mechcont.analysis.downlock import downlock_point

    run = make_runner()
    out = tmp_path / "d.csv"
    r = run("design", "nose_gear", "--bounds", "l_sp1=-0.175:0.175", "--bounds", "LU=1.3:1.35", "--levels", "2",
            "--sensitivity", "LU,k", "--out", out)
    assert r.exit_code == 0, r.output
    rows = list(csv.DictReader(out.open()))
    model = load_model("nose_gear")
    for row in rows:
        lu = float(row["LU (m)"])
        x = downlock_point(model, {"LU": lu})
        for p, unit in (("LU", "N/m"), ("k", "N/(N/m)")):
            fd = central(lambda y: downlock_point(model, {"LU": y[model.index("LU")], "k": y[model.index("k")]})[
                model.index("F")], model, x, p)
            assert relative_error(float(row[f"dF/d{p} at l_sp1=0.1 ({unit})"]), fd) < 1e-6, (lu, p)
        lock = margin_sensitivity(model, "l_sp1", ["LU"], {"LU": lu}, kind="lock", bounds=(-0.175, 0.175))
        assert float(row["d(lock margin)/dLU (1)"]) == pytest.approx(lock["LU"], rel=1e-9)
    assert rows[0]["d(margin to fold)/dLU (1)"] != "none" and rows[1]["d(margin to fold)/dLU (1)"] == "none"
    one_line_error(run("design", "nose_gear", "--bounds", "l_sp1=-0.175:0.175", "--bounds", "LU=1.3:1.35",
                       "--sensitivity", "theta1"), "--sensitivity", "solved for")
