"""Paper-style 25 equations vs the gear generated from its description: branches, folds, balance."""

from __future__ import annotations

import numpy as np
import pytest

from mechcont.analysis.downlock import downlock, downlock_point
from mechcont.continuation import ContinuationOptions, continuation, continue_folds, locate_fold
from mechcont.mechanism import load
from mechcont.models.nose_gear import COORDINATES, build_nose_gear

HOLD = {"theta4": 0.0}
TOL = 1e-8


@pytest.fixture(scope="module")
def paper():
    return build_nose_gear()


@pytest.fixture(scope="module")
def generated():
    return load("nose_gear")


def _coords(system, x):
    return np.array([x[system.index(n)] for n in (*COORDINATES, "F", "l_sp1", "LU")])


@pytest.mark.parametrize("values", [{}, {"U": 80.0, "l_sp1": -0.12}, {"LU": 1.27, "k": 5000.0},
                                    {"Ax": -1.35}, {"L4": 0.4, "U": 50.0}])
def test_downlocked_points_agree(paper, generated, values):
    a = downlock_point(paper, values)
    b = downlock_point(generated, values, hold=HOLD)
    assert np.max(np.abs(_coords(paper, a) - _coords(generated, b))) < TOL


def test_branches_agree_point_by_point(paper, generated):
    """Every point of the generated gear's l_sp1 branch solves the paper-style equations to 1e-8."""
    br = downlock(generated, "l_sp1", {"l_sp1": (-0.175, 0.175)}, hold=HOLD).branch
    assert len(br) > 10
    for row in br.values:
        vals = {n: row[generated.index(n)] for n in ("l_sp1",)}
        x = downlock_point(paper, vals)
        assert abs(x[paper.index("F")] - row[generated.index("F")]) < TOL
        assert np.max(np.abs(_coords(paper, x)[:15] - np.array([row[generated.index(n)] for n in COORDINATES]))) < TOL
    # and the stability from both mechanics is the same
    pb = downlock(paper, "l_sp1", {"l_sp1": (-0.175, 0.175)}).branch
    assert set(pb.n_unstable) == set(br.n_unstable)


def test_misaligned_drag_branch_agrees(paper, generated):
    vals = {"L35": 0.3480, "psi2": -0.0585}
    a = downlock(paper, "U", {"U": (0.0, 100.0)}, values=vals).branch
    for U, F in zip(a["U"][::5], a["F"][::5]):
        x = downlock_point(generated, {**vals, "U": float(U)}, hold=HOLD)
        assert abs(x[generated.index("F")] - F) < TOL


def test_fig7_branch_agrees(paper, generated):
    """Continuation in F with theta4 free (no spring, no airflow) on the paper model; each point solves the generated one."""
    from mechcont.continuation import find_equilibrium

    x0 = downlock_point(paper, {"k": 0.0})
    br = continuation(paper, x0, "F", options=ContinuationOptions(ds=0.05, dsmax=0.3,
                                                                    bounds={"F": (-300, 300), "theta4": (-0.5, 0.5)}))
    guess = downlock_point(generated, {"k": 0.0}, hold=HOLD)
    for row in br.values[::10]:
        t4 = row[paper.index("theta4")]
        x = find_equilibrium(generated, values={"k": 0.0}, hold={"theta4": t4}, free=["F"], guess=guess)
        assert abs(x[generated.index("F")] - row[paper.index("F")]) < TOL
        guess = x


def _force_branch(system, hold=None):
    x0 = downlock_point(system, None, hold=hold)
    return continuation(system, x0, "F", hold=["theta4"], free=["l_sp1"],
                        options=ContinuationOptions(ds=0.02, dsmax=0.1, bounds={"l_sp1": (-0.175, 0.175),
                                                                                  "F": (-1000, 1000)}))


def test_folds_agree(paper, generated):
    a = _force_branch(paper).special("LP")
    b = _force_branch(generated, HOLD).special("LP")
    assert len(a) == len(b) == 2
    for p, q in zip(sorted(a, key=lambda p: p["l_sp1"]), sorted(b, key=lambda p: p["l_sp1"])):
        xp, _, _ = locate_fold(paper, p, "F")
        xq, _, _ = locate_fold(generated, q, "F")
        for n in ("F", "l_sp1", "theta3"):
            assert abs(xp[paper.index(n)] - xq[generated.index(n)]) < TOL


