"""A model: an equation system with everything a mechanism's analyses need, as declared fields.

:class:`Model` is an :class:`~mechcont.equations.EquationSystem` (the equations, their
compiled derivatives, the mechanics, the scene, the value checks) plus the typed, optional
facts about the mechanism behind it: its potential energy, the description it came from,
its degrees of freedom, reactions, dropped redundant rows, declared conditions, stops, dampers and downlock
(the last three as typed records: :class:`StopLimit`, :class:`DamperFacts`, :class:`DownlockFacts`).
Every field is declared and set when the model is made; nothing is attached afterwards
(assigning any other attribute raises :class:`AttributeError`), so analyses read fields
instead of probing for attributes. :meth:`~mechcont.equations.EquationSystem.with_values`
and :meth:`~mechcont.equations.EquationSystem.evolve` copy a model with its fields and its
compiled code; pickling carries every field (the callables are picklable objects).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import MISSING, dataclass, field, fields
from typing import TYPE_CHECKING, Any, Protocol, TypedDict

import numpy as np

from ..units import SI, UnitSystem
from . import _deferred
from ._system import EquationSystem

if TYPE_CHECKING:
    import sympy as sp

    from ._dynamics import OdeFacts
    from ._protocols import Description, DofFacts, Reselect

__all__ = ["Model", "units_of", "StopLimit", "DamperFacts", "DownlockFacts", "ValueFields", "FieldsAt", "at_values",
           "check_values_at"]


class DownlockAssembly(Protocol):
    """``assemble(values, hold=None) -> x``: a closed-form downlocked full vector at the parameter ``values``
    (SI) with the held states ``hold`` (default: the downlock's)."""

    def __call__(self, values: Mapping[str, float], hold: Mapping[str, float] | None = None, /) -> np.ndarray: ...


@dataclass(frozen=True)
class DownlockFacts:
    """The downlock of a model: the condition its lock is held at and what the downlock analyses start from.

    ``hold``: the held states ``{state: value}`` (SI; e.g. the nose gear's ``{"theta4": 0.0}``);
    ``force``: the parameter freed as the downlock force (N); ``pose``: a full variable vector of the
    downlocked equilibrium at the model's defaults, or None; ``assemble``: ``assemble(values, hold) -> x``,
    a closed-form downlocked guess at the parameter ``values`` (SI), or None. Read by
    :mod:`mechcont.analysis.downlock` and the studies."""

    hold: Mapping[str, float]
    force: str = "F"
    pose: np.ndarray | None = field(default=None, repr=False, compare=False)
    assemble: DownlockAssembly | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class StopLimit:
    """A stop of a model: the condition it limits, its contact reaction and its limit.

    ``side`` is +1 when the condition stays at or above ``limit`` (a min stop), -1 at or below;
    ``limit`` is in the condition's unit (its value at the model's parameter values: a limit
    written in parameters follows :meth:`Model.with_values`);
    ``reaction`` names the contact reaction parameter (>= 0 in contact; see
    :mod:`mechcont.mechanism._stops`); ``restitution`` is Newton's coefficient ``e`` (0 to 1) the
    time simulation applies at an impact on it; ``contact`` is ``"rigid"`` or ``"compliant"`` (the
    time simulation's penalty reaction ``max(0, stiffness p + damping p')`` on the penetration
    ``p``, ``stiffness`` and ``damping`` per unit of the condition, at the model's parameter values)."""

    name: str
    condition: str
    reaction: str
    side: int
    limit: float
    restitution: float = 0.0
    contact: str = "rigid"
    stiffness: float = 0.0
    damping: float = 0.0

    @property
    def key(self) -> str:
        """``"min"`` (side +1) or ``"max"`` (side -1), as in the description's stop table."""
        return "min" if self.side > 0 else "max"

    def gap(self, condition_value: float) -> float:
        """How far (condition unit) the condition is from the stop, >= 0 on the allowed side."""
        return self.side * (condition_value - self.limit)


@dataclass(frozen=True)
class DamperFacts:
    """A damper of a model: its tension ``c v + c2 v |v|`` (N) with ``v`` the rate of its length (m/s), the
    coefficients ``c`` (N s/m) and ``c2`` (N s^2/m^2) at the model's parameter values (written in parameters,
    they follow :meth:`Model.with_values`). What a time simulation's damper tensions need of the description;
    the scene draws the damper's ends (:attr:`~mechcont.equations.Scene.dampers`)."""

    name: str
    c: float
    c2: float = 0.0


class ValueFields(TypedDict, total=False):
    """The fields of a :class:`Model` that depend on its parameter values (what :attr:`Model.fields_at` gives)."""

    conditions: Mapping[str, float | None]
    downlock: DownlockFacts | None
    stops: tuple[StopLimit, ...]
    dampers: tuple[DamperFacts, ...]


class FieldsAt(Protocol):
    """What :attr:`Model.fields_at` is: the fields that depend on the parameter values, at ``values`` (every
    parameter, SI), and of the values it computes (key paths of the description, e.g.
    ``"stops.top.max"``), the parameters each is written in and its exact derivatives at ``values``
    (each None for a key path it does not compute)."""

    def __call__(self, values: Mapping[str, float], /) -> ValueFields: ...

    def written_in(self, field: str, /) -> frozenset[str] | None: ...

    def derivatives(self, field: str, params: Iterable[str], values: Mapping[str, float], /
                    ) -> dict[str, float] | None: ...


@dataclass(eq=False)
class Model(EquationSystem):
    """An :class:`EquationSystem` with the declared facts of the mechanism behind it.

    Parameters (besides those of :class:`EquationSystem`; every one optional)
    --------------------------------------------------------------------------
    potential_energy:
        ``V`` (J) as a SymPy expression in the variables' symbols, or None.
    mechanism:
        The description (:class:`~mechcont.mechanism.Mechanism`) the model was generated
        from; None for a hand-formulated model.
    unit_system:
        The :class:`~mechcont.units.UnitSystem` its numbers are in: the description's declared units
        (``[mechanism] units``), SI by default. Kept beside ``mechanism`` so that reading it needs no
        description (one loaded from the disk cache is unpickled, with SymPy, only when used).
    dof:
        The :class:`~mechcont.mechanism.DofReport` of the assembled configuration.
    reaction_names:
        Names of the joint reactions (N, N m), one per kept constraint row.
    coordinates_of:
        ``coordinates_of(x) -> {coordinate: value}`` (m, rad) for every body coordinate,
        eliminated ones included.
    dropped_constraints:
        Equation names of the redundant constraint rows dropped (``redundant = "drop"``).
    dropped_residual:
        ``dropped_residual(x) -> float``: the largest residual of the dropped rows (m, rad).
    conditions:
        Each declared condition's target, ``{name: value or None}``.
    downlock:
        The downlock (:class:`DownlockFacts`: held states, force, downlocked pose, closed-form
        assembly), or None when the model declares none.
    stops:
        The stops (:class:`StopLimit`): one-sided limits of conditions with their contact reactions.
    dampers:
        The dampers (:class:`DamperFacts`): name and coefficients at the model's parameter values.
    fields_at:
        ``fields_at(values) -> ValueFields`` (a :class:`FieldsAt`): the fields that depend on the parameter values
        (the conditions' targets, the downlock hold, the stops' limits, the dampers' coefficients), at ``values`` (all
        parameters, SI); :meth:`with_values` applies it, :meth:`written_in` and :meth:`value_derivatives` ask it
        first (compiled where the model was built: no SymPy). None when no field depends on them.
    reselect:
        For a model with dropped redundant rows whose choice depends on the configuration (a
        spatial ``redundant = "drop"`` mechanism): an object with ``quality(x) -> float``
        (positive while the dropped rows suit the full vector ``x``; continuation ends a piece
        where it turns negative) and ``switch(model, x) -> (model, x) or None`` (the variant of
        the system with another choice and ``x`` with its reactions solved again). None otherwise.
    ode:
        For an ODE model (a ``[system]`` file, :func:`~mechcont.equations.ode_model`): which
        variables are its states and whether it is algebraic (:class:`OdeFacts`); None for a
        mechanism. :func:`~mechcont.equations.dynamics_of` gives the dynamics of either.
    """

    potential_energy: sp.Expr | None = None
    mechanism: Description | None = None
    dof: DofFacts | None = None
    reaction_names: tuple[str, ...] = ()
    coordinates_of: Callable[[np.ndarray], dict[str, float]] | None = None
    dropped_constraints: tuple[str, ...] = ()
    dropped_residual: Callable[[np.ndarray], float] | None = None
    conditions: Mapping[str, float | None] = field(default_factory=dict)
    downlock: DownlockFacts | None = None
    stops: tuple[StopLimit, ...] = ()
    dampers: tuple[DamperFacts, ...] = ()
    fields_at: FieldsAt | None = field(default=None, repr=False)
    reselect: Reselect | None = field(default=None, repr=False)
    ode: OdeFacts | None = None
    unit_system: UnitSystem = SI

    def with_values(self, values: Mapping[str, float]) -> Model:
        """:meth:`EquationSystem.with_values`, with the fields that depend on the parameter values
        (a condition's target, the downlock hold, a stop's limit written as an expression in
        parameters) evaluated at the new values."""
        new = super().with_values(values)
        if self.fields_at is None:
            return new
        params = {v.name: v.value for v in new.variables if v.kind == "parameter"}
        return new.evolve(**self.fields_at(params))

    def limit_derivatives(self, stop: str, params: Iterable[str]) -> dict[str, float]:
        """``{parameter: d limit / d parameter}`` of the stop ``stop``'s limit (condition unit per parameter unit)
        at the model's parameter values, the limit as its description writes it in parameters: how a quantity
        solved with the stop held at its limit changes with them (see :meth:`value_derivatives`)."""
        found = next((s for s in self.stops if s.name == stop), None)
        if found is None:
            raise KeyError(stop)
        return self.value_derivatives(f"stops.{stop}.{found.key}", params)

    def target_derivatives(self, condition: str, params: Iterable[str]) -> dict[str, float]:
        """``{parameter: d target / d parameter}`` of the declared condition ``condition``'s target (the value
        the downlock holds it at), as its description writes it (see :meth:`value_derivatives`)."""
        return self.value_derivatives(f"conditions.{condition}.target", params)

    def written_in(self, field: str) -> frozenset[str]:
        """The parameters the description's value at key path ``field`` is written in (empty for a number, an
        unknown key path or a model without a description's expressions)."""
        if self.fields_at is not None:
            found = self.fields_at.written_in(field)
            if found is not None:
                return found
        value = getattr(self.mechanism, "value", None)
        try:
            expr = value(field) if value is not None else None
        except KeyError:
            return frozenset()
        return frozenset(s.name for s in getattr(expr, "free_symbols", ()))

    def value_derivatives(self, field: str, params: Iterable[str]) -> dict[str, float]:
        """``{parameter: d value / d parameter}`` of the description's value at key path ``field`` (an expression
        in parameters) at the model's parameter values, exact (the expression differentiated); 0 for a
        parameter it does not use, and for every parameter of a model without a description's expressions."""
        params = list(params)
        if self.fields_at is not None:
            at = {v.name: v.value for v in self.variables if v.kind == "parameter"}
            found = self.fields_at.derivatives(field, params, at)
            if found is not None:
                return found
        out = dict.fromkeys(params, 0.0)
        value = getattr(self.mechanism, "value", None)
        if value is None:
            return out
        try:
            expr = value(field)
        except KeyError:
            return out
        symbols = {s.name: s for s in getattr(expr, "free_symbols", ())}
        if not any(p in symbols for p in params):
            return out
        subs = {sym: self.variable(n).value for n, sym in symbols.items()}
        for p in params:
            if p in symbols:
                out[p] = float(expr.diff(symbols[p]).xreplace(subs))
        return out

    def __setattr__(self, name: str, value: object) -> None:
        if name not in _declared(type(self)):
            raise AttributeError(f"{type(self).__name__} has no field {name!r}: a model's fields are declared "
                                 f"(make a copy with evolve(...) or declare the field)")
        object.__setattr__(self, name, value)

    def compiled_state(self) -> dict[str, Any]:
        """:meth:`EquationSystem.compiled_state` plus every other field of the model (``"fields"``).

        The fields' callables (scene, value checks, coordinates, ...) are picklable objects, so the
        state pickles whole; :meth:`from_compiled_state` makes the model again, compiling nothing.
        """
        state = super().compiled_state()
        core = {"name", "variables", "equations", "equation_names", "mechanics", "description", "limits"}
        state["fields"] = {f.name: getattr(self, f.name) for f in fields(self) if f.init and f.name not in core}
        return state

    @classmethod
    def from_compiled_state(cls, state: dict[str, Any]) -> Model:
        """A :class:`Model` from :meth:`compiled_state` (validated, nothing compiled again)."""
        system = EquationSystem.from_compiled_state(state)
        given = dict(state.get("fields", {}))
        own = {k: given.pop(k) for k in list(given) if k not in _declared(EquationSystem)}
        return cls.from_system(system.evolve(**given), **own)

    @classmethod
    def from_system(cls, system: EquationSystem, **fields_: object) -> Model:
        """A model of ``system`` (its equations and compiled code shared, nothing rebuilt) with ``fields_`` set."""
        model = object.__new__(cls)
        given = system.__dict__
        for f in fields(cls):
            if f.name in given and f.name in _declared(EquationSystem):
                value = given[f.name]
            elif f.name in _declared(EquationSystem) and (_deferred.DEFERRED in given or f.name == "symbols"):
                continue  # in the system's inner pickle (a loaded system), or made on first use
            elif f.default is not MISSING:
                value = f.default
            elif f.default_factory is not MISSING:
                value = f.default_factory()
            else:  # pragma: no cover - every Model field has a default
                raise TypeError(f"no value for field {f.name!r}")
            object.__setattr__(model, f.name, value)
        if _deferred.DEFERRED in given:
            object.__setattr__(model, _deferred.DEFERRED, given[_deferred.DEFERRED])
        for k in fields_:
            if k not in _declared(cls) or k in _declared(EquationSystem):
                raise TypeError(f"Model.from_system() got an unknown model field {k!r}")
        for k, v in fields_.items():
            object.__setattr__(model, k, v)
        return model


_deferred.defaults_off_the_class(Model)

_DECLARED: dict[type, frozenset[str]] = {}


def _declared(cls: type) -> frozenset[str]:
    """Names of the dataclass fields of ``cls``."""
    names = _DECLARED.get(cls)
    if names is None:
        names = _DECLARED[cls] = frozenset(f.name for f in fields(cls))
    return names


def check_values_at(system: EquationSystem, values: Mapping[str, float], field: str = "values") -> None:
    """Check ``values`` (SI, rad) for ``system`` as every option that gives values does (``--set``,
    ``--scan``, ``--design``, ``--dist``, ``--params``): each name a variable of the model (a state's value is
    a guess), each value finite, and the parameters, together with the model's other parameter values,
    within the model's valid ranges: its value checks (``check_values``, an analysis's ranges: a spring of
    zero stiffness allowed) and its declared limits that depend on parameters alone (positive lengths).
    Raises :class:`InputError` naming ``field`` and the value's own name or key path."""
    from ..errors import InputError

    for name, value in values.items():
        system.index(name)  # an unknown name: its own error, listing the valid ones
        if not math.isfinite(float(value)):
            raise InputError(field, f"{name} = {value}: give a finite number")
    params = {v.name for v in system.variables if v.kind == "parameter"}
    given = [n for n in values if n in params]
    if not given:
        return
    x = system.vector(values)
    try:
        if system.check_values is not None:
            system.check_values({n: float(x[system.index(n)]) for n in params})
        if system.limits:
            limit_values = system.limit_values(x)
            uses = system._limit_uses()
            for i in system.limits_of(given):
                lim, v = system.limits[i], float(limit_values[i])
                if uses[i] <= params and (not math.isfinite(v) or (v <= 0 if lim.strict else v < 0)):
                    raise InputError(lim.name, lim.message(v))
    except InputError as exc:
        raise InputError(field, str(exc)) from None


def at_values(model: Model, values: Mapping[str, float] | None, field: str = "values") -> Model:
    """The model at ``values`` (SI, rad): the one way a value reaches a model in mechcont.

    ``values`` are checked (:func:`check_values_at`, errors naming ``field``), then
    :meth:`Model.with_values`: the parameters take their values and everything written in them
    follows (a stop's limit, a condition's target, the downlock hold); a state's value is the guess
    the solves start from. Returns ``model`` itself when ``values`` is empty."""
    if not values:
        return model
    check_values_at(model, values, field)
    return model.with_values({k: float(v) for k, v in values.items()})


def units_of(system: EquationSystem) -> UnitSystem:
    """The units the numbers of ``system`` are in: those its description declares (a :class:`Model`'s
    ``unit_system``), SI for a built-in or hand-formulated model or a bare equation system."""
    return system.unit_system if isinstance(system, Model) else SI
