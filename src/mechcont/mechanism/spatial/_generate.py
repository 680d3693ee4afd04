"""Generate the static equilibrium system of a spatial mechanism.

Unknowns: body coordinates ``q`` (origin and Euler parameters of each body), one reaction per
constraint row (joints, length-mode actuators, and the normalisation multiplier ``mu_<body>``
per body) and one state per condition. Equations, as for planar mechanisms:

    Q(q, p) - Phi_q(q, p)^T lambda = 0      one row per coordinate (Fx_b, Fy_b, Fz_b, Qe0_b..Qe3_b)
    Phi_k(q, p) = 0                          a rigid row
    Phi_k(q, p) - lambda_k / k_k = 0         a compliant row (joint stiffness k_k)
    c(q, p) - NAME = 0                       a condition row

The mechanics (stability, dynamics) sees the rigid rows as constraints and each compliant row
as the potential ``k Phi^2 / 2``. Redundant rigid rows (an over-constrained closure) are
refused with the joints involved and the fix (a joint stiffness, which makes the reactions
determinate, or ``redundant = "drop"``); a rigid closure that cannot be assembled is reported
with its misfit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import partial

import numpy as np
import sympy as sp

from ...equations import EquationSystem, MechanicalModel, Model, Variable
from ...equations._codegen import gradient
from ...errors import InputError
from .._assembly import DofReport, close_constraints, dof_report
from .._conditions import condition_rows
from .._description import PointForce
from .._expr import symbol
from .._generate import (
    _coordinates_of,
    _dropped_residual,
    _equilibrium,
    _scales,
    condition_and_parameter_variables,
    condition_fields,
    value_fields,
)
from .._stops import stop_forces
from .._values import evaluate, parameter_values
from ._description import SpatialMechanism
from ._joints import SpatialRow
from ._kinematics import SpatialKinematics, spatial_loads
from ._rotation import quaternion_from_rotation_vector
from ._scene import spatial_scene_function
from ._values import check_spatial_values, spatial_limits, spatial_value_check

__all__ = ["generate"]


def _row_name(coord: str) -> str:
    head, _, body = coord.partition("_") if coord[0] == "e" else (coord[0], "", coord[1:].lstrip("_"))
    return f"Q{head}_{body}" if coord[0] == "e" else f"F{head}_{body}"


def _spatial_scales(kin: SpatialKinematics, values: dict[str, float]) -> tuple[float, float]:
    """Typical length (m) and force (N) of the spatial mechanism at ``values``: the largest body
    (distance between its points), bar, free or actuator length; the largest of the weight, spring
    forces over that length and point-force magnitudes."""
    mech = kin.mech
    at = {symbol(k): v for k, v in values.items()}
    Lc = _scales(mech, values)[0]
    for b in mech.bodies:
        pts = [[float(c.xreplace(at)) for c in kin.local_point(b.name, p)] for p in mech.point_names(b.name)]
        P = np.array(pts)
        if len(P) > 1:
            Lc = max(Lc, float(np.max(np.linalg.norm(P[:, None, :] - P[None, :, :], axis=-1))))
    forces = [1e-3]
    if mech.gravity is not None:
        g = abs(evaluate(mech.value("gravity.g"), values, ""))
        forces.append(g * sum(evaluate(mech.value(f"bodies.{b.name}.mass"), values, "") for b in mech.bodies))
    forces += [abs(evaluate(mech.value(f"springs.{sp_.name}.k"), values, "")) * Lc for sp_ in mech.springs]
    forces += [abs(evaluate(mech.value(f"loads.{ld.name}.magnitude"), values, "")) for ld in mech.loads
               if isinstance(ld, PointForce)]
    return Lc, max(forces)


def _initial_guess(kin: SpatialKinematics, values: dict[str, float]) -> dict[str, float]:
    """Coordinates near the design pose: given ``initial`` values, bodies placed through the
    joints that make two points coincide, unit Euler parameters from ``initial.rotation``."""
    mech = kin.mech
    num = {symbol(k): v for k, v in values.items()}
    guess: dict[str, float] = {}
    placed = {"ground"}
    for b in mech.bodies:
        f = f"bodies.{b.name}.initial"
        names = mech._coordinate_names(b.name)
        for key, name in zip("xyz", names):
            guess[name] = evaluate(mech.value(f"{f}.{key}"), values, f"{f}.{key}") if key in b.initial else 0.0
        rot = ([evaluate(mech.value(f"{f}.rotation.{c}"), values, f"{f}.rotation") for c in "xyz"]
               if "rotation" in b.initial else [0.0, 0.0, 0.0])
        if not math.hypot(*rot) <= 2 * math.pi:  # beyond one turn (1e308: cos/sin of an overflow) nothing is meant
            raise InputError(f"{f}.rotation", f"its angle |r| = {math.hypot(*rot):.6g} rad must be at most 2 pi: give "
                                              "the axis times an angle of at most one turn")
        guess.update(zip(names[3:], quaternion_from_rotation_vector(rot)))
        if all(k in b.initial for k in "xyz"):
            placed.add(b.name)
    held = {k: evaluate(mech.value(f"assembly.hold.{k}"), values, f"assembly.hold.{k}") for k in mech.hold}
    guess.update(held)
    changed = True
    while changed:
        changed = False
        for j in mech.joints:
            ba, bb = j.a.split(".")[0], j.b.split(".")[0]
            if not j.COINCIDENT or (ba in placed) == (bb in placed):
                continue
            known, new = (j.a, j.b) if ba in placed else (j.b, j.a)
            body = new.split(".")[0]
            at = {**num, **{symbol(k): v for k, v in guess.items()}}
            P = np.array([float(c) for c in kin.point(known).xreplace(at)])
            origin = kin.body_r[body]
            local = np.array([float(c) for c in kin.point(new).xreplace({**at, **{s: 0 for s in origin}})])
            for s, v in zip(origin, P - local):
                guess[str(s)] = float(v)
            placed.add(body)
            changed = True
    guess.update(held)  # a held coordinate keeps its value: placing its body by a joint must not move it
    return guess


def _misfit_error(mech: SpatialMechanism, rows: list[SpatialRow], phi: np.ndarray) -> InputError:
    """One line: the rigid closure cannot be assembled; its misfit, joint by joint."""
    gaps: dict[str, float] = {}
    for row, r in zip(rows, phi):
        if not row.joint.startswith("norm_"):   # a normalisation row is no joint: its residual is rounding
            gaps[row.joint] = float(np.hypot(gaps.get(row.joint, 0.0), r))
    order = {j.name: i for i, j in enumerate(mech.joints)}
    # largest first, equal misfits (to the 4 digits shown) in declaration order: a tie must not
    # depend on the last bits of a least-squares solve
    worst = sorted(((g, j) for j, g in gaps.items() if g > 1e-9),
                   key=lambda gj: (-float(f"{gj[0]:.4g}"), order.get(gj[1], len(order))))[:3]
    shown = ", ".join(f"{j} {g:.4g}" for g, j in worst)
    field = f"joints.{worst[0][1]}" if worst and worst[0][1] in {j.name for j in mech.joints} else "joints"
    return InputError(field, f"the rigid closure cannot be assembled: misfit (m or rad, least squares) {shown}; "
                             "an over-constrained closure only assembles when its constraints are exactly "
                             "compatible: correct the geometry or give an attachment a stiffness "
                             "(joints.NAME.stiffness, N/m) so it deflects")


def _joints_only(names) -> list[str]:
    """The joint names among row owners (the normalisation rows ``norm_<body>`` left out)."""
    return [n for n in names if not n.startswith("norm_")]


def _redundancy_error(report: DofReport, rows: list[SpatialRow], dependent: list[int]) -> InputError:
    joints: list[str] = []
    for i in dependent:
        for g in report.redundant:
            if g[0] == rows[i].joint:
                joints.extend(j for j in _joints_only(g) if j not in joints)
    joints = joints or sorted({rows[i].joint for i in dependent})
    rx = ", ".join(rows[i].reaction for i in dependent[:6]) + (", ..." if len(dependent) > 6 else "")
    return InputError("mechanism.redundant",
                      f"over-constrained: {len(dependent)} redundant constraint(s) among joints {', '.join(joints)}; "
                      f"statics cannot determine their reactions ({rx} and the rows they depend on): give one of "
                      f"those joints a stiffness (joints.NAME.stiffness, N/m, or rotational_stiffness, N m/rad) to "
                      f"make them determinate, or set redundant = \"drop\" under [mechanism] for one particular "
                      f"solution")


@dataclass
class _Variant:
    """The spatial system with a given set of redundant rigid rows dropped: its rows, equations and
    mechanics, and (after the first build) its model, copied with new values by later builds."""

    rows: list[SpatialRow]
    dropped: list[SpatialRow]
    equilibrium: list[sp.Expr]
    closure: MechanicalModel      # every kept row taken as rigid: the assembled reactions
    mechanics: MechanicalModel    # rigid rows as constraints, compliant rows as springs
    elastic: sp.Expr
    condition_values: object | None = None
    model: Model | None = None


@dataclass
class _Structure:
    """Everything of a spatial system that does not depend on parameter values, made once per description."""

    kin: SpatialKinematics
    rows: list[SpatialRow]        # rigid rows first, then the compliant ones
    arrows: list
    coords: list[str]
    forces: list[sp.Expr]
    mass: sp.Matrix
    V: sp.Expr
    conditions: list
    closure: MechanicalModel      # every row taken as rigid (first assembly, degrees of freedom)
    variants: dict[tuple[int, ...], _Variant] = field(default_factory=dict)

    @property
    def cnames(self) -> list[str]:
        """Names of the condition states."""
        return [c.name for c, _ in self.conditions]

    def variant(self, mech: SpatialMechanism, dependent: tuple[int, ...]) -> _Variant:
        """The system with the rows ``dependent`` (indices into :attr:`rows`) dropped."""
        out = self.variants.get(dependent)
        if out is None:
            keep = [i for i in range(len(self.rows)) if i not in set(dependent)]
            rows = [self.rows[i] for i in keep]
            equilibrium, closure = _equilibrium(mech, self.coords, rows, self.forces, self.mass, self.cnames,
                                                gradient=gradient)
            elastic = sum((r.expr ** 2 * r.stiffness / 2 for r in rows if r.stiffness is not None), sp.S.Zero)
            mech_forces = [f - d for f, d in zip(self.forces, gradient(elastic, self.kin.q))]
            rigid_rows = [r for r in rows if r.stiffness is None]
            mechanics = MechanicalModel(closure.names, self.coords, [r.expr for r in rigid_rows], mech_forces,
                                        self.mass, [r.equation for r in rigid_rows])
            out = self.variants[dependent] = _Variant(rows, [self.rows[i] for i in dependent], equilibrium, closure,
                                                      mechanics, elastic)
            if self.conditions:
                from ...equations._codegen import compile_dense

                out.condition_values = compile_dense([symbol(n) for n in closure.names],
                                                     [e for _, e in self.conditions])
        return out


def _structure(mech: SpatialMechanism) -> _Structure:
    """The value-independent part of ``mech``'s system, made by its first build and kept with it."""
    st = mech._generated.get("spatial")
    if st is not None:
        return st
    kin = SpatialKinematics(mech)
    ld = spatial_loads(kin)
    coords = list(kin.coords)
    # rigid rows first: a dependency among rows that involves a compliant row is then found at
    # a compliant row (determinate); one among rigid rows only, at a rigid row (indeterminate)
    all_rows = kin.constraints()
    rows = [r for r in all_rows if r.stiffness is None] + [r for r in all_rows if r.stiffness is not None]
    forces = [-dv + qnc for dv, qnc in zip(gradient(ld.V, kin.q), ld.Q_nc)]
    mass = kin.mass_matrix()
    conditions = condition_rows(kin, {})
    if mech.stops:
        forces = [f + g for f, g in zip(forces, stop_forces(mech, conditions, kin.q, gradient=gradient))]
    names = [*coords, *(r.reaction for r in rows), *(c.name for c, _ in conditions), *(p.name for p in mech.parameters)]
    closure = MechanicalModel(names, coords, [r.expr for r in rows], forces, mass)
    st = mech._generated["spatial"] = _Structure(kin, rows, ld.arrows, coords, forces, mass, ld.V, conditions,
                                                 closure)
    return st


