"""A diagnostic report on a mechanism description: what mechcont made of it, and whether it is sound.

(Longer than most modules: the report, its gathering and its text are one unit that the
``check`` command prints; they change together.)

:func:`check_report` builds the description as every command does, then gathers what an
engineer checks before trusting a model: the degrees of freedom from the rank of the
constraint Jacobian against the intended count, the sizes of the system, redundant
constraints, the loop-closure residual of every joint at the assembled configuration, the
variable scales of the continuation, the parameters, the states at the assembled
configuration and at the equilibrium Newton reaches from there, and that equilibrium's
physical stability.

Two defects that make :meth:`Mechanism.build` refuse a file are reported as *findings*
instead, with the rest of the report still gathered: a degree-of-freedom count different
from the intended one (the report is built with the counted one), and an over-constrained
mechanism with ``redundant = "error"`` (built with ``redundant = "drop"``). Any other error
(unreadable file, unknown name, a loop that cannot close) is raised as usual.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ..equations import Model, StabilityResult
from ..errors import ConvergenceError, InputError, one_line
from ..units import SI, UnitSystem, undeclared_label
from ._check_text import aligned, short, shown
from ._compliant import compliant_constraints
from ._equilibrium import free_equilibrium
from ._paths import find_description

if TYPE_CHECKING:
    from ._description import Mechanism

__all__ = ["check_report", "CheckReport", "Quantity", "State"]

#: Largest loop-closure or dropped-row residual that counts as closed: rad, or m per metre of the
#: mechanism's length (its position scale) for a joint's gap.
CLOSURE_TOL = 1e-9


class Quantity(NamedTuple):
    """A named value (SI units, radians) with its unit and meaning."""

    name: str
    value: float
    unit: str = ""
    description: str = ""


class State(NamedTuple):
    """A state at the assembled configuration and at the equilibrium (None if none was found)."""

    name: str
    assembled: float
    equilibrium: float | None
    unit: str = ""
    description: str = ""


@dataclass(frozen=True)
class CheckReport:
    """What :func:`check_report` found. All values SI, angles in radians.

    Attributes
    ----------
    name, source, description:
        The mechanism's name, where it came from (file path) and its description.
    reduced:
        Whether the reduced form was checked.
    dof, intended_dof, rank:
        Degrees of freedom counted from the rank of ``Phi_q`` at the assembled
        configuration, the ``dof`` the description declares, and that rank.
    n_coordinates, n_constraints, n_equations, n_unknowns, n_parameters:
        Sizes of the generated system (``n_unknowns``: its states: coordinates, reactions
        and any condition values).
    redundant:
        One entry per redundant constraint row: ``(row, joints)``, the dropped row and the
        joints whose rows it is a combination of.
    dropped_residual:
        ``max |Phi|`` of the dropped rows at the assembled configuration (m or rad); None
        when none were dropped.
    closure:
        ``max |Phi|`` of each joint's rows at the assembled configuration: its position
        rows (``m``) and, for welds and prismatic joints, its angle row (``rad``) separately.
    eliminated_joints:
        Reduced form: joints closed exactly by the tree elimination (no rows left).
    imbalance:
        The largest force or moment residual of the equilibrium rows at the assembled
        configuration, ``Quantity(row, value, unit)``; set to zero when it is within
        rounding (then the assembled configuration is the equilibrium).
    equilibrium_note:
        How the equilibrium was found, or why none was.
    stability:
        :class:`~mechcont.equations.StabilityResult` at the equilibrium, or None.
    scales, parameters, states:
        Every variable's continuation scale; the parameters; the states.
    findings:
        Problems, one line each; empty when all is well (:attr:`ok`).
    system, x, x_equilibrium:
        The built system, the assembled full vector and the equilibrium's (or None).
    compliant:
        Spatial mechanisms: each compliant joint row (a joint with a ``stiffness``), its
        deflection (m or rad) at the equilibrium (else the assembled configuration), and in
        its description the reaction and the stiffness that make that reaction determinate.
    """

    name: str
    source: str
    description: str
    reduced: bool
    dof: int
    intended_dof: int | None
    rank: int
    n_coordinates: int
    n_constraints: int
    n_equations: int
    n_unknowns: int
    n_parameters: int
    redundant: tuple[tuple[str, tuple[str, ...]], ...]
    dropped_residual: float | None
    closure: tuple[Quantity, ...]
    eliminated_joints: tuple[str, ...]
    imbalance: Quantity
    equilibrium_note: str
    stability: StabilityResult | None
    scales: tuple[Quantity, ...]
    parameters: tuple[Quantity, ...]
    states: tuple[State, ...]
    findings: tuple[str, ...]
    system: Model = field(repr=False, compare=False)
    x: np.ndarray = field(repr=False, compare=False)
    x_equilibrium: np.ndarray | None = field(repr=False, compare=False)
    compliant: tuple[Quantity, ...] = ()
    #: the coordinates held at assembly (``[assembly] hold``)
    hold: tuple[str, ...] = ()
    #: what is sound but likely not what was meant, one line each (a bar's point beyond its ends)
    warnings: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        """True when there are no findings."""
        return not self.findings

    @property
    def held(self) -> tuple[Quantity, ...]:
        """The coordinates held at assembly (``[assembly] hold``), at their assembled values."""
        return tuple(Quantity(n, float(self.x[self.system.index(n)]), self.system.variable(n).unit) for n in self.hold)

    @property
    def assembled_is_equilibrium(self) -> bool:
        """True when the assembled configuration is itself in equilibrium."""
        return self.x_equilibrium is not None and self.imbalance.value == 0.0

    def to_text(self, extra: str = "") -> str:
        """The report as plain text (angles of states and parameters in degrees); ``extra`` (lines of
        text, e.g. the stops section of ``mechcont check``) follows the equilibrium and its stability."""
        out = [f"mechanism {self.name}" + (" (reduced form)" if self.reduced else "") + f": {one_line(self.source)}"]
        if self.description:
            out.append(f"  {self.description}")
        out.append("")
        dof_ok = "as intended" if self.dof == self.intended_dof else f"INTENDED {self.intended_dof}"
        out.append(f"degrees of freedom: {self.dof} ({dof_ok}): {self.n_coordinates} coordinates - rank "
                   f"{self.rank} of the constraint Jacobian")
        out.append(f"size: {self.n_coordinates} coordinates, {self.n_constraints} constraint rows, "
                   f"{self.n_equations} equations in {self.n_unknowns} unknowns (the states), "
                   f"{self.n_parameters} parameters")
        if self.redundant:
            out.append(f"redundant constraints: {len(self.redundant)} row(s) dropped")
            for row, joints in self.redundant:
                out.append(f"  {row}: implied by joints {', '.join(joints[1:]) or '(none)'} "
                           f"(statically indeterminate: {', '.join(joints)})")
            out.append(f"  dropped-row residual at the assembled configuration: {short(self.dropped_residual)}")
        else:
            out.append("redundant constraints: none")
        if self.compliant:
            out.append(f"compliant joint rows (their stiffness makes the reactions determinate), deflection at the "
                       f"{'equilibrium' if self.x_equilibrium is not None else 'assembled configuration'}:")
            out += aligned([(q.name, f"{short(q.value)} {q.unit}", q.description) for q in self.compliant])
        out.append("")
        held = ", ".join(f"{q.name} = {shown(q.value, q.unit)}" for q in self.held) or "nothing"
        out.append(f"loop closure at the assembled configuration (held: {held}), max |Phi| per joint:")
        width = max((len(q.name) for q in self.closure), default=0)
        for q in self.closure:
            out.append(f"  {q.name:<{width}}  {short(q.value)} {q.unit}")
        if self.eliminated_joints:
            out.append(f"  closed exactly by the reduced form: {', '.join(self.eliminated_joints)}")
        out.append("")
        imb = self.imbalance
        if self.assembled_is_equilibrium:
            out.append("equilibrium: the assembled configuration is one")
        else:
            out.append(f"equilibrium: the assembled configuration is not one at these parameter values "
                       f"(largest imbalance {short(imb.value)} {imb.unit} in {imb.name})")
        out.append(f"  {self.equilibrium_note}")
        st = self.stability
        if st is None:
            out.append("stability: not assessed (no equilibrium)")
        else:
            ev = ", ".join(short(float(np.real(e))) if abs(np.imag(e)) == 0 else f"{complex(e):.4g}"
                           for e in np.atleast_1d(st.eigenvalues))
            kind = "reduced tangent stiffness" if st.conservative else "omega^2 of the reduced system (1/s^2)"
            status = "stable" if st.stable else f"UNSTABLE in {st.n_unstable} direction(s)"
            out.append(f"stability at the equilibrium: {status} (eigenvalues of the {kind}: {ev or 'none'})")
        if extra:
            out += ["", extra]
        out.append("")
        out.append("parameters:")
        out += aligned([(p.name, shown(p.value, p.unit), p.description) for p in self.parameters])
        out.append("")
        eq = self.x_equilibrium is not None
        out.append("states:" + ("  assembled | equilibrium" if eq else "  assembled"))
        rows = []
        for s in self.states:
            cells = [s.name, shown(s.assembled, s.unit)]
            if eq:
                cells.append(shown(s.equilibrium, s.unit))
            rows.append((*cells, s.description))
        out += aligned(rows)
        out.append("")
        out.append("continuation scales (each in its variable's unit, as system.scales()):")
        out += aligned([(q.name, f"{short(q.value)} {q.unit}".rstrip()) for q in self.scales])
        out.append("")
        if self.warnings:
            out.append(f"warnings: {len(self.warnings)}")
            out += [f"  - {w}" for w in self.warnings]
        if self.findings:
            out.append(f"findings: {len(self.findings)}")
            out += [f"  - {f}" for f in self.findings]
        else:
            out.append("findings: none")
        return "\n".join(out)


# -- gathering ---------------------------------------------------------------------------------
_DOF = re.compile(r"has (\d+) degree\(s\) of freedom, intended")


def _build(mech: Mechanism, reduced: bool, overrides: Mapping[str, float]) -> tuple[Model, list[str], Mechanism]:
    """Build ``mech``; a wrong dof count or a refused redundancy becomes a finding and a rebuild."""
    findings: list[str] = []
    for _ in range(3):
        try:
            build = mech.build_reduced if reduced else mech.build
            return build(**overrides), findings, mech
        except InputError as exc:
            field_ = exc.field.rsplit(": ", 1)[-1]
            m = _DOF.search(str(exc))
            if field_ == "mechanism.dof" and m and int(m.group(1)) != mech.dof:
                findings.append(str(exc))
                mech = dataclasses.replace(mech, dof=int(m.group(1)))
            elif field_ == "mechanism.redundant" and mech.redundant == "error":
                findings.append(str(exc))
                mech = dataclasses.replace(mech, redundant="drop")
            else:
                raise
    raise AssertionError("unreachable: at most one rebuild per kind")  # pragma: no cover


class _Facts(NamedTuple):
    """What the report says of the description itself (its name, intended dof, joints...)."""

    name: str
    description: str
    dof: int | None
    joints: tuple[str, ...]
    hold: tuple[str, ...]
    normalisations: frozenset[str]   # constraint rows that are no joint's (see Mechanism.normalisation_rows)
    warnings: tuple[str, ...] = ()   # sound but likely not meant (bar_point_warnings)
    units: UnitSystem = SI           # the units the description's numbers are in

    @classmethod
    def of(cls, mech: Mechanism, overrides: Mapping[str, float]) -> _Facts:
        """The facts of ``mech`` at its parameter values with ``overrides`` (SI)."""
        from ._bar_points import bar_point_warnings
        from ._values import parameter_values

        return cls(mech.name, mech.description, mech.dof, tuple(j.name for j in mech.joints), tuple(mech.hold),
                   mech.normalisation_rows(),
                   bar_point_warnings(mech, parameter_values(mech, overrides)) + _unit_warnings(mech), mech.units)


def _unit_warnings(mech: Mechanism) -> tuple[str, ...]:
    """One line for the first parameter labelled in a length or mass unit the description does not declare
    (``"mm"`` without ``[mechanism] units``): its generated names would be labelled in the declared units."""
    for p in mech.parameters:
        found = undeclared_label(p.unit, mech.units)
        if found is not None:
            return (f"parameters.{p.name} is labelled '{p.unit}' but the description's units are {mech.units} "
                    f"([mechanism] units, SI by default): the generated names (coordinates, reactions) are labelled "
                    f"in those; if its numbers are in {found}, declare it (e.g. units = {{ length = \"mm\", "
                    f"mass = \"g\" }})",)
    return ()


def _stored_build(name_or_path: str | Path, reduced: bool,
                  overrides: Mapping[str, float]) -> tuple[Model, tuple[str, ...], _Facts]:
    """:func:`_build` of a description file, with the description's facts; kept in the disk cache
    (keyed by the file's name and full text, the form and the values), so a new process checking
    the same file neither reads it (SymPy) nor generates its equations again."""
    from ..equations import stored

    path = find_description(name_or_path)
    if path is None:
        from ._file import load_description

        load_description(name_or_path)  # raises the reader's error
        raise AssertionError("unreachable")  # pragma: no cover
    try:
        text = path.read_bytes()
    except OSError as exc:
        raise InputError(str(path), f"cannot read the file ({exc.__class__.__name__})") from None
    values = {k: float(v) for k, v in overrides.items()}

    def build() -> tuple[Model, tuple[str, ...], _Facts]:
        from ._file import load_description

        mech = load_description(path)
        system, findings, _ = _build(mech, reduced, values)
        return system, tuple(findings), _Facts.of(mech, values)

    return stored(lambda: ["check build 2", path.name, text, f"reduced={reduced}", repr(sorted(values.items()))], build,
                  valid=lambda obj: isinstance(obj, tuple) and len(obj) == 3 and isinstance(obj[0], Model))


def check_report(mech_or_path: Mechanism | str | Path, *, reduced: bool = False,
                 **overrides: float) -> CheckReport:
    """Build a mechanism description and report what was made of it.

    Parameters
    ----------
    mech_or_path:
        A :class:`Mechanism`, a description file path or the stem of a shipped one.
    reduced:
        Check the reduced form instead of the full one.
    **overrides:
        Parameter values (SI) replacing the description's defaults.

    Returns
    -------
    CheckReport
        With :attr:`CheckReport.findings` listing a degree-of-freedom count other than
        the intended one, an over-constrained mechanism refused by ``redundant = "error"``,
        and any joint or dropped row left open by more than ``CLOSURE_TOL``.

    Raises
    ------
    InputError
        Any other reason the description cannot be read or built (e.g. a loop that
        cannot close), as :meth:`Mechanism.build` raises it.
    """
    found: Sequence[str]
    if isinstance(mech_or_path, (str, Path)):
        source = str(find_description(mech_or_path))
        system, found, mech = _stored_build(mech_or_path, reduced, overrides)
    else:
        source = mech_or_path.source[0] if isinstance(mech_or_path.source, tuple) else "(Python object)"
        system, found, _ = _build(mech_or_path, reduced, overrides)
        mech = _Facts.of(mech_or_path, overrides)
    findings = list(found)
    intended = mech.dof
    x = system.defaults()
    model = system.mechanics
    report = system.dof
    assert model is not None and report is not None, "a generated model has its mechanics and degrees of freedom"
    nq, nc = len(model.coordinates), model.n_constraints

    # loop closure per joint: equation names <joint>_x, _y, _z, _n, _n1 (m), <joint>_angle and
    # <joint>_rot1.. (rad); a spatial model's rigid rows are named by its mechanics, and its
    # Euler-parameter normalisation rows (norm_<body>) are no joint
    phi = np.abs(model.phi(x)) if nc else np.zeros(0)
    names = model.constraint_names if model.constraint_names is not None else system.equation_names[nq:]
    gaps: dict[tuple[str, str], float] = {}
    normalisations = mech.normalisations
    for eq, r in zip(names, phi):
        if eq in normalisations:
            continue
        joint, kind = eq.rsplit("_", 1)
        unit = "rad" if kind == "angle" or kind.startswith("rot") else mech.units.label("m")
        gaps[(joint, unit)] = max(gaps.get((joint, unit), 0.0), float(r))
    closure = tuple(Quantity(j, v, u) for (j, u), v in gaps.items())
    kept = {j for j, _ in gaps}
    dropped_joints = {eq.rsplit("_", 1)[0] for eq in system.dropped_constraints}
    # only the reduced form closes joints away; a spatial joint whose rows are all compliant has none
    # among the constraints either, and is reported with its deflections instead
    eliminated = tuple(j for j in mech.joints if j not in kept and j not in dropped_joints) if reduced else ()
    # a gap in metres against the mechanism's length (its position scale): the same closure in any units
    metre = mech.units.label("m")
    length = max([float(sc) for sc, v in zip(system.scales(), system.variables) if v.kind == "state" and v.unit == metre],
                 default=1.0)
    for q in closure:
        if not q.value <= CLOSURE_TOL * (length if q.unit == metre else 1.0):
            findings.append(f"joint {q.name} is open by {q.value:.3g} {q.unit} at the assembled configuration")
    dropped = system.dropped_residual(x) if system.dropped_constraints and system.dropped_residual else None
    if dropped is not None and not dropped <= CLOSURE_TOL:
        findings.append(f"the dropped redundant rows are violated by {dropped:.3g} at the assembled configuration")
    redundant = tuple((row, tuple(j for j in group if j not in normalisations))
                      for row, group in zip(system.dropped_constraints, report.redundant))

    # equilibrium: the assembled configuration's imbalance, then Newton on every state from it
    res = system.residual(x)[:nq]
    worst = int(np.argmax(np.abs(res))) if nq else 0
    coord = model.coordinates[worst] if nq else ""
    imbalance = Quantity(system.equation_names[worst] if nq else "", float(np.abs(res[worst])) if nq else 0.0,
                         mech.units.label("N" if nq and system.variable(coord).unit == metre else "N m"))
    # relative to the reactions' size alone (a floor of 1 N would be a billion times too loose in km and grams)
    reaction_scale = max([system.variable(n).scale for n in system.reaction_names], default=1.0)
    xe, stability = None, None
    at_rest = imbalance.value <= 1e-9 * reaction_scale
    if at_rest:
        imbalance = imbalance._replace(value=0.0)
        # a compliant row holds only where its deflection is its reaction over its stiffness; the
        # assembly closed it as if rigid, so with a reaction it is not yet in equilibrium
        spring = _compliant_gap(system, x, mech.units)
        if spring is not None:
            imbalance, at_rest = spring, False
    if at_rest:
        xe, note = x.copy(), "reactions solved at the assembled configuration"
    else:
        try:
            xe, how = free_equilibrium(system, x)
            scale, move = system.scales(), xe - x
            for k in model.q_index:   # an angle that went once around has not moved
                if system.variables[k].unit == "rad":
                    move[k] = math.remainder(move[k], 2 * math.pi)
            i = max(model.q_index, key=lambda k: abs(move[k]) / scale[k])
            v = system.variables[i]
            note = (f"an equilibrium at these parameter values, found by {how} from the assembled configuration "
                    f"with every coordinate free (largest move: {v.name} by {shown(float(move[i]), v.unit)})")
        except (ConvergenceError, InputError) as exc:
            note = f"no equilibrium found from the assembled configuration with every coordinate free: {exc}"
            if not system.stops:  # with stops, the equilibrium may be one with a stop in contact
                findings.append(f"no equilibrium found at these parameter values: {exc}")
    if xe is not None:
        stability = model.stability(xe)

    compliant = _compliant_rows(system, x if xe is None else xe, mech.units)
    variables = system.variables
    states = tuple(State(v.name, float(x[i]), None if xe is None else float(xe[i]), v.unit, v.description)
                   for i, v in enumerate(variables) if v.kind == "state")
    params = tuple(Quantity(v.name, float(x[i]), v.unit, v.description) for i, v in enumerate(variables)
                   if v.kind == "parameter")
    scales = tuple(Quantity(n, float(s), v.unit) for n, s, v in zip(system.names, system.scales(), variables))
    return CheckReport(
        name=mech.name, source=source, description=mech.description, reduced=reduced, dof=report.dof,
        intended_dof=intended, rank=report.rank, n_coordinates=nq, n_constraints=nc,
        n_equations=system.n_equations, n_unknowns=len(system.state_names),
        n_parameters=len(system.parameter_names), redundant=redundant, dropped_residual=dropped,
        closure=closure, eliminated_joints=eliminated, imbalance=imbalance, equilibrium_note=note,
        stability=stability, scales=scales, parameters=params, states=states, findings=tuple(findings),
        system=system, x=x, x_equilibrium=xe, compliant=compliant, hold=mech.hold,
        warnings=mech.warnings)


def _compliant_gap(system: Model, x: np.ndarray, units: UnitSystem) -> Quantity | None:
    """The compliant row farthest from its spring law at ``x`` (``|Phi - lambda / k|``, a length in
    ``units`` or rad), if any is off by more than ``CLOSURE_TOL``; else None."""
    rows = compliant_constraints(system, x)
    if not rows:
        return None
    res = system.residual(x)
    i, r, _ = max(rows, key=lambda row: abs(res[row[0]]))
    if not abs(res[i]) > CLOSURE_TOL:
        return None
    force = system.variable(r).unit == units.label("N")
    return Quantity(system.equation_names[i], float(abs(res[i])), units.label("m") if force else "rad")


def _compliant_rows(system: Model, x: np.ndarray, units: UnitSystem) -> tuple[Quantity, ...]:
    """Each compliant constraint row (see :func:`compliant_constraints`) as
    ``Quantity(row, deflection, unit, "reaction ..., stiffness ...")``, labelled in ``units``."""
    out = []
    for i, r, c in compliant_constraints(system, x):
        lam, unit = float(x[system.index(r)]), system.variable(r).unit
        force = unit == units.label("N")
        k_unit = units.label("N/m" if force else "N m/rad")
        out.append(Quantity(system.equation_names[i], -c * lam, units.label("m") if force else "rad",
                            f"reaction {r} = {lam:.6g} {unit}, stiffness {-1 / c:.4g} {k_unit}"))
    return tuple(out)
