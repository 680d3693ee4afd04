"""Physical ranges and value checks of a spatial description (see :mod:`.._values` for planar)."""

from __future__ import annotations

from collections.abc import Mapping

from ...equations import Limit
from ...errors import InputError
from .._stops import stop_value_limits
from .._values import check_finite, check_stop_limits, check_vectors, evaluate
from ._description import SpatialMechanism
from ._joints import Universal

__all__ = ["spatial_limits", "check_spatial_values"]


def spatial_limits(mech: SpatialMechanism, *, solve: bool = True) -> list[Limit]:
    """Masses, lengths, principal inertias, free lengths, actuator lengths and joint stiffnesses
    positive; damping non-negative; spring stiffness positive in the file and non-negative for
    an analysis (``solve``). Each :class:`~mechcont.equations.Limit` is named by its key path."""
    out: list[Limit] = []

    def need(field: str, positive: bool, what: str) -> None:
        out.append(Limit(field, mech.value(field), positive, what))

    for b in mech.bodies:
        f = f"bodies.{b.name}"
        need(f + ".mass", True, "mass (kg)")
        if b.length is not None:
            need(f + ".length", True, "length (m)")
        if b.inertia is not None:
            for k in ("xx", "yy", "zz"):
                need(f"{f}.inertia.{k}", True, "principal moment of inertia (kg m^2)")
    for s in mech.springs:
        need(f"springs.{s.name}.k", not solve, "stiffness (N/m)")
        need(f"springs.{s.name}.free_length", True, "free length (m)")
    for d in mech.dampers:
        need(f"dampers.{d.name}.c", False, "damping (N s/m)")
        need(f"dampers.{d.name}.c2", False, "quadratic damping (N s^2/m^2)")
    for args in stop_value_limits(mech):
        need(*args)
    for act in mech.actuators:
        if act.length is not None:
            need(f"actuators.{act.name}.length", True, "actuator length (m)")
    for ld in mech.loads:
        for field, strict, what in ld.limits():
            need(field, strict, what)
    for j in mech.joints:
        if j.stiffness is not None:
            need(f"joints.{j.name}.stiffness", True, "joint stiffness (N/m)")
        if j.rotational_stiffness is not None:
            need(f"joints.{j.name}.rotational_stiffness", True, "joint rotational stiffness (N m/rad)")
    return out


def _vector_fields(mech: SpatialMechanism) -> list[str]:
    """The key paths of the description's vectors that must not be zero (directions, axes)."""
    fields = [f for ld in mech.loads for f in ld.vectors()]
    fields += mech.gravity.vectors() if mech.gravity is not None else []
    for j in mech.joints:
        fields += [f"joints.{j.name}.{k}" for k in j.VECTORS]
    return fields


def spatial_value_check(mech: SpatialMechanism, exact):
    """``exact(values)`` (:func:`check_spatial_values` for an analysis) screened by compiled code (see
    :class:`~mechcont.mechanism._compiled.ValueCheck`): the same limits, vectors and perpendicular axes."""
    from .._values import value_check

    vectors = [[mech.value(f"{f}.{c}") for c in "xyz"] for f in _vector_fields(mech)]
    pairs = [[mech.value(f"joints.{j.name}.{axis}.{c}") for axis in ("axis_a", "axis_b") for c in "xyz"]
             for j in mech.joints if isinstance(j, Universal)]
    return value_check(mech, exact, spatial_limits(mech, solve=True), vectors, pairs)


def check_spatial_values(mech: SpatialMechanism, values: Mapping[str, float], *, solve: bool = False) -> None:
    """Reject impossible values at the parameter ``values``: non-finite numbers, quantities out of
    their :func:`spatial_limits` range, zero direction vectors. Raises a one-line InputError."""
    check_finite(mech, values)
    check_stop_limits(mech, values)
    for lim in spatial_limits(mech, solve=solve):
        v = evaluate(lim.expr, values, lim.name)
        if (v <= 0) if lim.strict else (v < 0):
            raise InputError(lim.name, lim.message(v))
    for b in mech.bodies:
        if b.inertia is not None:
            _check_inertia(mech, values, f"bodies.{b.name}.inertia", len(b.inertia))
    check_vectors(mech, values, _vector_fields(mech))
    for j in mech.joints:
        if isinstance(j, Universal):
            a = [evaluate(mech.value(f"joints.{j.name}.axis_a.{c}"), values, "") for c in "xyz"]
            b = [evaluate(mech.value(f"joints.{j.name}.axis_b.{c}"), values, "") for c in "xyz"]
            c = sum(p * q for p, q in zip(a, b)) / (sum(p * p for p in a) * sum(q * q for q in b)) ** 0.5
            if abs(c) > 1e-9:
                raise InputError(f"joints.{j.name}.axis_b", f"must be perpendicular to axis_a in the design pose "
                                                            f"(cosine of the angle between them {c:.3g})")


def _check_inertia(mech: SpatialMechanism, values: Mapping[str, float], field: str, n: int) -> None:
    """An inertia tensor about the CG must be positive definite and its principal moments obey the
    triangle inequality (each at most the sum of the other two: a real body's mass distribution)."""
    import numpy as np

    keys = ("xx", "yy", "zz", "xy", "xz", "yz")[:n]
    v = dict(zip(keys, (evaluate(mech.value(f"{field}.{k}"), values, f"{field}.{k}") for k in keys)))
    xy, xz, yz = v.get("xy", 0.0), v.get("xz", 0.0), v.get("yz", 0.0)
    tensor = np.array([[v["xx"], xy, xz], [xy, v["yy"], yz], [xz, yz, v["zz"]]])
    scale = float(np.max(np.abs(tensor)))
    moments = np.linalg.eigvalsh(tensor / scale) * scale
    shown = ", ".join(f"{m:.6g}" for m in moments)
    if moments[0] <= 1e-12 * scale:
        raise InputError(field, f"is not positive definite (principal moments {shown} kg m^2); a body's inertia "
                                "tensor has positive principal moments")
    if moments[2] > (moments[0] + moments[1]) * (1 + 1e-9):
        raise InputError(field, f"principal moments {shown} kg m^2 violate the triangle inequality (the largest must "
                                "not exceed the sum of the other two): no body has this mass distribution")
