"""Cycles of a closed-loop mechanism (issue 35, item 4): tests/data/fourbar_shimmy.toml, a caster wheel steered
through a four-bar (9 coordinates, 8 loop-closure rows, one tyre state), against the independent one-angle Lagrange
model of tests/fourbar_shimmy_reference.py: its Hopf speeds in closed form (the Routh-Hurwitz quadratic), its limit
cycles by long DOP853 integrations, their Floquet multipliers by central differences of that flow. The loop closure
is checked on the written coordinates with the linkage's own geometry (not the program's constraint rows)."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import fourbar_shimmy_reference as ref
import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from scipy.interpolate import CubicHermiteSpline

from mechcont.continuation import ContinuationOptions, cycles_from_hopf, find_equilibrium
from mechcont.equations import dynamics_of, ode_model
from mechcont.errors import ConvergenceError
from mechcont.mechanism import parse_description

DATA = Path(__file__).parent / "data" / "fourbar_shimmy.toml"
SPEEDS = (2.0, 5.0)


def _rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def _closure(get) -> float:
    """The largest gap (m) of the linkage's four pins from the coordinates ``get(name)`` (arrays): the wheel's arm
    point on the coupler's end a, the coupler's end b on the crank's end b, the crank's end a on B, the wheel on O."""
    tw, tc, tk = get("theta_wheel"), get("theta_crank"), get("theta_coupler")
    wx, wy = get("x_wheel"), get("y_wheel")
    arm = (wx - ref.RA * np.sin(tw), wy + ref.RA * np.cos(tw))
    k_a = (get("x_coupler") - 0.5 * ref.B * np.cos(tk), get("y_coupler") - 0.5 * ref.B * np.sin(tk))
    k_b = (get("x_coupler") + 0.5 * ref.B * np.cos(tk), get("y_coupler") + 0.5 * ref.B * np.sin(tk))
    c_a = (get("x_crank") - 0.5 * ref.A * np.cos(tc), get("y_crank") - 0.5 * ref.A * np.sin(tc))
    c_b = (get("x_crank") + 0.5 * ref.A * np.cos(tc), get("y_crank") + 0.5 * ref.A * np.sin(tc))
    gaps = [arm[i] - k_a[i] for i in (0, 1)] + [k_b[i] - c_b[i] for i in (0, 1)]
    gaps += [c_a[0] - ref.BX, c_a[1], wx, wy]
    return float(max(np.max(np.abs(g)) for g in gaps))


@pytest.fixture(scope="module")
def truth():
    """The reference's Hopf speeds and frequencies, and per speed of SPEEDS its cycle and multipliers."""
    speeds, omegas = ref.hopf_speeds()
    cycles = {}
    for V in SPEEDS:
        period, lo, hi, z = ref.cycle(V, t_end=20.0)
        mu = np.linalg.eigvals(ref.monodromy(V, z, period))
        cycles[V] = (period, lo, hi, mu[np.argsort(-np.abs(mu))])
    return speeds, omegas, cycles


@pytest.fixture(scope="module")
def cli(tmp_path_factory):
    """``continue --dynamic`` in V and ``cycles`` from its HB1 with rows at SPEEDS, run once: the file paths."""
    d = tmp_path_factory.mktemp("fourbar")
    run = make_runner()
    b, c, o = d / "b.csv", d / "c.csv", d / "o.csv"
    r = run("continue", DATA, "--vary", "V", "--bounds", "V=0.3:20", "--dynamic", "--out", b, "--quiet")
    assert r.exit_code == 0, r.output
    r = run("cycles", DATA, "--point", f"{b}:HB1", "--vary", "V", "--bounds", "V=0.5:5.5", "--at",
            ",".join(["V=" + str(SPEEDS[0]), *map(str, SPEEDS[1:])]), "--out", c, "--orbits", o, "--quiet")
    assert r.exit_code == 0, r.output
    return {"branch": b, "cycles": c, "orbits": o, "run": run, "dir": d}


