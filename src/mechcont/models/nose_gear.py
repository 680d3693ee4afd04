"""The planar nose landing gear in the paper's own formulation (Knowles et al. 2010, Section III-A).

Five bars in a vertical plane (paper Figure 6): drag stay upper (1) pinned to the airframe
at A, drag stay lower (2), main fitting (3) pinned at the origin O, lock links (4, 5) from
the drag-stay knee K to the main fitting; a linear lock-link spring from bar 4 to the main
fitting; gravity; a vertical force ``F`` (+ up, the unlock direction) at the lock-link joint
J; the drag moment of eq. 12 on the main fitting. Geometry and masses:
:mod:`mechcont.models.nose_gear_geometry`.

States (25): the 15 body coordinates ``x_i, y_i, theta_i`` (centre of gravity, angle from
+x) and 10 inter-link force components ``R12x, R12y, R14x, R14y, R23x, R23y, R45x, R45y,
R53x, R53y`` (global axes, N): ``Rij`` is the force bar *i* exerts on bar *j* at their
joint. Equations (25): the 14 pin constraints (paper order: A, knee 1–2, lug 2–3, pivot O,
knee 1–4, joint 4–5, lug 5–3) and 11 equilibrium rows: moment of bar 1 about A, force and
moment of bar 2, moment of bar 3 about O, force and moment of bars 4 and 5 (moments of bars
2, 4, 5 about their centres). The ground reactions at A and O are eliminated by taking the
moments of bars 1 and 3 about those pins, and the joint equilibria by writing one force per
joint and its reaction on the other bar: 37 -> 25, exactly the paper's count. Plain SI
throughout: geometric rows in m, force rows in N, moment rows in N m, forces in N (the
solvers judge each residual against the size of its row's terms, so no row is rescaled).
``F`` acts on bar 4 at J. Directions: bar 1 points from A to K, bar 2 from K to P2, bar 3
from the axle to O (theta3 ~ 80 deg when down), bar 4 from K to J, bar 5 from J to P5.

What the paper's text leaves garbled, and what is used instead
---------------------------------------------------------------
* Eq. 9 (the matrix A of ``A F - B = 0``) is missing from the text altogether; the 11
  equilibrium rows here are derived from free-body diagrams (above).
* Eqs. 5–6 place the drag-stay lug at ``x3 + (L23/2) cos(theta3 + psi1)`` while the moment
  arm in [C] (eq. 10) is ``L32 sin(theta3 + psi1) - (L3/2) sin theta3``, i.e. a lug at
  ``O - L32 e(theta3 + psi1)``. The two disagree (and name the length L23 and L32). This
  module uses the lug of [C], written on bar 3's own coordinates:
  ``x2 + L2/2 cos theta2 - (x3 + L3/2 cos theta3) + L32 cos(theta3 + psi1) = 0``.
* [C] uses ``psi1`` for the lock-link lug where eqs. 13–14 use ``theta3 - psi2``; here the
  lock-link lug is ``O - L35 e(theta3 - psi2)`` (eqs. 13–14).
* Rows 5 of B and [C] mix moments about O (gravity) with arms measured from the centre of
  gravity (the ``-L3/2`` terms); with O eliminated the moment must be about O, so the arms
  here are measured from O.
* Row 8 of B writes the spring arm on bar 4 as ``(1 - l_sp1/L4)/2`` while the text says
  ``l_sp1 > 0`` towards the sidestay end and ``< 0`` towards the lock-link joint, i.e.
  measured from the centre. Here ``l_sp1`` is the distance from bar 4's centre, positive
  towards the knee: the attachment is ``G4 - l_sp1 e4``.
* Eq. 12's drag ``D = rho/4 (U cos(alpha - theta3 + pi/2))^2 d L3^2 C_D`` is used as a
  counter-clockwise moment on the main fitting about O (the cross-flow on the hanging strut
  pushes the wheel aft, towards extension). It depends on theta3 only, so on this
  pivoted body it is a conservative moment (derivative of a potential in theta3); the
  mechanics treat it as a general applied force and find the reduced stiffness symmetric.

The :class:`~mechcont.equations.MechanicalModel` attached to the system uses the 15 body
coordinates, the 14 pin constraints, and generalised forces from gravity, the spring
(with optional damping ``c`` along it), ``F``, the drag moment (with optional pivot damping
``c3``) and the mass matrix ``diag(m, m, m L^2/12)`` per bar: physical stability and time
simulation come from it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from functools import partial
from typing import TYPE_CHECKING, overload

import numpy as np

from ..equations import DownlockFacts, EquationSystem, Limit, MechanicalModel, Model, Scene, Variable, velocity_symbol
from ..errors import InputError
from .nose_gear_geometry import PARAMETERS, defaults, downlocked_pose

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["build_nose_gear", "overcentre_angle", "COORDINATES", "FORCES"]

COORDINATES = tuple(f"{c}{i}" for i in range(1, 6) for c in ("x", "y", "theta"))
FORCES = ("R12x", "R12y", "R14x", "R14y", "R23x", "R23y", "R45x", "R45y", "R53x", "R53y")


@overload
def overcentre_angle(theta4: float, theta5: float) -> float: ...
@overload
def overcentre_angle(theta4: np.ndarray, theta5: np.ndarray) -> np.ndarray: ...
def overcentre_angle(theta4: float | np.ndarray, theta5: float | np.ndarray) -> float | np.ndarray:
    """The angle between the lock links at their joint J (rad): ``pi + theta4 - theta5``.

    ``pi`` when aligned; larger when J lies above the line from the knee to the lug P5.
    Works on floats and arrays (e.g. branch columns).
    """
    return np.pi + np.asarray(theta4) - np.asarray(theta5)


def _cross(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    """The z component of the cross product of two plane vectors."""
    return a[0] * b[1] - a[1] * b[0]


def _e(a: sp.Expr) -> sp.Matrix:
    """The unit vector at the angle ``a`` (rad) from +x."""
    import sympy as sp

    return sp.Matrix([sp.cos(a), sp.sin(a)])


def _points(s: Mapping[str, sp.Symbol]) -> tuple[dict[int, sp.Matrix], dict[int, sp.Matrix], dict[str, sp.Matrix]]:
    """Every named point of the gear, each expressed on its own body's coordinates."""
    import sympy as sp

    G = {i: sp.Matrix([s[f"x{i}"], s[f"y{i}"]]) for i in range(1, 6)}
    e = {i: _e(s[f"theta{i}"]) for i in range(1, 6)}
    t3 = s["theta3"]
    O3 = G[3] + s["L3"] / 2 * e[3]
    return G, e, {
        "A1": G[1] - s["L1"] / 2 * e[1], "K1": G[1] + s["L1"] / 2 * e[1],
        "K2": G[2] - s["L2"] / 2 * e[2], "P2_2": G[2] + s["L2"] / 2 * e[2],
        "O3": O3, "P2_3": O3 - s["L32"] * _e(t3 + s["psi1"]), "P5_3": O3 - s["L35"] * _e(t3 - s["psi2"]),
        "S3": O3 - s["l_sp2"] * _e(t3 + s["psi3"]), "W3": O3 - s["L3"] * e[3],
        "K4": G[4] - s["L4"] / 2 * e[4], "J4": G[4] + s["L4"] / 2 * e[4], "S4": G[4] - s["l_sp1"] * e[4],
        "J5": G[5] - s["L5"] / 2 * e[5], "P5_5": G[5] + s["L5"] / 2 * e[5],
    }


