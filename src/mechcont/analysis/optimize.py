"""Design optimisation on exact gradients: a quantity of interest minimised or maximised within bounds, under constraints.

The quantities are those :mod:`mechcont.analysis.sensitivity` differentiates exactly: the
downlock force, the unlock force (the fold bounding the locked state when the force
increases, :mod:`mechcont.analysis.unlock`), the load at a fold followed from a start fold,
and any parameter itself. A lock resting on its stops (a description with ``[stops]``) has its
unlock load from rest through the stops' release (:mod:`mechcont.analysis.stop_lock`) and each
stop's preload at rest, its reaction ``R_NAME`` (``stop_preload >= b`` stands for every stop's,
:mod:`mechcont.analysis._stop_quantities`). SciPy's SLSQP gets their values and gradients; the design
variables are mapped to ``[0, 1]`` by their bounds and every function is divided by a typical
magnitude, so newtons beside stiffnesses beside metres do not skew the steps.

At the optimum the active constraints and bounds carry multipliers ``mu`` with
``grad f = sum mu_i grad g_i``: ``mu_i`` is the change of the optimum per unit of the
constraint's bound (what one more newton of margin costs, in the objective's units).

A probability constraint ``P(not locking) <= p`` (reliability-based design) holds the
first-order reliability index of the downlock force over given distributions instead:
``beta >= Phi^-1(1 - p)`` (:mod:`mechcont.analysis.reliability`), with
``d beta / d d = (dg/dd at the design point) / |grad_u g|`` (the design point moves along the
limit state, so only the explicit change of ``g`` counts). A design parameter that also has a
distribution is a toleranced nominal value: its distribution moves with it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .._lazy import lazy_exports
from ..equations import Model, units_of
from ..errors import ConvergenceError, InputError
from ._slsqp import Inequality, better, multipliers, start_points, unmet
from ._stop_quantities import stop_reactions
from .sensitivity import Sensitivity, downlock_sensitivity, fold_sensitivity, write_json
from .study._spec import Distribution

if TYPE_CHECKING:
    import os

    from ._optimum_map import OptimumMap, optimum_map
    from .reliability import LimitState, Variables

__all__ = ["Constraint", "OptimumResult", "optimize", "QUANTITIES", "NOT_LOCKING", "BETA", "OptimumMap", "optimum_map"]

#: Named quantities besides the model's parameters.
QUANTITIES = ("downlock_force", "unlock_force", "fold_load", "stop_preload")
#: The probability of a constraint ``P(not locking) <= p``, and the reliability index that stands for it inside.
NOT_LOCKING, BETA = "P(not locking)", "beta(not locking)"
_PROBABILITY = re.compile(r"^\s*P\(\s*not\s+locking(?:\s+unaided)?\s*\)\s*(<=|>=)\s*"
                          r"((?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*$")

# name, comparison, number: nothing else is accepted (never evaluated as an expression)
_CONSTRAINT = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*(<=|>=)\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*$")


@dataclass(frozen=True)
class Constraint:
    """``quantity >= bound`` or ``quantity <= bound`` (SI units)."""

    quantity: str
    sense: str
    bound: float

    @classmethod
    def parse(cls, text: str) -> Constraint:
        """``"downlock_force >= 200"`` -> Constraint; :class:`InputError` for anything but NAME (<=|>=) NUMBER
        or ``P(not locking) <= NUMBER`` (a probability in (0, 1))."""
        p = _PROBABILITY.match(text)
        if p is not None:
            bound = float(p.group(2))
            if not 0 < bound < 1:
                raise InputError("constraint", f"'{text}': a probability must lie strictly between 0 and 1")
            return cls(NOT_LOCKING, p.group(1), bound)
        m = _CONSTRAINT.match(text)
        if m is None:
            raise InputError("constraint", f"'{text}' is not NAME >= NUMBER or NAME <= NUMBER (e.g. downlock_force >= 200)")
        bound = float(m.group(3))
        if not math.isfinite(bound):
            raise InputError("constraint", f"'{text}': the bound must be a finite number")
        return cls(m.group(1), m.group(2), bound)

    def __str__(self) -> str:
        return f"{self.quantity} {self.sense} {self.bound:g}"


@dataclass(frozen=True)
class OptimumResult:
    """The outcome of :func:`optimize`.

    Attributes
    ----------
    design:
        ``{parameter: value}`` at the optimum (SI).
    objective, value:
        The quantity optimised and its value there (SI).
    quantities:
        Every quantity of the problem at the optimum (SI).
    active:
        ``[(what, multiplier)]``: each active constraint (``"downlock_force >= 200"``) or bound
        (``"k <= 300"``) with the change of the optimum per unit of its bound.
    iterations, evaluations:
        SLSQP's iterations and the points where the quantities were solved.
    success, message:
        Whether SLSQP converged, and its message.
    violated:
        Each constraint the returned design does not meet (``"downlock_force >= 1e+09"``), beyond 1e-6 of its
        scale: an infeasible problem (no design within the bounds meets it), or one SLSQP did not solve.
    """

    design: dict[str, float]
    objective: str
    value: float
    quantities: dict[str, float]
    active: list[tuple[str, float]]
    iterations: int
    evaluations: int
    success: bool
    message: str
    units: dict[str, str] = field(default_factory=dict)
    violated: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, object]:
        """JSON-ready: design, objective, value, quantities, active (with multipliers), iterations, units."""
        return {"design": self.design, "objective": self.objective, "value": self.value, "quantities": self.quantities,
                "active": [{"constraint": c, "multiplier": m} for c, m in self.active], "iterations": self.iterations,
                "evaluations": self.evaluations, "success": self.success, "message": self.message, "units": self.units,
                "violated": self.violated}

    def to_json(self, path: str | os.PathLike[str]) -> None:
        """Write :meth:`to_dict` as JSON, atomically."""
        write_json(path, self.to_dict())

    def summary(self) -> str:
        """Plain text: the optimum, the active constraints with multipliers, the iteration count."""
        u = self.units
        lines = [f"{'converged' if self.success else 'NOT converged'}: {self.message} ({self.iterations} iterations, "
                 f"{self.evaluations} solves)",
                 f"{self.objective} = {self.value:.10g} {u.get(self.objective, '')}".rstrip()]
        lines += [f"  {n} = {v:.10g} {u.get(n, '')}".rstrip() for n, v in self.design.items() if n != self.objective]
        lines += [f"  {n} = {v:.10g} {u.get(n, '')}".rstrip() for n, v in self.quantities.items()
                  if n != self.objective and n not in self.design]
        lines.append("active: " + ("; ".join(f"{c} (multiplier {m:.6g})" for c, m in self.active) or "none"))
        if self.violated:
            lines.append("VIOLATED (not a feasible design): " + "; ".join(self.violated))
        return "\n".join(lines)


class _Quantities:
    """Values and exact gradients of the named quantities at a design, solved once per design."""

    def __init__(self, system: Model, design: Sequence[str], values: Mapping[str, float],
                 fold: tuple[np.ndarray, Sequence[str], str] | None, random: Mapping[str, Distribution] | None = None,
                 force: str | None = None):
        self.system, self.design, self.values = system, list(design), dict(values)
        self.force = force  # the force that opens a lock on stops
        self.reactions = stop_reactions(system)
        self.rest: np.ndarray | None = None  # the last lock at rest on its stops: the next preload starts there
        self.fold = fold  # (x, states, vary) of the fold followed by fold_load, updated as the design moves
        self.random = dict(random or {})
        self.u_star: dict[str | None, np.ndarray] = {}  # the last design point of each limit state: the next FORM starts there
        self.unlock_x: np.ndarray | None = None
        self.cache: dict[tuple[float, ...], dict[str, tuple[float, np.ndarray]]] = {}
        self.evaluations = 0

    def at(self, z: np.ndarray, names: Sequence[str]) -> dict[str, tuple[float, np.ndarray]]:
        key = tuple(float(v) for v in z)
        got = self.cache.setdefault(key, {})
        missing = [n for n in names if n not in got]
        if missing:
            self.evaluations += 1
            vals = {**self.values, **dict(zip(self.design, key))}
            for n in missing:
                got[n] = self._one(n, vals)
        return got

    def _one(self, name: str, vals: dict[str, float]) -> tuple[float, np.ndarray]:
        where = ", ".join(f"{k} = {v:.6g}" for k, v in vals.items() if k in self.design)
        if name in self.design:
            return vals[name], np.array([1.0 if n == name else 0.0 for n in self.design])
        if name in self.reactions:
            return self._preload(name, vals, where)
        if name in self.system.names:
            return vals.get(name, self.system.variable(name).value), np.zeros(len(self.design))
        try:
            if name == BETA:
                return self._beta(vals)
            s = self._sensitivity(name, vals)
        except ConvergenceError as exc:
            raise InputError(name, f"not found at {where}: {exc}") from None
        return s.value, np.array([s[n] for n in self.design])

    def _preload(self, name: str, vals: dict[str, float], where: str) -> tuple[float, np.ndarray]:
        """A stop's reaction at rest (all stops held) and its gradient over the design."""
        from ._stop_quantities import preload_sensitivity

        try:
            s = preload_sensitivity(self.system, vals, name, self.design, guess=self.rest)
        except ConvergenceError:
            try:  # from the description's configuration instead of the last design's
                s = preload_sensitivity(self.system, vals, name, self.design)
            except ConvergenceError as exc:
                raise InputError(name, f"no lock at rest on the stops at {where}: {exc}") from None
        self.rest = s.x
        return s.value, np.array([s[n] for n in self.design])

    def _beta(self, vals: dict[str, float]) -> tuple[float, np.ndarray]:
        """FORM's reliability index of the downlock force at this design, and its gradient over the design.

        A lock on stops fails when any stop leaves its stop: the limit state is the smallest of the stops' reactions
        at rest (a series system), its gradient that of the smallest."""
        from .reliability import Variables, downlock_limit_state

        names = list(self.random)
        shift = [vals[n] - d.centre if n in self.design else 0.0 for n, d in self.random.items()]
        fixed = {k: v for k, v in vals.items() if k not in self.random}
        variables = Variables(names, list(self.random.values()), shift)
        wrt = list(dict.fromkeys([*names, *self.design]))
        if not self.reactions:
            return self._form(None, downlock_limit_state(self.system, names, fixed), variables, fixed,
                              lambda at: downlock_sensitivity(self.system, wrt, at))
        from ._stop_quantities import preload_sensitivity

        if self.rest is None:  # FORM's points may leave the stops (negative reactions): they start from the design's rest
            where = ", ".join(f"{k} = {v:.6g}" for k, v in vals.items() if k in self.design)
            self._preload(next(iter(self.reactions)), vals, where)

        def weakest(at: Mapping[str, float], params: Sequence[str]) -> Sensitivity:
            """The smallest stop reaction at rest at ``at``, differentiated by ``params``."""
            return min((preload_sensitivity(self.system, at, r, params, guess=self.rest) for r in self.reactions),
                       key=lambda q: q.value)

        def limit(x: np.ndarray) -> tuple[float, np.ndarray]:
            s = weakest({**fixed, **dict(zip(names, map(float, x)))}, names)
            return s.value, np.array([s[n] for n in names])

        return self._form("stops", limit, variables, fixed, lambda at: weakest(at, wrt))

    def _form(self, key: str | None, limit: LimitState, variables: Variables, fixed: Mapping[str, float],
              sensitivity: Callable[[dict[str, float]], Sensitivity]) -> tuple[float, np.ndarray]:
        """FORM of one limit state (warm-started from its last design point, ``key``) and d beta / d design."""
        from .reliability import form

        p = form(limit, variables)
        if key in self.u_star:
            # a curved g = 0 has several local design points (the nose gear's F = 0 is U-shaped in (l_sp1, LU)): the
            # one found from the last design point counts only when nearer the mean than the one found from the mean
            try:
                warm = form(limit, variables, u0=self.u_star[key])
            except ConvergenceError:
                warm = p
            if np.linalg.norm(warm.u) < np.linalg.norm(p.u):
                p = warm
        self.u_star[key] = p.u
        at = {**fixed, **dict(zip(variables.names, p.x))}
        # a designed toleranced value moves x itself (dx/dd = 1): its derivative is dg/dx
        s = sensitivity(at)
        return p.beta, np.array([s[n] for n in self.design]) / float(np.linalg.norm(p.grad_u))

    def _sensitivity(self, name: str, vals: dict[str, float]) -> Sensitivity:
        system = self.system.with_values(vals)  # the model at this design: what is written in its parameters follows
        if name == "downlock_force":
            return downlock_sensitivity(system, self.design, vals)
        if name == "fold_load":
            if self.fold is None:
                raise InputError("fold_load", "needs a start fold (a point labelled LP of a branch)")
            from ..continuation import move_point

            x, states, vary = self.fold
            # followed from the last design to this one as a fold (never re-polished blindly: it could land on
            # the other fold); PointLost in one line when it ends on the way (past a cusp)
            at = {k: v for k, v in vals.items() if k not in (*states, vary)}
            moved = move_point(system, x, at, solved=[*states, vary], vary=vary, states=states, name="the fold")
            s = fold_sensitivity(system, moved.x, states, vary, self.design, null_vector=moved.v)
            assert s.x is not None  # a fold's sensitivity carries the polished fold
            self.fold = (s.x, states, vary)  # followed: the next design starts from here
            return s
        return self._unlock(vals)

    def _unlock(self, vals: dict[str, float]) -> Sensitivity:
        from ..continuation import choose_unknowns
        from .downlock import downlock_condition, downlock_point
        from .unlock import unlock_folds

        system = self.system.with_values(vals)  # the model at this design (a stop's limit, the downlock hold)
        if self.reactions:
            from ._stop_quantities import stop_unlock_sensitivity
            from .stop_lock import lock_force

            return stop_unlock_sensitivity(system, vals, lock_force(system, self.force), self.design)
        hold, force = downlock_condition(system)
        x = downlock_point(system, vals, hold=hold, force=force)
        folds = unlock_folds(system, x, force, released=tuple(hold), stability=False)
        where = ", ".join(f"{k} = {v:.6g}" for k, v in vals.items() if k in self.design)
        if folds.above is None:
            raise InputError("unlock_force", f"no unlock fold at {where}: {'; '.join(folds.notes)}")
        lens = choose_unknowns(system, exclude=[force])
        return fold_sensitivity(system, folds.above.x, lens, force, self.design,
                                null_vector=folds.above.null_vector)


