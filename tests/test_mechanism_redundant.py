"""Over-constrained mechanisms: a parallelogram with a third parallel crank (the planar analogue of
a dual side-stay). Its constraint count says 0 degrees of freedom, its rank says 1: one constraint
is redundant. By default mechcont refuses it naming the joints; with ``redundant = "drop"`` it drops
the dependent row and the continued branch equals the closed form."""

import math

import numpy as np
import pytest

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.errors import InputError
from mechcont.mechanism import dof_report, parse_description

P = dict(L=0.5, m_c=1.0, m_cp=2.0, g=9.81, k=30.0, L0=0.3, sx=1.0, sy=1.2)

TRIPLE = """
[mechanism]
name = "triple_crank"
dof = 1
{extra}

[parameters]
L = 0.5
L3 = 0.5
m_c = 1.0
m_cp = 2.0
g = 9.81
k = 30.0
L0 = 0.3
T = {{ value = 0.0, unit = "N m" }}

[ground]
A = [0, 0]
B = [1, 0]
C = [2, 0]
S = [1.0, 1.2]

[bodies.c1]
length = "L"
mass = "m_c"
initial = {{ theta = 1.0 }}

[bodies.c2]
length = "L"
mass = "m_c"
initial = {{ theta = 1.0 }}

[bodies.c3]
length = "L3"
mass = "m_c"
initial = {{ theta = 1.0 }}

[bodies.cp]
length = 2.0
mass = "m_cp"
points = {{ mid = [0, 0] }}
initial = {{ theta = 0.0 }}

[joints.A]
type = "revolute"
a = "ground.A"
b = "c1.a"

[joints.B]
type = "revolute"
a = "ground.B"
b = "c2.a"

[joints.C]
type = "revolute"
a = "ground.C"
b = "c3.a"

[joints.A2]
type = "revolute"
a = "c1.b"
b = "cp.a"

[joints.B2]
type = "revolute"
a = "c2.b"
b = "cp.mid"

[joints.C2]
type = "revolute"
a = "c3.b"
b = "cp.b"

[springs.s]
a = "ground.S"
b = "cp.mid"
k = "k"
free_length = "L0"

[gravity]
g = "g"

[loads.T]
type = "moment"
body = "c1"
magnitude = "T"

[assembly]
hold = {{ theta_c1 = 1.0 }}
"""


def triple(extra=""):
    return parse_description(TRIPLE.format(extra=extra), "triple.toml")


def V0(th, p=P):
    """Closed-form potential (J) of the triple crank without T: the coupler translates."""
    mid = np.array([1 + p["L"] * math.cos(th), p["L"] * math.sin(th)])
    ell = math.hypot(p["sx"] - mid[0], p["sy"] - mid[1])
    return p["g"] * math.sin(th) * (3 * p["m_c"] * p["L"] / 2 + p["m_cp"] * p["L"]) + p["k"] / 2 * (ell - p["L0"]) ** 2


def d(f, x, h=1e-4):
    return (f(x + h) - f(x - h)) / (2 * h)


def d2(f, x, h=1e-4):
    return (f(x + h) - 2 * f(x) + f(x - h)) / h ** 2


def test_refused_by_default_with_count_and_every_joint_of_the_self_stress():
    with pytest.raises(InputError) as info:
        triple().build()
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith("triple.toml:")
    assert "mechanism.redundant" in msg and "1 redundant constraint(s)" in msg
    assert "the intended 1 degree(s) of freedom" in msg
    # the self-stress runs through all three cranks and the coupler: every joint carries it
    for joint in ("A", "B", "C", "A2", "B2", "C2"):
        assert f" {joint}," in msg or f" {joint} " in msg or f" {joint})" in msg
    assert 'redundant = "drop"' in msg


def test_dof_report_counts_rank_not_constraints():
    """Grubler: 4 bodies x 3 - 6 pins x 2 = 0; rank says 1 DOF and one dependent row, the last declared."""
    system = triple('redundant = "drop"').build()
    report = system.dof
    assert (report.dof, report.rank, len(report.dependent)) == (1, 11, 1)
    assert report.redundant[0][0] == "C2"
    assert set(report.redundant_joints) == {"A", "B", "C", "A2", "B2", "C2"}
    # a duplicate row is found whichever way round it is declared
    J = np.array([[1.0, 0.0], [0.0, 1.0], [2.0, 0.0]])
    r = dof_report(J, ["p", "q", "p_again"])
    assert (r.dof, r.rank, r.dependent, r.redundant) == (0, 2, (2,), (("p_again", "p"),))


def test_dropped_row_branch_equals_closed_form_and_stays_closed():
    system = triple('redundant = "drop"').build()
    assert system.dropped_constraints == ("C2_y",)
    assert "C2_y" in system.description
    assert len(system.equations) == len(system.state_names)
    x0 = find_equilibrium(system, hold={"theta_c1": 1.0}, free=["T"])
    branch = continuation(system, x0, "T", options=ContinuationOptions(bounds={"theta_c1": (0.2, 2.9)}))
    assert branch.success, branch.message
    th, T = branch["theta_c1"], branch["T"]
    assert th.max() - th.min() > 2.5
    for row, t, torque, stable in zip(branch.values, th, T, branch.stable):
        assert np.max(np.abs(system.mechanics.phi(row))) <= 1e-10
        assert system.dropped_residual(row) <= 1e-10  # the dropped row stays implied
        assert torque == pytest.approx(d(V0, t), rel=1e-6, abs=1e-6)
        k = d2(V0, t)
        if abs(k) > 1e-2:
            assert stable == (k > 0)
    assert not all(branch.stable) and any(branch.stable)  # the branch does change stability


def test_inconsistent_redundancy_cannot_close():
    """A third crank of a different length: the loop through it cannot close; say which and by how much."""
    with pytest.raises(InputError, match=r"the loop .* cannot close with the given lengths.* misses by"):
        triple('redundant = "drop"').build(L3=0.6)


def test_bad_redundant_option():
    with pytest.raises(InputError, match=r"triple.toml:\d+: mechanism.redundant: must be 'error' or 'drop'"):
        triple('redundant = "ignore"')