def test_fold_curves_and_cusp_agree(paper, generated):
    opts = ContinuationOptions(ds=0.01, dsmax=0.05, bounds={"l_sp1": (-0.175, 0.175), "LU": (1.25, 1.35)})
    ca = continue_folds(paper, _force_branch(paper)["LP1"], vary="F", free="LU", options=opts)
    cb = continue_folds(generated, _force_branch(generated, HOLD)["LP1"], vary="F", free="LU",
                        options=opts)
    cpa, cpb = ca.special("CP"), cb.special("CP")
    assert len(cpa) == len(cpb) == 1
    for n in ("LU", "l_sp1", "F"):
        assert abs(cpa[0][n] - cpb[0][n]) < 1e-6 * max(1.0, abs(cpa[0][n]))
    # every point of the paper model's fold curve is an extremum of F(l_sp1) of the generated model
    h = 1e-4
    for row in ca.values[:: max(1, len(ca) // 6)]:
        LU, l = row[paper.index("LU")], row[paper.index("l_sp1")]
        if abs(l) > 0.175 - h:
            continue
        F = [downlock_point(generated, {"LU": LU, "l_sp1": l + d}, hold=HOLD)[generated.index("F")]
             for d in (-h, 0.0, h)]
        assert abs(F[1] - row[paper.index("F")]) < TOL
        slope = (F[2] - F[0]) / (2 * h)
        curvature = (F[2] - 2 * F[1] + F[0]) / h**2
        assert abs(slope) < 1e-6 * max(1.0, abs(curvature) * 0.175), (slope, curvature)


# -- balance of every bar from the generated reaction forces (independent numpy check) ----------
def _e(a):
    return np.array([np.cos(a), np.sin(a)])


def _drag_force(v, theta3):
    """Cross-flow drag on the main fitting (N), at its mid-length: 1/2 rho C_D d L3 u_n |u_n| n,
    n the normal left of the axle -> pivot direction, u_n = U sin(alpha - theta3)."""
    n = np.array([-np.sin(theta3), np.cos(theta3)])
    un = v["U"] * np.sin(v["alpha"] - theta3)
    return 0.5 * v["rho"] * v["CD"] * v["d"] * v["L3"] * un * abs(un) * n


def test_generated_drag_is_the_papers_eq12(generated):
    """The built-in drag load on bar 3 does, about the pivot O, the paper's eq. 12 moment
    D = rho/4 (U cos(alpha - theta3 + pi/2))^2 d L3^2 C_D (counter-clockwise for 0 < theta3 - alpha < pi)."""
    x0 = downlock_point(generated, None, hold=HOLD)
    mech = generated.mechanics
    i = [generated.index(n) for n in ("x3", "y3", "theta3")]
    for U, alpha, t3 in ((100.0, 0.0, None), (60.0, 0.2, 1.1), (35.0, -0.3, 1.5)):
        x = x0.copy()
        if t3 is not None:  # O at the origin: G3 = -L3/2 e(theta3)
            half = x0[generated.index("L3")] / 2
            x[i] = [-half * np.cos(t3), -half * np.sin(t3), t3]
        t3 = x[i[2]]
        v = generated.as_dict(x)
        Qdrag = mech.applied_forces(generated.vector({"U": U, "alpha": alpha}, base=x)) - mech.applied_forces(
            generated.vector({"U": 0.0, "alpha": alpha}, base=x))
        # virtual work of a rotation of bar 3 about O (all other coordinates fixed): the moment about O
        dq = np.array([v["L3"] / 2 * np.sin(t3), -v["L3"] / 2 * np.cos(t3), 1.0])
        D = v["rho"] / 4 * (U * np.cos(alpha - t3 + np.pi / 2)) ** 2 * v["d"] * v["L3"] ** 2 * v["CD"]
        assert float(Qdrag[i] @ dq) == pytest.approx(D, rel=1e-9)
        assert D > 1.0  # a real check, not 0 == 0
        others = [j for j in range(len(Qdrag)) if j not in i]
        assert np.max(np.abs(Qdrag[others])) == 0.0  # only the main fitting is loaded


def _bar_balance(system, x):
    """Max |force| and |moment| imbalance over the five bars, from the generated reactions R_<joint>."""
    v = system.as_dict(x)
    G = {i: np.array([v[f"x{i}"], v[f"y{i}"]]) for i in range(1, 6)}
    t = {i: v[f"theta{i}"] for i in range(1, 6)}
    O = G[3] + v["L3"] / 2 * _e(t[3])
    pts = {
        "1.a": G[1] - v["L1"] / 2 * _e(t[1]), "1.b": G[1] + v["L1"] / 2 * _e(t[1]),
        "2.a": G[2] - v["L2"] / 2 * _e(t[2]), "2.b": G[2] + v["L2"] / 2 * _e(t[2]),
        "3.b": O, "3.lug2": O - v["L32"] * _e(t[3] + v["psi1"]), "3.lug5": O - v["L35"] * _e(t[3] - v["psi2"]),
        "4.a": G[4] - v["L4"] / 2 * _e(t[4]), "4.b": G[4] + v["L4"] / 2 * _e(t[4]),
        "5.a": G[5] - v["L5"] / 2 * _e(t[5]), "5.b": G[5] + v["L5"] / 2 * _e(t[5]),
    }
    joints = {"A": (None, "1.a"), "knee12": ("1.b", "2.a"), "lug23": ("2.b", "3.lug2"), "pivot": (None, "3.b"),
              "knee14": ("1.b", "4.a"), "joint45": ("4.b", "5.a"), "lug53": ("5.b", "3.lug5")}
    loads = {i: [] for i in range(1, 6)}  # (point, force)
    for name, (a, b) in joints.items():
        R = np.array([v[f"R_{name}_x"], v[f"R_{name}_y"]])  # force of a's body on b's body
        loads[int(b[0])].append((pts[b], R))
        if a is not None:
            loads[int(a[0])].append((pts[a], -R))
    for i in range(1, 6):
        loads[i].append((G[i], np.array([0.0, -v[f"m{i}"] * v["g"]])))
    S4 = G[4] - v["l_sp1"] * _e(t[4])
    S3 = O - v["l_sp2"] * _e(t[3] + v["psi3"])
    d = S3 - S4
    s = np.hypot(*d)
    T = v["k"] * (s - v["LU"]) * d / s
    loads[4] += [(S4, T), (pts["4.b"], np.array([0.0, v["F"]]))]
    loads[3].append((S3, -T))
    loads[3].append((G[3], _drag_force(v, t[3])))
    worst_f = worst_m = 0.0
    for i in range(1, 6):
        f = sum(F for _, F in loads[i])
        m = sum((p - G[i])[0] * F[1] - (p - G[i])[1] * F[0] for p, F in loads[i])
        worst_f, worst_m = max(worst_f, np.max(np.abs(f))), max(worst_m, abs(m))
    return worst_f, worst_m


def test_every_bar_balanced_at_every_point(generated):
    for vary, rng, vals in (("l_sp1", (-0.175, 0.175), {}), ("U", (0.0, 100.0), {"L35": 0.3480, "psi2": -0.0585}),
                            ("LU", (1.2, 1.4), {"l_sp1": -0.05})):
        br = downlock(generated, vary, {vary: rng}, values=vals, hold=HOLD).branch
        assert len(br) > 5
        for x in br.values:
            f, m = _bar_balance(generated, x)
            assert f < 1e-8 and m < 1e-8, (vary, f, m)


def test_balance_check_detects_a_wrong_reaction(generated):
    """The balance check is not vacuous: perturbing one reaction breaks it."""
    x = downlock_point(generated, None, hold=HOLD)
    x[generated.index("R_lug53_x")] += 1e-3
    f, m = _bar_balance(generated, x)
    assert f > 1e-4
