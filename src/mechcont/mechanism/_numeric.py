"""A description's values computed without SymPy: each expression compiled once into a numeric program.

A description's values are parsed into SymPy expressions (:mod:`._expr`), which the generators
need. A built model, though, also evaluates some of them again at other parameter values (a
condition's target, a stop's limit, a damper's coefficients: :attr:`~mechcont.equations.Model.fields_at`,
applied by every ``--set``), and a model loaded from the disk cache should not import SymPy
(0.5-1 s) for that. So each such expression is compiled, where the model is built, into a
:class:`NumericValue`: its tree in postfix order as plain tuples (numbers, parameter names, ``+``,
``*``, ``**`` and the functions of :data:`FUNCTIONS`), evaluated in double precision with
:mod:`math`. It pickles with the model and evaluates nothing but that program (no text is
parsed or evaluated as code). :class:`ValueFieldsAt` is a model's ``fields_at`` made of them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from ..equations import DamperFacts, DownlockFacts, StopLimit, ValueFields
from ..errors import InputError

if TYPE_CHECKING:
    import sympy as sp

    from ._description import Mechanism

__all__ = ["NumericValue", "numeric_value", "ValueFieldsAt", "value_fields_at", "FUNCTIONS"]


def _sign(u: float) -> float:
    return math.copysign(1.0, u) if u else 0.0


def _log(u: float, *base: float) -> float:
    return math.log(u) / (math.log(base[0]) if base else 1.0)


#: The functions a parsed expression may hold (by SymPy's name: those a description may call and
#: those SymPy's own simplification makes of them, such as ``cot`` from ``tan(x + pi/2)``), in floats.
FUNCTIONS: dict[str, Callable[..., float]] = {
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "asin": math.asin, "acos": math.acos, "atan": math.atan,
    "atan2": math.atan2, "sinh": math.sinh, "cosh": math.cosh, "tanh": math.tanh, "exp": math.exp, "log": _log,
    "Abs": abs, "Min": min, "Max": max, "sign": _sign,
    "cot": lambda u: 1.0 / math.tan(u), "sec": lambda u: 1.0 / math.cos(u), "csc": lambda u: 1.0 / math.sin(u),
    "acot": lambda u: math.atan(1.0 / u) if u else math.pi / 2, "asinh": math.asinh, "acosh": math.acosh,
    "atanh": math.atanh, "coth": lambda u: 1.0 / math.tanh(u),
}

#: One instruction: ``("num", value, 0)``, ``("sym", name, 0)``, ``("add", "", n)``, ``("mul", "", n)``,
#: ``("pow", "", 2)``, ``("call", function, n)`` (of :data:`FUNCTIONS`) or ``("sympy", function, n)``
#: (a function SymPy made that has no float form here, evaluated by SymPy at float arguments).
Instruction = tuple[str, "float | str", int]


@dataclass(frozen=True)
class NumericValue:
    """A compiled expression: ``value(values)`` in double precision, without SymPy.

    ``text`` is the expression as SymPy printed it (for messages), ``program`` its postfix
    instructions (:data:`Instruction`), ``names`` the names it uses."""

    text: str
    program: tuple[Instruction, ...]
    names: frozenset[str]

    def __call__(self, values: Mapping[str, float]) -> float:
        """The value at ``values`` (name -> value, SI): ``inf`` on an overflow, ``nan`` on a domain error
        (``sqrt(-1)``, ``acos(2)``, a division by zero), at once, never an arbitrary-precision blow-up.
        Raises KeyError for a name without a value."""
        stack: list[float] = []
        for op, arg, n in self.program:
            if op == "num":
                stack.append(float(arg))
                continue
            if op == "sym":
                stack.append(float(values[str(arg)]))
                continue
            args = stack[len(stack) - n:]
            del stack[len(stack) - n:]
            stack.append(_apply(op, str(arg), args))
        return stack[-1]

    def at(self, values: Mapping[str, float], field: str) -> float:
        """The value at ``values`` (SI); :class:`InputError` naming ``field`` unless it is a finite real number."""
        try:
            out = self(values)
        except KeyError:
            raise InputError(field, f"{self.text} depends on more than the parameters") from None
        if math.isnan(out):
            raise InputError(field, f"{self.text} is not a real number with the given parameters (a division by zero, "
                                    "the square root or logarithm of a negative number, asin or acos beyond +-1?)")
        if not math.isfinite(out):
            raise InputError(field, f"{self.text} overflows the floating-point range with the given parameters")
        return out


def _apply(op: str, name: str, args: Sequence[float]) -> float:
    """One operation of a program on float arguments (non-finite ones propagate: nan before inf)."""
    if not all(math.isfinite(a) for a in args):
        return math.nan if any(math.isnan(a) for a in args) else math.inf
    try:
        if op == "add":
            return math.fsum(args)
        if op == "mul":
            return math.prod(args)
        if op == "pow":
            return math.pow(*args)
        if op == "call":
            return float(FUNCTIONS[name](*args))
        import sympy as sp  # a function with no float form here: rare, and SymPy made the expression

        out = complex(getattr(sp, name)(*(sp.Float(a) for a in args)))
        return out.real if out.imag == 0 else math.nan
    except OverflowError:
        return math.inf
    except (ValueError, ZeroDivisionError, TypeError):
        return math.nan


def numeric_value(expr: sp.Expr) -> NumericValue:
    """Compile the SymPy expression ``expr`` (numbers, symbols, ``+ * **`` and functions) into a
    :class:`NumericValue` over its symbols' names. Raises ValueError on a head it cannot evaluate."""
    import sympy as sp

    program: list[Instruction] = []

    def emit(e: sp.Basic) -> None:
        if e.is_Symbol:
            program.append(("sym", str(e.name), 0))
            return
        if e.is_Number or e.is_NumberSymbol:
            program.append(("num", float(e), 0))
            return
        for a in e.args:
            emit(a)
        n = len(e.args)
        if e.is_Add:
            program.append(("add", "", n))
        elif e.is_Mul:
            program.append(("mul", "", n))
        elif e.is_Pow:
            program.append(("pow", "", n))
        elif (name := type(e).__name__) in FUNCTIONS:
            program.append(("call", name, n))
        elif getattr(sp, name, None) is type(e):
            program.append(("sympy", name, n))
        else:
            raise ValueError(f"no numeric form for {type(e).__name__} in {expr}")

    emit(sp.sympify(expr, strict=True))
    return NumericValue(str(expr), tuple(program), frozenset(str(s.name) for s in expr.free_symbols))


