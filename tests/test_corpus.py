"""A new user's corpus (issue 32): fresh mechanisms with stops and locks (tests/corpus/*.toml), each run
through the command line as a user would, each answer compared with an independent truth computed here
from the mechanism's own physics (a lever's moment balance in closed form, SciPy root finding and
integration), never with a number mechcont printed.

- brace_lock.toml, and the same lock in millimetres and grams (brace_lock_mm_g.toml): a lever pushed onto
  its stop by an over-centre strut. On the free branch F(theta) = (M_strut + M_weight) / (L cos theta);
  the stop releases at F(theta_s) and the unlock fold is where dF/dtheta = 0. check, continue --stops,
  folds (along l0) and downlock (along k) are compared with these.
- freefall_lock_leg.toml: a leg falling onto its downlock; freefall and simulate --stops against
  solve_ivp (rtol 1e-12) of theta'' = M(theta) / I_O, and the lock's reaction against -M(theta_lock).
- stay_downlock.toml: an over-centre side stay with its downlock declared; downlock along the leg load P
  against the stay's virtual work F(t) = -(Q_spring + Q_P) / (a cos t) and its folds either side.
- skew_hinge_stop_3d.toml: a spatial bar on a skewed hinge held by a tether stop; check's reaction
  against -V'(phi) / gap'(phi) at the taut angle, found by brentq on the bar's own rotation about n.

Tolerances: a value the CLI prints to 6 digits is compared to 1e-5 relative; table values (full double
precision) to 1e-8 relative (the folds and releases are polished to the solver's tolerance; the truth's
own error is below 1e-12); a simulation to 1e-5 (the integrator's error control).
"""

from __future__ import annotations

import csv
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner
from corpus.scaling import write_scaled
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

CORPUS = Path(__file__).parent / "corpus"


def _number(pattern: str, text: str) -> float:
    m = re.search(pattern, text)
    assert m, f"{pattern!r} not in:\n{text}"
    return float(m.group(1))


def _table(path: Path) -> list[dict[str, str]]:
    with path.open() as f:
        return list(csv.DictReader(f))


def _column(row: dict[str, str], name: str) -> float:
    return float(next(v for k, v in row.items() if k.split(" [")[0] == name))


# -- the brace lock: closed form -----------------------------------------------------------------------

#: brace_lock.toml's values (SI): the truth reads the same numbers, never mechcont's answers
BRACE = dict(m=3.0, L=0.8, a=0.5, Sx=0.9, k=20000.0, l0=0.6, g=9.81, theta_s=0.45)


def lever_force(theta, p=BRACE):
    """The tip force (N, + down) that holds the lever at ``theta`` off its stop: the moment balance about O.
    Complex-safe (the fold's derivative is taken by complex step)."""
    px, py = p["a"] * np.cos(theta), p["a"] * np.sin(theta)
    dx, dy = px - p["Sx"], py
    length = np.sqrt(dx * dx + dy * dy)
    tension = p["k"] * (length - p["l0"])  # < 0: the strut is compressed and pushes
    strut = -tension / length * (py * p["Sx"])  # P x (force on P), force = -tension (P - S)/|P - S|
    weight = -p["m"] * p["g"] * p["L"] / 2 * np.cos(theta)
    return (strut + weight) / (p["L"] * np.cos(theta))


def lever_slope(theta, p=BRACE):
    """dF/dtheta (N/rad) by complex step (exact to rounding)."""
    return float(np.imag(lever_force(theta + 1e-30j, p)) / 1e-30)


def lever_fold(p=BRACE) -> tuple[float, float]:
    """(theta, F) of the unlock fold: the largest F on the free branch below the stop."""
    theta = brentq(lambda t: lever_slope(t, p), 0.05, p["theta_s"], xtol=1e-15)
    return theta, float(lever_force(theta, p))


@pytest.mark.parametrize("name, L, M", [("brace_lock", 1.0, 1.0), ("brace_lock_mm_g", 1e3, 1e3)],
                         ids=["SI", "mm-g"])
