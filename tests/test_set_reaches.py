"""Values given for one analysis reach every part of it (the audit of ``--set`` and the analyses' own values on
description files; tests/test_set_everywhere.py compares each command's ``--set`` with the edited file).

tests/data/freefall_pendulum.toml: a bar of length L hinged at O, its drag at its midpoint and a damper to the
ground point (0, 2 L) written in L; the equilibria it hangs in satisfy cos(theta) = m g / (k U^2) with
k = rho C_D d L / 2, so the stall branch folds at theta = 0, U_c = sqrt(2 m g / (rho C_D d L)) (tests/test_freefall.py).
"""

from __future__ import annotations

import math
import re

import pytest
from cli_helpers import csv_rows, make_runner, one_line_error

from mechcont.dynamics.freefall import critical_scan
from mechcont.models import model_at

PATH = "tests/data/freefall_pendulum.toml"
run = make_runner()


def fold_speed(L: float = 1.0, d: float = 0.2, m: float = 10.0) -> float:
    """The closed-form quasi-static critical airspeed U_c (m/s)."""
    return math.sqrt(2 * m * 9.81 / (1.225 * 1.2 * d * L))


def test_a_scanned_length_moves_the_quasi_static_predictor():
    """freefall --critical --scan L: the quasi-static critical airspeed beside each bracket is the one at that
    scanned length (it was the model's own, L = 1, beside every bracket: 23.106 m/s at L = 1.5, where the truth is
    18.866 m/s, and the comparison then said the runs "contradict the statics")."""
    system = model_at(PATH, {"d": 0.25})
    lengths = [1.0, 1.5]
    # one run at each end of a bracket wide enough to hold both critical values: the predictor is what is checked
    scan = critical_scan(system, {"angle": 1.0}, "U", 15.0, 32.0, lock="downlock", until=30.0, tol=17.0,
                         scan=("L", lengths), end_at_lock=True)
    truth = [fold_speed(L, d=0.25) for L in lengths]
    assert [row[3] for row in scan.rows()] == [pytest.approx(u, rel=1e-9) for u in truth]
    assert scan.quasi_static_values == tuple(pytest.approx(u, rel=1e-9) for u in truth)
    assert all(q is not None and q.fold and abs(q.pose) < 1e-9 for q in scan.quasi_static)
    lines = scan.describe()
    for L, u in zip(lengths, truth):
        (line,) = [ln for ln in lines if ln.startswith(f"L = {L:g}: quasi-static critical U = ")]
        assert float(line.split(" = ")[2].split()[0]) == pytest.approx(u, rel=1e-6)  # printed to 6 digits
        (diff,) = [ln for ln in lines if ln.startswith(f"L = {L:g}: dynamic - quasi-static = ")]
        bracket = scan.brackets[lengths.index(L)]
        assert float(diff.split(" = ")[2].split()[0]) == pytest.approx(bracket.locked - u, rel=1e-3)


LOCK = "tests/data/spring_lock.toml"  # a bar on a max stop at c_max


def test_a_value_varied_in_time_that_moves_a_stop_is_refused(tmp_path):
    """sweep --stops --ramp c_max (the stop's limit): the bar stayed on the stop at the model's 0.3 rad while the
    table's c_max column ramped to 0.1; now one line naming --ramp's field and nothing written. A time simulation
    keeps its stops fixed (simulate's loads alike); a stop's parameter is given by --set."""
    from mechcont.dynamics import simulate
    from mechcont.errors import InputError

    out = tmp_path / "sw.csv"
    r = run("sweep", LOCK, "--start", "theta_bar=0.2", "--ramp", "c_max=0.3:0.1:1", "--watch", "theta_bar", "--stops",
            "--out", out)
    one_line_error(r, "ramp", "c_max moves stop top", "--set")
    assert not out.exists()
    system = model_at(LOCK, {"c_max": 0.25})
    with pytest.raises(InputError, match=r"^loads: c_max moves stop top"):
        simulate(system, system.defaults(), (0.0, 0.1), loads={"c_max": lambda t: 0.25 - t}, stops=True)
    ok = run("sweep", LOCK, "--start", "theta_bar=0.2", "--ramp", "c_max=0.3:0.1:1", "--watch", "theta_bar",
             "--no-equilibrium")
    assert ok.exit_code == 0, ok.output  # without --stops the stops are not simulated: nothing moves them