def test_hopf_speeds_of_the_closed_loop_match_the_routh_hurwitz_closed_form(cli, truth):
    speeds, omegas, _ = truth
    rows = _rows(cli["branch"])
    hb = [r for r in rows if r["label"].startswith("HB")]
    assert len(hb) == 2
    for r, v, w in zip(hb, speeds, omegas):
        assert float(r["V [m/s]"]) == pytest.approx(v, rel=1e-8)
        assert float(r["leading_frequency [rad/s]"]) == pytest.approx(w, rel=1e-8)
    # the steered equilibrium (preloaded joints) of the reference, on every row; shimmy between the speeds only
    psi = ref.equilibrium()
    for r in rows:
        assert float(r["theta_wheel [rad]"]) == pytest.approx(psi, abs=1e-12)
        if not r["label"].startswith("HB"):
            assert (int(float(r["n_unstable_dynamic"])) > 0) == (speeds[0] < float(r["V [m/s]"]) < speeds[1])


def test_cycles_table_and_orbits_match_the_long_simulations_and_keep_the_loop_closed(cli, truth):
    speeds, omegas, cycles = truth
    rows = _rows(cli["cycles"])
    assert rows[0]["label"] == "HB" and float(rows[0]["V [m/s]"]) == pytest.approx(speeds[0], rel=1e-8)
    assert float(rows[0]["period [s]"]) == pytest.approx(2 * math.pi / omegas[0], rel=1e-8)
    uz = [r for r in rows if r["label"] == "UZ"]
    assert [float(r["V [m/s]"]) for r in uz] == pytest.approx(list(SPEEDS), abs=1e-12)
    for r, V in zip(uz, SPEEDS):
        period, lo, hi, mu = cycles[V]
        # NTST 20, NCOL 4: the period's error is of order h^8 (measured 1e-9 relative against the reference)
        assert float(r["period [s]"]) == pytest.approx(period, rel=1e-7)
        # min/max over the nodes and Gauss points only: 160 samples a period miss a peak by ~ psi'' dt^2 / 8 ~ 4e-5
        assert float(r["min_theta_wheel [rad]"]) == pytest.approx(lo, abs=5e-5)
        assert float(r["max_theta_wheel [rad]"]) == pytest.approx(hi, abs=5e-5)
        assert float(r["floquet_max"]) == pytest.approx(abs(mu[1]), abs=1e-6)  # mu[0] is the trivial one
        assert r["stability"] == "stable" and int(r["n_unstable"]) == 0
    # the loop is closed at every written instant of every orbit (48 a period), by the linkage's own geometry
    orb = _rows(cli["orbits"])
    assert len(orb) == 49 * len(rows)
    gap = _closure(lambda name: np.array([float(r[f"{name} [{'rad' if name.startswith('theta') else 'm'}]"])
                                          for r in orb]))
    assert gap < 1e-10


@pytest.fixture(scope="module")
def family():
    """The family from HB1 in the Python API, with rows at SPEEDS (dense orbits, node vectors, multipliers)."""
    speeds, _ = ref.hopf_speeds()
    model = parse_description(DATA.read_text()).build(V=speeds[0])
    x = find_equilibrium(model)
    fam = cycles_from_hopf(model, x, "V", at=list(SPEEDS), options=ContinuationOptions(bounds={"V": (0.5, 5.5)}))
    return model, fam


