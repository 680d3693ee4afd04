"""Over-constrained mechanisms in time (issue 38): redundant rows left out of the solve by a pivoted QR
and chosen again where they lose rank (dynamics._redundant), checked against energy conservation and
independent minimal-coordinate models; ``check``'s equilibrium search on the same linkages."""

import math
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

from mechcont.dynamics import assemble, simulate
from mechcont.dynamics._redundant import KeptRows
from mechcont.dynamics._stall import UNRESOLVED, motion_warning
from mechcont.dynamics._udwadia_kalaba import ConstrainedDynamics
from mechcont.mechanism import load
from mechcont.mechanism._check import check_report

DATA = Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def bricard():
    return load(DATA / "spatial" / "bricard.toml")


def test_bricard_conserves_energy_and_swings_back(bricard):
    """Bricard's 6R loop (benchmark A04) released from rest: no friction, so E = -29.43 J throughout; at
    each turning point the kinetic energy is zero, so rod 3's end returns to its start (x = 1 m). On the
    old solve (all 35 rows, pseudo-inverse cut at 1e-8 of the drift-level singular value) it crawled:
    4658 evaluations for 2 s at rtol 1e-6 instead of ~550 (a smooth one-degree-of-freedom swing)."""
    x0 = assemble(bricard, {})
    r = simulate(bricard, x0, (0.0, 6.0), rtol=1e-8, atol=1e-10)
    assert r.success and not r.motion_warning
    E = r.energy["E_kin"] + r.energy["E_pot"]
    assert E[0] == pytest.approx(-29.43, abs=1e-12)
    assert np.max(np.abs(E - E[0])) < max(r.balance.bound, 1e-6)
    x3 = r["x_rod3"]
    back = np.flatnonzero((r.t > 3.0) & (x3 > 0.99))
    assert back.size and x3[back].max() == pytest.approx(1.0, abs=2e-3)  # the swing comes back
    assert x3.min() < -0.8  # and went through the bottom (x3 = 0 at the equilibrium) to the far side
    assert r.constraint_drift < 1e-8
    assert r.indeterminate_rows == len(r.t)  # the reactions of the over-constrained loop are indeterminate
    fast = simulate(bricard, x0, (0.0, 2.0))
    assert fast.nfev < 1200


def _rot(u: np.ndarray, t: float) -> np.ndarray:
    """Rotation by ``t`` about the unit vector ``u`` (Rodrigues)."""
    K = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * K @ K


class _Bricard6R:
    """bricard.toml as a joint-angle model, nothing of mechcont's: rod i turned by theta_i about joint i's axis
    relative to rod i-1 (theta_1 about J1 from the ground); the loop closed at J6 (rod 5's end on F, its J6
    axis along x: 5 equations, 4 unknowns theta_2..5, one redundant, consistent: least squares). One degree
    of freedom theta_1: T = m(theta_1) theta_1'^2 / 2 and V(theta_1) tabulated along the closed loop and
    splined, then m theta'' + m' theta'^2 / 2 + V' = 0 integrated by solve_ivp."""

    P = [np.array(p, float) for p in ([0, 0, 0], [1, 0, 0], [1, -1, 0], [1, -1, 1], [0, -1, 1], [0, 0, 1])]
    U = [np.array(u, float) for u in ([0, 1, 0], [0, 0, 1], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 0])]

    def __init__(self):
        self.inertia = [np.diag(np.where(np.abs(b - a) > 0.5, 0.02 / 12, 1.01 / 12)) for a, b in zip(self.P, self.P[1:])]

    def frames(self, th):
        R, X, out = np.eye(3), self.P[0], []
        for i in range(5):
            X = X if i == 0 else X + R @ (self.P[i] - self.P[i - 1])
            R = R @ _rot(self.U[i], th[i])
            out.append((R, X))
        return out

    def cgs(self, th):
        return [X + R @ ((b - a) / 2) for (R, X), a, b in zip(self.frames(th), self.P, self.P[1:])]

    def misfit(self, th):
        R, X = self.frames(th)[-1]
        axis = R @ self.U[5]
        return np.r_[X + R @ (self.P[5] - self.P[4]) - self.P[5], axis[1], axis[2]]

    def close(self, t1, y):
        y = np.array(y, float)
        for _ in range(50):
            J = np.column_stack([(self.misfit(np.r_[t1, y + h]) - self.misfit(np.r_[t1, y - h])) / 2e-7
                                 for h in np.eye(4) * 1e-7])
            dy = np.linalg.lstsq(J, -self.misfit(np.r_[t1, y]), rcond=None)[0]
            y = y + dy
            if np.abs(dy).max() < 1e-14:
                break
        assert np.abs(self.misfit(np.r_[t1, y])).max() < 1e-12
        return y

    def tables(self, grid, h=1e-6):
        """m (kg m^2) and V (J) at the theta_1 of ``grid``, the loop closed by continuation along it."""
        y, m, V = np.zeros(4), [], []
        for t1 in grid:
            y = self.close(t1, y)
            th = np.r_[t1, y]
            yp, ym = self.close(t1 + h, y), self.close(t1 - h, y)
            rate = np.r_[1.0, (yp - ym) / (2 * h)]
            vel = [(p - q) / (2 * h) for p, q in zip(self.cgs(np.r_[t1 + h, yp]), self.cgs(np.r_[t1 - h, ym]))]
            w, R, mk = np.zeros(3), np.eye(3), 0.0
            for i, (Ri, _) in enumerate(self.frames(th)):
                w = w + R @ self.U[i] * rate[i]  # joint i's axis is fixed in rod i-1
                R = Ri
                mk += vel[i] @ vel[i] + w @ (Ri @ self.inertia[i] @ Ri.T) @ w
            m.append(mk)
            V.append(9.81 * sum(c[1] for c in self.cgs(th)))
        return np.array(m), np.array(V)

    def rod3_centre(self, t):
        """Rod 3's centre (m) at the times ``t`` (up to 1 s) of the free swing from rest."""
        grid = np.linspace(-0.05, 1.15, 49)  # theta_1 reaches 1.035 rad at 1 s
        m, V = self.tables(grid)
        ms, Vs = CubicSpline(grid, m), CubicSpline(grid, V)
        dm, dV = ms.derivative(), Vs.derivative()
        sol = solve_ivp(lambda _, s: [s[1], -(0.5 * dm(s[0]) * s[1] ** 2 + dV(s[0])) / ms(s[0])], (0, t[-1]),
                        [0.0, 0.0], t_eval=t, rtol=1e-11, atol=1e-12)
        y, out = np.zeros(4), []
        for t1 in sol.y[0]:
            y = self.close(t1, y)
            out.append(self.cgs(np.r_[t1, y])[2])
        return np.array(out)


