"""A named system of algebraic equations G(x) = 0 with exact derivatives.

Every quantity of a model — configuration states, internal forces, loads, geometry — is
one *named variable*. The system does not decide which of them are unknown: that choice
(the "lens") is made later by :class:`mechcont.continuation.Problem`, so any state can be
held and any parameter freed without touching the equations.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Self

import numpy as np

from ..errors import InputError
from . import _cache, _compiled, _deferred
from ._cache_key import expr_text
from ._codegen import CompiledFunction, compile_dense, engine_arguments
from ._compiled import ColumnView, generate_code
from ._variables import Limit, Variable

if TYPE_CHECKING:
    import sympy as sp

    from ._protocols import Mechanics, SceneFunction, ValueCheck

__all__ = ["EquationSystem"]


@dataclass
class EquationSystem:
    """Equations ``G(x) = 0`` over named variables, compiled with exact derivatives.

    Parameters
    ----------
    name:
        Model name.
    variables:
        All variables, states and parameters. States are the default unknowns; their
        number must equal the number of equations.
    equations:
        SymPy expressions in the variables' symbols (``Variable.symbol``).
    equation_names:
        Optional label per equation (for readable output).
    mechanics:
        Optional :class:`~mechcont.equations.MechanicalModel` describing the physical
        mechanism (coordinates, constraints, forces, masses) behind the equations; it
        gives physical stability and the dynamic model.
    description:
        Free text shown by ``mechcont models``.
    scene:
        Optional callable ``scene(x) -> Scene`` giving drawing primitives at a full
        variable vector ``x`` (see :class:`mechcont.equations.Scene`).
    check_values:
        Optional callable ``check_values({name: value})`` raising
        :class:`~mechcont.errors.InputError` for physically impossible parameter values
        (a negative mass, a zero length); solves call it on the values they are given.
    limits:
        :class:`Limit` objects: physical ranges (lengths, masses, stiffnesses) that solves
        check and continuation stops at (``EP``).

    Attributes
    ----------
    names:
        Tuple of all variable names; numeric vectors ``x`` are ordered like this.
    """

    name: str
    variables: Sequence[Variable]
    equations: Sequence[sp.Expr]
    equation_names: Sequence[str] = ()
    mechanics: Mechanics | None = None
    description: str = ""
    scene: SceneFunction | None = None
    check_values: ValueCheck | None = None
    limits: Sequence[Limit] = ()
    # compiled code, filled on first use and shared by copies (with_values, load_model)
    _code: dict[str, Any] = field(default_factory=dict, init=False, repr=False)
    # derived in __post_init__ from the variables (their names never change)
    names: tuple[str, ...] = field(init=False, repr=False, compare=False)
    symbols: tuple[sp.Symbol, ...] = field(init=False, repr=False, compare=False)
    _index: dict[str, int] = field(init=False, repr=False, compare=False)
    #: fields that did not pickle and were reset to their defaults when this copy was unpickled
    unpickled_without: tuple[str, ...] = field(default_factory=tuple, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        import sympy as sp

        self.variables = tuple(self.variables)
        self.equations = tuple(sp.sympify(e, strict=True) for e in self.equations)
        self.limits = tuple(self.limits)
        self.names = tuple(v.name for v in self.variables)
        if len(set(self.names)) != len(self.names):
            dup = sorted({n for n in self.names if self.names.count(n) > 1})
            raise InputError(dup[0], "variable defined more than once")
        self._index = {n: i for i, n in enumerate(self.names)}
        self.symbols = tuple(v.symbol for v in self.variables)
        known = set(self.symbols)
        for i, e in enumerate(self.equations):
            unknown = {s for s in e.free_symbols if s not in known}
            if unknown:
                raise InputError(str(sorted(map(str, unknown))[0]), f"used in equation {i} but not declared as a variable")
        if not self.equation_names:  # None or none given: G0, G1, ...
            self.equation_names = tuple(f"G{i}" for i in range(len(self.equations)))
        self.equation_names = tuple(self.equation_names)
        n_states = len(self.state_names)
        if n_states != len(self.equations):
            raise InputError(
                self.name,
                f"{len(self.equations)} equations but {n_states} states; declare exactly one state per equation",
            )

    # -- naming ------------------------------------------------------------------------
    @property
    def n_equations(self) -> int:
        """Number of equations (one name each; a loaded system counts them without its SymPy form)."""
        return len(self.equation_names)

    @property
    def state_names(self) -> tuple[str, ...]:
        """Names of the default unknowns."""
        return tuple(v.name for v in self.variables if v.kind == "state")

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """Names of the default held quantities."""
        return tuple(v.name for v in self.variables if v.kind == "parameter")

    def index(self, name: str) -> int:
        """Position of ``name`` in :attr:`names`; :class:`InputError` if unknown."""
        try:
            return self._index[name]
        except KeyError:
            raise InputError(name, f"unknown variable of model '{self.name}'; valid names: {', '.join(self.names)}") from None

    def variable(self, name: str) -> Variable:
        """The :class:`Variable` called ``name``."""
        return self.variables[self.index(name)]

    def defaults(self) -> np.ndarray:
        """Vector of default values / initial guesses, ordered like :attr:`names`."""
        return np.array([v.value for v in self.variables], dtype=float)

    def vector(self, values: Mapping[str, float] | None = None, base: np.ndarray | None = None) -> np.ndarray:
        """A full value vector: ``base`` (or the defaults) with ``values`` overriding by name."""
        x = self.defaults() if base is None else np.array(base, dtype=float)
        for k, v in (values or {}).items():
            x[self.index(k)] = float(v)
        return x

    def as_dict(self, x: Iterable[float]) -> dict[str, float]:
        """Map a full value vector to ``{name: value}``."""
        return {n: float(v) for n, v in zip(self.names, x)}

    def scales(self) -> np.ndarray:
        """Typical magnitude of every variable, ordered like :attr:`names`."""
        return np.array([v.scale for v in self.variables])

    def with_values(self, values: Mapping[str, float]) -> Self:
        """A copy with new default values, sharing the compiled functions (no rebuild).

        Only defaults change; the equations are the same, so this is how a model is
        re-parametrised cheaply. Unknown names raise :class:`InputError`.
        """
        from dataclasses import replace

        for k in values:
            self.index(k)
        return self.evolve(variables=tuple(replace(v, value=float(values[v.name])) if v.name in values else v
                                           for v in self.variables))

    def evolve(self, **changes: Any) -> Self:
        """A copy with some declared fields replaced, sharing the compiled code (nothing is rebuilt).

        ``variables`` may change values, scales, units and descriptions but not names or kinds
        (the compiled equations are in them); ``equations`` cannot change. Any other declared
        field (``scene``, ``check_values``, a :class:`~mechcont.equations.Model`'s fields) may.
        Raises :class:`TypeError` for a name that is not a declared field.
        """
        import copy
        from dataclasses import fields

        declared = {f.name for f in fields(self) if f.init}
        for k in changes:
            if k not in declared or k in ("name", "equations", "equation_names"):
                raise TypeError(f"{type(self).__name__}.evolve() cannot set {k!r}")
        if "variables" in changes:
            variables = tuple(changes["variables"])
            if tuple((v.name, v.kind) for v in variables) != tuple((v.name, v.kind) for v in self.variables):
                raise ValueError("evolve() may change the variables' values and scales, not their names or kinds")
            changes["variables"] = variables
        new = copy.copy(self)
        for k, v in changes.items():
            object.__setattr__(new, k, v)
        return new

    # -- compiled numerics ------------------------------------------------------------
    def compile(self, second_derivatives: bool = False) -> Self:
        """Generate the numeric residual and Jacobian function (once), and optionally the second derivatives.

        Called on first numeric use; the second derivatives (:meth:`jacobian_derivative`,
        for folds and cusps) are compiled on their first use, or here with
        ``second_derivatives=True``. The result is shared by shallow copies, so a model
        re-parametrised with :meth:`with_values` is never compiled twice. The compiled code
        comes from the disk cache when an earlier process compiled the same equations
        (see :mod:`mechcont.equations._cache`; ``MECHCONT_NO_CACHE=1`` turns it off).
        """
        if "res_jac" not in self._code:
            self._code.update(self._cached_code("residual_jacobian"))
        if second_derivatives and "hess_values" not in self._code:
            self._code.update(self._cached_code("second_derivatives"))
        if "hess_values" in self._code:
            self._code.pop("_symbolic", None)  # both parts made: the SymEngine form is no longer needed
        return self

    def _cached_code(self, part: str) -> dict[str, Any]:
        """One compiled part (``residual_jacobian`` or ``second_derivatives``), from the disk cache or made. A model
        loaded from the cache before its second derivatives were compiled holds their entry's key (``second_derivatives_key``,
        :meth:`compiled_state`): with it they come from the cache without the SymPy equations the key is made from."""
        n_eq, n = self.n_equations, len(self.names)
        if part == "residual_jacobian":
            def valid(obj: object) -> bool:
                return (isinstance(obj, dict) and set(obj) == {"res_jac"} and isinstance(obj["res_jac"], CompiledFunction)
                        and obj["res_jac"].n_args == n and obj["res_jac"].shape == (n_eq + n_eq * n,))
        else:
            def valid(obj: object) -> bool:
                return (isinstance(obj, dict) and set(obj) == {"hess_values", "hess_j", "hess_ik"}
                        and obj["hess_values"].n_args == n and len(obj["hess_j"]) == obj["hess_values"].n_out)

        return _cache.cached(lambda: self._key_parts(part), lambda: generate_code(self._engine_form(), part), valid,
                             key=self._code.get(f"{part}_key"))

    def _engine_form(self) -> dict[str, Any]:
        """The SymEngine form the parts are compiled from (positional argument symbols ``syms``, equations
        ``eqs``), made once and kept for the other part (shared by copies, never pickled)."""
        sym = self._code.get("_symbolic")
        if sym is None:
            syms, eqs = engine_arguments(self.symbols, self.equations)
            sym = self._code["_symbolic"] = {"syms": syms, "eqs": eqs}
        return sym

    def _key_parts(self, part: str) -> list[str]:
        """A part's disk-cache key: the compiled form (positional arguments, SymEngine equations' text, made once)."""
        sym = self._engine_form()
        if "texts" not in sym:
            sym["texts"] = [expr_text(e) for e in sym["eqs"]]
        # the chunking (of distinct expressions) decides the compiled functions (their values' last bits): another
        # limit's entry, or an entry of the earlier chunks of every expression, is not this
        chunk = [f"chunk={_compiled.SECOND_DERIVATIVES_CHUNK},distinct"] if part == "second_derivatives" else []
        return ["system", part, str(len(sym["syms"])), *chunk, *sym["texts"]]

    def limit_values(self, x: np.ndarray) -> np.ndarray:
        """Value of every :attr:`limits` quantity at the full vector ``x`` (SI units)."""
        if not self.limits:
            return np.zeros(0)
        fn = self._code.get("limits")
        if fn is None:
            fn = self._code["limits"] = compile_dense(self.symbols, [lim.expr for lim in self.limits])
        return np.asarray(fn(np.asarray(x, dtype=float)), dtype=float).reshape(-1)

    def check_limits(self, x: np.ndarray) -> None:
        """Raise :class:`InputError` naming the first limit that ``x`` violates."""
        for lim, v in zip(self.limits, self.limit_values(x)):
            if not math.isfinite(v) or (v <= 0 if lim.strict else v < 0):
                raise InputError(lim.name, lim.message(v))

    def limits_of(self, names: Iterable[str]) -> list[int]:
        """Indices of the limits whose quantity depends on any of ``names``."""
        wanted = {self.variable(n).name for n in names}
        return [i for i, uses in enumerate(self._limit_uses()) if uses & wanted]

    def _limit_uses(self) -> tuple[frozenset[str], ...]:
        """The variable names each limit's quantity depends on (kept with the compiled code)."""
        uses = self._code.get("limit_uses")
        if uses is None:
            uses = self._code["limit_uses"] = tuple(frozenset(s.name for s in lim.expr.free_symbols) for lim in self.limits)
        return uses

    def residual(self, x: np.ndarray) -> np.ndarray:
        """G(x): one residual per equation (units of each equation), ``x`` in :attr:`names` order."""
        return self.residual_and_jacobian(x)[0]

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """dG/dx with respect to *all* variables: array (n_equations, n_variables)."""
        return self.residual_and_jacobian(x)[1]

    def residual_and_jacobian(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(G(x), dG/dx)`` from one evaluation (see :meth:`residual`, :meth:`jacobian`)."""
        try:
            fn = self._code["res_jac"]
        except KeyError:
            fn = self.compile()._code["res_jac"]
        out = fn(x)
        n_eq = self.n_equations
        return out[:n_eq], out[n_eq:].reshape(n_eq, len(self.names))

    def jacobian_derivative(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """d/dx (J(x) v): the second derivative of G contracted with ``v`` over all variables.

        ``v`` is a full-length vector (zeros for names it does not involve). Returns an
        array (n_equations, n_variables) whose column k is sum_j d2G/dx_j dx_k v_j.
        Used for fold and cusp conditions.
        """
        code = self._code if "hess_values" in self._code else self.compile(second_derivatives=True)._code
        n_eq, n = self.n_equations, len(self.names)
        w = code["hess_values"](x) * np.asarray(v)[code["hess_j"]]
        return np.bincount(code["hess_ik"], weights=w, minlength=n_eq * n).reshape(n_eq, n)

    def columns(self, columns: Sequence[int] | np.ndarray) -> ColumnView:
        """Evaluation restricted to the Jacobian columns ``columns`` (a solve's unknowns), for hot loops.

        Returns a :class:`ColumnView`: the same values as :meth:`residual_and_jacobian` and
        :meth:`jacobian_derivative` followed by ``[:, columns]``, without forming the other
        columns. Views are kept with the compiled code (shared by copies), one per set of columns.
        """
        key = tuple(int(c) for c in np.asarray(columns).reshape(-1))
        views: dict[tuple[int, ...], ColumnView] = self._code.setdefault("_views", {})
        view = views.get(key)
        if view is None:
            view = views[key] = ColumnView(self, key)
        return view

    def residual_batch(self, X: np.ndarray) -> np.ndarray:
        """G at every row of ``X`` (shape ``(m, n_variables)``): array ``(m, n_equations)``.

        One call into the compiled code (it runs row by row in machine code), so each row is
        bit-identical to :meth:`residual` at that row. The Jacobian is computed alongside
        (the compiled function gives both): see :meth:`residual_and_jacobian_batch`.
        """
        return self.residual_and_jacobian_batch(X)[0]

    def residual_and_jacobian_batch(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(G, dG/dx)`` at every row of ``X``: arrays ``(m, n_equations)`` and ``(m, n_equations, n_variables)``.

        Bit-identical row by row to :meth:`residual_and_jacobian`, in one call.
        """
        try:
            fn = self._code["res_jac"]
        except KeyError:
            fn = self.compile()._code["res_jac"]
        X = np.asarray(X, dtype=float)
        if X.ndim != 2:
            raise ValueError(f"expected a 2-D array (points, {len(self.names)} variables), got shape {X.shape}")
        out = fn.batch(X)
        n_eq = self.n_equations
        return out[:, :n_eq], out[:, n_eq:].reshape(len(X), n_eq, len(self.names))

    # -- pickling: the compiled numeric core ------------------------------------------
    def compiled_state(self) -> dict[str, Any]:
        """The compiled numeric core as plain picklable data (see :meth:`from_compiled_state`).

        Compiles whatever is not compiled yet (residual and Jacobian, second derivatives,
        limits, every part of the mechanics), so a process that loads the state compiles
        nothing; except while a built model is kept in the disk cache
        (:func:`~mechcont.equations._deferred.compiling_later`: :func:`~mechcont.equations.stored`),
        when the second derivatives and the mechanics' groups not compiled yet stay so and their
        entries' keys are kept instead: a process that loads the model and needs them takes them
        from the disk cache, where the first process that compiled them put them. Included: name,
        variables, equations and their names, description, limits, the
        :class:`~mechcont.equations.MechanicalModel` (its symbolic model and compiled functions)
        and the compiled functions. Not included: the other fields (``scene``,
        ``check_values``); :meth:`mechcont.equations.Model.compiled_state` adds them and a
        model's own fields, and pickling the system itself keeps every field that pickles
        (see :meth:`__getstate__`).
        """
        from ._mechanics import MechanicalModel

        later = _deferred.compiling_later()
        self.compile(second_derivatives=not later)
        if later and "hess_values" not in self._code and "second_derivatives_key" not in self._code:
            self._code["second_derivatives_key"] = _cache.cache_key(self._key_parts("second_derivatives"))
        if self.limits and "limits" not in self._code:
            self._code["limits"] = compile_dense(self.symbols, [lim.expr for lim in self.limits])
        self._limit_uses()
        if isinstance(self.mechanics, MechanicalModel):
            self.mechanics.compile_all(later)
        return {"format": 1, "name": self.name, "variables": tuple(self.variables), "equations": tuple(self.equations),
                "equation_names": tuple(self.equation_names), "description": self.description,
                "limits": tuple(self.limits), "mechanics": self.mechanics,
                "code": {k: v for k, v in self._code.items() if not k.startswith("_")}}

    @classmethod
    def from_compiled_state(cls, state: dict[str, Any]) -> EquationSystem:
        """An :class:`EquationSystem` from :meth:`compiled_state` (validated, nothing compiled again)."""
        if not isinstance(state, dict) or state.get("format") != 1:
            raise ValueError("not a compiled state of an EquationSystem (format 1)")
        system = cls(name=state["name"], variables=state["variables"], equations=state["equations"],
                     equation_names=state["equation_names"], mechanics=state["mechanics"],
                     description=state["description"], limits=state["limits"])
        system._code.update(state["code"])
        return system

    def __getstate__(self) -> dict[str, Any]:
        """Pickle: the compiled numeric core (:meth:`compiled_state`) plus every other attribute that pickles.

        A field that does not pickle (a closure given as ``scene`` or ``check_values``) is
        left out and back at its default after unpickling; an attribute attached after
        construction (not a declared field) that does not pickle is absent.
        ``unpickled_without`` names them all. The built-in models and generated descriptions
        give picklable callables, so their models travel whole.
        """
        state = EquationSystem.compiled_state(self)  # the core; the other fields below, each if it pickles
        core = {"name", "variables", "equations", "equation_names", "mechanics", "description", "limits",
                "_code", "names", "_index", "symbols", "unpickled_without"}
        # what needs SymPy to unpickle (the equations, a potential energy, a description) is kept
        # apart, unpickled on first use: a loaded model runs on its compiled code (see _deferred)
        apart = {"equations": state.pop("equations")}
        extras: dict[str, object] = {}
        omitted: list[str] = []
        for k, v in self.__dict__.items():
            if k in core:
                continue
            try:
                heavy = _deferred.needs_heavy(v)
            except Exception:  # noqa: BLE001 - whatever does not pickle stays behind
                omitted.append(k)
            else:
                (apart if heavy else extras)[k] = v
        state["extras"], state["omitted"] = extras, tuple(omitted)
        state["deferred_keys"], state["deferred"] = tuple(apart), _deferred.pack(apart)
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        from dataclasses import MISSING, fields

        if state.get("format") != 1:
            raise ValueError("not a compiled state of an EquationSystem (format 1)")
        d = self.__dict__
        for k in ("name", "equation_names", "mechanics", "description"):
            d[k] = state[k]
        # no validation (a pickle holds a system that was valid when built) and no SymPy: the
        # equations and the symbols come back on first use (__getattr__)
        d["variables"], d["limits"] = tuple(state["variables"]), tuple(state["limits"])
        d["names"] = tuple(v.name for v in d["variables"])
        d["_index"] = {n: i for i, n in enumerate(d["names"])}
        d["_code"] = dict(state["code"])
        if "equations" in state:  # a state from compiled_state()
            d["equations"] = tuple(state["equations"])
        if state.get("deferred") is not None:
            d[_deferred.DEFERRED] = state["deferred"]
        d.update(state.get("extras", {}))
        omitted = tuple(state.get("omitted", ()))
        apart = set(state.get("deferred_keys", ()))
        for f in fields(self):  # a declared field that did not pickle is back at its default
            if f.name in omitted or (f.name not in d and f.name not in apart and f.init):
                if f.default is not MISSING:
                    d[f.name] = f.default
                elif f.default_factory is not MISSING:
                    d[f.name] = f.default_factory()
        d["unpickled_without"] = omitted

    def __getattr__(self, name: str) -> Any:
        # reached only for attributes missing from the instance: a loaded system's symbolic
        # parts (kept apart when pickled) and its symbols, made on first use
        if name == "symbols" and "variables" in self.__dict__:
            value = self.__dict__["symbols"] = tuple(v.symbol for v in self.variables)
            return value
        if name.startswith("__"):
            raise AttributeError(name)
        return _deferred.materialize(self, name)

    def __copy__(self) -> EquationSystem:
        # a plain shallow copy (with_values relies on sharing _code); not the pickled state
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        return new

    # -- display ----------------------------------------------------------------------
    def pretty(self, shared: bool = False) -> str:
        """The equations as readable text, one per line, labelled.

        With ``shared=True`` sub-expressions used more than once (a spring's length, its
        direction) are named ``w0, w1, ...`` and listed first, as a hand derivation would.
        """
        import sympy as sp

        eqs = list(self.equations)
        lines = []
        if shared:
            names = sp.numbered_symbols("w")
            reps, eqs = sp.cse(eqs, symbols=names, optimizations="basic")
            lines = [f"{s} = {sp.sstr(e)}" for s, e in reps]
        lines += [f"{name}: {sp.sstr(e)} = 0" for name, e in zip(self.equation_names, eqs)]
        return "\n".join(lines)

    def latex(self) -> str:
        """The equations as a LaTeX ``align`` environment."""
        import sympy as sp

        def label(name: str) -> str:
            return name.replace("_", "\\_")  # underscores are special in LaTeX text mode

        rows = [f"{sp.latex(e)} &= 0 && \\text{{({label(name)})}}" for name, e in zip(self.equation_names, self.equations)]
        return "\\begin{align}\n" + " \\\\\n".join(rows) + "\n\\end{align}"


_deferred.defaults_off_the_class(EquationSystem)
