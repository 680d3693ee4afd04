"""Over-constrained mechanisms in time (issue 38): redundant rows left out of the solve by a pivoted QR
and chosen again where they lose rank (dynamics._redundant), checked against energy conservation and
independent minimal-coordinate models; ``check``'s equilibrium search on the same linkages."""

import math
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from scipy.integrate import solve_ivp

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
