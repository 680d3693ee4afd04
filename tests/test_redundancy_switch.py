"""Redundant rows dropped and chosen again along a branch: the Bennett linkage through a whole turn of
its crank, checked against its loop closure solved here in plain NumPy (rotations about the joint
axes, nothing of mechcont's equations) and the virtual work of gravity."""

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from mechcont.analysis.redundancy import redundancy_along
from mechcont.continuation import ContinuationOptions, continuation
from mechcont.mechanism import assemble, load

DATA = Path(__file__).parent / "data" / "spatial"


def _rot(u: np.ndarray, t: float) -> np.ndarray:
    """Rotation by ``t`` about the unit vector ``u`` (Rodrigues)."""
    K = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * K @ K


class _Bennett:
    """The linkage of bennett.toml by hand: the crank turned by ``theta`` about axis A, the coupler by
    ``psi`` about axis B relative to the crank, the rocker by ``phi`` about axis D; the loop closes
    where the coupler's point C and its axis C meet the rocker's."""

    def __init__(self, path: Path):
        d = tomllib.loads(path.read_text())
        self.P = {**{k: np.array(v, float) for k, v in d["ground"].items()},
                  **{k: np.array(v, float) for b in d["bodies"].values() for k, v in b["points"].items()}}
        self.u = {k: np.array(j["axis"], float) / np.linalg.norm(j["axis"]) for k, j in d["joints"].items()}
        self.cg = {k: np.array(b["cg"], float) for k, b in d["bodies"].items()}
        self.m = {k: float(b["mass"]) for k, b in d["bodies"].items()}
        self.g = float(d["parameters"]["g"]["value"])

    def frames(self, theta, psi, phi):
        """(R, origin point, its design position) of crank, coupler and rocker."""
        P, u = self.P, self.u
        R1 = _rot(u["A"], theta)
        R2 = R1 @ _rot(u["B"], psi)
        R3 = _rot(u["D"], phi)
        B = P["A"] + R1 @ (P["B"] - P["A"])
        return {"crank": (R1, P["A"], P["A"]), "coupler": (R2, B, P["B"]), "rocker": (R3, P["D"], P["D"])}

    def misfit(self, theta, y):
        f = self.frames(theta, *y)
        R2, B, B0 = f["coupler"]
        R3 = f["rocker"][0]
        C2 = B + R2 @ (self.P["C"] - B0)
        C3 = self.P["D"] + R3 @ (self.P["C"] - self.P["D"])
        return np.concatenate([C2 - C3, (R2 - R3) @ self.u["C"]])

    def close(self, theta, y):
        """(psi, phi) closing the loop at ``theta`` from the guess ``y``: Gauss-Newton (5 independent of 6
        equations in 2 unknowns, consistent), central-difference Jacobian."""
        y = np.array(y, float)
        for _ in range(60):
            r = self.misfit(theta, y)
            J = np.column_stack([(self.misfit(theta, y + h) - self.misfit(theta, y - h)) / 2e-7
                                 for h in np.eye(2) * 1e-7])
            dy = np.linalg.lstsq(J, -r, rcond=None)[0]
            y = y + dy
            if np.abs(dy).max() < 1e-15:
                break
        assert np.abs(self.misfit(theta, y)).max() < 1e-13
        return y

    def potential(self, theta, y) -> float:
        """Gravitational potential (J) at ``theta`` (gravity along -z)."""
        f = self.frames(theta, *y)
        return sum(self.m[b] * self.g * (o + R @ (self.cg[b] - o0))[2] for b, (R, o, o0) in f.items())

    def moment(self, theta, y, h=2e-3) -> float:
        """M = dV/dtheta (N m): 8th-order central differences, the loop closed at every abscissa."""
        c = [4 / 5, -1 / 5, 4 / 105, -1 / 280]
        return sum(ck * (self.potential(theta + k * h, self.close(theta + k * h, y))
                         - self.potential(theta - k * h, self.close(theta - k * h, y)))
                   for k, ck in enumerate(c, start=1)) / h


