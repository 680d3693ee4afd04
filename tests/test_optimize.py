"""``optimize``: closed-form optima of the overcentre, a nose-gear optimum checked by re-solving, the constraint
whitelist and the CLI."""

import json

import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.analysis.optimize import Constraint, optimize
from mechcont.analysis.sensitivity import downlock_sensitivity
from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.errors import InputError

run = make_runner()
L, W = 1.5, 9.81  # the overcentre's bar length and (m1 + m2) g / 2


@pytest.mark.parametrize("text, parsed", [("downlock_force >= 200", ("downlock_force", ">=", 200.0)),
                                          (" unlock_force<=-9.5e2 ", ("unlock_force", "<=", -950.0)),
                                          ("k>=.5", ("k", ">=", 0.5))])
def test_constraint_parses_name_comparison_number(text, parsed):
    c = Constraint.parse(text)
    assert (c.quantity, c.sense, c.bound) == parsed


@pytest.mark.parametrize("text", ["downlock_force > 200", "downlock_force == 200", "k >= 2*100", "k >= LU",
                                  "__import__('os').system('x') >= 1", "k >= 1; LU <= 2", "k >= nan", "k >= 1e999",
                                  ">= 3", "k >="])
def test_constraint_refuses_anything_else(text):
    with pytest.raises(InputError, match="constraint"):
        Constraint.parse(text)


@pytest.fixture(scope="module")
def upper_fold(overcentre):
    x0 = find_equilibrium(overcentre, values={"LU": 0.4}, hold={"theta1": 0.3}, free=["F"])
    branch = continuation(overcentre, x0, "F", options=ContinuationOptions(bounds={"F": (-200.0, 200.0)}))
    p = max(branch.special("LP"), key=lambda q: q["F"])
    return p.x, p.info["unknowns"], p.info["vary"]


def test_overcentre_closed_form_optimum(overcentre, upper_fold):
    """Largest free length LU keeping the upper fold load F* = W + k L u^{3/2} >= 60 N, k in [50, 200]:
    k* = 200 (bound), u* = ((60 - W) / (k* L))^{2/3}, LU* = L (1 - u*)^{3/2}; multipliers dLU*/d60 =
    1 / (dF*/dLU) and dLU*/dk_max = -(dF*/dk) / (dF*/dLU) from the hand derivatives."""
    res = optimize(overcentre, "LU", {"k": (50.0, 200.0), "LU": (0.2, 1.2)}, maximize=True,
                   constraints=[Constraint.parse("fold_load >= 60")], fold=upper_fold)
    k = 200.0
    u = ((60 - W) / (k * L)) ** (2 / 3)
    lu = L * (1 - u) ** 1.5
    dF_dLU, dF_dk = -k * u ** 0.5 * (lu / L) ** (-1 / 3), L * u ** 1.5
    assert res.success
    assert res.design["LU"] == pytest.approx(lu, rel=1e-8)
    assert res.design["k"] == pytest.approx(k, rel=1e-10)
    assert res.quantities["fold_load"] == pytest.approx(60.0, rel=1e-9)
    active = dict(res.active)
    assert set(active) == {"fold_load >= 60", "k <= 200"}
    assert active["fold_load >= 60"] == pytest.approx(1 / dF_dLU, rel=1e-6)
    assert active["k <= 200"] == pytest.approx(-dF_dk / dF_dLU, rel=1e-6)


def test_nose_gear_longest_spring_that_locks_with_margin():
    """Longest free length LU with a downlock force of at least 100 N, k in [10, 30] kN/m: k at its upper
    bound (a stiffer spring locks harder), the constraint active; the optimum re-solved gives 100 N and the
    multipliers are the sensitivities' ratios there (dLU*/d100 = 1 / F_LU, dLU*/dk_max = -F_k / F_LU)."""
    from mechcont.analysis import downlock_point
    from mechcont.models import load_model

    model = load_model("nose_gear")
    res = optimize(model, "LU", {"k": (10000.0, 30000.0), "LU": (1.2, 1.4)}, maximize=True,
                   constraints=[Constraint.parse("downlock_force >= 100")])
    assert res.success
    assert res.design["k"] == pytest.approx(30000.0, rel=1e-10)
    x = downlock_point(model, res.design)
    assert x[model.index("F")] == pytest.approx(100.0, rel=1e-8)
    s = downlock_sensitivity(model, ["k", "LU"], x=x)
    active = dict(res.active)
    assert set(active) == {"downlock_force >= 100", "k <= 30000"}
    assert active["downlock_force >= 100"] == pytest.approx(1 / s["LU"], rel=1e-6)
    assert active["k <= 30000"] == pytest.approx(-s["k"] / s["LU"], rel=1e-6)
    assert res.iterations >= 1 and res.evaluations >= res.iterations