@dataclass(frozen=True)
class ValueFieldsAt:
    """``fields_at(values) -> ValueFields`` of a generated model (see :attr:`~mechcont.equations.Model.fields_at`):
    each condition's target, the downlock, the stops' limits (and a compliant stop's stiffness and damping)
    and the dampers' coefficients at the parameter ``values`` (SI), from the description's expressions
    compiled (:class:`NumericValue`, by key path in ``values``; ``slopes``: a target's and a stop limit's
    derivatives by each parameter it is written in). Raises :class:`InputError` naming the key path of a
    value that is not finite there.

    ``targets``: ``(condition, key path or None, default target)``; ``downlock``: ``(condition, force)``;
    ``stops``: each stop's record (its limit and contact values to be filled) with the key paths of its limit
    and (compliant) stiffness and damping; ``dampers``: ``(name, key path of c, key path of c2)``."""

    values: Mapping[str, NumericValue]
    slopes: Mapping[str, Mapping[str, NumericValue]]
    targets: tuple[tuple[str, str | None, float | None], ...]
    downlock: tuple[str, str] | None
    stops: tuple[tuple[StopLimit, str, str | None, str | None], ...]
    dampers: tuple[tuple[str, str, str], ...]

    def _at(self, field: str | None, values: Mapping[str, float], default: float = 0.0) -> float:
        return self.values[field].at(values, field) if field is not None else default

    def __call__(self, values: Mapping[str, float]) -> ValueFields:
        """The value-dependent fields of the model at ``values`` (every parameter, SI)."""
        targets = {name: (self.values[key].at(values, key) if key is not None else default)
                   for name, key, default in self.targets}
        out: ValueFields = {"conditions": targets}
        if self.downlock is not None:
            held, force = self.downlock
            target = targets[held]
            assert target is not None  # the parser refuses a downlock condition without a target
            out["downlock"] = DownlockFacts({held: target}, force)
        if self.stops:
            out["stops"] = tuple(replace(record, limit=self._at(limit, values), stiffness=self._at(k, values),
                                         damping=self._at(c, values)) for record, limit, k, c in self.stops)
        if self.dampers:
            out["dampers"] = tuple(DamperFacts(name, self._at(c, values), self._at(c2, values))
                                   for name, c, c2 in self.dampers)
        return out

    def _constant_targets(self) -> set[str]:
        """The key paths of the targets not written in the file (a condition kind's default)."""
        return {f"conditions.{name}.target" for name, key, _ in self.targets if key is None}

    def written_in(self, field: str) -> frozenset[str] | None:
        """The parameters the value at key path ``field`` is written in; None for a key path not held here."""
        found = self.values.get(field)
        if found is not None:
            return found.names
        return frozenset() if field in self._constant_targets() else None

    def derivatives(self, field: str, params: Iterable[str], values: Mapping[str, float]) -> dict[str, float] | None:
        """``{parameter: d value / d parameter}`` of the target or stop limit at key path ``field`` at ``values``
        (SI; exact: the expression differentiated where the model was built; 0 for a parameter it does not use);
        None for a key path whose derivatives are not held here."""
        slopes = self.slopes.get(field)
        if slopes is None:
            return dict.fromkeys(params, 0.0) if field in self._constant_targets() else None
        return {p: (slopes[p].at(values, field) if p in slopes else 0.0) for p in params}


def value_fields_at(mech: Mechanism) -> ValueFieldsAt:
    """The compiled :class:`ValueFieldsAt` of the description ``mech`` (made where its model is built)."""
    values: dict[str, NumericValue] = {}
    slopes: dict[str, dict[str, NumericValue]] = {}

    def compiled(field: str, slope: bool = False) -> str:
        expr = mech.value(field)
        values[field] = numeric_value(expr)
        if slope:
            slopes[field] = {str(s.name): numeric_value(expr.diff(s)) for s in expr.free_symbols}
        return field

    targets = tuple((c.name, compiled(f"conditions.{c.name}.target", True), None) if c.target is not None
                    else (c.name, None, c.default_target()) for c in mech.conditions)
    downlock = (mech.downlock.condition, mech.downlock.force) if mech.downlock is not None else None
    stops = []
    for s in mech.stops:
        compliant = s.contact == "compliant"
        stops.append((StopLimit(s.name, s.condition, s.reaction, s.side, math.nan, s.restitution, s.contact),
                      compiled(f"stops.{s.name}.{s.key}", True),
                      compiled(f"stops.{s.name}.stiffness") if compliant else None,
                      compiled(f"stops.{s.name}.damping") if compliant else None))
    dampers = tuple((d.name, compiled(f"dampers.{d.name}.c"), compiled(f"dampers.{d.name}.c2")) for d in mech.dampers)
    return ValueFieldsAt(values, slopes, targets, downlock, tuple(stops), dampers)
