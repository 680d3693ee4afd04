"""What makes a planar description fail to assemble, said in one line: a loop that cannot close
(and by how much), redundant constraints, a degenerate assembled configuration."""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
import sympy as sp

from ..equations import MechanicalModel
from ..errors import InputError
from ._expr import float_value, symbol
from ._kinematics import ConstraintRow, PlanarKinematics

if TYPE_CHECKING:
    from ._assembly import DofReport
    from ._description import Mechanism

__all__ = ["least_squares_closure", "loop_error", "redundancy_error", "check_assembled"]


def least_squares_closure(model: MechanicalModel, x: np.ndarray, free_q: np.ndarray) -> np.ndarray:
    """The configuration minimising |Phi|^2 near ``x`` (to measure by how much loops miss)."""
    from scipy.optimize import least_squares
    idx = model.q_index[free_q]
    cols = np.flatnonzero(free_q)

    def fun(u: np.ndarray) -> np.ndarray:
        y = x.copy()
        y[idx] = u
        return model.phi(y)

    def jac(u: np.ndarray) -> np.ndarray:
        y = x.copy()
        y[idx] = u
        return model.phi_q(y)[:, cols]

    sol = least_squares(fun, x[idx], jac=jac, method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=2000)
    y = x.copy()
    y[idx] = sol.x
    return y


def loop_error(mech: Mechanism, rows: list[ConstraintRow], phi: np.ndarray,
               hold: Mapping[str, object] | None = None) -> InputError:
    """Name the loop that cannot close and by how much (sum of the joint gaps around it, in the
    description's length unit); ``hold``: the values held (the description's ``[assembly] hold`` if None)."""
    gaps: dict[str, float] = {}
    for row, r in zip(rows, phi):
        gaps[row.joint] = math.hypot(gaps.get(row.joint, 0.0), r)
    worst = max(gaps, key=gaps.__getitem__)
    hold = mech.hold if hold is None else hold
    actuators = {n: g for n, g in gaps.items() if g > 1e-9 and any(a.name == n for a in mech.actuators)}
    if actuators:  # a length-mode actuator that cannot reach its length: name it, not a joint
        held = f" with held {', '.join(f'{k} = {v}' for k, v in hold.items())}" if hold else ""
        return InputError(f"actuators.{max(actuators, key=actuators.__getitem__)}.length",
                          f"cannot be met{held}: the loop through the actuator misses by {sum(gaps.values()):.4g} "
                          f"{mech.unit('m')} at best")
    joint = next(j for j in mech.joints if j.name == worst)
    start, goal = joint.a.split(".")[0], joint.b.split(".")[0]
    edges = [(j.name, j.a.split(".")[0], j.b.split(".")[0]) for j in mech.joints if j.name != worst]
    prev: dict[str, tuple[str, str] | None] = {start: None}
    todo = deque([start])
    while todo:
        node = todo.popleft()
        for name, a, b in edges:
            for u, v in ((a, b), (b, a)):
                if u == node and v not in prev:
                    prev[v] = (node, name)
                    todo.append(v)
    held = f" with held {', '.join(f'{k} = {v}' for k, v in hold.items())}" if hold else ""
    if goal not in prev:
        return InputError(f"joints.{worst}", f"cannot be satisfied{held}: gap {gaps[worst]:.4g} {mech.unit('m')}")
    bodies, joints, node = [goal], [], goal
    step = prev[node]
    while step is not None:
        node, name = step
        bodies.append(node)
        joints.append(name)
        step = prev[node]
    bodies, joints = bodies[::-1], [*joints[::-1], worst]  # start ... goal, then back to start by `worst`
    if "ground" in bodies:  # read the loop from the ground
        i = bodies.index("ground")
        bodies, joints = bodies[i:] + bodies[:i], joints[i:] + joints[:i]
    gap = sum(gaps.get(j, 0.0) for j in joints)
    loop = " - ".join([*bodies, bodies[0]])
    return InputError(f"joints.{worst}",
                      f"the loop {loop} (joints {', '.join(joints)}) cannot close with the given "
                      f"lengths{held}: it misses by {gap:.4g} {mech.unit('m')} at best")


