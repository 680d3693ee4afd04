"""Retraction kinematics of the dual-sidestay main gear, hand-formulated in natural coordinates.

A reference model built without the spatial description layer (which did not exist when it
was written): the main fitting turns by the retraction angle ``theta`` about the trunnion
axis; each sidestay's knee ``K`` and lock-link joint ``J`` are points (3 coordinates each)
held by six quadratic/linear constraints per sidestay:

    |K - A|^2 = L1^2,  |K - B(theta)|^2 = L2^2,  (K - A) . n = 0,
    |J - K|^2 = L4^2,  |J - P(theta)|^2 = L5^2,  (J - A) . n = 0,

with ``B(theta) = R(theta) B0`` and ``P(theta) = R(theta) P0`` lugs on the main fitting and
``n`` the unit normal of the sidestay's fold plane (the hinge axis of its upper arm at A and
of its knee and lock links). The lower arm and the second lock link end in ball joints on the
fitting (spherical ``B`` and ``P``), which keeps this idealisation determinate: 12 states,
12 equations, one degree of freedom (``theta``). Each row is divided by twice its length so
that all rows are in metres.

Continuing in ``theta`` gives the retraction; a fold (LP) in ``theta`` is a geometric lock-up:
the lock links (or the sidestay arms) reach alignment and cannot follow further retraction.
Loads (gravity of the fitting and wheels and of the sidestay arms) enter only the analysis
(:mod:`mechcont.analysis.retraction`), by virtual work along the branch.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from ..equations import EquationSystem, Limit, Model, Scene, Variable, branch_rates
from .dual_sidestay_geometry import DEFAULT_GEOMETRY, GearGeometry, rotation, trunnion_axis

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["build_dual_sidestay_kinematics", "GearDescription",
           "geometry_of", "geometry_values", "points_at", "gear_scene", "loaded_scene",
           "actuator_tension", "gravity_rate", "start_values", "actuator_length_rate", "SIDES", "POINTS"]

SIDES = ("fwd", "aft")
POINTS = ("K", "J")
_AXES = "xyz"


def _vec(prefix: str) -> list[str]:
    return [f"{prefix}_{c}" for c in _AXES]


def geometry_values(geo: GearGeometry) -> dict[str, float]:
    """Parameter values of :func:`build_dual_sidestay_kinematics` for ``geo`` (SI units)."""
    out = {"theta": 0.0, "delta": float(geo.delta)}
    for side, st in (("fwd", geo.forward), ("aft", geo.aft)):
        for name, vec in (("A", st.A), ("n", st.normal), ("B0", st.B), ("P0", st.P)):
            out.update(zip(_vec(f"{side}_{name}"), map(float, vec)))
        out.update({f"{side}_L1": st.upper, f"{side}_L2": st.lower, f"{side}_L4": st.link1, f"{side}_L5": st.link2})
    return out


def start_values(geo: GearGeometry) -> dict[str, float]:
    """Knee and lock-link joint coordinates (m) of ``geo`` with the gear down."""
    out: dict[str, float] = {}
    for side, st in (("fwd", geo.forward), ("aft", geo.aft)):
        out.update(zip(_vec(f"{side}_K"), map(float, st.K)))
        out.update(zip(_vec(f"{side}_J"), map(float, st.J)))
    return out


def _rodrigues(axis: sp.Matrix, angle: sp.Expr) -> sp.Matrix:
    """The rotation matrix by ``angle`` (rad) about the unit ``axis`` (Rodrigues' formula), symbolic."""
    import sympy as sp

    k = sp.Matrix([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return sp.eye(3) + sp.sin(angle) * k + (1 - sp.cos(angle)) * k * k


def _variables(geo: GearGeometry) -> list[Variable]:
    """The states at the gear-down position of ``geo`` and the parameters at its geometry (SI)."""
    values = geometry_values(geo)
    start = start_values(geo)
    variables = []
    for side in SIDES:
        for pt in POINTS:
            for c in _AXES:
                name = f"{side}_{pt}_{c}"
                variables.append(Variable(name, "state", start[name], "m", 1.0, f"{side} sidestay {pt}, {c}"))
    variables.append(Variable("theta", "parameter", 0.0, "rad", 1.0, "retraction angle about the trunnion axis"))
    variables.append(Variable("delta", "parameter", values["delta"], "rad", 1.0, "trunnion axis inclination"))
    for name, val in values.items():
        if name in ("theta", "delta"):
            continue
        variables.append(Variable(name, "parameter", val, "" if "_n_" in name else "m", 1.0, _geometry_description(name)))
    return variables


#: What each geometry parameter is, by its name without the side and axis (``fwd_A_x`` -> ``A``).
_GEOMETRY_MEANING = {
    "A": "upper-arm airframe hinge A",
    "n": "fold-plane unit normal (hinge axis at A)",
    "B0": "lower-arm lug B on the fitting, gear down",
    "P0": "lock-link lug P on the fitting, gear down",
    "L1": "upper arm length, A to knee K",
    "L2": "lower arm length, knee K to lug B",
    "L4": "lock link 1 length, knee K to joint J",
    "L5": "lock link 2 length, joint J to lug P",
}


def _geometry_description(name: str) -> str:
    """``"fwd_A_x"`` -> ``"forward sidestay: upper-arm airframe hinge A, x"`` (shown by ``mechcont models``)."""
    side, _, rest = name.partition("_")
    key, _, axis = rest.partition("_")
    text = f"{'forward' if side == 'fwd' else 'aft'} sidestay: {_GEOMETRY_MEANING[key]}"
    return f"{text}, {axis}" if axis else text


@dataclass(frozen=True)
class GearDescription:
    """The description a model of :func:`build_dual_sidestay_kinematics` is built from (its ``mechanism``): the
    gear's :class:`GearGeometry`; :meth:`build` builds the model again at other parameter values."""

    geometry: GearGeometry
    name: str = "dual_sidestay_kinematics"

    def build(self, **overrides: float) -> Model:
        """The retraction kinematics of this gear at the parameter values ``overrides`` (SI; the others at its
        geometry's)."""
        model = build_dual_sidestay_kinematics(self.geometry)
        return model.with_values(overrides) if overrides else model


def build_dual_sidestay_kinematics(geo: GearGeometry = DEFAULT_GEOMETRY) -> Model:
    """The compiled retraction kinematics (12 states ``fwd_K_x .. aft_J_z`` in m; parameters
    ``theta`` (rad), ``delta`` (rad) and per sidestay ``A``, ``n``, ``B0``, ``P0`` vectors and
    ``L1, L2, L4, L5`` lengths (m)), its defaults the gear-down position of ``geo``.

    The scene draws the gear in 3-D (fitting, arms, lock links, actuator, weight). The
    equations are generated and compiled once per process; another ``geo`` only changes the
    defaults and the model's ``mechanism`` (a :class:`GearDescription` of ``geo``). A new
    process loads them with their compiled code from the disk cache (keyed by mechcont's source) when an earlier one built them.
    """
    if "system" not in _STRUCTURE:
        from ..equations import stored

        _STRUCTURE["system"] = stored(lambda: ["dual_sidestay_kinematics structure"],
                                      lambda: _build(_variables(DEFAULT_GEOMETRY)),
                                      valid=lambda obj: isinstance(obj, EquationSystem)
                                      and obj.name == "dual_sidestay_kinematics")
    model = Model.from_system(_STRUCTURE["system"].evolve(variables=_variables(geo)), mechanism=GearDescription(geo))
    return model.evolve(scene=partial(loaded_scene, model))


#: What ``mechcont models`` says about the model.
DESCRIPTION = "dual-sidestay main gear retraction kinematics (knees and lock-link joints in natural coordinates)"

_STRUCTURE: dict[str, EquationSystem] = {}


def _build(variables: list[Variable]) -> EquationSystem:
    """Generate and compile the kinematic equations in the ``variables`` (their values are the defaults)."""
    import sympy as sp

    s = {v.name: v.symbol for v in variables}
    axis = sp.Matrix([-sp.cos(s["delta"]), 0, -sp.sin(s["delta"])])
    R = _rodrigues(axis, s["theta"])

    def vec(prefix: str) -> sp.Matrix:
        return sp.Matrix([s[n] for n in _vec(prefix)])

    eqs, names = [], []
    for side in SIDES:
        A, n, B, P = vec(f"{side}_A"), vec(f"{side}_n"), R * vec(f"{side}_B0"), R * vec(f"{side}_P0")
        K, J = vec(f"{side}_K"), vec(f"{side}_J")
        L1, L2, L4, L5 = (s[f"{side}_L{i}"] for i in (1, 2, 4, 5))
        rows = [((K - A).dot(K - A) - L1**2) / (2 * L1), ((K - B).dot(K - B) - L2**2) / (2 * L2), (K - A).dot(n),
                ((J - K).dot(J - K) - L4**2) / (2 * L4), ((J - P).dot(J - P) - L5**2) / (2 * L5), (J - A).dot(n)]
        eqs += rows
        names += [f"{side}_upper", f"{side}_lower", f"{side}_knee_plane", f"{side}_link1", f"{side}_link2",
                  f"{side}_link_plane"]
    # the rows hold |K - A|^2 = L1^2 (and so on): a negative length would solve them too, so it is refused
    limits = [Limit(f"{side}_L{i}", s[f"{side}_L{i}"], True, f"{side} {what} length (m)")
              for side in SIDES for i, what in ((1, "upper arm"), (2, "lower arm"), (4, "lock link 1"), (5, "lock link 2"))]
    limits += [Limit(f"{side}_n", sum((c**2 for c in vec(f"{side}_n")), sp.S.Zero), True,
                     f"{side} sidestay plane normal: squared length")
               for side in SIDES]
    system = EquationSystem(name="dual_sidestay_kinematics", variables=variables, equations=eqs, equation_names=names,
                            description=DESCRIPTION, limits=limits)
    return system.compile()


def geometry_of(system: Model) -> GearGeometry:
    """The :class:`GearGeometry` a model of :func:`build_dual_sidestay_kinematics` was built from."""
    description = system.mechanism
    if not isinstance(description, GearDescription):
        raise TypeError(f"model '{system.name}' is not built from a GearGeometry (build_dual_sidestay_kinematics)")
    return description.geometry


def points_at(system: Model, x: np.ndarray) -> dict[str, np.ndarray]:
    """Every named point (m) of the gear at the full vector ``x``: ``O``, ``axle``, ``cg``, actuator ends
    ``C``/``D``, and per side ``<side>_A``, ``_B``, ``_P``, ``_K``, ``_J``."""
    v = system.as_dict(x)
    geo = geometry_of(system)
    R = rotation(trunnion_axis(v["delta"]), v["theta"])
    out = {"O": np.zeros(3), "axle": R @ geo.axle, "cg": R @ geo.cg, "C": np.asarray(geo.actuator_airframe, float),
           "D": R @ geo.actuator_lug}
    for side in SIDES:
        out[f"{side}_A"] = np.array([v[n] for n in _vec(f"{side}_A")])
        out[f"{side}_B"] = R @ np.array([v[n] for n in _vec(f"{side}_B0")])
        out[f"{side}_P"] = R @ np.array([v[n] for n in _vec(f"{side}_P0")])
        for pt in POINTS:
            out[f"{side}_{pt}"] = np.array([v[n] for n in _vec(f"{side}_{pt}")])
    return out


def gear_scene(system: Model, x: np.ndarray, actuator_tension: float = 0.0) -> Scene:
    """3-D :class:`Scene` of the gear at ``x``: fitting, sidestay arms, lock links, actuator (``actuator_tension``
    in N, positive pulling), the fitting's weight, the trunnion and hinge axes."""
    p = points_at(system, np.asarray(x, float))
    geo = geometry_of(system)
    v = system.as_dict(x)
    e = trunnion_axis(v["delta"])
    t_fwd, t_aft = 0.35 * e, -0.35 * e
    sc = Scene()
    sc.bars.append(("fitting", np.array([t_fwd, p["O"], p["D"], p["O"], p["fwd_B"], p["fwd_P"], p["axle"], p["aft_P"],
                                         p["aft_B"], p["O"], t_aft])))
    for side in SIDES:
        sc.bars.append((f"{side} upper", np.array([p[f"{side}_A"], p[f"{side}_K"]])))
        sc.bars.append((f"{side} lower", np.array([p[f"{side}_K"], p[f"{side}_B"]])))
        sc.bars.append((f"{side} lock links", np.array([p[f"{side}_K"], p[f"{side}_J"], p[f"{side}_P"]])))
        sc.pins += [p[f"{side}_K"], p[f"{side}_J"], p[f"{side}_B"], p[f"{side}_P"]]
        sc.grounds.append(p[f"{side}_A"])
        n = np.array([v[m] for m in _vec(f"{side}_n")])
        sc.joint_axes += [(f"{side} hinge", p[f"{side}_A"], n), (f"{side} knee", p[f"{side}_K"], n)]
    sc.grounds += [t_fwd, t_aft]
    sc.joint_axes.append(("trunnion", p["O"], e))
    sc.anchors.append(p["C"])
    sc.actuators.append(("actuator", p["C"], p["D"], float(actuator_tension)))
    sc.forces.append(("W", p["cg"], np.array([0.0, 0.0, -geo.fitting_mass * geo.g])))
    sc.points += [("axle", p["axle"])]
    return sc


def _arm_mid_z_rate(system: Model, x: np.ndarray, dx: np.ndarray, side: str, a: str, b: str) -> float:
    """Rate of the z of the middle of the segment between points ``a`` and ``b`` of ``side``."""
    def z_rate(pt: str) -> float:
        if pt == "A":
            return 0.0
        if pt == "B":  # on the fitting: rotates with theta
            v = system.as_dict(x)
            e = trunnion_axis(v["delta"])
            B = points_at(system, x)[f"{side}_B"]
            return float(np.cross(e, B)[2] * dx[system.index("theta")])
        return float(dx[system.index(f"{side}_{pt}_z")])

    return 0.5 * (z_rate(a) + z_rate(b))


def gravity_rate(system: Model, x: np.ndarray, dx: np.ndarray, arms: bool = True) -> float:
    """dV/d(theta) of gravity (J/rad) for the rate ``dx``: the fitting with wheels at its cg and, with
    ``arms``, each sidestay arm's mass at its middle (lock links massless)."""
    geo = geometry_of(system)
    e = trunnion_axis(system.as_dict(x)["delta"])
    cg = points_at(system, x)["cg"]
    dv = geo.fitting_mass * geo.g * float(np.cross(e, cg)[2]) * dx[system.index("theta")]
    if arms:
        for side, st in (("fwd", geo.forward), ("aft", geo.aft)):
            dv += st.upper_mass * geo.g * _arm_mid_z_rate(system, x, dx, side, "A", "K")
            dv += st.lower_mass * geo.g * _arm_mid_z_rate(system, x, dx, side, "K", "B")
    return dv


def actuator_length_rate(system: Model, x: np.ndarray, dx: np.ndarray) -> tuple[float, float]:
    """Retraction actuator length (m) between its airframe end C and fitting lug D, and its rate (m/rad)."""
    p = points_at(system, x)
    d = p["D"] - p["C"]
    ell = float(np.linalg.norm(d))
    e = trunnion_axis(system.as_dict(x)["delta"])
    return ell, float(d @ np.cross(e, p["D"]) / ell * dx[system.index("theta")])


def actuator_tension(system: Model, x: np.ndarray) -> float:
    """Quasi-static retraction actuator load (N, + tension) at ``x`` by virtual work (gravity of the fitting and
    the arms); ``nan`` at a fold, where the mechanism cannot be driven by ``theta``."""
    from ..errors import InputError

    try:
        dx = branch_rates(system, x, "theta")
    except InputError:
        return float("nan")
    return -gravity_rate(system, x, dx) / actuator_length_rate(system, x, dx)[1]


def loaded_scene(system: Model, x: np.ndarray) -> Scene:
    """:func:`gear_scene` with the actuator's quasi-static load (0 drawn at a fold)."""
    t = actuator_tension(system, x)
    return gear_scene(system, x, 0.0 if not np.isfinite(t) else t)