def test_brace_lock(tmp_path, name, L, M):
    """check, continue --stops, folds and downlock on the brace lock, in SI and in mm and grams."""
    path, run = CORPUS / f"{name}.toml", make_runner()
    force, moment = L * M, L * L * M
    release = float(lever_force(BRACE["theta_s"]))
    t_fold, f_fold = lever_fold()

    r = run("check", path)
    assert r.exit_code == 0, r.output
    assert _number(r"reaction R_lock = (\S+)", r.output) == pytest.approx(
        release * BRACE["L"] * np.cos(BRACE["theta_s"]) * moment, rel=1e-5)

    out = tmp_path / "b.csv"
    r = run("continue", path, "--vary", "F", "--bounds", f"F={-100 * force}:{1500 * force}", "--bounds",
            "theta_lever=-1:1", "--stops", "--start", "angle=0.4", "--out", out)
    assert r.exit_code == 0, r.output
    rows = _table(out)
    stops = [row for row in rows if row["label"][:2] in ("SC", "SR")]
    folds = [row for row in rows if row["label"].startswith("LP")]
    assert len(stops) == 1 and len(folds) == 1, [row["label"] for row in rows if row["label"]]
    assert _column(stops[0], "F") / force == pytest.approx(release, rel=1e-8)
    assert _column(folds[0], "F") / force == pytest.approx(f_fold, rel=1e-8)
    assert _column(folds[0], "theta_lever") == pytest.approx(t_fold, abs=1e-7)

    # the fold followed in l0: every row is a fold of the lever at its own l0
    out = tmp_path / "f.csv"
    r = run("folds", path, "--start", "angle=0.4", "--vary", "F", "--along", "l0",
            "--bounds", f"l0={0.55 * L}:{0.65 * L}", "--out", out)
    assert r.exit_code == 0, r.output
    rows = _table(out)
    assert len(rows) >= 3
    l0s = [_column(row, "l0") / L for row in rows]
    assert min(l0s) == pytest.approx(0.55) and max(l0s) == pytest.approx(0.65)
    for row in rows:
        p = dict(BRACE, l0=_column(row, "l0") / L)
        t = _column(row, "theta_lever")
        assert _column(row, "F") / force == pytest.approx(float(lever_force(t, p)), rel=1e-8)
        assert lever_slope(t, p) == pytest.approx(0.0, abs=1e-7 * abs(float(lever_force(t, p))))

    # downlock along k: the lock's preload and its unlock fold at each k
    out = tmp_path / "d.csv"
    r = run("downlock", path, "--force", "F", "--vary", "k", "--bounds", f"k={15000 * M}:{25000 * M}", "--out", out)
    assert r.exit_code == 0, r.output
    rows = _table(out)
    assert len(rows) >= 3
    for row in rows:
        p = dict(BRACE, k=_column(row, "k") / M)
        held = float(lever_force(p["theta_s"], p)) * p["L"] * np.cos(p["theta_s"])
        assert _column(row, "R_lock") / moment == pytest.approx(held, rel=1e-8)
        assert _column(row, "unlock_F") / force == pytest.approx(lever_fold(p)[1], rel=1e-8)


# -- the falling leg: its own integrator ---------------------------------------------------------------

def leg_fall(path: Path) -> tuple[float, float, float]:
    """(time to lock s, impact speed rad/s, lock reaction N m) of freefall_lock_leg.toml from rest at 0.3 rad."""
    doc = tomllib.loads(path.read_text())
    p = {k: v["value"] for k, v in doc["parameters"].items()}
    S = np.array(doc["ground"]["S"], dtype=float)
    lock = doc["stops"]["downlock"]["min"]

    def moment(t):
        P = p["a"] * np.array([np.cos(t), np.sin(t)])
        d = P - S
        tension = p["k"] * (np.linalg.norm(d) - p["l0"])
        return -tension / np.linalg.norm(d) * (P[0] * d[1] - P[1] * d[0]) - p["m"] * p["g"] * p["c"] * np.cos(t)

    inertia = p["I"] + p["m"] * p["c"] ** 2

    def hit(t, y):
        return y[0] - lock
    hit.terminal = True  # type: ignore[attr-defined]
    sol = solve_ivp(lambda t, y: [y[1], moment(y[0]) / inertia], (0.0, 3.0), [0.3, 0.0], events=hit,
                    rtol=1e-12, atol=1e-12)
    return float(sol.t_events[0][0]), float(abs(sol.y_events[0][0][1])), float(-moment(lock))


def test_leg_falls_onto_its_lock():
    """freefall and simulate --stops: the time and speed of the impact and the lock's reaction."""
    path, run = CORPUS / "freefall_lock_leg.toml", make_runner()
    t_lock, speed, reaction = leg_fall(path)
    r = run("freefall", path, "--start", "angle=0.3", "--lock", "downlock", "--until", "3")
    assert r.exit_code == 0, r.output
    assert "outcome: locked" in r.output
    assert _number(r"time to lock: (\S+) s", r.output) == pytest.approx(t_lock, rel=1e-5)
    assert _number(r"impact speed at the lock: (\S+) rad/s", r.output) == pytest.approx(speed, rel=1e-5)
    assert _number(r"peak stop reaction downlock: (\S+)", r.output) == pytest.approx(reaction, rel=1e-5)
    r = run("simulate", path, "--start", "angle=0.3", "--until", "1", "--stops")
    assert r.exit_code == 0, r.output
    assert _number(r"t = (\S+) s\s+impact\s+downlock", r.output) == pytest.approx(t_lock, rel=1e-6)
    assert _number(r"impact\s+downlock\s+speed (\S+) rad/s", r.output) == pytest.approx(speed, rel=1e-5)


# -- the skewed hinge: the bar's own rotation ------------------------------------------------------------