def _check_analysis_values(mech: SpatialMechanism, values: Mapping[str, float]) -> None:
    """The description's physical checks at ``values`` (the defaults where not given; a zero stiffness allowed)."""
    check_spatial_values(mech, {p.name: float(values.get(p.name, p.value)) for p in mech.parameters}, solve=True)


def generate(mech: SpatialMechanism, overrides: dict, reduced: bool) -> Model:
    """Build the static system of the spatial ``mech`` with parameter ``overrides`` (SI).

    The equations are generated and compiled by the first build of the description; a build at
    other values only assembles the mechanism again (see :class:`_Structure`).
    """
    if reduced:
        raise InputError("reduced", "the reduced form exists for planar mechanisms only; build the full system")
    values = parameter_values(mech, overrides)
    check_spatial_values(mech, values)
    st = _structure(mech)
    kin, coords, rows, cnames, closure = st.kin, st.coords, st.rows, st.cnames, st.closure
    Lc, Fc = _spatial_scales(kin, values)
    guess = _initial_guess(kin, values)
    nq = len(coords)
    x = np.array([guess.get(n, 0.0) for n in coords] + [0.0] * (len(rows) + len(cnames))
                 + [values[p.name] for p in mech.parameters])
    free_q = np.array([c not in mech.hold for c in coords])
    rigid = np.array([r.stiffness is None for r in rows])
    x_all, ok = close_constraints(closure.phi, closure.phi_q, x, closure.q_index, free_q)
    if ok:
        x = x_all
    elif rigid.all():
        raise _misfit_error(mech, rows, closure.phi(x_all))
    else:  # the compliant joints take up the misfit of the rigid rows
        x, ok = close_constraints(lambda y: closure.phi(y)[rigid], lambda y: closure.phi_q(y)[rigid], x,
                                  closure.q_index, free_q)
        if not ok:
            raise _misfit_error(mech, [r for r in rows if r.stiffness is None], closure.phi(x)[rigid])
    report = dof_report(closure.phi_q(x), [r.joint for r in rows])
    if report.dof != mech.dof:
        red = (f"; redundant constraints among joints {', '.join(_joints_only(report.redundant_joints))}"
               if report.redundant else "")
        raise InputError("mechanism.dof", f"the assembled mechanism has {report.dof} degree(s) of freedom, intended "
                                          f"{mech.dof} (rank {report.rank} of {len(rows)} constraint rows on "
                                          f"{nq} coordinates, {len(mech.bodies)} of them normalisation rows){red}")
    dependent = tuple(i for i in report.dependent if rows[i].stiffness is None)
    if dependent and mech.redundant != "drop":
        raise _redundancy_error(report, rows, list(dependent))
    var = st.variant(mech, dependent)
    if var.dropped:
        x = np.concatenate([x[:nq], np.zeros(len(var.rows)), x[nq + len(rows):]])
    rows = var.rows
    x[nq:nq + len(rows)] = var.closure.multipliers(x)
    if var.condition_values is not None:
        x[nq + len(rows):nq + len(rows) + len(cnames)] = np.asarray(var.condition_values(x), dtype=float).reshape(-1)
    for cond, value in zip(mech.conditions, x[nq + len(rows):nq + len(rows) + len(cnames)]):
        if cond.kind == "distance" and not value > 1e-9 * Lc:  # |b - a| has no derivative where a = b
            raise InputError(f"conditions.{cond.name}", f"its points {cond.points[0]} and {cond.points[1]} coincide at "
                                                        f"the assembled configuration (distance {value:.3g} m): the "
                                                        "distance has no derivative there; move a point or assemble "
                                                        "elsewhere (bodies' initial, [assembly] hold)")
    variables = []
    for c, v in zip(coords, x):
        euler = c.startswith("e")
        variables.append(Variable(c, "state", float(v), "" if euler else "m", 1.0 if euler else Lc,
                                  "Euler parameter of a body's orientation" if euler
                                  else f"{c[0]} position of a body's frame origin"))
    for r, v in zip(rows, x[nq:]):
        if r.reaction.startswith("mu_"):
            what = "multiplier of the Euler-parameter normalisation (no physical meaning)"
        elif r.equation.endswith("_length"):
            what = f"tension of actuator {r.joint} (+ pulls its ends together)"
        else:
            what = f"reaction of joint {r.joint} (on its second body)" + (
                "; compliant: the joint deflects by reaction / stiffness" if r.stiffness is not None else "")
        variables.append(Variable(r.reaction, "state", float(v), r.unit, Fc * Lc if r.unit == "N m" else Fc, what))
    variables += condition_and_parameter_variables(mech, st.conditions, x[nq + len(rows):], values, Lc, Fc)
    targets, downlock = condition_fields(mech, values)
    at = partial(value_fields, mech) if mech.conditions else None
    if var.model is not None:  # the same structure built before: new values, the same compiled code
        return var.model.evolve(variables=variables, dof=report, conditions=targets, fields_at=at, **downlock)
    lam = [symbol(r.reaction) for r in rows]
    row_exprs = [r.expr - k / r.stiffness if r.stiffness is not None else r.expr for r, k in zip(rows, lam)]
    dropped = var.dropped
    system = EquationSystem(
        name=mech.name,
        variables=variables,
        equations=[*var.equilibrium, *row_exprs, *(e - symbol(c.name) for c, e in st.conditions)],
        equation_names=[*(_row_name(c) for c in coords), *(r.equation for r in rows), *(f"cond_{n}" for n in cnames)],
        mechanics=var.mechanics,
        description=(mech.description or f"generated from the description of {mech.name}")
        + (f" [redundant constraint rows dropped: {', '.join(r.equation for r in dropped)}]" if dropped else ""),
        limits=spatial_limits(mech, solve=True),
        scene=spatial_scene_function(kin, st.arrows, [v.symbol for v in variables]),
        check_values=spatial_value_check(mech, partial(_check_analysis_values, mech)),
    )
    var.model = Model.from_system(
        system,
        potential_energy=st.V + var.elastic,
        mechanism=mech,
        dof=report,
        reaction_names=tuple(r.reaction for r in rows),
        coordinates_of=_coordinates_of(kin, system, {}),
        dropped_constraints=tuple(r.equation for r in dropped),
        dropped_residual=_dropped_residual(system, dropped),
        conditions=targets,
        fields_at=at,
        **downlock,
    )
    return var.model.evolve()  # a copy: the kept model is never handed out (compiled on first numeric use)
