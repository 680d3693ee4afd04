"""Generate the static equilibrium system of a described mechanism.

Unknowns: the body coordinates ``q`` and one reaction per scalar constraint (``lambda``,
named ``R_<joint>_x``, ``R_<joint>_y``, ``R_<joint>`` or ``T_<joint>``). Equations:

    Q(q, p) - Phi_q(q, p)^T lambda = 0     (one row per coordinate: Fx_<b>, Fy_<b>, M_<b>)
    Phi(q, p) = 0                           (one row per constraint: <joint>_x, ...)
    c(q, p) - NAME = 0                      (one row per condition: cond_<NAME>, state NAME)

where ``Q`` includes each stop's contact reaction ``s R_<stop> dc/dq`` (see :mod:`._stops`)

with ``Q = -dV/dq + Q_nc`` at rest (see :mod:`._forces`). Length-mode actuators are
constraint rows (reaction ``T_<actuator>``, see :mod:`.elements.actuator`); condition rows are
outputs that the mechanics never see (see :mod:`._conditions`). For a body whose frame origin is
its centre of gravity the rows are exactly the force and moment balance of that body with
the inter-link forces as unknowns, as in the paper. The reduced form is described in
:mod:`._reduce`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import sympy as sp

from ..equations import (
    EquationSystem,
    MechanicalModel,
    Model,
    Variable,
    velocity_symbol,
)
from ..errors import InputError
from ..units import UnitSystem, typical_scale
from ._assembly import close_constraints, dof_report
from ._compiled import CoordinatesOf, DroppedResidual
from ._conditions import condition_description, condition_rows, condition_scale
from ._diagnose import check_assembled, least_squares_closure, loop_error, redundancy_error
from ._element_states import collect_states, rest_rows, steady_states
from ._expr import Gradient, symbol
from ._forces import loads
from ._kinematics import ConstraintRow, PlanarKinematics, place_along_joints
from ._numeric import ValueFieldsAt, value_fields_at
from ._reduce import reduce_form, velocity_map
from ._scene import scene_function
from ._stops import stop_forces
from ._values import analysis_value_check, check_values, evaluate, parameter_values, physical_limits
from .elements.torsion_spring import TorsionSpring

if TYPE_CHECKING:
    from ._conditions import Condition
    from ._description import Mechanism
    from ._elements import Parameter
    from .elements._base import ElementState
    from .spatial._kinematics import SpatialKinematics

__all__ = ["generate"]

_ROW_NAME = {"x": "Fx", "y": "Fy", "theta": "M"}


def _row_name(coord: str) -> str:
    for prefix in ("theta", "x", "y"):
        if coord.startswith(prefix):
            return f"{_ROW_NAME[prefix]}_{coord[len(prefix):].lstrip('_')}"
    return f"Q_{coord}"  # pragma: no cover - coordinates always start with x, y or theta


def _scales(mech: Mechanism, values: dict[str, float], kin: PlanarKinematics | None = None) -> tuple[float, float]:
    """Typical length (m) and force (N) of the mechanism at ``values``. Where the file states no length (no bar,
    no spring length), the largest distance between two points of one body (with ``kin``); where it states no
    force, the torsion springs' moment per radian over that length: a file of general bodies and torsion springs
    (Ziegler's column) then steps alike in m and kg as in mm and g."""
    lengths = [abs(evaluate(mech.value(f"bodies.{b.name}.length"), values, "")) for b in mech.bodies
               if b.length is not None]
    lengths += [abs(evaluate(mech.value(el.field(k)), values, "")) for el in mech.force_elements() for k in el.LENGTH_KEYS]
    if kin is not None and not any(v > 0 for v in lengths):
        lengths = _point_spans(mech, kin, values)
    Lc = max([v for v in lengths if v > 0], default=1.0)
    forces = []
    if mech.gravity is not None:
        g = abs(evaluate(mech.value("gravity.g"), values, ""))
        forces.append(g * sum(evaluate(mech.value(f"bodies.{b.name}.mass"), values, "") for b in mech.bodies))
    forces += element_forces(mech, values, Lc)
    forces += load_forces(mech, values)
    if not all(math.isfinite(f) for f in [Lc, *forces]):
        raise InputError("mechanism", "its values give forces or lengths beyond floating point (a weight, spring "
                                      "force or load above 1e308): write them in a unit that keeps them finite")
    # the largest force the file states; a floor only when it states none (a floor under stated forces would
    # swamp them in a file written in km and grams)
    if not any(f > 0 for f in forces):
        forces = [abs(evaluate(mech.value(el.field("k")), values, "")) / Lc for el in mech.force_elements()
                  if isinstance(el, TorsionSpring)]
    return Lc, max([f for f in forces if f > 0], default=1e-3)


def _point_spans(mech: Mechanism, kin: PlanarKinematics, values: Mapping[str, float]) -> list[float]:
    """The largest distance (m) between two points of each body at ``values``."""
    at = {symbol(k): v for k, v in values.items()}
    spans = []
    for b in mech.bodies:
        pts = np.array([[float(c.xreplace(at)) for c in kin.local_point(b.name, p)] for p in mech.point_names(b.name)])
        if len(pts) > 1:
            spans.append(float(np.max(np.linalg.norm(pts[:, None, :] - pts[None, :, :], axis=-1))))
    return spans


def element_forces(mech: Mechanism, values: Mapping[str, float], Lc: float) -> list[float]:
    """The typical forces (N) of the force elements at ``values``: each stiffness (N/m) times ``Lc`` (m)."""
    return [abs(evaluate(mech.value(el.field(k)), values, "")) * Lc for el in mech.force_elements() for k in el.STIFFNESS_KEYS]


def load_forces(mech: Mechanism, values: Mapping[str, float]) -> list[float]:
    """The magnitudes (N) of the loads that state one (:attr:`~.loads.Load.FORCE_KEY`) at ``values``."""
    return [abs(evaluate(mech.value(ld.field(ld.FORCE_KEY)), values, "")) for ld in mech.loads
            if ld.FORCE_KEY is not None]


def _parameter_scale(p: Parameter, value: float, Lc: float, Fc: float) -> float:
    if p.scale is not None:
        return float(p.scale)
    typical = typical_scale(p.unit, Lc, Fc)  # "mm", "kN" and "g mm/s^2" are a length and a force too
    if typical is not None:
        return typical
    return abs(value) if value != 0 and math.isfinite(value) else 1.0


def _initial_guess(mech: Mechanism, kin: PlanarKinematics, values: dict[str, float]) -> dict[str, float]:
    """Approximate coordinates: the given initial values, bodies placed along pin chains."""
    guess: dict[str, float] = {}
    placed = {"ground"}
    for b in mech.bodies:
        xs, ys, ts = (str(s) for s in kin.body_q[b.name])
        f = f"bodies.{b.name}.initial"
        for key, name in (("x", xs), ("y", ys), ("theta", ts)):
            guess[name] = evaluate(mech.value(f"{f}.{key}"), values, f"{f}.{key}") if key in b.initial else 0.0
        if "x" in b.initial and "y" in b.initial:
            placed.add(b.name)
    place_along_joints(kin, placed, guess, values)
    return guess


@dataclass
class _Variant:
    """The symbolic system of a structure with a given set of redundant rows dropped, and its model.

    ``model`` is made (and its code compiled) at the first build; later builds copy it with
    their own values (:meth:`~mechcont.equations.EquationSystem.evolve`)."""

    rows: list[ConstraintRow]
    dropped: list[ConstraintRow]
    equilibrium: list[sp.Expr]
    mechanics: MechanicalModel
    condition_values: Callable[[np.ndarray], np.ndarray] | None = None
    model: Model | None = None


@dataclass
class _Structure:
    """Everything of a generated system that does not depend on parameter values.

    Made once per description and form (full or reduced) and kept with the description, so a
    build at other values generates and compiles nothing: only the assembly (initial guess,
    loop closure, reactions, condition values, scales) is redone."""

    kin: PlanarKinematics
    rows: list[ConstraintRow]
    arrows: list
    coords: list[str]
    forces: list[sp.Expr]
    mass: sp.Matrix
    subs: dict
    V: sp.Expr
    conditions: list
    mechanics: MechanicalModel
    equilibrium: list[sp.Expr]
    states: list = field(default_factory=list)  # the elements' first-order states (ElementState)
    variants: dict[tuple[int, ...], _Variant] = field(default_factory=dict)

    @property
    def cnames(self) -> list[str]:
        """Names of the condition states."""
        return [c.name for c, _ in self.conditions]

    def variant(self, mech: Mechanism, dependent: tuple[int, ...]) -> _Variant:
        """The system with the rows ``dependent`` (indices into :attr:`rows`) dropped."""
        out = self.variants.get(dependent)
        if out is None:
            if dependent:
                keep = [i for i in range(len(self.rows)) if i not in set(dependent)]
                rows = [self.rows[i] for i in keep]
                equilibrium, mechanics = _equilibrium(mech, self.coords, rows, self.forces, self.mass, self.cnames,
                                                      potential=self.V, states=self.states)
            else:
                rows, equilibrium, mechanics = self.rows, self.equilibrium, self.mechanics
            out = self.variants[dependent] = _Variant(rows, [self.rows[i] for i in dependent], equilibrium, mechanics)
            if self.conditions:
                from ..equations import compile_dense

                out.condition_values = compile_dense([symbol(n) for n in mechanics.names],
                                                     [e for _, e in self.conditions])
        return out


def _structure(mech: Mechanism, reduced: bool) -> _Structure:
    """The value-independent part of ``mech``'s (full or reduced) system, made once per description."""
    key = "reduced" if reduced else "full"
    st = mech._generated.get(key)
    if st is not None:
        return st
    kin = PlanarKinematics(mech)
    rows = kin.constraints()
    ld = loads(kin)
    M = kin.mass_matrix()
    if reduced:
        coords, rows, forces, mass, subs = reduce_form(kin, rows, ld.V, ld.Q_nc, M)
        V = ld.V.xreplace(subs)
        states = collect_states(kin, velocity_map(kin, subs)[2], subs)
        for k in mech.hold:
            if k not in coords:
                raise InputError(f"assembly.hold.{k}", "is eliminated in the reduced form; hold a kept coordinate "
                                                       f"({', '.join(coords)})")
    else:
        coords, mass, subs, V = list(kin.coords), M, {}, ld.V
        forces = [-sp.diff(ld.V, qi) + qnc for qi, qnc in zip(kin.q, ld.Q_nc)]
        states = collect_states(kin)
    conditions = condition_rows(kin, subs)
    if mech.stops:
        forces = [f + g for f, g in zip(forces, stop_forces(mech, conditions, [symbol(c) for c in coords]))]
    equilibrium, model = _equilibrium(mech, coords, rows, forces, mass, [c.name for c, _ in conditions], potential=V,
                                      states=states)
    st = _Structure(kin, rows, ld.arrows, coords, forces, mass, subs, V, conditions, model, equilibrium, states)
    mech._generated[key] = st
    return st


def generate(mech: Mechanism, overrides: dict, reduced: bool) -> Model:
    """Build the (full or reduced) static system of ``mech``; see :meth:`Mechanism.build`.

    The equations are generated and compiled once per description and form; a build at other
    parameter values reuses them and only assembles the mechanism at those values.
    """
    values = parameter_values(mech, overrides)
    check_values(mech, values)
    st = _structure(mech, reduced)
    kin, coords, rows, cnames, model = st.kin, st.coords, st.rows, st.cnames, st.mechanics
    Lc, Fc = _scales(mech, values, kin)
    # -- first assembly: consistent coordinates near the initial guess ------------------
    guess = _initial_guess(mech, kin, values)
    x = np.array([guess.get(n, 0.0) for n in coords] + [0.0] * (len(rows) + len(cnames))
                 + [s.initial for s in st.states] + [values[p.name] for p in mech.parameters])
    free_q = np.array([c not in mech.hold for c in coords])
    metre = mech.units.from_si("m")  # the minimum-norm steps of the SI twin: the same pose in any units
    x, ok = close_constraints(model.phi, model.phi_q, x, model.q_index, free_q,
                              scale=np.array([1.0 if c.startswith("theta") else Lc for c in coords]),
                              step_scale=np.array([1.0 if c.startswith("theta") else metre for c in coords]),
                              row_scale=row_units(mech.units, rows))
    if not ok:
        raise loop_error(mech, rows, model.phi(least_squares_closure(model, x, free_q)))
    report = dof_report(model.phi_q(x), [r.joint for r in rows])
    if report.dof != mech.dof:
        red = report.redundant_joints
        why = (f"; {len(report.dependent)} redundant constraint(s) among joints {', '.join(red)}" if red else "")
        if any(a.length is not None for a in mech.actuators):
            why += "; each actuator given a length locks one degree of freedom"
        raise InputError("mechanism.dof", f"the assembled mechanism has {report.dof} degree(s) of freedom, intended "
                                          f"{mech.dof} (rank {report.rank} of {len(rows)} constraints on "
                                          f"{len(coords)} coordinates){why}")
    if report.redundant and mech.redundant != "drop":
        raise redundancy_error(mech, rows, report)
    var = st.variant(mech, tuple(report.dependent) if report.redundant else ())
    if var.dropped:
        x = np.concatenate([x[:len(coords)], np.zeros(len(var.rows)), x[len(coords) + len(rows):]])
    rows, model = var.rows, var.mechanics
    nq = len(coords)
    x = steady_states(model, x)  # before the reactions: the forces may use the states
    x[nq:nq + len(rows)] = model.multipliers(x)
    if var.condition_values is not None:  # each condition's value at the assembled configuration
        x[nq + len(rows):nq + len(rows) + len(cnames)] = np.asarray(var.condition_values(x), dtype=float).reshape(-1)
    check_assembled(mech, kin, model, x, st.subs, Lc, coords, rows, cnames)
    variables = []
    for c, v in zip(coords, x):
        unit, scale, text = _coordinate_unit_text(c, Lc)
        variables.append(Variable(c, "state", float(v), mech.unit(unit), scale, text))
    for r, v in zip(rows, x[nq:]):
        variables.append(Variable(r.reaction, "state", float(v), mech.unit(r.unit), Fc * Lc if r.unit == "N m" else Fc,
                                  _reaction_text(r)))
    variables += condition_and_parameter_variables(mech, st.conditions, x[nq + len(rows):], values, Lc, Fc, st.states)
    targets, downlock, at = fields_at_values(mech, values)
    if var.model is not None:  # the same structure built before: new values, the same compiled code
        return var.model.evolve(variables=variables, dof=report, conditions=targets, fields_at=at, **downlock)
    dropped = var.dropped
    system = EquationSystem(
        name=mech.name + ("_reduced" if reduced else ""),
        variables=variables,
        equations=[*var.equilibrium, *(r.expr for r in rows), *(e - symbol(c.name) for c, e in st.conditions),
                   *rest_rows(st.states, coords)],
        equation_names=[*(_row_name(c) for c in coords), *(r.equation for r in rows), *(f"cond_{n}" for n in cnames),
                        *(f"rate_{s.name}" for s in st.states)],
        mechanics=model,
        description=(mech.description or f"generated from the description of {mech.name}")
        + (f" [redundant constraint rows dropped: {', '.join(r.equation for r in dropped)}]" if dropped else ""),
        limits=physical_limits(mech, solve=True),
        scene=scene_function(kin, st.arrows, [v.symbol for v in variables], st.subs),
        check_values=analysis_value_check(mech),
    )
    var.model = Model.from_system(
        system,
        potential_energy=st.V,
        mechanism=mech,
        unit_system=mech.units,
        dof=report,
        reaction_names=tuple(r.reaction for r in rows),
        coordinates_of=_coordinates_of(kin, system, st.subs),
        dropped_constraints=tuple(r.equation for r in dropped),
        dropped_residual=_dropped_residual(system, dropped),
        conditions=targets,
        fields_at=at,
        **downlock,
    )
    return var.model.evolve()  # a copy: the kept model is never handed out (compiled on first numeric use)


def fields_at_values(mech: Mechanism, values: Mapping[str, float]) -> tuple[Mapping[str, float | None], dict,
                                                                             ValueFieldsAt | None]:
    """Each condition's target at the parameter ``values`` (SI), the downlock, stop and damper fields of a
    :class:`Model` there (each only when the description has one), and the model's ``fields_at`` (None when no
    field depends on the values): the fields computed by the compiled ``fields_at`` itself, so that a build at
    ``values`` and :meth:`Model.with_values` give the same numbers."""
    at = value_fields_at(mech)
    fields = at(values)
    rest = {k: v for k, v in fields.items() if k != "conditions"}
    return fields["conditions"], rest, at if mech.conditions or mech.dampers else None


def condition_and_parameter_variables(mech: Mechanism, conditions: Sequence[tuple[Condition, sp.Expr]],
                                      condition_values: Iterable[float], values: Mapping[str, float],
                                      Lc: float, Fc: float, states: Sequence[ElementState] = ()) -> list[Variable]:
    """The condition states (at ``condition_values``), the elements' first-order ``states`` (at the values
    that follow, :class:`~.elements.ElementState`) and the parameters (at ``values``) as variables, scaled by
    the typical length ``Lc`` and force ``Fc`` (the description's units); shared by planar and spatial builds.
    Each generated name's unit is in the description's units (:meth:`~.Mechanism.unit`)."""
    out = [Variable(c.name, "state", float(v), mech.condition_unit(c), condition_scale(c, Lc, Fc),
                    condition_description(c)) for (c, _), v in zip(conditions, condition_values)]
    out += [Variable(s.name, "state", float(v), mech.unit(s.unit), s.scale,
                     s.description or "first-order state of an element")
            for s, v in zip(states, list(condition_values)[len(conditions):])]
    for p in mech.parameters:
        val = values[p.name]
        out.append(Variable(p.name, "parameter", val, p.unit, _parameter_scale(p, val, Lc, Fc), p.description))
    return out


def row_units(units: UnitSystem, rows: Sequence[ConstraintRow]) -> np.ndarray:
    """One SI unit of each constraint row's residual in ``units`` (the row times its reaction is work:
    1000 for a position row, whose reaction is a force, in mm; 1 for an angle or a normalisation row, whose
    reaction is a moment; all 1 in SI)."""
    return np.array([units.from_si(f"J/({r.unit})") for r in rows])


def _coordinate_unit_text(coord: str, Lc: float = 1.0) -> tuple[str, float, str]:
    """Unit, scale and description of a body coordinate (``Lc``: the typical length, m)."""
    angle = coord.startswith("theta")
    return ("rad" if angle else "m", 1.0 if angle else Lc,
            f"{'angle' if angle else coord[0] + ' position'} of body frame")


def _reaction_text(row: ConstraintRow) -> str:
    """What the reaction of a constraint row is."""
    if row.equation == f"{row.joint}_length":
        return f"tension of actuator {row.joint} (+ pulls its ends together)"
    return f"reaction of joint {row.joint} (on its second body)"


def summary(mech: Mechanism) -> tuple[str, list[tuple[str, str, str, str, float | None]]] | None:
    """What a full build of ``mech`` declares, without generating or compiling its equations.

    Returns the description and ``(name, kind, unit, description, default)`` per variable in
    the build's order (``default`` None for states), or None when only an assembly can tell
    (``redundant = "drop"``: which rows are dropped depends on the assembled configuration).
    """
    if mech.redundant == "drop":
        return None
    kin = PlanarKinematics(mech)
    out: list[tuple[str, str, str, str, float | None]] = []
    for c in kin.coords:
        unit, _, text = _coordinate_unit_text(c)
        out.append((c, "state", mech.unit(unit), text, None))
    out += [(r.reaction, "state", mech.unit(r.unit), _reaction_text(r), None) for r in kin.constraints()]
    out += [(c.name, "state", mech.condition_unit(c), condition_description(c), None) for c in mech.conditions]
    out += [(s.name, "state", mech.unit(s.unit), s.description or "first-order state of an element", None)
            for s in collect_states(kin)]
    out += [(p.name, "parameter", p.unit, p.description, float(p.value)) for p in mech.parameters]
    return mech.description or f"generated from the description of {mech.name}", out


def _equilibrium(mech: Mechanism, coords: list[str], rows: Sequence[ConstraintRow], forces: list[sp.Expr],
                 mass: sp.Matrix, conditions: Sequence[str] = (), *,
                 gradient: Gradient | None = None, potential: sp.Expr | None = None,
                 states: Sequence = ()) -> tuple[list[sp.Expr], MechanicalModel]:
    """Equilibrium rows ``Q - Phi_q^T lambda`` (at rest) and the compiled mechanical model.

    ``conditions`` are the names of the condition states (variables after the reactions;
    not coordinates of the mechanics). ``gradient(expr, symbols)`` differentiates the rows
    (default: SymPy, one coordinate at a time). ``potential``: the loads' potential energy ``V`` (J)
    the mechanical model keeps for the time simulation's energy audit. ``states``: the elements' first-order
    states (:class:`~.elements.ElementState`, variables after the conditions; their rates go to the model)."""
    q = [symbol(c) for c in coords]
    at_rest = {velocity_symbol(c): 0 for c in coords}
    lam = [symbol(r.reaction) for r in rows]
    equilibrium = [Qi.xreplace(at_rest) for Qi in forces]
    index = {qi: i for i, qi in enumerate(q)}
    for row, lk in zip(rows, lam):
        used = [qi for qi in q if qi in row.expr.free_symbols]  # a row differentiates only in its own coordinates
        ds = gradient(row.expr, used) if gradient is not None else [sp.diff(row.expr, qi) for qi in used]
        for qi, d in zip(used, ds):
            if d != 0:
                equilibrium[index[qi]] -= d * lk
    names = [*coords, *(r.reaction for r in rows), *conditions, *(s.name for s in states), *(p.name for p in mech.parameters)]
    clash = {n for n in names if names.count(n) > 1}
    if clash:
        first = sorted(clash)[0]
        where = ("conditions" if first in conditions else "states" if first in {s.name for s in states}
                 else "parameters")
        raise InputError(f"{where}.{first}", "clashes with a generated coordinate or reaction name")
    return equilibrium, MechanicalModel(names, coords, [r.expr for r in rows], forces, mass, potential=potential,
                                        state_rates={s.name: s.rate for s in states} or None)


def _dropped_residual(system: EquationSystem, dropped: Sequence[ConstraintRow]) -> DroppedResidual:
    """The compiled residual of the ``dropped`` rows of ``system`` (see :class:`DroppedResidual`)."""
    from ..equations import compile_dense
    return DroppedResidual(compile_dense(list(system.symbols), [r.expr for r in dropped]) if dropped else None)


def _coordinates_of(kin: PlanarKinematics | SpatialKinematics, system: EquationSystem, subs: dict) -> CoordinatesOf:
    """The compiled body coordinates of ``system`` (see :class:`CoordinatesOf`)."""
    from ..equations import compile_dense
    exprs = [subs.get(s, s) for s in kin.q]
    return CoordinatesOf(tuple(kin.coords), compile_dense(list(system.symbols), exprs))
