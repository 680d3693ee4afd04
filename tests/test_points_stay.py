"""Special points moved to other parameter values stay themselves (issue 32, item 2; item 6's sensitivity part).

The fixture is a brace lock written for these tests (tests/data/brace_lock.toml): an arm pinned at O,
a lock spring from its tip to S compressed past the line O-S, the arm's weight, a tilted unlock force
F at the tip and a stop on the arm's angle at ``c_min``. Its free equilibria have the closed form
F(th) = k a(th) + b(th) (below), so the folds, the cusp where the two folds meet and the release on
the stop are known independently of mechcont.
"""

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from scipy.optimize import brentq, minimize_scalar

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.continuation._sensitivity import point_sensitivity
from mechcont.errors import InputError

FILE = __file__.rsplit("/", 1)[0] + "/data/brace_lock.toml"
L, D, L0, G = 1.0, 1.6, 0.75, 9.81


def parts(th, m=200.0, ux=0.4):
    """``(a, b)`` with F(th) = k a(th) + b(th) on the free branch (N per N/m, N), from V = k/2 (l - l0)^2
    + m g L/2 sin th - F u.P: the spring's and the weight's moments over the force's lever u.dP/dth."""
    px, py = L * np.cos(th), L * np.sin(th)
    l = np.hypot(px - D, py)
    dl = ((px - D) * -py + py * px) / l
    lever = (ux * -py + px) / np.hypot(ux, 1.0)
    return (l - L0) * dl / lever, m * G * L / 2 * np.cos(th) / lever


def free_load(th, k=10000.0, **kw):
    a, b = parts(th, **kw)
    return k * a + b


def slope(f, th, h=1e-5):
    return (f(th + h) - f(th - h)) / (2 * h)


def fold_k(th, **kw):
    """The k at which th is a fold: k a'(th) + b'(th) = 0."""
    return -slope(lambda t: parts(t, **kw)[1], th) / slope(lambda t: parts(t, **kw)[0], th)


def fold_at(k, lo, hi, **kw):
    th = brentq(lambda t: fold_k(t, **kw) - k, lo, hi, xtol=1e-14)
    return th, free_load(th, k, **kw)


@pytest.fixture(scope="module")
def model():
    from mechcont.models import load_model

    return load_model(FILE)


@pytest.fixture(scope="module")
def folds(model):
    x0 = find_equilibrium(model, hold={"brace": -0.1}, free=["F"])
    br = continuation(model, x0, "F", options=ContinuationOptions(bounds={"brace": (-1, 1), "F": (-9000, 9000)}))
    lower = min(br.special("LP"), key=lambda p: p["brace"])  # the unlock fold, below the line O-S
    return br, lower


def test_fold_followed_in_k_is_the_closed_form_fold(model, folds):
    _, lp = folds
    for k in (13000.0, 1100.0):
        s = point_sensitivity(model, lp, ["k"], vary="F", values={"k": k})
        th, F = fold_at(k, -0.18, -0.005)  # K(th) = fold_k: k_c at the cusp (th ~ 0), above 16000 at -0.18
        assert s.value == pytest.approx(F, rel=1e-9)
        assert s.x[model.index("brace")] == pytest.approx(th, abs=1e-7)
        assert s["k"] == pytest.approx(parts(th)[0], rel=1e-6)  # envelope theorem: dF*/dk = a(th*)


def test_fold_past_its_cusp_is_said_to_end_there(model, folds):
    _, lp = folds
    cusp = minimize_scalar(lambda t: fold_k(t), bounds=(-0.05, 0.05), method="bounded", options={"xatol": 1e-10})
    k_c = float(cusp.fun)  # the folds meet here: below it F(th) has no fold near the line O-S
    assert 900 < k_c < 1000
    with pytest.raises(InputError) as err:  # today: a ConvergenceError from the blind polish
        point_sensitivity(model, lp, ["k"], vary="F", values={"k": 900.0})
    assert err.value.last["k"] == pytest.approx(k_c, rel=2e-3)
    assert "cusp" in str(err.value) and "\n" not in str(err.value)


def test_fold_does_not_jump_to_another_fold(model, folds):
    # m = 400, ux = -0.8, k = 2000: the unlock fold's load runs off to infinity at the pole of the lever
    # (u.dP = 0 at tan th = 1/ux); a fold exists past the pole (th = -1.72, F = 3099.7 N) and the blind
    # re-polish called it this fold. Closed form: no fold between the pole and the line O-S.
    _, lp = folds
    kw = {"m": 400.0, "ux": -0.8}
    pole = np.arctan(1 / -0.8)
    th = np.linspace(pole + 1e-3, -1e-3, 20001)
    k_of = np.array([fold_k(t, **kw) for t in th])
    assert np.all(np.abs(k_of - 2000.0) > 50)  # no fold at k = 2000 on this side
    with pytest.raises(InputError):
        point_sensitivity(model, lp, ["k"], vary="F", values={"k": 2000.0, **kw})