def test_quantity_that_vanishes_is_a_clear_message():
    from mechcont.models import load_model

    model = load_model("nose_gear")  # at its defaults the release run has no unlock fold
    with pytest.raises(InputError, match="no unlock fold at k = 20000"):
        optimize(model, "unlock_force", {"k": (10000.0, 40000.0)})


def test_cli_writes_the_optimum_and_refuses_bad_constraints(tmp_path):
    branch = tmp_path / "b.csv"
    r = run("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
            "--bounds", "F=-200:200", "--out", branch, "--quiet")
    assert r.exit_code == 0, r.output
    upper = max(("LP1", "LP2"), key=lambda n: _fold_force(branch, n))
    out = tmp_path / "o.json"
    r = run("optimize", "overcentre", "--maximize", "LU", "--design", "k=50:200", "--design", "LU=0.2:1.2",
            "--constraint", "fold_load >= 60", "--point", f"{branch}:{upper}", "--out", out)
    assert r.exit_code == 0, r.output
    assert "active: fold_load >= 60" in r.output
    doc = json.loads(out.read_text())
    u = ((60 - W) / (200 * L)) ** (2 / 3)
    assert doc["design"]["LU"] == pytest.approx(L * (1 - u) ** 1.5, rel=1e-8)
    bad = tmp_path / "bad.json"
    r = run("optimize", "overcentre", "--maximize", "LU", "--design", "k=50:200",
            "--constraint", "fold_load >= eval('1')", "--point", f"{branch}:{upper}", "--out", bad)
    one_line_error(r, "--constraint", "NAME >= NUMBER")
    r = run("optimize", "overcentre", "--maximize", "LU", "--design", "k=50:200", "--constraint", "weight <= 3",
            "--point", f"{branch}:{upper}", "--out", bad)
    one_line_error(r, "weight", "valid:", "downlock_force")
    assert not bad.exists()


def _fold_force(path, name):
    from mechcont.continuation import Branch

    return Branch.read_csv(path).point(name)["F"]


def test_lockstay_least_unlock_force_with_downlock_margin():
    """The lock stay (a description with a declared downlock): least unlock force with a downlock force of at
    least 100 N. At the optimum the downlock force re-solved is 100 N, and the constraint's multiplier is
    dU/dLU / dD/dLU with both slopes from central differences of re-solved quantities (the unlock fold from
    a fresh release run)."""
    from mechcont.analysis import downlock_point
    from mechcont.analysis.unlock import unlock_folds
    from mechcont.models import load_model

    model = load_model("lockstay")
    res = optimize(model, "unlock_force", {"k": (10000.0, 30000.0), "LU": (0.5, 0.7)},
                   constraints=[Constraint.parse("downlock_force >= 100")])
    assert res.success
    x = downlock_point(model, res.design)
    assert x[model.index("F")] == pytest.approx(100.0, rel=1e-8)

    def forces(lu):
        y = downlock_point(model, {**res.design, "LU": lu})
        return y[model.index("F")], unlock_folds(model, y, "F", released=["aligned"], stability=False).locked_range[1]

    lu, h = res.design["LU"], 1e-4 * res.design["LU"]
    (d_lo, u_lo), (d_hi, u_hi) = forces(lu - h), forces(lu + h)
    (d_lo2, u_lo2), (d_hi2, u_hi2) = forces(lu - h / 2), forces(lu + h / 2)
    dD = (4 * (d_hi2 - d_lo2) / h - (d_hi - d_lo) / (2 * h)) / 3
    dU = (4 * (u_hi2 - u_lo2) / h - (u_hi - u_lo) / (2 * h)) / 3
    assert dict(res.active)["downlock_force >= 100"] == pytest.approx(dU / dD, rel=1e-6)
    assert res.value == pytest.approx(forces(lu)[1], rel=1e-9)