def test_bricard_trajectory_against_a_joint_angle_model(bricard):
    """Rod 3's centre over the first second of the swing (it moves 0.6 m), against the joint-angle model."""
    t = np.linspace(0.0, 1.0, 11)
    r = simulate(bricard, assemble(bricard, {}), (0.0, 1.0), rtol=1e-9, atol=1e-11, t_eval=t)
    ours = np.column_stack([r["x_rod3"], r["y_rod3"], r["z_rod3"]])
    truth = _Bricard6R().rod3_centre(t)
    assert np.linalg.norm(ours[-1] - ours[0]) > 0.6
    assert np.max(np.abs(ours - truth)) < 1e-6


def test_bricard_check_finds_the_equilibrium(bricard):
    """check's free equilibrium: plain Newton from the assembled pose diverged (steps to 1e127) and said
    "no equilibrium"; by symmetry of the loop about the plane x = z through the diagonal... the hanging
    pose found has rod 3's mid-point on x = 0 and the potential at a minimum (stable)."""
    rep = check_report(DATA / "spatial" / "bricard.toml")
    assert rep.x_equilibrium is not None and rep.ok
    xe = rep.x_equilibrium
    sysm = rep.system
    assert np.max(np.abs(sysm.residual(xe))) < 1e-8
    assert rep.stability is not None and rep.stability.stable
    # the potential there is below the start's, and no lower than the lowest point the free swing reaches
    ys = [xe[sysm.index(f"y_rod{i}")] for i in range(1, 6)]
    assert 9.81 * sum(ys) < -29.43


def test_check_says_no_equilibrium_only_with_evidence():
    """The Bennett linkage with 100 N m on its crank, some six times the largest moment gravity can hold
    (1 + 1.5 + 1 kg within 0.5 m of the axis): no equilibrium on its mobile branch. The search says what it
    tried and the residual each reached; the exact root the least squares finds in the rigid assembly mode
    (0 degrees of freedom: the reactions take the moment) is named and refused."""
    rep = check_report(DATA / "spatial" / "bennett.toml", M=100.0)
    assert rep.x_equilibrium is None
    note = rep.equilibrium_note
    for words in ("tried Newton", "max residual", "trust-region least-squares search", "another assembly mode",
                  "0 degree(s) of freedom instead of 1"):
        assert words in note, note
    assert any("no equilibrium found" in f for f in rep.findings)