def _force_unit(system: Model, q: _Quantities, name: str) -> str:
    """The unit of the quantity ``name`` (``downlock_force``, ``unlock_force``): its force parameter's, which may
    be a moment (N m) or written in other units; the model's force unit (``"N"`` in SI) when it names no such
    force."""
    from .downlock import downlock_condition
    from .stop_lock import lock_force

    try:
        force = lock_force(system, q.force) if name == "unlock_force" and q.reactions else downlock_condition(system)[1]
        return system.variable(force).unit
    except (InputError, KeyError):
        return units_of(system).label("N")


def optimize(system: Model, objective: str, bounds: Mapping[str, tuple[float, float]], *,
             maximize: bool = False, constraints: Sequence[Constraint] = (), values: Mapping[str, float] | None = None,
             fold: tuple[np.ndarray, Sequence[str], str] | None = None, max_iter: int = 100,
             tol: float = 1e-10, random: Mapping[str, Distribution] | None = None, starts: int = 1,
             force: str | None = None) -> OptimumResult:
    """Minimise (or maximise) ``objective`` over the parameters of ``bounds`` subject to ``constraints``.

    Parameters
    ----------
    system:
        The model.
    objective:
        ``"downlock_force"``, ``"unlock_force"``, ``"fold_load"`` or a parameter's name; on a model with
        stops also a stop's reaction ``R_NAME``: its preload at rest (all stops held at their limits).
    bounds:
        ``{parameter: (low, high)}`` (SI): the design variables.
    maximize:
        Maximise instead of minimise.
    constraints:
        :class:`Constraint` objects on the same quantities.
    values:
        Other parameter values (SI); the design starts at the model's values clipped into the bounds.
    fold:
        ``(x, states, vary)``: the start fold followed by ``fold_load`` (e.g. a branch's ``LP``:
        ``(p.x, p.info["unknowns"], p.info["vary"])``).
    max_iter, tol:
        SLSQP's iteration limit and tolerance (on the scaled objective).
    random:
        ``{parameter: Distribution}``: the tolerances of a ``P(not locking)`` constraint (a
        design parameter among them is the nominal value its distribution moves with).
    starts:
        SLSQP finds a local optimum: with ``starts`` = n > 1 it also starts from the n^d points
        of an even grid over the bounds (corners included) and keeps the best feasible optimum.
    force:
        The force that opens a lock on stops, for its ``unlock_force`` (default the model's downlock
        force, else ``F``). A ``stop_preload`` constraint stands for one on each stop's reaction.

    Returns an :class:`OptimumResult`. Raises :class:`InputError` for an unknown quantity, a
    design name that is not a parameter, empty bounds, or a quantity that does not exist at
    a design the optimiser tried (the message says where).
    """
    # longer than 60 lines: the SLSQP objective and constraints are closures over the scaled problem
    # (bounds, scales, the quantities' cache) set up here, and the multi-start loop uses them all
    from scipy.optimize import minimize

    design = list(bounds)
    if not design:
        raise InputError("design", "give at least one design parameter with its bounds")
    valid = (*QUANTITIES, *system.parameter_names)
    constraints = _stop_constraints(system, _reliability_constraints(system, constraints, random))
    if objective == "stop_preload":
        reactions = ", ".join(stop_reactions(system)) or "none"
        raise InputError("stop_preload", f"as an objective name one stop's reaction: {reactions}")
    for name in (objective, *(c.quantity for c in constraints if c.quantity != BETA)):
        if name not in valid:
            raise InputError(name, f"not a quantity; valid: {', '.join(valid)}"
                                   + (f" ({NOT_LOCKING} only in a constraint)" if name == NOT_LOCKING else ""))
    for n in design:
        if system.variable(n).kind != "parameter" or n in stop_reactions(system):
            raise InputError(n, "design variables must be parameters (not a stop's reaction); valid: "
                                + ", ".join(system.parameter_names))
        low, high = bounds[n]
        if not (math.isfinite(low) and math.isfinite(high) and low < high):
            raise InputError(n, f"needs finite bounds LO < HI, got {low:g}:{high:g}")
    lo = np.array([bounds[n][0] for n in design])
    hi = np.array([bounds[n][1] for n in design])
    base = system.vector(values or {})
    z0 = np.clip(np.array([base[system.index(n)] for n in design]), lo, hi)
    q = _Quantities(system, design, values or {}, fold, random, force)
    names = list(dict.fromkeys([objective, *(c.quantity for c in constraints)]))
    sign = -1.0 if maximize else 1.0

    def phys(t: np.ndarray) -> np.ndarray:
        z: np.ndarray = lo + (hi - lo) * np.asarray(t, float)  # (NumPy's stubs type this product as Any)
        return z

    start = q.at(z0, names)
    f_scale = max(abs(start[objective][0]), 1e-12)
    g_scale = [max(abs(c.bound), abs(start[c.quantity][0]), 1e-12) for c in constraints]

    def fun(t: np.ndarray) -> tuple[float, np.ndarray]:
        v, g = q.at(phys(t), names)[objective]
        return sign * v / f_scale, sign * g * (hi - lo) / f_scale

    def cons(i: int, c: Constraint) -> Inequality:
        side = 1.0 if c.sense == ">=" else -1.0

        def value(t: np.ndarray) -> float:
            return side * (q.at(phys(t), names)[c.quantity][0] - c.bound) / g_scale[i]

        def jac(t: np.ndarray) -> np.ndarray:
            g: np.ndarray = side * q.at(phys(t), names)[c.quantity][1] * (hi - lo) / g_scale[i]
            return g

        return {"type": "ineq", "fun": value, "jac": jac}

    slsqp = [cons(i, c) for i, c in enumerate(constraints)]
    res, lost = None, None
    for t0 in start_points(z0, lo, hi, starts):
        try:
            r = minimize(fun, t0, jac=True, method="SLSQP", bounds=[(0.0, 1.0)] * len(design), constraints=slsqp,
                         options={"maxiter": max_iter, "ftol": tol})
        except InputError as exc:
            lost = exc  # from this start the optimiser went where a quantity does not exist: that start is lost
            continue
        if res is None or better(r, res, slsqp):
            res = r
    if res is None:
        assert lost is not None
        raise lost
    t = np.clip(res.x, 0.0, 1.0)
    z = phys(t)
    at = q.at(z, names)
    active = multipliers(design, t, lo, hi, at, objective, constraints, g_scale)
    units = {n: system.variable(n).unit for n in design}
    units.update({n: (_force_unit(system, q, n) if n in QUANTITIES else "" if n == BETA else system.variable(n).unit)
                  for n in names})
    if fold is not None and "fold_load" in names and q.fold is not None:
        units["fold_load"] = system.variable(q.fold[2]).unit
    quantities = {n: float(at[n][0]) for n in names}
    if BETA in quantities:
        from scipy.stats import norm

        quantities[NOT_LOCKING] = float(norm.cdf(-quantities[BETA]))
    violated = [f"{constraints[i]} ({constraints[i].quantity} = {quantities[constraints[i].quantity]:.6g})"
                for i in unmet(slsqp, t)]
    return OptimumResult({n: float(v) for n, v in zip(design, z)}, objective, float(at[objective][0]),
                         quantities, active, int(res.nit), q.evaluations, bool(res.success), str(res.message), units,
                         violated)