def _constraints(s: Mapping[str, sp.Symbol], P: Mapping[str, sp.Matrix]) -> tuple[list[sp.Expr], list[str]]:
    """The 14 pin rows (m) and their names."""
    import sympy as sp

    A = sp.Matrix([s["Ax"], s["Ay"]])
    pairs = [(P["A1"], A), (P["K1"], P["K2"]), (P["P2_2"], P["P2_3"]), (P["O3"], sp.zeros(2, 1)),
             (P["K1"], P["K4"]), (P["J4"], P["J5"]), (P["P5_5"], P["P5_3"])]
    names = ["A", "knee12", "lug23", "pivotO", "knee14", "joint45", "lug53"]
    rows, labels = [], []
    for (a, b), n in zip(pairs, names):
        rows += [a[0] - b[0], a[1] - b[1]]
        labels += [f"{n}_x", f"{n}_y"]
    return rows, labels


def _spring(s: Mapping[str, sp.Symbol], P: Mapping[str, sp.Matrix]) -> tuple[sp.Matrix, sp.Expr]:
    """The lock-link spring's vector from its end on bar 4 to its end on bar 3, and its length (m)."""
    import sympy as sp

    dvec = P["S3"] - P["S4"]
    length = sp.sqrt(dvec.dot(dvec))
    return dvec, length