def skew_reaction(path: Path) -> float:
    """The tether's reaction (N) on skew_hinge_stop_3d.toml, from the bar's rotation about the hinge axis."""
    doc = tomllib.loads(path.read_text())
    p = {k: v["value"] for k, v in doc["parameters"].items()}
    n = np.array(doc["joints"]["hinge"]["axis"], dtype=float)
    n /= np.linalg.norm(n)
    x = np.array([1.0, 0.0, 0.0])  # the bar's axis in the design pose, normal to n
    assert abs(n @ x) < 1e-15
    Q = np.array(doc["ground"]["Q"], dtype=float)

    def axis(phi):  # the bar's axis after turning phi about n (right-handed)
        return np.cos(phi) * x + np.sin(phi) * np.cross(n, x)

    def gap(phi):
        return float(np.linalg.norm(p["L"] * axis(phi) - Q)) - p["d_max"]

    def potential(phi):
        return p["m"] * p["g"] * p["L"] / 2 * axis(phi)[2]

    hanging = minimize_scalar(potential, bounds=(0.0, np.pi), method="bounded", options={"xatol": 1e-12}).x
    taut = brentq(gap, 0.6, hanging, xtol=1e-15)  # from the start (phi ~ 0.3) towards the hanging pose
    h = 1e-6
    return -(potential(taut + h) - potential(taut - h)) / (gap(taut + h) - gap(taut - h))


@pytest.mark.parametrize("L, M", [(1.0, 1.0), (1e-3, 1.0), (1e6, 1.0), (1e3, 1e3)], ids=["SI", "km-kg", "um-kg", "mm-g"])
def test_skew_hinge_on_its_tether(tmp_path, L, M):
    """check: the spatial bar rests on its tether with the reaction of its own moment balance (N: x L M in
    the file rewritten with lengths x L, masses x M; in km the stop search's Newton weighed its rows
    against a floor of 1 and did not converge)."""
    path = CORPUS / "skew_hinge_stop_3d.toml"
    scaled = write_scaled(path, tmp_path / "skew.toml", L, M, labels=True)
    r = make_runner()("check", scaled)
    assert r.exit_code == 0, r.output
    assert _number(r"reaction R_tether = (\S+)", r.output) == pytest.approx(skew_reaction(path) * L * M, rel=1e-5)


# -- the side stay's downlock: virtual work ----------------------------------------------------------------

STAY = dict(a=0.5, b=0.6, k=8000.0, l0=0.3, Sx=0.3, Sy=-0.5)


def stay_force(t, P, p=STAY):
    """The knee force F (N, + up) that holds stay_downlock.toml's upper link at angle ``t`` under the leg
    load ``P`` (N): the virtual work of the lock spring, P at the slider end and F at the knee. Complex-safe."""
    a, b = p["a"], p["b"]
    c, s = np.cos(t), np.sin(t)
    kx, ky = a * c, a * s
    dkx, dky = -a * s, a * c
    dbx = -a * s - a * a * s * c / np.sqrt(b * b - a * a * s * s)
    dx, dy = kx - p["Sx"], ky - p["Sy"]
    length = np.sqrt(dx * dx + dy * dy)
    tension = p["k"] * (length - p["l0"])
    spring = -tension / length * (dx * dkx + dy * dky)
    return -(spring - P * dbx) / (a * c)


def stay_fold(P, side: int) -> float:
    """The first fold of F from the aligned stay (t = 0) towards ``side`` (+1: the knee rising, F increasing
    to it; -1: the other way): the first zero of dF/dt, bracketed on a grid and refined by brentq."""
    slope = lambda t: float(np.imag(stay_force(t + 1e-30j, P)) / 1e-30)  # noqa: E731
    grid = side * np.linspace(1e-3, 1.2, 241)
    k = next(i for i in range(240) if slope(grid[i]) * slope(grid[i + 1]) < 0)
    return float(stay_force(brentq(slope, grid[k], grid[k + 1], xtol=1e-15), P))


def test_stay_downlock(tmp_path):
    """downlock along P: the aligned stay's force (P does no work there: the same at every P) and the unlock
    folds either side, at every row."""
    run = make_runner()
    path, out = CORPUS / "stay_downlock.toml", tmp_path / "d.csv"
    r = run("check", path)
    assert r.exit_code == 0 and "findings: none" in r.output, r.output
    r = run("downlock", path, "--vary", "P", "--bounds", "P=1300:1550", "--out", out)
    assert r.exit_code == 0, r.output
    rows = _table(out)
    assert len(rows) >= 3
    for row in rows:
        P = _column(row, "P")
        assert _column(row, "aligned") == pytest.approx(0.0, abs=1e-12)
        assert _column(row, "F") == pytest.approx(float(stay_force(0.0, P)), rel=1e-9)
        assert _column(row, "unlock_F") == pytest.approx(stay_fold(P, +1), rel=1e-8)
        assert _column(row, "unlock_F_decreasing") == pytest.approx(stay_fold(P, -1), rel=1e-8)