def _stop_constraints(system: Model, constraints: Sequence[Constraint]) -> list[Constraint]:
    """``stop_preload >= b`` as ``R_NAME >= b`` for each stop of the model (the lock rests on all of them)."""
    reactions = stop_reactions(system)
    out = []
    for c in constraints:
        if c.quantity != "stop_preload":
            out.append(c)
        elif not reactions:
            raise InputError("constraint", f"'{c}': model '{system.name}' has no stops (declare [stops.NAME])")
        else:
            out += [Constraint(r, c.sense, c.bound) for r in reactions]
    return out


def _reliability_constraints(system: Model, constraints: Sequence[Constraint],
                             random: Mapping[str, Distribution] | None) -> list[Constraint]:
    """``P(not locking) <= p`` as ``beta(not locking) >= Phi^-1(1 - p)``; the distributions checked."""
    from scipy.stats import norm

    out = []
    for c in constraints:
        if c.quantity != NOT_LOCKING:
            out.append(c)
            continue
        if not random:
            raise InputError("dist", f"'{c}' needs the tolerances: give each random parameter's distribution "
                                     "(--dist NAME=normal:MEAN:SD)")
        out.append(Constraint(BETA, ">=" if c.sense == "<=" else "<=", float(norm.isf(c.bound))))
    for n in random or {}:
        if system.variable(n).kind != "parameter":
            raise InputError(n, f"only parameters can have a distribution; valid: {', '.join(system.parameter_names)}")
    return out


# the design map of an optimum builds on this module (_optimum_map imports it): imported on first use
__getattr__, __dir__ = lazy_exports(__package__, dict.fromkeys(["OptimumMap", "optimum_map"], "_optimum_map"), globals())