def test_every_collocation_node_closes_the_loop_and_the_spectrum_has_the_minimal_dimension(family, truth):
    model, fam = family
    _, _, cycles = truth
    dyn = dynamics_of(model)
    # the minimal state: the wheel's angle, its rate, the tyre's deflection (not 9 coordinates and 9 rates)
    assert dyn.state_names == ("theta_wheel", "theta_wheel_dot", "y_tyre")
    mech = model.mechanics
    names = list(model.names)
    for i in range(len(fam)):
        mesh, u = fam.orbits[i]
        xv = fam.x_base.copy()
        xv[model.index("V")] = fam.p[i]
        full = np.array([dyn.full_vector(z, xv) for z in u])
        assert _closure(lambda name, full=full: full[:, names.index(name)]) < 1e-10
        vel = np.array([mech.phi_q(f) @ dyn.coordinate_velocities(z, xv) for f, z in zip(full, u)])
        assert np.max(np.abs(vel)) < 1e-9  # and the velocities are tangent to the loop
        # 3 states - the trivial multiplier (at the Hopf row also the critical pair): the constraints add none
        assert len(fam.multipliers[i]) == (1 if fam.labels[i] == "HB" else 2)
    for V in SPEEDS:
        i = fam.row(f"UZ{SPEEDS.index(V) + 1}")
        period, lo, hi, mu = cycles[V]
        _, Z = fam.orbit(i, samples=20000)
        assert fam.period[i] == pytest.approx(period, rel=1e-7)
        # between the mesh points the error is of order h^5: 1e-6 of the amplitude
        assert Z[:, 0].min() == pytest.approx(lo, abs=1e-7)
        assert Z[:, 0].max() == pytest.approx(hi, abs=1e-7)
        # the non-trivial multipliers: those of the reference's flow (one real pair: 0.52 and 0.0019 at V = 2)
        np.testing.assert_allclose(np.sort(np.abs(fam.multipliers[i])), np.sort(np.abs(mu[1:])), atol=1e-6)
        assert np.min(np.abs(fam.multipliers[i] - 1.0)) > 0.1
        assert fam.stability()[i] == "stable"


def _extrema(path, t_from):
    """``(period, min, max)`` of theta_wheel in a simulate table after ``t_from``: its extrema located on the cubic
    Hermite interpolant of the rows (angle and rate, error ~ omega^4 A dt^4 / 384)."""
    rows = _rows(path)
    t = np.array([float(r["t [s]"]) for r in rows])
    keep = np.concatenate([[True], np.diff(t) > 0])  # an event's row repeats its time
    psi = np.array([float(r["theta_wheel [rad]"]) for r in rows])[keep]
    w = np.array([float(r["theta_wheel_dot [rad/s]"]) for r in rows])[keep]
    spl = CubicHermiteSpline(t[keep], psi, w)
    roots = spl.derivative().roots(extrapolate=False)
    roots = roots[roots > t_from]
    values = spl(roots)
    maxima = roots[spl.derivative(2)(roots) < 0]
    return float(np.mean(np.diff(maxima))), float(values.min()), float(values.max())


@pytest.mark.slow
def test_simulate_from_near_the_orbit_converges_onto_the_computed_cycle(cli, family):
    """``mechcont simulate`` (full coordinates, the loop held by its own constraint stabilisation: not the
    minimal coordinates of the collocation) from the wheel at 0.1 rad at rest, at V = 2 m/s: after 16 s (26
    periods; the cycle attracts by its multiplier 0.52 a period) its last 2 s have the computed cycle's period
    and extremes."""
    _, fam = family
    out = cli["dir"] / "h.csv"
    r = cli["run"]("simulate", DATA, "--set", "V=2", "--start", "theta_wheel=0.1", "--until", "16", "--rtol", "1e-10",
                   "--atol", "1e-12", "--out", out, "--no-progress")
    assert r.exit_code == 0, r.output
    period, lo, hi = _extrema(out, 14.0)
    i = fam.row("UZ1")
    _, Z = fam.orbit(i, samples=20000)
    # the distance left after 26 periods (0.03 rad x 0.52^23 ~ 1e-8), the tolerances' and the interpolation's errors
    # (measured: 2e-8 relative in the period, 3e-9 rad in the extremes)
    assert period == pytest.approx(fam.period[i], rel=2e-7)
    assert lo == pytest.approx(Z[:, 0].min(), abs=1e-7)
    assert hi == pytest.approx(Z[:, 0].max(), abs=1e-7)


def test_cycles_of_a_mechanism_from_a_point_that_is_not_a_hopf_point_is_one_line(cli):
    run, b = cli["run"], cli["branch"]
    one_line_error(run("cycles", DATA, "--point", f"{b}:EP1", "--vary", "V"), "--point", "EP")
    one_line_error(run("cycles", DATA, "--point", f"{b}:3", "--vary", "V"), "--point")
    # the table's HB1 at other parameter values: the Hopf speed is elsewhere
    one_line_error(run("cycles", DATA, "--point", f"{b}:HB1", "--vary", "V", "--set", "c=1"), "--point",
                   "not a Hopf point")