def _drag(s: Mapping[str, sp.Symbol]) -> sp.Expr:
    """The aerodynamic drag moment on the main fitting (N m, counter-clockwise)."""
    import sympy as sp

    return s["rho"] / 4 * (s["U"] * sp.cos(s["alpha"] - s["theta3"] + sp.pi / 2)) ** 2 * s["d"] * s["L3"] ** 2 * s["CD"]


def _equilibrium(s: Mapping[str, sp.Symbol], G: Mapping[int, sp.Matrix],
                 P: Mapping[str, sp.Matrix]) -> tuple[list[sp.Expr], list[str]]:
    """The 11 equilibrium rows (N, N m) of the bars, with their names."""
    import sympy as sp

    R = {n: sp.Matrix([s[f"{n}x"], s[f"{n}y"]]) for n in ("R12", "R14", "R23", "R45", "R53")}
    grav = {i: sp.Matrix([0, -s[f"m{i}"] * s["g"]]) for i in range(1, 6)}
    dvec, length = _spring(s, P)
    T = s["k"] * (length - s["LU"])  # tension
    Fs4 = T * dvec / length  # spring force on bar 4 (towards the fitting lug); -Fs4 on bar 3
    Fj = sp.Matrix([0, s["F"]])
    rows = [
        # bar 1: moment about A (ground reaction eliminated)
        _cross(P["K1"] - P["A1"], -R["R12"] - R["R14"]) + _cross(G[1] - P["A1"], grav[1]),
        # bar 2: forces and moment about its centre
        *(R["R12"] - R["R23"] + grav[2]),
        _cross(P["K2"] - G[2], R["R12"]) + _cross(P["P2_2"] - G[2], -R["R23"]),
        # bar 3: moment about O (ground reaction eliminated), drag moment D counter-clockwise
        _cross(P["P2_3"] - P["O3"], R["R23"]) + _cross(P["P5_3"] - P["O3"], R["R53"])
        + _cross(G[3] - P["O3"], grav[3]) + _cross(P["S3"] - P["O3"], -Fs4) + _drag(s),
        # bar 4: forces and moment about its centre (F acts at J on bar 4)
        *(R["R14"] - R["R45"] + Fj + Fs4 + grav[4]),
        _cross(P["K4"] - G[4], R["R14"]) + _cross(P["J4"] - G[4], Fj - R["R45"]) + _cross(P["S4"] - G[4], Fs4),
        # bar 5: forces and moment about its centre
        *(R["R45"] - R["R53"] + grav[5]),
        _cross(P["J5"] - G[5], R["R45"]) + _cross(P["P5_5"] - G[5], -R["R53"]),
    ]
    labels = ["moment1_A", "force2_x", "force2_y", "moment2", "moment3_O", "force4_x", "force4_y", "moment4",
              "force5_x", "force5_y", "moment5"]
    return rows, labels


def _mechanics(names: Sequence[str], s: Mapping[str, sp.Symbol], G: Mapping[int, sp.Matrix], P: Mapping[str, sp.Matrix],
               constraints: list[sp.Expr]) -> tuple[MechanicalModel, sp.Expr]:
    """The gear's mechanics (masses, forces, potential energy with F's work) and its potential energy (J)."""
    import sympy as sp

    q = [s[n] for n in COORDINATES]
    qd = [velocity_symbol(n) for n in COORDINATES]
    dvec, length = _spring(s, P)
    V = sum(s[f"m{i}"] * s["g"] * s[f"y{i}"] for i in range(1, 6)) + s["k"] / 2 * (length - s["LU"]) ** 2
    V -= s["F"] * P["J4"][1]
    rate = sum((sp.diff(length, qi) * vi for qi, vi in zip(q, qd)), sp.S.Zero)
    forces = [-sp.diff(V, qi) - s["c"] * rate * sp.diff(length, qi) for qi in q]
    i3 = COORDINATES.index("theta3")
    forces[i3] += _drag(s) - s["c3"] * qd[i3]
    inertia = []
    for i in range(1, 6):
        m, L = s[f"m{i}"], s[f"L{i}"]
        inertia += [m, m, m * L**2 / 12]
    return MechanicalModel(names, COORDINATES, constraints, forces, sp.diag(*inertia), potential=V), V


