"""``mechcont continue --dynamic``: the dynamic stability columns of a branch, against a closed form.

Ziegler's double pendulum written in the description format: two bodies with their mass at their far
end (2m at the joint, m at the tip) and a small rotary inertia ``eps`` each (the format asks for one > 0),
rotary springs as custom moments in the coordinates, the follower force as a custom force turning with
the second body. In the absolute angles from the vertical, ``M = m l^2 [[3, 1], [1, 1]] + eps I`` and
``K = k [[2 - p, p - 1], [-1, 1]]`` (``p = P l/k``): the eigenvalues are ``s = +-sqrt(-mu)``, ``mu`` the
eigenvalues of ``M^-1 K``; flutter where they turn complex, ``p`` near ``7/2 - sqrt 2`` (exactly there for
``eps = 0``).
"""

from __future__ import annotations

import csv

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error

EPS = 1e-6
ZIEGLER = f"""
[mechanism]
name = "ziegler"
dof = 2
[parameters]
P = {{ value = 0.0, unit = "N", scale = 1.0 }}
k = {{ value = 1.0, unit = "N m/rad" }}
m = {{ value = 1.0, unit = "kg" }}
l = {{ value = 1.0, unit = "m" }}
[ground]
O = [0, 0]
[bodies.b1]
mass = "2*m"
inertia = {EPS}
cg = ["l", 0]
points = {{ j = ["l", 0] }}
initial = {{ theta = 1.5707963267948966 }}
[bodies.b2]
mass = "m"
inertia = {EPS}
cg = ["l", 0]
points = {{ tip = ["l", 0] }}
initial = {{ theta = 1.5707963267948966 }}
[joints.O]
type = "revolute"
a = "ground.O"
b = "b1.origin"
[joints.J]
type = "revolute"
a = "b1.j"
b = "b2.origin"
[loads.spring_O]
type = "custom"
at = "b1.origin"
moment = "-k*(theta_b1 - 1.5707963267948966) + k*(theta_b2 - theta_b1)"
[loads.spring_J]
type = "custom"
at = "b2.origin"
moment = "-k*(theta_b2 - theta_b1)"
[loads.follower]
type = "custom"
at = "b2.tip"
fx = "-P*cos(theta_b2)"
fy = "-P*sin(theta_b2)"
"""


def _closed_form(p: float) -> np.ndarray:
    M = np.array([[3.0, 1.0], [1.0, 1.0]]) + EPS * np.eye(2)
    K = np.array([[2.0 - p, p - 1.0], [-1.0, 1.0]])
    s = np.sqrt(-np.linalg.eigvals(np.linalg.solve(M, K)).astype(complex))
    return np.concatenate([s, -s])


def test_continue_dynamic_writes_the_columns(tmp_path):
    path = tmp_path / "ziegler.toml"
    path.write_text(ZIEGLER)
    out = tmp_path / "z.csv"
    run = make_runner()
    res = run("continue", path, "--vary", "P", "--bounds", "P=0:3", "--ds", 2, "--dsmax", 20, "--out", out,
              "--dynamic")
    assert res.exit_code == 0, res.output
    rows = list(csv.DictReader(out.open()))
    assert {"n_unstable_dynamic", "leading_real [1/s]", "leading_frequency [rad/s]"} <= set(rows[0])
    flutter = stable = 0
    for r in rows:
        p = float(r["P [N]"])
        lam = _closed_form(p)
        n = int(np.count_nonzero(lam.real > 1e-9 * np.abs(lam).max()))
        assert int(float(r["n_unstable_dynamic"])) == n
        top = lam.real.max()
        tied = lam[lam.real >= top - 1e-9 * np.abs(lam).max()]
        assert float(r["leading_real [1/s]"]) == pytest.approx(top, rel=1e-7, abs=1e-12)
        assert float(r["leading_frequency [rad/s]"]) == pytest.approx(np.abs(tied.imag).min(), rel=1e-7)
        flutter += n > 0
        stable += n == 0
    assert flutter > 10 and stable > 10   # the branch crosses the flutter load
    assert "dynamically unstable" in res.output
    plain = tmp_path / "plain.csv"
    assert run("continue", path, "--vary", "P", "--bounds", "P=0:1", "--out", plain).exit_code == 0
    assert "leading_real [1/s]" not in plain.read_text().splitlines()[0]


SLIDER = """
[mechanism]
name = "msd"
[parameters]
m = 3.0
k = { value = 1200.0, unit = "N/m", scale = 100.0 }
c = 18.0
[ground]
O = [0, 0]
S = [-1.0, 0]
[bodies.block]
mass = "m"
inertia = 0.2
initial = { x = 0.1, y = 0, theta = 0 }
[joints.rail]
type = "prismatic"
a = "ground.O"
b = "block.origin"
[springs.spring]
a = "ground.S"
b = "block.origin"
k = "k"
free_length = 1.1
[dampers.damper]
a = "ground.S"
b = "block.origin"
c = "c"
"""


def test_continue_dynamic_with_mass_proportional_damping(tmp_path):
    """A block (m) on a rail with a spring k and a damper c, plus mass-proportional damping d: its equation
    is ``m x'' + (c + d m) x' + k x = 0``, so ``leading_real = -(c + d m)/(2 m)`` and ``leading_frequency =
    sqrt(k/m - leading_real^2)`` while underdamped, along a branch in k."""
    path = tmp_path / "msd.toml"
    path.write_text(SLIDER)
    out = tmp_path / "msd.csv"
    run = make_runner()
    res = run("continue", path, "--vary", "k", "--bounds", "k=500:2000", "--out", out, "--dynamic", "--damping", 2.0)
    assert res.exit_code == 0, res.output
    rows = list(csv.DictReader(out.open()))
    k = np.array([float(r["k [N/m]"]) for r in rows])
    assert k.min() < 600 and k.max() > 1900
    sigma = -(18.0 + 2.0 * 3.0) / (2 * 3.0)
    assert np.allclose([float(r["leading_real [1/s]"]) for r in rows], sigma, rtol=1e-12)
    assert np.allclose([float(r["leading_frequency [rad/s]"]) for r in rows], np.sqrt(k / 3.0 - sigma ** 2),
                       rtol=1e-10)
    assert all(float(r["n_unstable_dynamic"]) == 0 for r in rows)
    # the table is a branch of its model again (its points usable as --point sources): the added columns
    # are left out of the variables when it is read
    from mechcont.continuation import Branch
    from mechcont.continuation._branch import check_branch_table
    from mechcont.models import load_model

    branch = Branch.read_csv(out)
    model = load_model(str(path))
    check_branch_table(branch, model, out)
    assert list(branch.names) == list(model.names)


@pytest.mark.parametrize("args, words", [(["--dynamic", "--damping", -1], ["--damping", "non-negative"]),
                                         (["--damping", 1], ["--damping", "--dynamic"])])
def test_bad_damping_is_one_line(tmp_path, args, words):
    path = tmp_path / "msd.toml"
    path.write_text(SLIDER)
    out = tmp_path / "msd.csv"
    res = make_runner()("continue", path, "--vary", "k", "--bounds", "k=500:2000", "--out", out, *args)
    one_line_error(res, *words)
    assert not out.exists()
