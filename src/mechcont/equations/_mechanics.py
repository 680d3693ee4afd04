"""The physical mechanism behind an equation system: coordinates, constraints, forces, masses.

A :class:`MechanicalModel` is what both physical stability and time simulation need:

* generalised coordinates ``q`` (planar: x, y, theta per body), a subset of the
  system's variables;
* holonomic constraints ``Phi(q, p) = 0``;
* generalised applied forces ``Q(q, qdot, p)`` (gravity, springs, dampers, loads);
* the mass matrix ``M(q, p)``.

Static equilibrium is ``Q - Phi_q^T lambda = 0, Phi = 0`` (lambda: joint reactions).
Stability (see :meth:`MechanicalModel.stability`) uses the tangent stiffness
``K = -dQ/dq + sum_k lambda_k Hess(Phi_k)`` reduced to the null space of ``Phi_q``: the
constraint-curvature term is what hand-made codes forget.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from . import _cache, _codegen, _deferred, _stability
from ._cache_key import expr_text
from ._codegen import CompiledFunction, compile_scattered, compile_values, derivative_entries, engine_arguments, is_smooth
from ._layout import _flat, _Part, _StaticsLayout  # noqa: F401 (_StaticsLayout: pickles of compiled groups name it here)
from ._stability import StabilityResult, constraint_rank  # noqa: F401 (public here too)
from ._velocity_names import velocity_name

if TYPE_CHECKING:
    import symengine as se
    import sympy as sp

__all__ = ["MechanicalModel", "StabilityResult", "velocity_symbol"]


def velocity_symbol(name: str) -> sp.Symbol:
    """The symbol standing for the time derivative of coordinate ``name`` (``name_dot``)."""
    import sympy as sp

    return sp.Symbol(velocity_name(name), real=True)


def _velocity_product_forces(keys: Sequence[tuple[int, int]], m_exprs: Sequence[se.Basic], qs: Sequence[se.Symbol],
                             qd: Sequence[se.Symbol]) -> list[se.Basic]:
    """SymEngine expressions of ``h(q, qdot) = -(Mdot qdot - 1/2 d(qdot^T M qdot)/dq)``, the velocity-product
    terms of Lagrange's equations for ``T = 1/2 qdot^T M(q) qdot`` (``keys``: the positions of ``M``'s
    non-zero entries ``m_exprs``, both triangles). Component ``i`` is ``-sum_jk c_ijk qdot_j qdot_k`` with
    the Christoffel symbols ``c_ijk = dM_ij/dq_k - 1/2 dM_jk/dq_i``: centrifugal and Coriolis forces of a
    frame away from the centre of gravity, ``omega x J omega`` of a body in Euler parameters, and those of
    a reduced form's ``J^T M J``. Only the entries that depend on ``q`` contribute."""
    import symengine as se

    h = [se.Integer(0)] * len(qs)
    for (n, k), d in derivative_entries(m_exprs, qs, True):
        i, j = keys[n]
        h[i] = h[i] - d * qd[k] * qd[j]
        h[k] = h[k] + d * qd[i] * qd[j] / 2
    return h