def _release_table(model, tmp_path, c_min):
    from mechcont.analysis.stops import continuation_with_stops, equilibrium_on_stops

    m = model.with_values({"c_min": c_min, "F": -1000.0})
    guess = {"theta_arm": c_min, "brace": c_min, "x_arm": 0.5 * np.cos(c_min), "y_arm": 0.5 * np.sin(c_min)}
    x, contact = equilibrium_on_stops(m, guess)
    assert contact == ["down"]
    run = continuation_with_stops(m, x, "F", options=ContinuationOptions(bounds={"brace": (-1, 1), "F": (-3000, 3000)}))
    path = tmp_path / f"release{c_min}.csv"
    run.branch.to_csv(path)
    return path, run.branch


@pytest.mark.parametrize("c_min, label", [(-0.3, "SR1"), (-0.15, "NSF1")])
def test_release_from_a_stops_table_and_its_limit_derivative(model, tmp_path, c_min, label):
    # the release is where the free branch meets the stop: F_r(c) = F(th = c); truth dF_r/dc by differences
    path, branch = _release_table(model, tmp_path, c_min)
    assert label in branch.point_names()
    run = make_runner()
    res = run("sensitivity", FILE, "--point", f"{path}:{label}", "--params", "c_min,k", "--set", "c_min=-0.2"
              if label == "NSF1" else "c_min=-0.35", "--out", tmp_path / "s.json")
    assert res.exit_code == 0, res.output
    import json

    doc = json.loads((tmp_path / "s.json").read_text())
    c = -0.2 if label == "NSF1" else -0.35  # --set moves the stop's limit and with it the release
    assert doc["quantity"]["value"] == pytest.approx(free_load(c), rel=1e-9)
    assert doc["c_min"] == pytest.approx(slope(free_load, c), rel=1e-6)
    assert doc["k"] == pytest.approx(parts(c)[0], rel=1e-6)
    # at the table's own values: the release there (today: the default limit's release and dF/dc_min = 0)
    res = run("sensitivity", FILE, "--point", f"{path}:{label}", "--params", "c_min", "--out", tmp_path / "t.json")
    assert res.exit_code == 0, res.output
    doc = json.loads((tmp_path / "t.json").read_text())
    assert doc["quantity"]["value"] == pytest.approx(free_load(c_min), rel=1e-9)
    assert doc["c_min"] == pytest.approx(slope(free_load, c_min), rel=1e-6)


def test_cli_fold_past_cusp_one_line(folds, tmp_path):
    br, _ = folds
    br.to_csv(tmp_path / "b.csv")
    name = next(n for n, p in zip(br.point_names(), br.special_points) if p.label == "LP" and p["brace"] < 0)
    one_line_error(make_runner()("sensitivity", FILE, "--point", f"{tmp_path / 'b.csv'}:{name}", "--params", "k",
                                 "--set", "k=900"), "--point", name, "does not continue", "cusp")


def test_cli_k_alone_does_not_jump_to_the_fold_past_the_pole(tmp_path):
    # the issue's case on this lock: a table at m = 400 kg, ux = -0.8 and `--set k=2300`. Today the unlock
    # fold (th = -0.26 at k = 10000) re-polished at k = 2300 lands on the fold at th = -1.371, F = 3576.9 N,
    # on the far side of the lever's pole (tan th = 1/ux): another fold. Closed form: on the near side the
    # fold exists only for k above min K(th) = 2454.3 (it runs into the pole there), so it ends on the way.
    kw = {"m": 400.0, "ux": -0.8}
    pole = np.arctan(1 / kw["ux"])
    th = np.linspace(pole + 1e-4, -1e-3, 200001)
    k_end = float(np.min(np.where(fold_k(th, **kw) > 0, fold_k(th, **kw), np.inf)))
    assert 2300 < k_end < 2500
    run = make_runner()
    table = tmp_path / "heavy.csv"
    res = run("continue", FILE, "--set", "m=400", "--set", "ux=-0.8", "--vary", "F", "--start", "brace=-0.1",
              "--bounds", "brace=-0.85:1", "--bounds", "F=-9000:9000", "--out", table, "--quiet")
    assert res.exit_code == 0, res.output
    from mechcont.continuation import Branch

    br = Branch.read_csv(table)
    name = next(n for n, p in zip(br.point_names(), br.special_points) if p.label == "LP" and p["brace"] < 0)
    res = run("sensitivity", FILE, "--point", f"{table}:{name}", "--params", "k", "--set", "k=2300")
    one_line_error(res, "does not continue", "ends near k = ")
    last = float(res.stderr.split("ends near k = ")[1].split()[0])
    assert last == pytest.approx(k_end, rel=1e-3)
