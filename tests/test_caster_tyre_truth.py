"""A castering wheel with a torsion spring, a rotary damper and a linear stretched-string tyre with pneumatic trail
(tests/data/caster_tyre*.toml, written from docs/mechanism-format.md), through `continue --dynamic`, against its
linear stability derived from the physics.

Swivel angle psi about the fixed pivot, contact point e behind it, side force F = C y / sigma acting e + t behind
the pivot along the lateral axis (moment -(e + t) F), deflection rate dy/dt = e psi' + V sin psi - (V / sigma) y:

    I psi'' + c psi' + k psi + (e + t) C y / sigma = 0,    dy/dt = e psi' + V sin psi - V y / sigma.

Linearised, the characteristic polynomial is the cubic I s^3 + (c + I V/sigma) s^2 + (k + c V/sigma + e (e + t) C /
sigma) s + V (k + (e + t) C) / sigma; Routh-Hurwitz puts the Hopf speed where a2 a1 = a3 a0, omega^2 = a1 / a3. The
only nonlinearity is V sin psi, so Kuznetsov's l1 is Re(conj(p_y) (-V |q_psi|^2 q_psi)) / (2 omega) (B = 0).
The same wheel in millimetres and grams, and with its pivot and body frame moved, gives the same answers.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner
from scipy.optimize import brentq

DATA = Path(__file__).resolve().parent / "data"
I_W, C_D, K, E, T_P, SIGMA, C_Y = 0.5, 2.0, 2000.0, 0.1, 0.02, 0.3, 5.0e4


def _truth(scale_len: float = 1.0, scale_mass: float = 1.0):
    """(V_H, omega, l1) in the file's units: lengths times ``scale_len``, masses times ``scale_mass``."""
    def cubic(V):
        return [I_W, C_D + I_W * V / SIGMA, K + C_D * V / SIGMA + E * (E + T_P) * C_Y / SIGMA, V * (K + (E + T_P) * C_Y) / SIGMA]

    def hurwitz(V):
        a3, a2, a1, a0 = cubic(V)
        return a2 * a1 - a3 * a0

    V = brentq(hurwitz, 0.1, 10.0, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    omega = math.sqrt(cubic(V)[2] / I_W)
    # l1 in the file's units: states psi (rad), psi' (rad/s), y (length unit)
    L, M = scale_len, scale_mass
    i, c, k, e, t, s, C, v = I_W * M * L**2, C_D * M * L**2, K * M * L**2, E * L, T_P * L, SIGMA * L, C_Y * M * L, V * L
    A = np.array([[0, 1, 0], [-k / i, -c / i, -(e + t) * C / (s * i)], [v, e, -v / s]])
    lam, R = np.linalg.eig(A)
    q = R[:, np.argmin(abs(lam - 1j * omega))]
    q /= np.linalg.norm(q)
    lamT, W = np.linalg.eig(A.T)
    p = W[:, np.argmin(abs(lamT + 1j * omega))]
    p /= np.conj(np.vdot(p, q))
    l1 = float(np.real(np.conj(p[2]) * (-v * abs(q[0]) ** 2 * q[0]))) / (2 * omega)
    return V * L, omega, l1


@pytest.fixture(scope="module")
def run():
    return make_runner()


def _hb(run, tmp_path, name, lo, hi):
    out = tmp_path / f"{name}.csv"
    res = run("continue", DATA / f"{name}.toml", "--vary", "V", "--bounds", f"V={lo}:{hi}", "--dynamic", "--out", out)
    assert res.exit_code == 0, res.output
    with open(out, newline="") as fh:
        (row,) = [r for r in csv.DictReader(fh) if r["label"] == "HB"]
    line = next(ln for ln in res.output.splitlines() if ln.startswith("HB1 at"))
    return float(row[next(k for k in row if k.startswith("V "))]), float(row["leading_frequency [rad/s]"]), \
        float(line.split("l1 = ")[1].split(":")[0]), line


@pytest.mark.parametrize("name, length, mass, l1_tol", [
    ("caster_tyre", 1.0, 1.0, 1e-4),            # measured 6e-6 (the old steps, sized by psi', 1.1e-2)
    ("caster_tyre_mm_g", 1e3, 1e3, 2e-3),       # measured 4e-4 (1.1e-2): the dependent coordinates' Newton noise
    ("caster_tyre_moved", 1.0, 1.0, 2e-3),      # measured 2e-4 (1.2e-2)
])
def test_shimmy_onset_speed_frequency_and_lyapunov_coefficient(run, tmp_path, name, length, mass, l1_tol):
    V, omega, l1 = _truth(length, mass)
    got_V, got_omega, got_l1, line = _hb(run, tmp_path, name, 0.5 * length, 50 * length)
    assert got_V == pytest.approx(V, rel=1e-10)
    assert got_omega == pytest.approx(omega, rel=1e-10)
    assert got_l1 == pytest.approx(l1, rel=l1_tol)  # printed to 6 digits
    assert "supercritical" in line


def test_saturating_tyre_cycles_against_an_integration_of_the_physics(run, tmp_path):
    """With F = F_max tanh(C y / (sigma F_max)) the Hopf point is the same and the stable cycles at V = 3 and 6 m/s
    are those a long integration of the equations above settles on; the table's velocity columns carry rad/s."""
    from scipy.integrate import solve_ivp

    branch = tmp_path / "b.csv"
    res = run("continue", DATA / "caster_tyre_saturating.toml", "--vary", "V", "--bounds", "V=0.5:10", "--dynamic",
              "--out", branch)
    assert res.exit_code == 0, res.output
    cycles = tmp_path / "c.csv"
    res = run("cycles", DATA / "caster_tyre_saturating.toml", "--point", f"{branch}:HB1", "--vary", "V",
              "--bounds", "V=0.5:10", "--at", "V=3,6", "--out", cycles)
    assert res.exit_code == 0, res.output
    with open(cycles, newline="") as fh:
        rows = [r for r in csv.DictReader(fh) if r["label"] == "UZ"]
    assert "max_theta_wheel_dot [rad/s]" in rows[0]
    f_max = 2000.0
    for row in rows:
        V = float(row["V [m/s]"])

        def rhs(_, z, V=V):
            psi, w, y = z
            F = f_max * math.tanh(C_Y * y / (SIGMA * f_max))
            return [w, (-K * psi - C_D * w - (E + T_P) * F) / I_W, E * w + V * math.sin(psi) - V * y / SIGMA]
        turn = lambda _, z: z[1]  # noqa: E731
        turn.direction = -1
        # the transient coarsely (the multiplier 0.86 per 0.09 s leaves ~1e-13 of it after 16 s), then finely
        z = solve_ivp(rhs, [0, 16], [0.05, 0, 0], method="DOP853", rtol=1e-8, atol=1e-10).y[:, -1]
        sol = solve_ivp(rhs, [0, 0.3], z, method="DOP853", rtol=1e-12, atol=1e-13, events=turn, dense_output=True)
        t0, t1 = sol.t_events[0][-2:]
        psi = sol.sol(np.linspace(t0, t1, 20001))[0]
        assert float(row["period [s]"]) == pytest.approx(t1 - t0, rel=1e-7)
        # the table's max is over the nodes and collocation points (about 2 pi / 160 apart): within 1 - cos of that
        assert float(row["max_theta_wheel [rad]"]) == pytest.approx(psi.max(), rel=1e-3)
        assert row["stability"] == "stable"


def test_simulate_writes_the_history_of_a_mechanism_with_a_tyre(run, tmp_path):
    """`simulate --out` on a mechanism with element states (no energy audit: the tyre's deflection stores and
    dissipates energy the audit does not count) writes its table, exit 0 (it stopped at 'this history has no energy
    audit', exit 2, nothing written), and the swivel angle follows an integration of the physics."""
    from scipy.integrate import solve_ivp

    out = tmp_path / "sim.csv"
    res = run("simulate", DATA / "caster_tyre_saturating.toml", "--set", "V=3", "--start", "theta_wheel=0.05",
              "--until", "0.2", "--method", "Radau", "--rtol", "1e-10", "--atol", "1e-12", "--out", out)
    assert res.exit_code == 0, res.output
    assert "no energy balance" in res.output
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    t = np.array([float(r["t [s]"]) for r in rows])
    theta = np.array([float(r["theta_wheel [rad]"]) for r in rows])
    f_max, V = 2000.0, 3.0

    def rhs(_, z):
        psi, w, y = z
        F = f_max * math.tanh(C_Y * y / (SIGMA * f_max))
        return [w, (-K * psi - C_D * w - (E + T_P) * F) / I_W, E * w + V * math.sin(psi) - V * y / SIGMA]
    truth = solve_ivp(rhs, [0, t[-1]], [0.05, 0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-13, t_eval=t).y[0]
    assert np.max(np.abs(theta - truth)) < 1e-8  # measured 1e-12 at 0.5 s (the tolerances asked: 1e-10)