def _scene(names: tuple[str, ...], x: np.ndarray) -> Scene:
    """Drawing primitives of the gear at the full variable vector ``x`` (m, N), variables ``names``."""
    v = dict(zip(names, np.asarray(x, float)))

    def e(a: float) -> np.ndarray:
        return np.array([math.cos(a), math.sin(a)])

    G = {i: np.array([v[f"x{i}"], v[f"y{i}"]]) for i in range(1, 6)}
    t = {i: v[f"theta{i}"] for i in range(1, 6)}
    A = G[1] - v["L1"] / 2 * e(t[1])
    K = G[1] + v["L1"] / 2 * e(t[1])
    O = G[3] + v["L3"] / 2 * e(t[3])
    axis = lambda r: O - r * e(t[3])  # noqa: E731
    P2 = O - v["L32"] * e(t[3] + v["psi1"])
    P5 = O - v["L35"] * e(t[3] - v["psi2"])
    S3 = O - v["l_sp2"] * e(t[3] + v["psi3"])
    J = G[4] + v["L4"] / 2 * e(t[4])
    S4 = G[4] - v["l_sp1"] * e(t[4])
    fitting = np.array([O, axis(v["L35"]), P5, axis(v["L35"]), axis(v["L32"]), P2, axis(v["L32"]),
                        axis(v["l_sp2"]), S3, axis(v["l_sp2"]), axis(v["L3"])])
    sc = Scene()
    sc.bars = [("drag stay upper", np.array([A, K])), ("drag stay lower", np.array([K, P2])),
               ("main fitting", fitting), ("lock link 1", np.array([K, J])), ("lock link 2", np.array([J, P5]))]
    sc.pins = [K, P2, J, P5]
    sc.grounds = [A, O]
    sc.springs = [("lock-link spring", S4, S3)]
    sc.forces = [("F", J, np.array([0.0, v["F"]]))]
    return sc


#: Parameters that must be positive (lengths, m) and non-negative (masses, stiffness, damping, air data).
_POSITIVE = ("L1", "L2", "L3", "L4", "L5", "L32", "L35", "l_sp2", "LU", "d")
_NON_NEGATIVE = ("m1", "m2", "m3", "m4", "m5", "k", "c", "c3", "rho", "CD", "g")
_GEOMETRY = ("Ax", "Ay", "L1", "L2", "L3", "L4", "L5", "L32", "psi1", "L35", "psi2")


def check_values(values: Mapping[str, float]) -> None:
    """Raise :class:`InputError` naming the first parameter of ``values`` (SI) outside its valid range.

    Lengths (m) must be positive; masses (kg), stiffness (N/m), damping, air density, drag
    coefficient and gravity non-negative; every value finite.
    """
    for n, v in values.items():
        v = float(v)
        if not math.isfinite(v):
            raise InputError(n, f"must be a finite number, got {v!r}")
        if n in _POSITIVE and not v > 0:
            raise InputError(n, f"must be positive (m), got {v:g}")
        if n in _NON_NEGATIVE and v < 0:
            raise InputError(n, f"must not be negative, got {v:g}")


def _assemble_downlocked(system: EquationSystem, downlocked: np.ndarray, values: Mapping[str, float],
                         hold: Mapping[str, float] | None = None) -> np.ndarray:
    """Full vector at ``values`` (SI) with the lock links at the held theta4, assembled in closed form.

    A guess for Newton (the inter-link forces and F are those of the default pose ``downlocked``).
    Raises :class:`InputError` when the gear cannot close at these values.
    """
    base = system.vector(dict(values), base=downlocked)
    p = {n: float(base[system.index(n)]) for n in PARAMETERS}
    t4 = float((hold or {}).get("theta4", 0.0))
    try:
        q = downlocked_pose(p, t4)
    except InputError as exc:
        changed = [n for n in values if n in _GEOMETRY] or ["theta4"]
        raise InputError(changed[0], f"the gear cannot assemble with theta4 = {t4:g} rad at "
                         f"{', '.join(f'{n}={values[n]:g}' for n in changed if n in values) or 'these values'}: "
                         f"{exc}") from None
    return system.vector(q, base=base)


def _variables(p: dict[str, float], q: dict[str, float]) -> list[Variable]:
    """The 40 variables: coordinates at the pose ``q``, forces 0, parameters at ``p`` (SI)."""
    variables = []
    for n in COORDINATES:
        kind_unit = "rad" if n.startswith("theta") else "m"
        what = "angle from +x" if n.startswith("theta") else "centre of gravity, " + n[0]
        variables.append(Variable(n, "state", q[n], kind_unit, 1.0, f"bar {n[-1]} {what}"))
    for n in FORCES:
        variables.append(Variable(n, "state", 0.0, "N", 1000.0, f"force of bar {n[1]} on bar {n[2]}, {n[3]} component"))
    for n, (_, unit, scale, desc) in PARAMETERS.items():
        variables.append(Variable(n, "parameter", p[n], unit, scale, desc))
    return variables


