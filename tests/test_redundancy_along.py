"""Redundant constraints along a branch: structural (Bennett linkage, planar loops in space) and at a
singular configuration (a parallelogram four-bar folded flat, where it gains a degree of freedom)."""

import math
import types
from pathlib import Path

import numpy as np

from mechcont.analysis.redundancy import redundancy_along
from mechcont.continuation import ContinuationOptions, continuation
from mechcont.mechanism import assemble, load

DATA = Path(__file__).parent / "data" / "spatial"


def test_bennett_redundancy_is_structural_and_its_dropped_rows_stay_implied():
    s = load(DATA / "bennett.toml")
    b = continuation(s, assemble(s, hold={"crank": 0.0}, free=["M"]), "crank", free=["M"],
                     options=ContinuationOptions(bounds={"crank": (-0.8, 2.0)}))
    r = redundancy_along(s, b)
    assert len(r.states) == 1 and not r.changes
    assert r.states[0].dof == 1 and np.all(r.dof == 1)
    assert r.dropped == ("D_z", "D_rot1", "D_rot2") and r.dropped_residual < 1e-10
    assert "dropped at build" in r.lines()[0]


def _parallelogram(system, theta: float, a=0.3, b=0.7) -> np.ndarray:
    """Exact configuration of the parallelogram four-bar (crank = rocker = a, coupler = ground = b)."""
    c, s = math.cos(theta), math.sin(theta)
    return system.vector({"x_crank": a / 2 * c, "y_crank": a / 2 * s, "theta_crank": theta,
                          "x_coupler": a * c + b / 2, "y_coupler": a * s, "theta_coupler": 0.0,
                          "x_rocker": b + a / 2 * c, "y_rocker": a / 2 * s, "theta_rocker": theta},
                         base=system.defaults())


def test_parallelogram_folded_flat_gains_a_degree_of_freedom():
    s = load("fourbar", a=0.3, b=0.7, c=0.3, d=0.7)
    xs = np.array([_parallelogram(s, t) for t in (0.6, 0.3, 0.0)])
    for x in xs:
        assert np.max(np.abs(s.mechanics.phi(x))) < 1e-12
    r = redundancy_along(s, types.SimpleNamespace(values=xs))
    assert list(r.dof) == [1, 1, 2]
    assert len(r.changes) == 1 and r.changes[0].start == 2
    flat = r.changes[0]
    # folded flat along x, the links can carry axial forces in equilibrium with each other (a
    # self-stress): the reactions along the links are indeterminate, the normal ones are not
    assert set(flat.indeterminate) == {"R_A_x", "R_B_x", "R_C_x", "R_D_x"}
    assert set(flat.joints) == {"A", "B", "C", "D"}
    assert r.states[0].indeterminate == ()
