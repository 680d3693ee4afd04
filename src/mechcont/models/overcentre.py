"""The overcentre mechanism exactly as the paper formulates it (Knowles et al. 2010, eq. 6).

Two bars in a vertical plane. Bar 1 (length ``L1``) is pinned to the ground at the
origin; bar 2 (length ``L2``) is pinned to bar 1 at the *apex* and its other end slides
along the ground line y = 0 (a translational/rotational joint). A linear spring joins a
point of bar 1 at distance ``m`` beyond its centre of gravity (towards the apex) to a point
of bar 2 at distance ``n`` beyond its centre of gravity (towards the apex). A vertical force
``F`` (positive upward) acts at the apex; gravity ``g`` acts in -y.

States (the paper's six): centre of gravity ``x1, y1, x2, y2`` (m) and orientations
``theta1, theta2`` (rad, from +x). ``theta2`` is measured from bar 2's slider end towards
the apex, so in the symmetric pose ``theta2 = pi - theta1``.

Equations: the five geometric rows of eq. 6 and its force/moment row

    F_sx1 [(1/2 - m/L1) tan(theta1) - (1/2 - n/L2) tan(theta2)]
        + F_sy1 (m/L1 - n/L2) + (w1 + w2)/2 - F = 0,

where ``(F_sx1, F_sy1) = k (LU - l) d / l`` is the spring force that bar 1 exerts on the
spring (compression positive), ``d`` the vector from the bar-1 to the bar-2 attachment, ``l
= |d|``, and ``w_i = m_i g``. With this sign convention the row equals the virtual-work
equilibrium dV/dtheta1 = 0 of the potential
``V = m1 g y1 + m2 g y2 + k/2 (l - LU)^2 - F y_apex`` for any ``m, n, L1, L2`` (checked in
the tests). The paper states neither its sign convention for ``F_s`` nor this fact.

Default values: the paper does not publish its parameter values. The defaults here
(``L1 = L2 = 1.5 m``, ``m1 = m2 = 1 kg``, ``k = 127 N/m``, ``m = n = 0``) are chosen so that
its qualitative results reappear: one stable branch at ``LU = 2 m``, two folds and a
hysteresis loop at ``LU = 0.4 m``, a cusp between (at ``LU = L1 = 1.5 m`` in the symmetric
case), and the lower fold crossing ``F = 0`` near ``LU = 1.2 m``.
"""

from __future__ import annotations

import math
from typing import overload

import numpy as np

from ..equations import Limit, MechanicalModel, Model, Variable, velocity_symbol

__all__ = ["build_overcentre", "symmetric_force", "symmetric_folds", "symmetric_cusp", "symmetric_stable",
           "DEFAULTS"]

DEFAULTS = {
    "L1": 1.5, "L2": 1.5, "m1": 1.0, "m2": 1.0, "g": 9.81, "k": 127.0, "LU": 0.4,
    "m": 0.0, "n": 0.0, "F": 0.0, "c": 0.0,
}


def _variables(p: dict) -> list[Variable]:
    L = 0.5 * (p["L1"] + p["L2"])
    f_scale = max(p["k"] * L, (p["m1"] + p["m2"]) * p["g"], 1e-3)
    th = 0.5
    return [
        Variable("x1", "state", p["L1"] / 2 * math.cos(th), "m", L, "bar 1 centre of gravity, x"),
        Variable("y1", "state", p["L1"] / 2 * math.sin(th), "m", L, "bar 1 centre of gravity, y"),
        Variable("theta1", "state", th, "rad", 1.0, "bar 1 angle from +x"),
        Variable("x2", "state", p["L1"] * math.cos(th) + p["L2"] / 2 * math.cos(th), "m", L, "bar 2 centre of gravity, x"),
        Variable("y2", "state", p["L1"] / 2 * math.sin(th), "m", L, "bar 2 centre of gravity, y"),
        Variable("theta2", "state", math.pi - th, "rad", 1.0, "bar 2 angle from +x, slider end to apex"),
        Variable("L1", "parameter", p["L1"], "m", L, "length of bar 1"),
        Variable("L2", "parameter", p["L2"], "m", L, "length of bar 2"),
        Variable("m1", "parameter", p["m1"], "kg", 1.0, "mass of bar 1"),
        Variable("m2", "parameter", p["m2"], "kg", 1.0, "mass of bar 2"),
        Variable("g", "parameter", p["g"], "m/s^2", 10.0, "gravitational acceleration"),
        Variable("k", "parameter", p["k"], "N/m", max(p["k"], 1.0), "spring stiffness"),
        Variable("LU", "parameter", p["LU"], "m", L, "unstrained spring length"),
        Variable("m", "parameter", p["m"], "m", L, "spring offset on bar 1 from its CG towards the apex"),
        Variable("n", "parameter", p["n"], "m", L, "spring offset on bar 2 from its CG towards the apex"),
        Variable("F", "parameter", p["F"], "N", f_scale, "vertical force at the apex, positive up"),
        Variable("c", "parameter", p["c"], "N s/m", 1.0, "damping along the spring (dynamic model only)"),
    ]


