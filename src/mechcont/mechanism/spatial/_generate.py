"""Generate the static equilibrium system of a spatial mechanism.

Unknowns: body coordinates ``q`` (origin and Euler parameters of each body), one reaction per
constraint row (joints, length-mode actuators, and the normalisation multiplier ``mu_<body>``
per body) and one state per condition. Equations, as for planar mechanisms:

    Q(q, p) - Phi_q(q, p)^T lambda = 0      one row per coordinate (Fx_b, Fy_b, Fz_b, Qe0_b..Qe3_b)
    Phi_k(q, p) = 0                          a rigid row
    Phi_k(q, p) - lambda_k / k_k = 0         a compliant row (joint stiffness k_k)
    c(q, p) - NAME = 0                       a condition row

The mechanics (stability, dynamics) sees every rigid row as a constraint and each compliant
row as the potential ``k Phi^2 / 2``. Redundant rigid rows (an over-constrained closure) are
refused with the joints involved and the fix (a joint stiffness, which makes the reactions
determinate, or ``redundant = "drop"``); a rigid closure that cannot be assembled is reported
with its misfit. With ``redundant = "drop"`` a dependent row's equation ``<row>_dropped`` holds
its reaction at zero (``lambda_k = 0``) instead of the row; which rows are dropped is chosen at
the build pose and again along a branch where the kept rows lose rank (:class:`_RowChoice`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy as sp

from ...equations import EquationSystem, MechanicalModel, Model, Variable, gradient
from ...errors import InputError
from .._assembly import DofReport, close_constraints, dof_report
from .._conditions import condition_rows
from .._dropped_rows import SWITCH_RATIO, choose_dropped, conditioning
from .._element_states import collect_states, rest_rows, steady_states
from .._expr import symbol
from .._forces import loads
from .._generate import (
    _coordinates_of,
    _dropped_residual,
    _equilibrium,
    _scales,
    condition_and_parameter_variables,
    element_forces,
    fields_at_values,
    load_forces,
    row_units,
)
from .._kinematics import place_along_joints
from .._stops import stop_forces
from .._values import analysis_value_check, check_values, evaluate, parameter_values, physical_limits
from ._kinematics import SpatialKinematics
from ._rotation import quaternion_from_rotation_vector
from ._scene import spatial_scene_function
from .joints import SpatialRow

if TYPE_CHECKING:
    from ._description import SpatialMechanism

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
    forces += element_forces(mech, values, Lc)
    forces += load_forces(mech, values)
    return Lc, max(forces)


def _initial_guess(kin: SpatialKinematics, values: dict[str, float]) -> dict[str, float]:
    """Coordinates near the design pose: given ``initial`` values, bodies placed through the
    joints that make two points coincide, unit Euler parameters from ``initial.rotation``."""
    mech = kin.mech
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
    place_along_joints(kin, placed, guess, values)
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


def _joints_only(names: Iterable[str]) -> list[str]:
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
    """The spatial system with a given set of redundant rigid rows dropped.

    Every row keeps its reaction among the unknowns; a dropped row's equation holds its reaction
    at zero instead of the row at zero, and the equilibrium rows leave it out (so its column is
    that one entry: the Jacobian is the one of the system without the dropped rows, bordered).
    So all variants have the same variables, and a branch passes from one to the next with its
    vector unchanged but for the reactions. After its first build the variant keeps its model,
    copied by later builds."""

    dropped: tuple[int, ...]
    equilibrium: list[sp.Expr]    # Q - Phi_q^T lambda over the kept rows
    equations: list[sp.Expr]
    equation_names: list[str]
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
    mechanics: MechanicalModel    # every rigid row (dropped or not) a constraint, compliant rows springs
    elastic: sp.Expr
    condition_values: Callable[[np.ndarray], np.ndarray] | None
    states: list = field(default_factory=list)  # the elements' first-order states (ElementState)
    variants: dict[tuple[int, ...], _Variant] = field(default_factory=dict)

    @property
    def cnames(self) -> list[str]:
        """Names of the condition states."""
        return [c.name for c, _ in self.conditions]

    @property
    def n_rigid(self) -> int:
        """Number of rigid rows (they come first in :attr:`rows`)."""
        return sum(r.stiffness is None for r in self.rows)

    @property
    def protect(self) -> np.ndarray:
        """Mask over the rigid rows: the Euler-parameter normalisations, never dropped."""
        return np.array([r.joint.startswith("norm_") for r in self.rows if r.stiffness is None], dtype=bool)

    def variant(self, mech: SpatialMechanism, dropped: tuple[int, ...]) -> _Variant:
        """The system with the rigid rows ``dropped`` (indices into :attr:`rows`) dropped."""
        out = self.variants.get(dropped)
        if out is None:
            # the dropped reactions, zero, are left out of the equilibrium rows: products with a zero
            # multiplier there would only bring rounding (down to subnormal numbers, slow to factorise)
            kept = [r for i, r in enumerate(self.rows) if i not in dropped]
            equilibrium, _ = _equilibrium(mech, self.coords, kept, self.forces, self.mass, self.cnames,
                                          gradient=gradient, states=self.states)
            eqs, names = [], []
            for i, r in enumerate(self.rows):
                lam = symbol(r.reaction)
                if i in dropped:
                    eqs.append(lam)
                    names.append(f"{r.equation}_dropped")
                else:
                    eqs.append(r.expr - lam / r.stiffness if r.stiffness is not None else r.expr)
                    names.append(r.equation)
            out = self.variants[dropped] = _Variant(dropped, equilibrium, eqs, names)
        return out

    def reactions(self, model: MechanicalModel, x: np.ndarray, dropped: Sequence[int]) -> np.ndarray:
        """The reactions of ``model``'s constraint rows balancing its applied forces at ``x`` with the
        rows ``dropped`` carrying none (least squares: exact at an equilibrium)."""
        A = model.phi_q(x)
        keep = np.setdiff1d(np.arange(len(A)), np.asarray(dropped, dtype=int))
        lam = np.zeros(len(A))
        lam[keep] = np.linalg.lstsq(A[keep].T, model.applied_forces(x), rcond=None)[0]
        return lam


@dataclass(frozen=True)
class _RowChoice:
    """The dropped rows of one variant, checked and chosen again along a branch (a model's ``reselect``).

    Why choose again rather than keep every row: rows dropped at one configuration can become
    dependent at another (the Bennett linkage's kept rows lose rank a few tens of degrees of crank
    away from the build pose, its reactions then grow without bound and continuation stalls), while
    the mechanism itself stays regular. Keeping every row with minimum-norm reactions would need no
    choice, but its Jacobian is singular everywhere: the corrector keeps whatever self-stress the
    predictor brings (reactions that depend on the path), and the tangent, fold and branch-point
    tests of the engine, which rely on a regular bordered Jacobian, no longer work. Switching keeps
    every piece a regular square system; only the split of the indeterminate reactions between
    the rows changes at a switch (the determinate ones, the loads solved for and the coordinates
    are continuous)."""

    mech: SpatialMechanism = field(repr=False)
    dropped: tuple[int, ...]

    def quality(self, x: np.ndarray) -> float:
        """``log(conditioning / SWITCH_RATIO)`` of the kept rigid rows at the full vector ``x``:
        positive while the dropped rows suit ``x``, negative once they should be chosen again."""
        ratio = conditioning(_structure(self.mech).mechanics.phi_q(x), self.dropped)
        return math.log(max(ratio, 1e-300) / SWITCH_RATIO)

    def switch(self, model: Model, x: np.ndarray, force: bool = False) -> tuple[Model, np.ndarray] | None:
        """The variant of ``model`` whose kept rows are best conditioned at the equilibrium ``x``, and
        ``x`` with its rigid reactions solved again (the dropped ones zero); None when it is this one,
        unless ``force`` (then ``model`` itself with the reactions solved again)."""
        st = _structure(self.mech)
        dropped = choose_dropped(st.mechanics.phi_q(x), st.protect)
        if dropped == self.dropped and not force:
            return None
        keep = ("dof", "conditions", "fields_at", "downlock", "stops", "dampers")
        new = model if dropped == self.dropped else _variant_model(
            self.mech, st, st.variant(self.mech, dropped), list(model.variables), **{k: getattr(model, k) for k in keep})
        nq = len(st.coords)
        y = np.array(x, dtype=float)
        y[nq:nq + st.n_rigid] = st.reactions(st.mechanics, y, dropped)
        return new, y


def _variant_model(mech: SpatialMechanism, st: _Structure, var: _Variant, variables: list[Variable],
                   **fields_: Any) -> Model:
    """A copy of ``var``'s model with ``variables`` and the model ``fields_`` (built and kept on first use)."""
    if var.model is None:
        dropped = [st.rows[i] for i in var.dropped]
        system = EquationSystem(
            name=mech.name,
            variables=variables,
            equations=[*var.equilibrium, *var.equations, *(e - symbol(c.name) for c, e in st.conditions),
                       *rest_rows(st.states, st.coords)],
            equation_names=[*(_row_name(c) for c in st.coords), *var.equation_names,
                            *(f"cond_{n}" for n in st.cnames), *(f"rate_{s.name}" for s in st.states)],
            mechanics=st.mechanics,
            description=(mech.description or f"generated from the description of {mech.name}")
            + (f" [redundant constraint rows dropped: {', '.join(r.equation for r in dropped)}]" if dropped else ""),
            limits=physical_limits(mech, solve=True),
            scene=spatial_scene_function(st.kin, st.arrows, [v.symbol for v in variables]),
            check_values=analysis_value_check(mech),
        )
        var.model = Model.from_system(
            system,
            potential_energy=st.V + st.elastic,
            mechanism=mech,
            unit_system=mech.units,
            reaction_names=tuple(r.reaction for r in st.rows),
            coordinates_of=_coordinates_of(st.kin, system, {}),
            dropped_constraints=tuple(r.equation for r in dropped),
            dropped_residual=_dropped_residual(system, dropped),
            reselect=_RowChoice(mech, var.dropped) if var.dropped else None,
        )
    return var.model.evolve(variables=variables, **fields_)  # a copy: the kept model is never handed out


def _structure(mech: SpatialMechanism) -> _Structure:
    """The value-independent part of ``mech``'s system, made by its first build and kept with it."""
    st = mech._generated.get("spatial")
    if st is not None:
        return st
    kin = SpatialKinematics(mech)
    ld = loads(kin)
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
    cnames = [c.name for c, _ in conditions]
    states = collect_states(kin)
    _, closure = _equilibrium(mech, coords, rows, forces, mass, cnames, gradient=gradient, states=states)
    elastic = sum((r.expr ** 2 * r.stiffness / 2 for r in rows if r.stiffness is not None), sp.S.Zero)
    mech_forces = [f - d for f, d in zip(forces, gradient(elastic, kin.q))]
    rigid_rows = [r for r in rows if r.stiffness is None]
    mechanics = MechanicalModel(closure.names, coords, [r.expr for r in rigid_rows], mech_forces, mass,
                                [r.equation for r in rigid_rows], potential=ld.V + elastic,
                                state_rates={s.name: s.rate for s in states} or None)
    condition_values = None
    if conditions:
        from ...equations import compile_dense

        condition_values = compile_dense([symbol(n) for n in closure.names], [e for _, e in conditions])
    st = mech._generated["spatial"] = _Structure(kin, rows, ld.arrows, coords, forces, mass, ld.V, conditions,
                                                 closure, mechanics, elastic, condition_values, states)
    return st


def generate(mech: SpatialMechanism, overrides: dict, reduced: bool) -> Model:
    """Build the static system of the spatial ``mech`` with parameter ``overrides`` (SI).

    The equations are generated and compiled by the first build of the description; a build at
    other values only assembles the mechanism again (see :class:`_Structure`).
    """
    if reduced:
        raise InputError("reduced", "the reduced form exists for planar mechanisms only; build the full system")
    values = parameter_values(mech, overrides)
    check_values(mech, values)
    st = _structure(mech)
    kin, coords, rows, cnames, closure = st.kin, st.coords, st.rows, st.cnames, st.closure
    Lc, Fc = _spatial_scales(kin, values)
    guess = _initial_guess(kin, values)
    nq = len(coords)
    x = np.array([guess.get(n, 0.0) for n in coords] + [0.0] * (len(rows) + len(cnames))
                 + [s.initial for s in st.states] + [values[p.name] for p in mech.parameters])
    free_q = np.array([c not in mech.hold for c in coords])
    rigid = np.array([r.stiffness is None for r in rows])
    # closed relative to each row's size (a position weighs Lc, an Euler parameter 1), in any units
    positions = {n for b in mech.bodies for n in mech._coordinate_names(b.name)[:3]}  # x1 of body 1 as x_leg
    weight = np.array([Lc if c in positions else 1.0 for c in coords])
    # ... with the minimum-norm steps of the SI twin, so the pose found is the same in any units
    si = np.array([mech.units.from_si("m") if c in positions else 1.0 for c in coords])
    per_row = row_units(mech.units, rows)
    x_all, ok = close_constraints(closure.phi, closure.phi_q, x, closure.q_index, free_q, scale=weight, step_scale=si,
                                  row_scale=per_row)
    if ok:
        x = x_all
    elif rigid.all():
        raise _misfit_error(mech, rows, closure.phi(x_all))
    else:  # the compliant joints take up the misfit of the rigid rows
        x, ok = close_constraints(lambda y: closure.phi(y)[rigid], lambda y: closure.phi_q(y)[rigid], x,
                                  closure.q_index, free_q, scale=weight, step_scale=si,
                                  row_scale=per_row[rigid])
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
    x = steady_states(st.mechanics, x)  # before the reactions: the forces may use the states
    x[nq:nq + len(rows)] = st.reactions(closure, x, dependent)
    if st.condition_values is not None:
        x[nq + len(rows):nq + len(rows) + len(cnames)] = np.asarray(st.condition_values(x), dtype=float).reshape(-1)
    for cond, value in zip(mech.conditions, x[nq + len(rows):nq + len(rows) + len(cnames)]):
        line = cond.line_of_action()  # a distance |b - a|: no derivative where a = b
        if line is not None and not value > 1e-9 * Lc:
            raise InputError(f"conditions.{cond.name}", f"its points {line[0]} and {line[1]} coincide at the "
                                                        f"assembled configuration (distance {value:.3g} {mech.unit('m')}): "
                                                        "the distance has no derivative there; move a point or assemble "
                                                        "elsewhere (bodies' initial, [assembly] hold)")
    variables = []
    for c, v in zip(coords, x):
        euler = c.startswith("e")
        variables.append(Variable(c, "state", float(v), "" if euler else mech.unit("m"), 1.0 if euler else Lc,
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
        variables.append(Variable(r.reaction, "state", float(v), mech.unit(r.unit), Fc * Lc if r.unit == "N m" else Fc,
                                  what))
    variables += condition_and_parameter_variables(mech, st.conditions, x[nq + len(rows):], values, Lc, Fc, st.states)
    targets, downlock, at = fields_at_values(mech, values)
    return _variant_model(mech, st, var, variables, dof=report, conditions=targets, fields_at=at, **downlock)