def check_assembled(mech: Mechanism, kin: PlanarKinematics, model: MechanicalModel, x: np.ndarray, subs: dict,
                     Lc: float, coords: list[str], rows: list[ConstraintRow], cnames: list[str]) -> None:
    """InputError naming what makes the assembled configuration degenerate: a spring, damper or
    actuator whose line of action has coincident points (its direction, and so its force, is
    undefined; :meth:`~._plugin.PlugIn.line_of_action`, not the drawing anchors), a distance
    condition between coincident points, or a load,
    reaction or condition that is not finite there."""
    at = {symbol(n): float(v) for n, v in zip(model.names, x)}

    def number(expr: sp.Expr) -> float:
        return float_value(sp.sympify(expr, strict=True).xreplace(subs), at)

    where = "; move an end point or assemble elsewhere (bodies' initial, [assembly] hold)"
    for el in mech.force_elements():
        line = el.line_of_action()  # not its drawing anchors: a rotary element's ends may share a pin
        if line is not None:
            a, b = line
            d = kin.point(b) - kin.point(a)
            gap = math.hypot(number(d[0]), number(d[1]))
            if not gap > 1e-9 * Lc:
                raise InputError(el.field(), f"its ends {a} and {b} coincide at the assembled configuration "
                                             f"(distance {gap:.3g} {mech.unit('m')}): the direction of its force is "
                                             f"undefined there{where}")
    for cond in mech.conditions:
        line = cond.line_of_action()  # a distance: |b - a| has no derivative where a = b (a NaN Jacobian)
        if line is not None:
            d = kin.point(line[1]) - kin.point(line[0])
            gap = math.hypot(number(d[0]), number(d[1]))
            if not gap > 1e-9 * Lc:
                raise InputError(f"conditions.{cond.name}", f"its points {line[0]} and {line[1]} coincide at the "
                                                            f"assembled configuration (distance {gap:.3g} "
                                                            f"{mech.unit('m')}): the "
                                                            f"distance has no derivative there{where}")
    for ld in mech.loads:
        for key in ld.COORDINATE_KEYS:  # the expressions in the coordinates
            v = number(mech.value(ld.field(key)))
            if not math.isfinite(v):
                raise InputError(ld.field(key), f"is {v} at the assembled configuration (a division "
                                                f"by zero there?){where}")
    nq, nr = len(coords), len(rows)
    for c, v in zip(cnames, x[nq + nr:nq + nr + len(cnames)]):
        if not math.isfinite(v):
            raise InputError(f"conditions.{c}", f"is {v} at the assembled configuration (a division by zero or an "
                                                f"angle between coincident points there?){where}")
    Q = model.applied_forces(x)
    lam = x[nq:nq + nr]
    bad = [c for c, v in zip(coords, Q) if not math.isfinite(v)]
    what = "applied forces"
    if not bad and not np.all(np.isfinite(lam)):
        bad, what = [r.reaction for r, v in zip(rows, lam) if not math.isfinite(v)], "joint reactions"
    if bad:
        raise InputError("assembly", f"the {what} are not finite at the assembled configuration ({', '.join(bad[:4])}"
                                     f"{', ...' if len(bad) > 4 else ''}): the geometry there is degenerate (two "
                                     f"points that carry a force coincide, or a load divides by zero){where}")


def redundancy_error(mech: Mechanism, rows: list[ConstraintRow], report: DofReport) -> InputError:
    """One line: how many constraints are redundant, which joints, and what to do."""
    n = len(report.dependent)
    groups = "; ".join(f"{rows[i].equation} is implied by joints {', '.join(g[1:]) or '(none)'}"
                       for i, g in zip(report.dependent, report.redundant))
    return InputError("mechanism.redundant",
                      f"over-constrained: {n} redundant constraint(s) among joints "
                      f"{', '.join(report.redundant_joints)} ({groups}); the mechanism has the intended {report.dof} "
                      f"degree(s) of freedom but those joints' reactions are statically indeterminate: "
                      f"relax one joint (e.g. a slider instead of a pin) or set redundant = \"drop\" under "
                      f"[mechanism] to drop the dependent rows")