#: What ``mechcont models`` says about the model.
DESCRIPTION = "Overcentre mechanism, paper eq. 6 (five constraints and one equilibrium row)"

_CACHE: dict[str, Model] = {}


def build_overcentre(**overrides: float) -> Model:
    """The paper's six-equation overcentre model (eq. 6) with its mechanics attached.

    Keyword arguments override the default parameter values (SI units). Returns a compiled
    :class:`EquationSystem` whose states are ``x1, y1, theta1, x2, y2, theta2`` and whose
    parameters are ``L1, L2, m1, m2, g, k, LU, m, n, F, c``. The equations are generated
    once per process, or loaded with their compiled code from the disk cache (keyed by
    mechcont's source) when an earlier process built them; later calls only change the defaults.
    """
    if "base" not in _CACHE:
        from ..equations import stored

        _CACHE["base"] = stored(lambda: ["overcentre", repr(sorted(DEFAULTS.items()))], lambda: _build(dict(DEFAULTS)),
                                valid=lambda obj: isinstance(obj, Model) and obj.name == "overcentre")
    p = dict(DEFAULTS)
    for key, val in overrides.items():
        if key not in p:
            from ..errors import InputError
            raise InputError(key, f"not a parameter of the overcentre; valid: {', '.join(p)}")
        p[key] = float(val)
    new = _CACHE["base"].evolve(variables=_variables(p))
    new.check_limits(new.defaults())
    return new


def _build(p: dict) -> Model:
    """Generate and compile the symbolic model (parameters ``p`` give the defaults)."""
    import sympy as sp

    variables = _variables(p)
    s = {v.name: v.symbol for v in variables}
    x1, y1, t1, x2, y2, t2 = (s[n] for n in ("x1", "y1", "theta1", "x2", "y2", "theta2"))
    L1, L2, m1, m2, g, k, LU, m, n, F, c = (s[n] for n in ("L1", "L2", "m1", "m2", "g", "k", "LU", "m", "n", "F", "c"))
    e1 = sp.Matrix([sp.cos(t1), sp.sin(t1)])
    e2 = sp.Matrix([sp.cos(t2), sp.sin(t2)])
    P1 = sp.Matrix([x1, y1]) + m * e1
    P2 = sp.Matrix([x2, y2]) + n * e2
    d = P2 - P1
    length = sp.sqrt(d.dot(d))
    Fsx, Fsy = k * (LU - length) * d[0] / length, k * (LU - length) * d[1] / length
    geometry = [
        x1 - L1 / 2 * sp.cos(t1),
        y1 - L1 / 2 * sp.sin(t1),
        x2 + L2 / 2 * sp.cos(t2) - (x1 + L1 / 2 * sp.cos(t1)),
        y2 + L2 / 2 * sp.sin(t2) - (y1 + L1 / 2 * sp.sin(t1)),
        y2 - L2 / 2 * sp.sin(t2),
    ]
    equilibrium = (Fsx * ((sp.Rational(1, 2) - m / L1) * sp.tan(t1) - (sp.Rational(1, 2) - n / L2) * sp.tan(t2))
                   + Fsy * (m / L1 - n / L2) + (m1 * g + m2 * g) / 2 - F)
    names = [v.name for v in variables]
    coords = ["x1", "y1", "theta1", "x2", "y2", "theta2"]
    q = [s[n_] for n_ in coords]
    qd = [velocity_symbol(n_) for n_ in coords]
    y_apex = y1 + L1 / 2 * sp.sin(t1)
    V = m1 * g * y1 + m2 * g * y2 + k / 2 * (length - LU) ** 2 - F * y_apex
    length_rate = sum((sp.diff(length, qi) * vi for qi, vi in zip(q, qd)), sp.S.Zero)
    forces = [-sp.diff(V, qi) - c * length_rate * sp.diff(length, qi) for qi in q]
    inertia1, inertia2 = m1 * L1**2 / 12, m2 * L2**2 / 12
    mass = sp.diag(m1, m1, inertia1, m2, m2, inertia2)
    mech = MechanicalModel(names, coords, geometry, forces, mass, potential=V)
    system = Model(
        name="overcentre",
        variables=variables,
        equations=[*geometry, equilibrium],
        equation_names=["pin1_x", "pin1_y", "apex_x", "apex_y", "slider_y", "equilibrium"],
        mechanics=mech,
        description=DESCRIPTION,
        limits=[Limit("L1", L1, True, "length of bar 1 (m)"), Limit("L2", L2, True, "length of bar 2 (m)"),
                Limit("m1", m1, True, "mass of bar 1 (kg)"), Limit("m2", m2, True, "mass of bar 2 (kg)"),
                Limit("k", k, False, "spring stiffness (N/m)"), Limit("LU", LU, True, "unstrained spring length (m)"),
                Limit("c", c, False, "damping (N s/m)")],
        potential_energy=V,
    )
    from .overcentre_scene import overcentre_scene

    return system.evolve(scene=overcentre_scene(system)).compile()


