"""Parameter values of a build and the physical checks of a description's numbers."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
import sympy as sp

from ..equations import Limit
from ..errors import InputError
from ._expr import _finite, evaluate, float_value

if TYPE_CHECKING:
    from ._compiled import ValueCheck
    from ._description import Mechanism

__all__ = ["parameter_values", "check_values", "check_finite", "check_stop_limits", "physical_limits",
           "value_check", "check_vectors",
           "vector_fields", "analysis_value_check"]


def parameter_values(mech: Mechanism, overrides: Mapping[str, float]) -> dict[str, float]:
    """Default parameter values with ``overrides`` applied; unknown names are an InputError."""
    values = {p.name: float(p.value) for p in mech.parameters}
    for k, v in overrides.items():
        if k not in values:
            raise InputError(k, f"not a parameter of '{mech.name}'; parameters: {', '.join(values) or 'none'}")
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise InputError(k, f"must be a finite number, got {v!r}")
        values[k] = float(v)
    return values


def check_finite(mech: Mechanism, values: Mapping[str, float]) -> None:
    """Every value of the description in the parameters alone must be a finite real number at
    ``values`` (floating-point evaluation: quick, and never an arbitrary-precision blow-up)."""
    num = {symbol: values[symbol.name] for symbol in mech.param_symbols.values() if symbol.name in values}
    for field, expr in mech._exprs.items():
        if expr.free_symbols <= num.keys():
            _finite(expr, float_value(expr, num), field)


def check_stop_limits(mech: Mechanism, values: Mapping[str, float]) -> None:
    """A condition with both a min and a max stop needs ``min <= max`` at ``values`` (else no
    configuration satisfies both); one-line InputError naming the max stop."""
    lows = {s.condition: s for s in mech.stops if s.side > 0}
    for s in mech.stops:
        low = lows.get(s.condition) if s.side < 0 else None
        if low is None:
            continue
        hi = evaluate(mech.value(f"stops.{s.name}.max"), values, f"stops.{s.name}.max")
        lo = evaluate(mech.value(f"stops.{low.name}.min"), values, f"stops.{low.name}.min")
        if lo > hi:
            raise InputError(f"stops.{s.name}.max", f"{hi:g} is below min = {lo:g} of stop {low.name} on the same "
                                                    f"condition {s.condition!r}: no configuration satisfies both; "
                                                    "give max >= min")


def physical_limits(mech: Mechanism, *, solve: bool = True) -> list[Limit]:
    """The physical ranges of a description's quantities, as :class:`~mechcont.equations.Limit`.

    Lengths (bodies, length-mode actuators), masses, (principal) inertias, free lengths, joint
    stiffnesses and drag diameters must be positive; damping,
    air density and drag coefficient non-negative; spring stiffness positive in the file
    (``solve=False``) and non-negative for an analysis (zero disconnects the spring, as in
    the paper's Fig. 7, "no spring load"). Each limit is named by its key path.
    """
    out: list[Limit] = []

    def need(field: str, positive: bool, what: str) -> None:
        out.append(Limit(field, mech.value(field), positive, what))

    for b in mech.bodies:
        f = f"bodies.{b.name}"
        need(f + ".mass", True, "mass (kg)")
        if b.length is not None:
            need(f + ".length", True, "length (m)")
        for field, what in b.inertia_limits():
            need(field, True, what)
    kin = mech.kinematics()
    for plugin in (*mech.force_elements(), *mech.loads, *mech.joints):
        out += plugin.limits(kin, solve)
    return out


def check_values(mech: Mechanism, values: Mapping[str, float], *, solve: bool = False) -> None:
    """Reject physically impossible values (at the parameter ``values``).

    Every :func:`physical_limits` quantity must lie in its range, each element's own checks
    pass (a drag segment needs two points, an inertia tensor is a body's, a universal joint's
    axes are perpendicular) and no direction is zero. With ``solve=True`` (values given for one
    analysis, not the file's defaults) a spring stiffness of zero is allowed. Raises
    :class:`InputError` naming the key path and the value.
    """
    check_finite(mech, values)
    check_stop_limits(mech, values)
    for lim in physical_limits(mech, solve=solve):
        v = evaluate(lim.expr, values, lim.name)
        if (v <= 0) if lim.strict else (v < 0):
            raise InputError(lim.name, lim.message(v))
    for b in mech.bodies:
        b.check_values(mech, values)
    for ld in mech.loads:
        ld.check_values(mech, values)
    check_vectors(mech, values, vector_fields(mech))
    for j in mech.joints:
        j.check_values(mech, values)


def vector_fields(mech: Mechanism) -> list[str]:
    """The key paths of the description's vectors that must not be zero (directions, axes)."""
    fields = [f for ld in mech.loads for f in ld.vectors()]
    fields += mech.gravity.vectors() if mech.gravity is not None else []
    return fields + [f"joints.{j.name}.{k}" for j in mech.joints for k in j.VECTORS]


def analysis_value_check(mech: Mechanism) -> ValueCheck:
    """``check(values)`` of :func:`check_values` for an analysis (the defaults where not given, a zero
    stiffness allowed), screened by compiled code (see :class:`~mechcont.mechanism._compiled.ValueCheck`):
    the same limits, vectors and perpendicular axes."""
    vectors = [[mech.value(f"{f}.{c}") for c in mech.AXES] for f in vector_fields(mech)]
    pairs = [pair for j in mech.joints for pair in j.perpendicular(mech)]
    static = any(ld.static_error() for ld in mech.loads)
    return value_check(mech, partial(_check_analysis_values, mech), physical_limits(mech, solve=True), vectors, pairs,
                       static_error=static)


def _check_analysis_values(mech: Mechanism, values: Mapping[str, float]) -> None:
    """The description's physical checks at ``values`` (the defaults where not given; a zero stiffness allowed)."""
    check_values(mech, {p.name: float(values.get(p.name, p.value)) for p in mech.parameters}, solve=True)


def check_vectors(mech: Mechanism, values: Mapping[str, float], fields: Sequence[str]) -> None:
    """Each vector at the key paths ``fields`` (components ``mech.AXES``) must not be zero at ``values``."""
    for f in fields:
        v = [evaluate(mech.value(f"{f}.{c}"), values, f) for c in mech.AXES]
        if not any(v):
            raise InputError(f, "must not be the zero vector")


def value_check(mech: Mechanism, exact: Callable[[dict[str, float]], None], limits: list[Limit],
                vectors: list[list[sp.Expr]], perpendicular: Sequence[list[sp.Expr]] = (),
                static_error: bool = False) -> ValueCheck:
    """A :class:`~mechcont.mechanism._compiled.ValueCheck` of ``mech``: ``exact(values)`` screened by
    its quantities compiled (the description's numbers in the parameters alone, the ``limits``,
    the ``vectors`` (each a list of expressions, not all zero) and the ``perpendicular`` pairs
    (six expressions: two 3-vectors)). No screen when a quantity depends on more than the
    parameters or ``static_error`` (a defect that does not depend on the values)."""
    from ..equations import compile_dense
    from ._compiled import ValueCheck

    names = [p.name for p in mech.parameters]
    syms = [mech.param_symbols[n] for n in names]
    known = set(syms)
    exprs = [e for e in mech._exprs.values() if e.free_symbols <= known]
    groups: list[tuple[str, int]] = [("finite", len(exprs))]
    for lim in limits:
        exprs.append(lim.expr)
        groups.append(("positive" if lim.strict else "nonnegative", 1))
    for vec in vectors:
        exprs += vec
        groups.append(("nonzero", len(vec)))
    for pair in perpendicular:
        exprs += pair
        groups.append(("perpendicular", 6))
    exprs = [sp.sympify(e, strict=True) for e in exprs]
    usable = not static_error and all(e.free_symbols <= known for e in exprs)
    screen = None
    if usable and exprs:
        # without parameters the quantities are numbers (SymEngine compiles no function of nothing)
        screen = compile_dense(syms, exprs) if syms else np.array([_number(e) for e in exprs])
    return ValueCheck(names, [p.value for p in mech.parameters], screen, groups if screen is not None else (), exact)


def _number(expr: sp.Expr) -> float:
    """The value of a constant expression, nan when it is not a real number."""
    try:
        return float(expr)
    except (TypeError, ValueError):
        return math.nan