class _LoopThatLocks:
    """The Stuart-Landau oscillator's dynamics whose rates cannot be evaluated beyond the radius 0.1 (as a
    mechanism's where its loop no longer assembles: MechanismDynamics raises ConvergenceError there)."""

    def __init__(self, dyn):
        self._dyn = dyn

    def __getattr__(self, name):
        if name.endswith("_batch"):  # point by point through the checks below
            raise AttributeError(name)
        return getattr(self._dyn, name)

    def _check(self, z):
        if float(z[0] ** 2 + z[1] ** 2) > 0.01:
            raise ConvergenceError(f"the dependent coordinates did not close the constraints at {z}")

    def rates(self, z, x):
        self._check(z)
        return self._dyn.rates(z, x)

    def rates_jacobian(self, z, x):
        self._check(z)
        return self._dyn.rates_jacobian(z, x)

    def parameter_rates(self, z, x, names):
        self._check(z)
        return self._dyn.parameter_rates(z, x, names)


def test_a_family_reaching_where_the_rates_fail_ends_there_keeping_its_orbits(monkeypatch):
    """A rate that cannot be evaluated at a predicted orbit (a closed loop past its toggle position) is a failed
    correction: the step shrinks, and the family ends there with its orbits (r = sqrt(mu) up to 0.1) and a message,
    instead of the error escaping the continuation with everything lost."""
    import sympy as sp

    import mechcont.equations as equations

    x, y, mu = sp.symbols("x y mu", real=True)
    model = ode_model("sl", {"x": 0.0, "y": 0.0}, {"mu": 0.0},
                      {"x": mu * x - y - x * (x**2 + y**2), "y": x + mu * y - y * (x**2 + y**2)})
    real = equations.dynamics_of
    monkeypatch.setattr(equations, "dynamics_of", lambda m, *a, **k: _LoopThatLocks(real(m, *a, **k)))
    fam = cycles_from_hopf(model, model.defaults(), "mu", options=ContinuationOptions(bounds={"mu": (-1.0, 1.0)}))
    assert not fam.status.success and "the rates fail along the orbit" in fam.message
    assert "did not close the constraints" in fam.message
    assert len(fam) > 3 and fam.labels[0] == "HB"
    radius = np.sqrt(np.max(fam.maximum[:, :2] ** 2, axis=1))
    assert 0.05 < radius.max() <= 0.1
    np.testing.assert_allclose(fam.maximum[1:, 0], np.sqrt(fam.p[1:]), rtol=1e-6)


SPATIAL = Path(__file__).parent / "data" / "spatial" / "fourbar_shimmy_3d.toml"


def _rotation(e0, e1, e2, e3):
    """Rotation matrices (m, 3, 3) of Euler parameters (arrays)."""
    return np.moveaxis(np.array([
        [1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
        [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1)],
        [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)]]), -1, 0)


def _closure_3d(get) -> float:
    """The largest gap (m, or 1 for the axes and norms) of the spatial linkage from its coordinates ``get(name)``:
    the four pins as in :func:`_closure`, each body's z axis on the global z (the revolute axes), unit Euler
    parameters."""
    bodies = {}
    gaps = []
    for b in ("wheel", "crank", "coupler"):
        e = [get(f"e{k}_{b}") for k in range(4)]
        gaps.append(sum(c * c for c in e) - 1.0)
        R = _rotation(*e)
        gaps += [R[:, 0, 2], R[:, 1, 2]]
        bodies[b] = (np.stack([get(f"x_{b}"), get(f"y_{b}"), get(f"z_{b}")], axis=1), R)

    def point(b, p):
        o, R = bodies[b]
        return o + R @ np.array(p, float)

    gaps += list((point("wheel", [0, 0, 0])).T)
    gaps += list((point("wheel", [0, ref.RA, 0]) - point("coupler", [-0.5 * ref.B, 0, 0])).T)
    gaps += list((point("coupler", [0.5 * ref.B, 0, 0]) - point("crank", [0.5 * ref.A, 0, 0])).T)
    gaps += list((point("crank", [-0.5 * ref.A, 0, 0]) - np.array([ref.BX, 0.0, 0.0])).T)
    return float(max(np.max(np.abs(g)) for g in gaps))