def test_the_critical_figure_draws_a_predictor_per_scanned_value():
    """critical_figure: one quasi-static value per scanned value (a length) is a line through them; one value, or
    the same at every scanned value (a damping), is the horizontal line."""
    import numpy as np

    from mechcont.outputs.critical_plots import critical_figure

    brackets = [(24.3, 24.6), (19.8, 20.0)]
    truth = [fold_speed(1.0, d=0.25), fold_speed(1.5, d=0.25)]
    for qs, drawn in ((truth, truth), (truth[0], [truth[0]] * 2), ([truth[0]] * 2, [truth[0]] * 2)):
        fig = critical_figure([1.0, 1.5], brackets, qs)
        (line,) = [ln for ln in fig.axes[0].get_lines() if ln.get_label().startswith("quasi-static")]
        y = np.asarray(line.get_ydata(), dtype=float)
        assert np.allclose(y, drawn[0] if np.ptp(drawn) == 0 else drawn, rtol=1e-12), (qs, y)


def _column(rows: list[dict[str, str]], name: str) -> list[float]:
    (key,) = [k for k in rows[0] if k.split(" [")[0] == name]
    return [float(row[key]) for row in rows]


def test_set_length_reaches_the_fold_its_curve_and_its_sensitivities(tmp_path):
    """--set L (the bar's length, and the points written in it: the drag's end L/2, the damper's anchor 2 L):
    the fold of continue, the fold curve of folds --point moved to other --set values than the row's, and the
    sensitivities of sensitivity --point there, against U_c = sqrt(2 m g / (rho C_D d L))."""
    table = tmp_path / "b.csv"
    r = run("continue", PATH, "--set", "L=1.5", "--vary", "U", "--start", "angle=-0.5", "--bounds", "U=0:60",
            "--out", table, "--quiet")
    assert r.exit_code == 0, r.output
    rows = csv_rows(table)
    (lp,) = [row for row in rows if row["label"] == "LP"]
    assert float(lp["U [m/s]"]) == pytest.approx(fold_speed(L=1.5), rel=1e-9)
    curve = tmp_path / "f.csv"
    r = run("folds", PATH, "--point", f"{table}:LP1", "--along", "m", "--set", "L=2", "--set", "d=0.3",
            "--bounds", "m=5:20", "--out", curve, "--quiet")
    assert r.exit_code == 0, r.output
    rows = csv_rows(curve)
    assert len(rows) > 5 and set(_column(rows, "L")) == {2.0} and set(_column(rows, "d")) == {0.3}
    for m, U in zip(_column(rows, "m"), _column(rows, "U")):
        assert U == pytest.approx(fold_speed(L=2.0, d=0.3, m=m), rel=1e-9)
    r = run("sensitivity", PATH, "--point", f"{table}:LP1", "--params", "m,L,d", "--set", "L=2")
    assert r.exit_code == 0, r.output
    U = fold_speed(L=2.0)
    assert float(re.search(r"at U = (\S+) m/s", r.output).group(1)) == pytest.approx(U, rel=1e-9)
    for name, value in (("m", 10.0), ("L", 2.0), ("d", 0.2)):  # U ~ sqrt(m / (d L)): dU/dp = +-U / (2 p)
        got = float(re.search(rf"^\s+{name}\s+(\S+)", r.output, re.M).group(1))
        assert got == pytest.approx((1 if name == "m" else -1) * U / (2 * value), rel=1e-8), name


def test_cycles_start_at_the_hopf_point_of_the_set_damping(tmp_path):
    """cycles --point HB1 --set c: the row is at c = 0.05, the family is born at the Hopf point of c = 0.08
    (the damped Ziegler column's flutter load and period, from its linearisation by numpy)."""
    from test_fresh_dynamics_mechanism import _flutter

    data = "tests/data/fresh/ziegler_pivot.toml"
    table = tmp_path / "z.csv"
    r = run("continue", data, "--vary", "P", "--bounds", "P=0:3", "--set", "c=0.05", "--dynamic", "--out", table,
            "--quiet")
    assert r.exit_code == 0, r.output
    out = tmp_path / "c.csv"
    r = run("cycles", data, "--set", "c=0.08", "--point", f"{table}:HB1", "--vary", "P", "--bounds", "P=1:2",
            "--max-steps", "2", "--out", out, "--quiet")
    assert r.exit_code == 0, r.output
    (hb,) = [row for row in csv_rows(out) if row["label"] == "HB"]
    P, omega = _flutter(0.08)
    assert abs(P - _flutter(0.05)[0]) > 1e-3  # the damping moves the Hopf point
    assert float(hb["P [N]"]) == pytest.approx(P, rel=1e-9)
    assert float(hb["period [s]"]) == pytest.approx(2 * math.pi / omega, rel=1e-8)