def _pendulum(phi0: float, t: np.ndarray, L=0.5, m=1.0, mc=2.0, g=9.81) -> np.ndarray:
    """The three-crank parallelogram as one pendulum: (m L^2 + mc L^2) phi'' = -(3 m L / 2 + mc L) g sin phi
    (three cranks of inertia m L^2 / 3 about their pivots, the coupler translating on a circle of radius L)."""
    k = (1.5 * m * L + mc * L) * g / (m * L**2 + mc * L**2)
    sol = solve_ivp(lambda _, y: [y[1], -k * math.sin(y[0])], (0, t[-1]), [phi0, 0.0], t_eval=t,
                    rtol=1e-11, atol=1e-12)
    return sol.y[0]


def test_parallelogram_with_a_redundant_link_swings_as_a_pendulum():
    system = load(DATA / "parallelogram3.toml")
    x0 = assemble(system, {"theta_c1": -0.6}, hold={"theta_c1": -0.6})
    r = simulate(system, x0, (0.0, 3.0), rtol=1e-9, atol=1e-11, t_eval=np.linspace(0, 3, 61))
    assert r.success and not r.motion_warning
    phi = r["theta_c1"] + math.pi / 2
    assert np.max(np.abs(phi - _pendulum(-0.6 + math.pi / 2, r.t))) < 1e-6
    for c in ("theta_c2", "theta_c3"):
        assert np.max(np.abs(r[c] - r["theta_c1"])) < 1e-8
    assert r.indeterminate_rows == len(r.t)


def test_bennett_linkage_in_time_conserves_energy(monkeypatch):
    """The Bennett linkage (three redundant rows) falling from its build pose through 93 degrees of crank:
    the rows left out of the solve are chosen again where the kept ones lose rank (as the statics does
    some 60 degrees from the build pose), and the energy is conserved across. The old solve took 5894
    evaluations for this second (the drift-level rows inverted at times); a smooth swing needs ~900."""
    made = []
    init = ConstrainedDynamics.__init__

    def spy(self, *args, **kwargs):
        init(self, *args, **kwargs)
        made.append(self)

    monkeypatch.setattr(ConstrainedDynamics, "__init__", spy)
    system = load(DATA / "spatial" / "bennett.toml")
    x0 = assemble(system, {})
    r = simulate(system, x0, (0.0, 1.0), rtol=1e-8, atol=1e-10)
    assert r.success and not r.motion_warning
    E = r.energy["E_kin"] + r.energy["E_pot"]
    assert np.max(np.abs(E - E[0])) < max(r.balance.bound, 1e-6)
    assert np.ptp(r["crank"]) > 1.5  # it swings through the row change
    kept = made[-1].kept
    assert kept is not None and len(kept.changes) >= 1 and not kept.singular
    assert r.nfev < 2000


class _Run:
    """The parts of a finished history :func:`motion_warning` reads."""

    def __init__(self, t, success=True):
        self.t, self.energy, self.integrator_failure, self.success = np.asarray(t), {}, "", success


def test_a_collapse_of_the_steps_is_one_line_saying_where():
    """Steps of 10 ms that fall to 1e-7 s from t = 0.38 s and stay there: the stall of the issue."""
    t = np.concatenate([np.arange(0, 0.38, 0.01), 0.38 + np.arange(1, 200) * 1e-7])
    line = motion_warning(_Run(t), None)
    assert line.startswith("the motion stalled at t = 0.38 s") and "\n" not in line
    assert "from 0.01 s to 1e-07 s" in line
    assert motion_warning(_Run(np.arange(0, 2, 0.01)), None) == ""  # steady steps: nothing to say
    bumpy = np.cumsum(np.r_[0, np.full(50, 0.01), np.full(5, 1e-7), np.full(50, 0.01)])
    assert motion_warning(_Run(bumpy), None) == ""  # a brief dip (an impact) is no stall
    assert motion_warning(_Run(t, success=False), None) == ""  # a failed run says why itself


def test_unresolvable_redundancy_is_one_line_exit_2_with_the_history_kept(monkeypatch, tmp_path):
    """Rows whose choice changes at most steps: the warning names it, and the CLI writes the history and
    exits 2 with that one line."""
    kept = KeptRows(1)
    kept.changes = list(np.linspace(0.1, 1.0, 60))
    t = np.linspace(0, 1, 101)
    line = motion_warning(_Run(t), type("D", (), {"kept": kept})())
    assert line.startswith(UNRESOLVED) and "60 times in 100 steps from t = 0.1 s" in line

    import mechcont.dynamics._simulate as sim

    monkeypatch.setattr(sim, "motion_warning", lambda result, dyn: f"{UNRESOLVED}: test")
    out = tmp_path / "h.csv"
    res = make_runner()("simulate", DATA / "parallelogram3.toml", "--until", "0.05", "--no-progress", "--out", out)
    one_line_error(res, f"redundant: {UNRESOLVED}: test")
    assert out.exists() and len(out.read_text().splitlines()) > 2