class MechanicalModel:
    """Coordinates, constraints, applied forces and masses of a mechanism, compiled.

    Parameters
    ----------
    names:
        All variable names of the owning :class:`EquationSystem` (numeric vectors ``x``
        are ordered like this).
    coordinates:
        Names of the generalised coordinates ``q`` (a subset of ``names``).
    constraints:
        SymPy expressions ``Phi_k`` that vanish when the mechanism is assembled.
    forces:
        Generalised applied forces ``Q_i`` conjugate to each coordinate; may use the
        velocity symbols ``velocity_symbol(q_i)`` (dampers). At rest they are zero.
    mass_matrix:
        SymPy matrix ``M`` (n_q x n_q).
    constraint_names:
        Optional name of each constraint (for reports); None when the constraints are the
        system's rows that follow the equilibrium rows.
    potential:
        Optional potential energy ``V(q, p)`` (J) of the conservative part of ``forces``
        (``forces = -dV/dq + ...``): gravity, springs, conservative loads. The time simulation's
        energy audit evaluates it (:meth:`potential_energy`); None when the model declares none.
    state_rates:
        Optional first-order element states (a tyre's lateral deflection): state variable name
        (a variable of the system, not a coordinate) -> its rate ``ds/dt`` as an expression in the
        variables and the velocity symbols. The static system holds each state at its steady state
        (its rate at rest is one of the system's rows); the time simulation and the dynamic analyses
        integrate or linearise it with the coordinates. ``forces`` may use the states.
    """

    def __init__(self, names: Sequence[str], coordinates: Sequence[str], constraints: Sequence[sp.Expr],
                 forces: Sequence[sp.Expr], mass_matrix: sp.Matrix, constraint_names: Sequence[str] | None = None,
                 potential: sp.Expr | None = None, state_rates: Mapping[str, sp.Expr] | None = None) -> None:
        import sympy as sp

        self.names = tuple(names)
        self.constraint_names = None if constraint_names is None else tuple(constraint_names)
        self.coordinates = tuple(coordinates)
        missing = [c for c in self.coordinates if c not in self.names]
        if missing:
            raise InputError(missing[0], "coordinate is not a variable of the system")
        self.q_index = np.array([self.names.index(c) for c in self.coordinates])
        nq = len(self.coordinates)
        self.constraints = [sp.sympify(c, strict=True) for c in constraints]
        self.forces = [sp.sympify(f, strict=True) for f in forces]
        self.mass_matrix = sp.Matrix(mass_matrix)
        self.potential = None if potential is None else sp.sympify(potential, strict=True)
        self.has_potential = potential is not None
        if len(self.forces) != nq:
            raise InputError("forces", f"need one generalised force per coordinate ({nq}), got {len(self.forces)}")
        if self.mass_matrix.shape != (nq, nq):
            raise InputError("mass_matrix", f"must be {nq}x{nq}, got {self.mass_matrix.shape}")
        syms = [sp.Symbol(n, real=True) for n in self.names]
        qs = [syms[i] for i in self.q_index]
        qd = [velocity_symbol(c) for c in self.coordinates]
        allowed = set(syms) | set(qd)
        for e in [*self.constraints, *self.forces, *self.mass_matrix, *([self.potential] if potential is not None else [])]:
            bad = e.free_symbols - allowed
            if bad:
                raise InputError(str(sorted(map(str, bad))[0]), "used in the mechanical model but not a variable")
        self.element_states = tuple(state_rates or ())
        self.state_rates = [sp.sympify(r, strict=True) for r in (state_rates or {}).values()]
        for n in self.element_states:
            if n not in self.names or n in self.coordinates:
                raise InputError(n, "an element state must be a variable of the system and not a coordinate")
        for e in self.state_rates:
            bad = e.free_symbols - allowed
            if bad:
                raise InputError(str(sorted(map(str, bad))[0]), "used in an element state's rate but not a variable")
        self._syms, self._qs, self._qd = syms, qs, qd
        self.n_constraints = len(self.constraints)
        #: Positions in ``x`` of the element states (in :attr:`element_states`' order).
        self.s_index = np.array([self.names.index(n) for n in self.element_states], dtype=np.intp)

    # Compiled functions, in three groups each compiled (or loaded from the disk cache) on
    # first use of one of its members: assembly needs only the kinematics, stability the
    # statics, time simulation the dynamics.
    _GROUPS = {"_phi": "kinematics", "_phi_q": "kinematics", "_Q": "kinematics",
               "_statics": "statics", "_statics_layout": "statics", "_dQdq": "statics", "_phi_hess": "statics",
               "_gamma": "dynamics", "_dQdqd": "dynamics", "_M": "dynamics", "_inertial": "dynamics",
               "_V": "dynamics", "_rates": "states", "_rates_jac": "states", "_dQds": "states"}
    _COMPILED = tuple(_GROUPS)
    # their types (declared only: each is missing from the instance until its group is made, see __getattr__)
    _phi: CompiledFunction
    _phi_q: CompiledFunction
    _Q: CompiledFunction
    _statics: CompiledFunction
    _statics_layout: _StaticsLayout
    _dQdq: _Part
    _phi_hess: _Part
    _gamma: CompiledFunction
    _dQdqd: CompiledFunction
    _M: CompiledFunction
    _inertial: CompiledFunction
    _V: CompiledFunction
    _rates: CompiledFunction
    _rates_jac: CompiledFunction
    _dQds: CompiledFunction

    #: The symbolic attributes, pickled apart (see :mod:`._deferred`).
    _SYMBOLIC = ("constraints", "forces", "mass_matrix", "potential", "state_rates", "_syms", "_qs", "_qd")

    def __getattr__(self, name: str) -> Any:
        # only reached for missing attributes: the compiled functions, built on first use, and
        # a loaded model's symbolic attributes
        group = MechanicalModel._GROUPS.get(name)
        if group is None:
            if name.startswith("__"):
                raise AttributeError(name)
            return _deferred.materialize(self, name)
        self._compile_group(group)
        return self.__dict__[name]

    def _compile(self) -> None:
        """Compile (or load) every group: Phi, Phi_q, Q; the statics; gamma, dQ/dqdot, M."""
        self.compile_all(later=False)

    def compile_all(self, later: bool) -> None:
        """Compile (or load) every group; with ``later``, keep the disk-cache key of each group not compiled
        yet instead (a copy loaded from the cache compiles or loads it on first use, by that key)."""
        for group in ("kinematics", "statics", "dynamics", *(("states",) if self.element_states else ())):
            if not later:
                self._compile_group(group)
            elif not self._has_group(group) and group not in self.__dict__.get("_group_keys", {}):
                self.__dict__.setdefault("_group_keys", {})[group] = _cache.cache_key(self._group_key_parts(group))

    def _has_group(self, group: str) -> bool:
        # all: a model pickled before a member was added builds it
        return all(n in self.__dict__ for n, g in MechanicalModel._GROUPS.items() if g == group)

    def _group_key_parts(self, group: str) -> list[str]:
        return ["mechanics", group, self._content_digest()]

    def _compile_group(self, group: str) -> None:
        if self._has_group(group):
            return
        names = [n for n, g in MechanicalModel._GROUPS.items() if g == group]

        def valid(obj: object) -> bool:
            return isinstance(obj, dict) and set(obj) == set(names)

        code = _cache.cached(lambda: self._group_key_parts(group), lambda: self._build_group(group), valid,
                             key=self.__dict__.get("_group_keys", {}).get(group))
        self.__dict__.update(code)

    def _content_digest(self) -> str:
        """Hash of the compiled form (for the disk cache): positional arguments, SymEngine expressions."""
        digest = self.__dict__.get("_digest")
        if digest is None:
            import hashlib

            s = self._symbolic()
            h = hashlib.sha256()
            parts = [f"{len(s['args'])} {len(self.coordinates)}", " ".join(map(str, self.q_index)),
                     *(expr_text(e) for e in s["cons"]), "forces",
                     *(expr_text(e) for e in s["forces"]), "mass",
                     *(f"{k}:{expr_text(e)}" for k, e in zip(*self._mass_entries())), "potential",
                     *(expr_text(e) for e in s["potential"])]
            if self.element_states:  # only then: a model without states keeps its cached code
                parts += ["states", " ".join(self.element_states), *(expr_text(e) for e in s["rates"])]
            for p in parts:
                b = p.encode()
                h.update(len(b).to_bytes(8, "little") + b)
            digest = self.__dict__["_digest"] = h.hexdigest()
        return digest

    def _mass_entries(self) -> tuple[list, list]:
        """Indices and SymEngine expressions (positional arguments) of the non-zero entries of M."""
        s = self._symbolic()
        if "mass" not in s:
            M = self.mass_matrix.todok()
            keys = sorted(k for k, v in M.items() if v != 0)
            s["mass"] = (keys, engine_arguments(self._syms + self._qd, [M[k] for k in keys])[1])
        return s["mass"]

    def _symbolic(self) -> dict:
        """The SymEngine forms shared by the groups (positional arguments, Phi_q entries), once."""
        sym = self.__dict__.get("_engine")
        if sym is None:
            nq, ns, nc = len(self.coordinates), len(self._syms), len(self.constraints)
            V = getattr(self, "potential", None)  # None also for a model pickled before potentials were kept
            nv = 0 if V is None else 1
            args, exprs = engine_arguments(self._syms + self._qd, [*self.constraints, *self.forces,
                                                                   *([] if V is None else [V]),
                                                                   *(self.state_rates if self.element_states else [])])
            qs = [args[i] for i in self.q_index]
            cons, forces, potential = exprs[:nc], exprs[nc:nc + nq], exprs[nc + nq:nc + nq + nv]
            sym = self.__dict__["_engine"] = {"args": args, "qs": qs, "qd": args[ns:ns + nq], "cons": cons,
                                              "forces": forces, "potential": potential,
                                              "rates": exprs[nc + nq + nv:], "ss": [args[i] for i in self.s_index]}
        return sym

    def _phi_q_entries(self) -> tuple[list, list[bool]]:
        """Non-zero entries of Phi_q (SymEngine) and which constraints differentiate in closed form."""
        s = self._symbolic()
        if "phi_q" not in s:
            smooth = [is_smooth(c) for c in s["cons"]]
            s["phi_q"] = (derivative_entries(s["cons"], s["qs"], smooth), smooth)
        return s["phi_q"]

    def _build_group(self, group: str) -> dict:
        """Differentiate (exactly, in SymEngine) and compile one group; see :meth:`_compile_group`."""
        s = self._symbolic()
        args, qs, qd, cons, forces = (s[k] for k in ("args", "qs", "qd", "cons", "forces"))
        phi_q, smooth = self._phi_q_entries()
        nq, nc = len(self.coordinates), len(cons)
        if group == "kinematics":
            return {"_phi": compile_values(args, cons), "_Q": compile_values(args, forces),
                    "_phi_q": compile_scattered(args, _flat(phi_q, (nc, nq)), [d for _, d in phi_q], (nc, nq))}
        if group == "states":
            # the element states' rates r(q, qdot, s) and their exact derivatives d r/d(q, qdot, s); dQ/ds
            rates, ss, n_s = s["rates"], s["ss"], len(self.element_states)
            drs = derivative_entries(rates, [*qs, *qd, *ss])
            dqs = derivative_entries(forces, ss)
            return {"_rates": compile_values(args, rates),
                    "_rates_jac": compile_scattered(args, _flat(drs, (n_s, 2 * nq + n_s)), [d for _, d in drs],
                                                    (n_s, 2 * nq + n_s)),
                    "_dQds": compile_scattered(args, _flat(dqs, (nq, n_s)), [d for _, d in dqs], (nq, n_s))}
        if group == "statics":
            # Hessians of the constraints, for the curvature term sum_k lambda_k Hess(Phi_k)
            hess = [((k, i, j), d2) for (k, i), d in phi_q for (_, j), d2 in derivative_entries([d], qs, smooth[k])]
            dqdq = derivative_entries(forces, qs)
            # everything stability needs at rest in one compiled call: the non-zero entries of
            # Phi_q, then Q, the non-zero entries of dQ/dq and of the constraint Hessians
            exprs = [*(d for _, d in phi_q), *forces, *(d for _, d in dqdq), *(d for _, d in hess)]
            h = np.array([k for k, _ in hess], dtype=np.intp).reshape(-1, 3)
            a_pos, dq_pos, hess_ij = _flat(phi_q, (nc, nq)), _flat(dqdq, (nq, nq)), h[:, 1] * nq + h[:, 2]
            dense = nc * nq + nq + nq * nq + nc * nq * nq <= _codegen.DENSE_MAX
            layout = _StaticsLayout(nc, nq, a_pos, dq_pos, h[:, 0], hess_ij, dense)
            if dense:
                statics = compile_scattered(args, layout.positions(), exprs, (layout.size,))
                parts = {"_dQdq": _Part(statics, layout.dq_slice, None, (nq, nq)),
                         "_phi_hess": _Part(statics, layout.hess_slice, None, (nc, nq, nq))}
            else:
                statics = compile_values(args, exprs)
                parts = {"_dQdq": _Part(statics, layout.dq_slice, dq_pos, (nq, nq)),
                         "_phi_hess": _Part(statics, layout.hess_slice, _flat(hess, (nc, nq, nq)), (nc, nq, nq))}
            return {"_statics": statics, "_statics_layout": layout, **parts}
        # dynamics. gamma = -(d/dq (Phi_q qdot)) qdot: right-hand side of Phi_q qddot = gamma
        import symengine as se

        rows = [se.Integer(0)] * nc
        for (k, i), d in phi_q:
            rows[k] = rows[k] + d * qd[i]
        gamma = [se.Integer(0)] * nc
        for (k, j), d in derivative_entries(rows, qs, smooth):
            gamma[k] = gamma[k] - d * qd[j]
        dqd = derivative_entries(forces, qd)
        keys, m_exprs = self._mass_entries()
        return {"_gamma": compile_values(args, gamma),
                "_dQdqd": compile_scattered(args, _flat(dqd, (nq, nq)), [d for _, d in dqd], (nq, nq)),
                "_M": compile_scattered(args, _flat([(k, None) for k in keys], (nq, nq)), m_exprs, (nq, nq)),
                "_inertial": compile_values(args, _velocity_product_forces(keys, m_exprs, qs, qd)),
                "_V": compile_values(args, s["potential"] or [se.Integer(0)])}

    def __getstate__(self) -> dict[str, Any]:
        """Picklable state: every compiled group built so far, and the symbolic model as an inner
        pickle (unpickled on first use: stability and simulation need only the compiled code)."""
        state = {k: v for k, v in self.__dict__.items() if k != "_engine" and k not in self._SYMBOLIC}
        if _deferred.DEFERRED not in state:
            state[_deferred.DEFERRED] = _deferred.pack({k: getattr(self, k) for k in self._SYMBOLIC})
        state.setdefault("n_constraints", len(self.constraints))
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self.__dict__.setdefault("element_states", ())  # pickled before element states existed
        self.__dict__.setdefault("s_index", np.zeros(0, dtype=np.intp))
        if "n_constraints" not in state and "constraints" in state:  # pickled before the count was kept
            self.__dict__["n_constraints"] = len(state["constraints"])

    # -- numeric evaluation (x: full variable vector, qdot: coordinate velocities) ---------
    def _args(self, x: np.ndarray, qdot: np.ndarray | None = None) -> np.ndarray:
        if qdot is None:  # at rest: x then zeros (one allocation; this runs at every point of a branch)
            x = np.asarray(x, float)
            a = np.zeros(len(x) + len(self.coordinates))
            a[:len(x)] = x
            return a
        return np.concatenate([np.asarray(x, float), np.asarray(qdot, float)])

    def phi(self, x: np.ndarray, qdot: np.ndarray | None = None) -> np.ndarray:
        """Constraint residuals Phi (units of each constraint, usually m)."""
        return self._phi(self._args(x, qdot))

    def phi_q(self, x: np.ndarray) -> np.ndarray:
        """Constraint Jacobian dPhi/dq, shape (n_constraints, n_q)."""
        return self._phi_q(self._args(x))

    def gamma(self, x: np.ndarray, qdot: np.ndarray) -> np.ndarray:
        """Right-hand side of the acceleration-level constraints Phi_q qddot = gamma."""
        return self._gamma(self._args(x, qdot))

    def applied_forces(self, x: np.ndarray, qdot: np.ndarray | None = None) -> np.ndarray:
        """Generalised applied forces Q(q, qdot) (N or N m per coordinate)."""
        return self._Q(self._args(x, qdot))

    def applied_forces_batch(self, X: np.ndarray, Qdot: np.ndarray) -> np.ndarray:
        """:meth:`applied_forces` at every row of ``X`` (full vectors, (m, n_variables)) with the velocities
        ``Qdot`` ((m, n_q)): array (m, n_q), one call into the compiled code."""
        return self._Q.batch(np.hstack([np.asarray(X, float), np.asarray(Qdot, float)]))

    def _batch_args(self, X: np.ndarray, Qdot: np.ndarray | None = None) -> np.ndarray:
        X = np.asarray(X, float)
        if Qdot is None:
            return np.hstack([X, np.zeros((len(X), len(self.coordinates)))])
        return np.hstack([X, np.asarray(Qdot, float)])

    def phi_batch(self, X: np.ndarray) -> np.ndarray:
        """:meth:`phi` at every row of ``X`` ((m, n_variables)): array (m, n_constraints), one compiled call."""
        return self._phi.batch(self._batch_args(X))

    def phi_q_batch(self, X: np.ndarray) -> np.ndarray:
        """:meth:`phi_q` at every row of ``X``: array (m, n_constraints, n_q), one compiled call."""
        return self._phi_q.batch(self._batch_args(X))

    def motion_terms(self, x: np.ndarray, qdot: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """What the equations of motion need at ``x`` with the velocities ``qdot``, from one argument vector:
        ``(M, Q + inertial_forces, gamma, element_state_rates)`` (see those methods for units and shapes)."""
        a = self._args(x, qdot)
        r = np.asarray(self._rates(a), float).reshape(-1) if self.element_states else np.zeros(0)
        return self._M(a), self._Q(a) + self._inertial(a), self._gamma(a), r

    def motion_terms_batch(self, X: np.ndarray, Qdot: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`motion_terms` at every row of ``X`` with the velocities ``Qdot``: arrays (m, n_q, n_q),
        (m, n_q), (m, n_constraints), (m, n_s), one compiled call each."""
        a = self._batch_args(X, Qdot)
        m = len(a)
        r = self._rates.batch(a).reshape(m, -1) if self.element_states else np.zeros((m, 0))
        return self._M.batch(a), self._Q.batch(a) + self._inertial.batch(a), self._gamma.batch(a), r

    def acceleration_terms(self, x: np.ndarray, qdot: np.ndarray, drift: bool = True,
                           varying_mass: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray,
                                                               np.ndarray | None]:
        """What one constrained acceleration needs at ``x`` with the velocities ``qdot``, from one argument vector:
        ``(phi_q, gamma, phi, forces, mass)`` as :meth:`phi_q`, :meth:`gamma`, :meth:`phi` (None without ``drift``),
        :meth:`applied_forces` plus, with ``varying_mass``, :meth:`inertial_forces`, and :meth:`mass` (None without
        ``varying_mass``: a constant mass matrix is known and its inertial forces are zero). The same values as
        those methods, one argument vector instead of one per call."""
        a = self._args(x, qdot)
        forces = self._Q(a)
        if varying_mass:  # through the method, as everything that asks for them
            forces = forces + self.inertial_forces(x, qdot)
        return (self._phi_q(a), self._gamma(a), self._phi(a) if drift else None, forces,
                self._M(a) if varying_mass else None)

    def damping_matrix(self, x: np.ndarray, qdot: np.ndarray | None = None) -> np.ndarray:
        """-dQ/dqdot, shape (n_q, n_q) (N s/m)."""
        return -self._dQdqd(self._args(x, qdot))

    def mass(self, x: np.ndarray) -> np.ndarray:
        """Mass matrix M(q), shape (n_q, n_q) (kg, kg m^2)."""
        return self._M(self._args(x))

    def inertial_forces(self, x: np.ndarray, qdot: np.ndarray) -> np.ndarray:
        """Velocity-product (centrifugal, Coriolis, gyroscopic) generalised forces
        ``-(Mdot qdot - 1/2 d(qdot^T M qdot)/dq)`` (N or N m per coordinate), exact from the
        generated ``M(q)``; zero when ``M`` is constant (frames at the centres of gravity) or at rest.
        The equations of motion are ``M qddot = Q + inertial_forces + Phi_q^T lambda``."""
        return self._inertial(self._args(x, qdot))

    def element_state_rates(self, x: np.ndarray, qdot: np.ndarray | None = None) -> np.ndarray:
        """The element states' rates ``r(q, qdot, s)`` (each state's unit per second), in
        :attr:`element_states`' order; empty without states."""
        if not self.element_states:
            return np.zeros(0)
        return np.asarray(self._rates(self._args(x, qdot)), dtype=float).reshape(-1)

    def element_state_jacobians(self, x: np.ndarray,
                                qdot: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Exact ``(dr/dq, dr/dqdot, dr/ds, dQ/ds)`` at ``x`` (and ``qdot``, default at rest): the rates'
        derivatives, shapes (n_s, n_q) each of the first two and (n_s, n_s), and the generalised forces'
        derivative in the states, (n_q, n_s)."""
        nq, ns = len(self.coordinates), len(self.element_states)
        if not ns:
            return np.zeros((0, nq)), np.zeros((0, nq)), np.zeros((0, 0)), np.zeros((nq, 0))
        a = self._args(x, qdot)
        J = self._rates_jac(a)
        return J[:, :nq], J[:, nq:2 * nq], J[:, 2 * nq:], self._dQds(a)

    def potential_energy(self, x: np.ndarray) -> float:
        """Potential energy ``V`` (J) at the full variable vector ``x`` (0 when the model declares none,
        see :attr:`has_potential`)."""
        return float(self._V(self._args(x))[0])

    def _decompose(self, x: np.ndarray, rtol: float = 1e-10) -> tuple[np.ndarray | None, np.ndarray, np.ndarray, int]:
        """SVD of Phi_q: (U, singular values, V^T, rank) — shared by multipliers and Z."""
        A = self.phi_q(x)
        if A.shape[0] == 0:
            return None, np.zeros(0), np.eye(A.shape[1]), 0
        U, sv, Vt = np.linalg.svd(A)
        return U, sv, Vt, constraint_rank(A, sv, rtol)

    def multipliers(self, x: np.ndarray) -> np.ndarray:
        """Constraint reactions lambda solving Phi_q^T lambda = Q in the least-squares sense.

        With redundant constraints the minimum-norm solution is returned.
        """
        U, sv, Vt, r = self._decompose(x)
        if U is None:
            return np.zeros(0)
        Q = self.applied_forces(x)
        return U[:, :r] @ ((Vt[:r] @ Q) / sv[:r])

    def force_jacobian(self, x: np.ndarray) -> np.ndarray:
        """dQ/dq at rest, shape (n_q, n_q) (N/m, N m/rad): :meth:`tangent_stiffness` with zero multipliers is its
        negative, without forming the constraints' curvature term."""
        return self._dQdq(self._args(x))

    def tangent_stiffness(self, x: np.ndarray, multipliers: np.ndarray | None = None) -> np.ndarray:
        """K = -dQ/dq + sum_k lambda_k Hess(Phi_k) at rest, shape (n_q, n_q)."""
        lam = self.multipliers(x) if multipliers is None else np.asarray(multipliers)
        return self._statics_layout.stiffness(self._statics(self._args(x)), lam)

    def allowed_motions(self, x: np.ndarray, rtol: float = 1e-10) -> np.ndarray:
        """Orthonormal basis Z of the null space of Phi_q: the motions the joints allow."""
        _, _, Vt, r = self._decompose(x, rtol)
        return Vt[r:].T

    def stability(self, x: np.ndarray, rtol: float = 1e-9, held: np.ndarray | None = None) -> StabilityResult:
        """Physical stability of the equilibrium at ``x`` (see :func:`._stability.stability`)."""
        return _stability.stability(self, x, rtol, held)

    def count_unstable(self, X: np.ndarray, rtol: float = 1e-9) -> np.ndarray:
        """Number of unstable directions at every row of ``X`` (see :func:`._stability.count_unstable`)."""
        return _stability.count_unstable(self, X, rtol)