@pytest.fixture(scope="module")
def turn():
    s = load(DATA / "bennett.toml")
    x0 = assemble(s, hold={"crank": 0.0}, free=["M"])
    b = continuation(s, x0, "crank", free=["M"],
                     options=ContinuationOptions(bounds={"crank": (-math.pi, math.pi)}, max_steps=2000))
    return s, b


def test_a_whole_turn_of_the_crank_with_the_dropped_rows_chosen_again(turn):
    s, b = turn
    assert b.status == "completed", b.message
    assert b["crank"][0] == pytest.approx(-math.pi, abs=1e-12) and b["crank"][-1] == pytest.approx(math.pi, abs=1e-12)
    switches = [p for p in b.special_points if p.label == "RC"]
    assert switches  # the rows dropped at build lose rank on the way (the reason for this test)
    for p in switches:
        before, after = p.info["dropped"]
        assert before != after and len(after) == 3
    # the turn closes: crank, coupler and rocker in the same pose at -pi and +pi (Euler parameters up to sign)
    for body in ("crank", "coupler", "rocker"):
        e = [np.array([b[f"e{k}_{body}"][i] for k in range(4)]) for i in (0, -1)]
        assert min(np.abs(e[0] - e[1]).max(), np.abs(e[0] + e[1]).max()) < 1e-9
        for c in "xyz":
            assert b[f"{c}_{body}"][0] == pytest.approx(b[f"{c}_{body}"][-1], abs=1e-9)
    for x in b.values:  # every rigid row holds, dropped or not
        assert np.abs(s.mechanics.phi(x)).max() < 1e-10


@pytest.fixture(scope="module")
def reference():
    """The hand-made linkage and its own assembly branch, followed from the design pose in 1 degree steps."""
    ref = _Bennett(DATA / "bennett.toml")
    sols = {0: np.zeros(2)}
    for sign in (1, -1):
        y = np.zeros(2)
        for k in range(1, 181):
            y = sols[sign * k] = ref.close(sign * math.radians(k), y)
    return ref, sols


def _moment_error(s, b, reference, every: int = 1) -> float:
    """Largest |M - dV/dtheta| (N m) over the rows of ``b``, each row's configuration checked against the reference's."""
    ref, sols = reference
    worst = 0.0
    for i in range(0, len(b), every):
        th = b["crank"][i]
        y = ref.close(th, sols[int(round(math.degrees(th)))])
        # the same configuration: the coupler's point C where mechcont has it
        R2, B, B0 = ref.frames(th, *y)["coupler"]
        v = s.as_dict(b.values[i])
        E = _quat_matrix(np.array([v[f"e{k}_coupler"] for k in range(4)]))
        origin = np.array([v["x_coupler"], v["y_coupler"], v["z_coupler"]])
        assert np.allclose(origin + E @ ref.P["C"], B + R2 @ (ref.P["C"] - B0), atol=1e-10)
        worst = max(worst, abs(b["M"][i] - ref.moment(th, y)))
    return worst


def test_driving_moment_matches_the_virtual_work_of_gravity_along_the_turn(turn, reference):
    s, b = turn
    assert _moment_error(s, b, reference, every=2) < 1e-9


def _quat_matrix(e: np.ndarray) -> np.ndarray:
    """Rotation matrix of the unit quaternion (e0, e1, e2, e3)."""
    e0, e1, e2, e3 = e
    return np.array([[1 - 2 * (e2 ** 2 + e3 ** 2), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
                     [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 ** 2 + e3 ** 2), 2 * (e2 * e3 - e0 * e1)],
                     [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 ** 2 + e2 ** 2)]])


