"""``MechanicalModel.count_unstable``: the stability of many points in one call gives the counts
``stability`` gives point by point, on every kind of mechanism it handles differently."""

import numpy as np
import pytest
import sympy as sp

from mechcont import MechanicalModel, Model, Variable
from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.models import load_model


def _one_by_one(mech, X):
    return np.array([mech.stability(x).n_unstable for x in X])


def test_overcentre_branch_through_both_folds(overcentre):
    x0 = find_equilibrium(overcentre, hold={"theta1": 0.3}, free=["F"])
    b = continuation(overcentre, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}))
    assert len(b.special("LP")) == 2
    counts = overcentre.mechanics.count_unstable(b.values)
    # the branch's own column comes from the batch: it is the same as point by point, folds included
    assert np.array_equal(counts, _one_by_one(overcentre.mechanics, b.values))
    assert np.array_equal(b.n_unstable, counts)
    assert set(counts.tolist()) == {0, 1}


def test_two_degrees_of_freedom_and_points_off_equilibrium():
    model = load_model("fivebar")
    x0 = find_equilibrium(model, guess=model.vector({"theta_b1": 1.9, "theta_b4": 1.2}))
    b = continuation(model, x0, "T1", options=ContinuationOptions(bounds={"T1": (-60.0, 60.0)}, max_steps=300))
    mech = model.mechanics
    assert np.array_equal(mech.count_unstable(b.values), _one_by_one(mech, b.values))
    # counts away from equilibrium too (the multipliers are then a least-squares fit), and
    # with both signs of the reduced stiffness's eigenvalues
    rng = np.random.default_rng(3)
    X = np.repeat(b.values, 4, axis=0)
    q = [model.index(n) for n in mech.coordinates]
    X[:, q] += rng.normal(scale=0.05, size=(len(X), len(q)))
    X[:, model.index("T1")] = rng.uniform(-200, 200, len(X))
    counts = mech.count_unstable(X)
    assert np.array_equal(counts, _one_by_one(mech, X))


def _follower_pendulum():
    """Two rigid links on torsional springs k under a follower load P (Ziegler's column,
    linearised): the stiffness -dQ/dq is not symmetric, so stability needs the masses."""
    names = ["th1", "th2", "P", "k", "m", "L"]
    th1, th2, P, k, m, L = sp.symbols(names, real=True)
    Q = [-2 * k * th1 + k * th2 + P * L * (th1 - th2), k * th1 - k * th2]
    M = m * L ** 2 * sp.Matrix([[3, 1], [1, 1]])
    vs = [Variable("th1", "state", 0.0, "rad"), Variable("th2", "state", 0.0, "rad"),
          Variable("P", "parameter", 0.0, "N"), Variable("k", "parameter", 10.0, "N m/rad"),
          Variable("m", "parameter", 1.0, "kg"), Variable("L", "parameter", 1.0, "m")]
    mech = MechanicalModel(names, ["th1", "th2"], [], Q, M)
    return Model("ziegler", vs, Q, mechanics=mech).compile()


def test_non_conservative_flutter_counts():
    s = _follower_pendulum()
    X = np.array([s.vector({"P": P}) for P in np.linspace(0.0, 60.0, 61)])
    counts = s.mechanics.count_unstable(X)
    assert np.array_equal(counts, _one_by_one(s.mechanics, X))
    assert counts[0] == 0 and counts.max() > 0  # stable without load, flutter under a large one


def test_no_constraints_and_empty_input():
    th, k, m, g, L = sp.symbols("th k m g L", real=True)
    Q = -(k * th - m * g * L * sp.sin(th))
    vs = [Variable("th", "state", 0.0, "rad"), Variable("k", "parameter", 100.0, "N m/rad"),
          Variable("m", "parameter", 5.0, "kg"), Variable("g", "parameter", 9.81, "m/s^2"),
          Variable("L", "parameter", 1.0, "m")]
    mech = MechanicalModel([v.name for v in vs], ["th"], [], [Q], sp.Matrix([[m * L ** 2]]))
    s = Model("column", vs, [Q], mechanics=mech).compile()
    X = np.array([s.vector({"th": t, "m": mm}) for t in np.linspace(-2, 2, 9) for mm in (1.0, 10.0, 10.19, 15.0)])
    counts = mech.count_unstable(X)
    assert np.array_equal(counts, _one_by_one(mech, X))
    # V'' = k - m g L cos(th): unstable where negative
    expected = (100.0 - X[:, 2] * 9.81 * np.cos(X[:, 0]) < 0).astype(int)
    assert np.array_equal(counts, expected)
    assert mech.count_unstable(np.zeros((0, len(vs)))).shape == (0,)


@pytest.mark.parametrize("name", ["nose_gear.toml", "lockstay"])
def test_generated_gears(name):
    model = load_model(name)
    x0 = model.vector({})  # the assembled default pose; off equilibrium is fine for comparing counts
    rng = np.random.default_rng(11)
    X = np.repeat(x0[None, :], 40, axis=0)
    q = [model.index(n) for n in model.mechanics.coordinates]
    X[:, q] += rng.normal(scale=0.02, size=(len(X), len(q)))
    assert np.array_equal(model.mechanics.count_unstable(X), _one_by_one(model.mechanics, X))