# -- closed form of the symmetric case (L1 = L2 = L, m = n = 0) ---------------------------
# With the spring joining the two centres of gravity its length is L cos(theta1), and
# V(theta) = (m1 + m2) g L/2 sin(theta) + k/2 (L cos(theta) - LU)^2 - F L sin(theta).
# dV/dtheta = 0 gives F(theta) below; dF/dtheta = k sec^2(theta) (LU - L cos^3(theta)), so the
# folds sit at cos^3(theta) = LU/L and V'' = L cos(theta) dF/dtheta fixes the stability.

@overload
def symmetric_force(theta1: float, L: float, m1: float, m2: float, g: float, k: float, LU: float) -> float: ...
@overload
def symmetric_force(theta1: np.ndarray, L: float, m1: float, m2: float, g: float, k: float, LU: float) -> np.ndarray: ...
def symmetric_force(theta1: float | np.ndarray, L: float, m1: float, m2: float, g: float, k: float,
                    LU: float) -> float | np.ndarray:
    """Equilibrium force F (N) at bar angle ``theta1`` (rad) for the symmetric overcentre."""
    return (m1 + m2) * g / 2 - k * (L * np.cos(theta1) - LU) * np.tan(theta1)


@overload
def symmetric_stable(theta1: float, L: float, LU: float) -> np.bool_: ...
@overload
def symmetric_stable(theta1: np.ndarray, L: float, LU: float) -> np.ndarray: ...
def symmetric_stable(theta1: float | np.ndarray, L: float, LU: float) -> np.bool_ | np.ndarray:
    """True where the symmetric equilibrium at ``theta1`` (|theta1| < pi/2) is stable: V'' > 0."""
    return LU - L * np.cos(theta1) ** 3 > 0


def symmetric_folds(L: float, m1: float, m2: float, g: float, k: float, LU: float) -> list[tuple[float, float]]:
    """Both folds ``(theta1 [rad], F [N])`` of the symmetric overcentre, empty if LU >= L.

    Folds satisfy cos^3(theta1) = LU / L; the one at positive theta1 is the lower fold in F.
    """
    if LU >= L or LU <= 0:
        return []
    th = math.acos((LU / L) ** (1 / 3))
    return [(t, float(symmetric_force(t, L, m1, m2, g, k, LU))) for t in (-th, th)]


def symmetric_cusp(L: float, m1: float, m2: float, g: float, k: float) -> tuple[float, float, float]:
    """The cusp ``(LU [m], theta1 [rad], F [N])`` where both folds meet: LU = L, theta1 = 0."""
    return L, 0.0, (m1 + m2) * g / 2