#: What ``mechcont models`` says about the model.
DESCRIPTION = "Planar nose landing gear, paper Section III-A: 15 coordinates and 10 inter-link forces"

_STRUCTURE: dict[str, Model] = {}


def summary_variables() -> list[Variable]:
    """The variables with the default parameters, without generating the equations or assembling the
    gear (for ``mechcont models``; the states' values are placeholders, 0)."""
    return _variables(defaults(), dict.fromkeys(COORDINATES, 0.0))


def _structure() -> Model:
    """The gear's equations, compiled, and its potential energy, generated once (values are data).

    Kept for the process, and in the disk cache with its compiled code (keyed by mechcont's
    source, see :mod:`mechcont.equations._stored`), so a new process neither derives the 25
    equations again nor imports SymPy.
    """
    if "system" not in _STRUCTURE:
        from ..equations import stored

        def derive() -> Model:
            system, V = _derive_structure()
            return Model.from_system(system, potential_energy=V)

        _STRUCTURE["system"] = stored(lambda: ["nose_gear structure"], derive,
                                      valid=lambda obj: isinstance(obj, Model) and obj.name == "nose_gear")
    return _STRUCTURE["system"]


def _derive_structure() -> tuple[EquationSystem, sp.Expr]:
    """The gear's equations (SymPy) and potential energy, derived from its geometry."""
    p = defaults()
    variables = _variables(p, downlocked_pose(p, 0.0))
    s = {v.name: v.symbol for v in variables}
    G, _, P = _points(s)
    geometry, g_labels = _constraints(s, P)
    equilibrium, e_labels = _equilibrium(s, G, P)
    mech, V = _mechanics([v.name for v in variables], s, G, P, geometry)
    system = EquationSystem(
        name="nose_gear",
        variables=variables,
        equations=[*geometry, *equilibrium],
        equation_names=[*g_labels, *e_labels],
        mechanics=mech,
        description=DESCRIPTION,
        limits=[Limit(n, s[n], n in _POSITIVE, f"{PARAMETERS[n][3]} ({PARAMETERS[n][1]})")
                for n in (*_POSITIVE, *_NON_NEGATIVE) if n in s],
        check_values=check_values,
    )
    return system, V


def build_nose_gear(**overrides: float) -> Model:
    """The paper's 25-equation nose landing gear, with mechanics and a scene attached.

    Keyword arguments override the parameter defaults of
    :data:`~mechcont.models.nose_gear_geometry.PARAMETERS` (SI units; ``L35``/``psi2``
    are re-derived for aligned lock links unless given). State defaults are the assembled
    downlocked pose (theta4 = 0) with its inter-link forces at ``F`` = the downlock force.
    The equations are generated and compiled once per process; other values only change
    the defaults and the assembled pose.

    The returned model carries its downlock (:class:`~mechcont.equations.DownlockFacts`: held
    ``{"theta4": 0.0}``, force ``"F"``, that pose and a closed-form assembly) and ``check_values``
    (valid ranges) for :func:`mechcont.analysis.downlock.downlock`.
    """
    check_values(overrides)
    p = defaults(**overrides)
    q = downlocked_pose(p, 0.0)
    core = _structure()
    system = core.evolve(variables=_variables(p, q))
    # inter-link forces at the downlocked pose: the equilibrium rows are linear in (R, F)
    x = system.defaults()
    unknown = [system.index(n) for n in (*FORCES, "F")]
    rows = np.arange(14, 25)
    J = system.jacobian(x)[np.ix_(rows, np.asarray(unknown))]
    x[unknown] = 0.0
    r0 = system.residual(x)[rows]
    sol = np.linalg.solve(J, -r0)
    x[unknown] = sol
    variables = tuple(replace(v, value=float(x[i])) if v.kind == "state" else v for i, v in enumerate(system.variables))
    return system.evolve(
        variables=variables,
        scene=partial(_scene, system.names),
        downlock=DownlockFacts({"theta4": 0.0}, "F", x, partial(_assemble_downlocked, core, x)),
    )  # type: ignore[return-value]