def test_determinate_part_of_the_reactions_is_continuous_across_the_switches(turn):
    s, b = turn
    mech = s.mechanics
    nq = len(mech.coordinates)
    nr = len(mech.constraints)
    lam = b.values[:, nq:nq + nr]
    mn = np.array([mech.multipliers(x) for x in b.values])   # minimum-norm reactions: a function of q alone
    proj = []
    for x, lk in zip(b.values, lam):
        U, sv, _ = np.linalg.svd(mech.phi_q(x))
        Ur = U[:, :int(np.sum(sv > 1e-9 * sv[0]))]
        proj.append(Ur @ (Ur.T @ lk))   # the part of the solved reactions that statics determines
    proj = np.array(proj)
    scale = np.abs(mn).max()
    assert np.abs(proj - mn).max() < 1e-9 * scale
    # and the solved reactions balance the loads with every rigid row (dropped ones included)
    for x, lk in zip(b.values, lam):
        assert np.abs(mech.phi_q(x).T @ lk - mech.applied_forces(x)).max() < 1e-8 * scale
    # no jump at a switch: the change per radian of crank across each RC row is that of its neighbours
    steps = np.linalg.norm(np.diff(proj, axis=0), axis=1) / np.abs(np.diff(b["crank"]))
    for p in b.special_points:
        if p.label == "RC":
            i = p.index
            assert steps[i - 1] < 1.5 * max(steps[i - 2], steps[i]) and steps[i] < 1.5 * max(steps[i - 1], steps[i + 1])


def test_continue_and_check_name_the_same_indeterminate_reactions(turn):
    s, b = turn
    r = redundancy_along(s, b)
    assert len(r.states) == 1 and r.states[0].dof == 1
    assert set(r.states[0].joints) == {"A", "B", "C", "D"}
    text = "\n".join(r.lines())
    assert "every reaction determinate" not in text and "RC at rows" in text
    assert all(f"{k}_D_" in text for k in "RT")   # the dropped rows' reactions by their names


def test_a_start_solved_by_another_choice_of_rows_is_taken_up(turn, reference):
    """The end of the turn was solved with other rows dropped than the build's: continuing from it with
    the built system chooses again there and solves the reactions again."""
    s, b = turn
    end = b.values[-1]
    assert np.abs(s.residual(end)).max() > 1e-6   # not a solution of the build's choice
    c = continuation(s, end, "crank", free=["M"], direction=-1,
                     options=ContinuationOptions(bounds={"crank": (2.5, math.pi)}, max_steps=200))
    assert c.status == "completed", c.message
    assert _moment_error(s, c, reference) < 1e-9


def test_check_and_continue_name_the_same_indeterminate_joints():
    from tests.cli_helpers import make_runner

    run = make_runner()
    chk = run("check", DATA / "bennett.toml")
    assert chk.exit_code == 0, chk.output
    named = {line.split("statically indeterminate: ")[1].rstrip(")") for line in chk.output.splitlines()
             if "statically indeterminate: " in line}
    assert named == {"D, A, B, C"}
    assert "compliant joint rows" not in chk.output   # a dropped row's equation (its reaction = 0) is no spring
    out = run("continue", DATA / "bennett.toml", "--start", "crank=0", "--free", "M", "--vary", "crank",
              "--bounds", "crank=-3.2:3.2")
    assert out.exit_code == 0, out.output
    assert "every reaction determinate" not in out.output and "RC1" in out.output
    line = next(ln for ln in out.output.splitlines() if "statically indeterminate" in ln)
    assert line.endswith("(joints A, B, C, D)")


def test_stability_along_the_turn_is_the_sign_of_the_stiffness_of_the_moment(turn):
    """With M held, the crank is stable where dM/dtheta = V'' > 0 (1 dof); the batch count over the
    branch (redundant rows included in the mechanics) agrees with the point-by-point one."""
    s, b = turn
    dM = np.gradient(b["M"], b["crank"])
    clear = np.abs(dM) > 0.05 * np.abs(dM).max()
    assert clear.sum() > 0.8 * len(b)
    assert np.array_equal(b.n_unstable[clear], (dM[clear] < 0).astype(int))
    assert list(b.n_unstable) == [s.mechanics.stability(x).n_unstable for x in b.values]