@pytest.mark.slow
def test_spatial_closed_loop_has_the_planar_hopf_speeds_and_cycle_with_every_row_closed(truth, tmp_path):
    """The same linkage in a spatial description (Euler parameters, the loop's out-of-plane rows redundant and
    dropped): its dynamic stability near the Hopf speeds (the Hopf test's gradient differences the linearisation
    off the constraint manifold, where the dropped rows turn independent), its Hopf speeds and its cycle at V = 2
    m/s are the planar reference's, and every written instant closes the loop."""
    speeds, omegas, cycles = truth
    run = make_runner()
    b, c, o = tmp_path / "b.csv", tmp_path / "c.csv", tmp_path / "o.csv"
    r = run("continue", SPATIAL, "--vary", "V", "--bounds", "V=0.3:20", "--dynamic", "--out", b, "--quiet")
    assert r.exit_code == 0, r.output
    hb = [row for row in _rows(b) if row["label"].startswith("HB")]
    assert len(hb) == 2
    for row, v, w in zip(hb, speeds, omegas):
        assert float(row["V [m/s]"]) == pytest.approx(v, rel=1e-8)
        assert float(row["leading_frequency [rad/s]"]) == pytest.approx(w, rel=1e-8)
    r = run("cycles", SPATIAL, "--point", f"{b}:HB1", "--vary", "V", "--bounds", "V=0.5:2.1", "--at", "V=2",
            "--out", c, "--orbits", o, "--quiet")
    assert r.exit_code == 0, r.output
    rows = _rows(c)
    (uz,) = [row for row in rows if row["label"] == "UZ"]
    period, lo, hi, mu = cycles[2.0]
    assert float(uz["period [s]"]) == pytest.approx(period, rel=1e-7)
    assert float(uz["floquet_max"]) == pytest.approx(abs(mu[1]), abs=1e-6)
    assert uz["stability"] == "stable"
    orb = _rows(o)
    assert len(orb) == 49 * len(rows)
    unit = {"x": " [m]", "y": " [m]", "z": " [m]"}
    assert _closure_3d(lambda name: np.array([float(row[name + unit.get(name[0], "")]) for row in orb])) < 1e-10


def test_cycles_table_has_the_extremes_of_the_dependent_coordinates_too(cli, truth):
    """The crank's and the coupler's angles are dependent coordinates (the wheel's is the state): their extremes
    over each orbit are columns of the table too. Truth: the wheel sweeps [lo, hi] of the reference cycle, so a
    loop angle sweeps its image under the reference's closed-form kinematics (the crank's is not monotone: it
    turns inside the sweep)."""
    _, _, cycles = truth
    uz = [r for r in _rows(cli["cycles"]) if r["label"] == "UZ"]
    for r, V in zip(uz, SPEEDS):
        period, lo, hi, _ = cycles[V]
        psi = np.linspace(lo, hi, 2001)
        rate = max(abs(float(r["min_theta_wheel_dot [rad/s]"])), abs(float(r["max_theta_wheel_dot [rad/s]"])))
        for k, name in ((0, "theta_crank"), (1, "theta_coupler")):
            kin = np.array([ref.kinematics(p) for p in psi])
            angle, slope, curve = kin[:, k], kin[:, k + 2], kin[:, k + 4]
            # sampled at the nodes and Gauss points (gaps below T/100): an extreme at the sweep's end is off by
            # the wheel's 5e-5 rad times the slope, one inside it by half its curvature times the half gap squared
            tol = 5e-5 * float(np.max(np.abs(slope))) + 0.5 * float(np.max(np.abs(curve))) * (
                rate * period / 200) ** 2 + 1e-9
            assert float(r[f"min_{name} [rad]"]) == pytest.approx(angle.min(), abs=tol)
            assert float(r[f"max_{name} [rad]"]) == pytest.approx(angle.max(), abs=tol)
    # the pinned wheel's position is a dependent coordinate that does not move
    for r in uz:
        assert abs(float(r["min_x_wheel [m]"])) < 1e-12 and abs(float(r["max_x_wheel [m]"])) < 1e-12
