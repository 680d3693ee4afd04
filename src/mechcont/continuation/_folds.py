"""Folds: exact location and two-parameter continuation (standard augmented system).

A fold (limit point) of equilibria in parameter ``p1`` satisfies, with ``G_s`` the
Jacobian with respect to the unknown states ``s``,

    G(s, p1, p2) = 0,    G_s v = 0,    (v^T v - 1) / 2 = 0,

(``2n + 1`` equations). With ``p2`` held this is square in ``(s, p1, v)`` and Newton
polishes a fold found by a sign change to machine precision. With ``p2`` free, it is
one more continuation problem for the same pseudo-arclength engine, whose solutions are
the fold curve in the ``(p1, p2)`` plane. Its Jacobian needs second derivatives of
``G``, contracted with ``v``: exact, from the system's generated Hessian.

A cusp (``CP``) is where the fold's quadratic coefficient ``a = w^T G_ss[v, v]``
changes sign (``w``: left null vector); the two folds of a hysteresis loop meet and
disappear there.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from ..equations import EquationSystem
from ..errors import InputError
from ._events import Event
from ._newton import newton_square
from ._problem import ContinuationProblem, choose_unknowns

__all__ = ["FoldProblem", "CuspEvent", "fold_quantities", "refine_fold"]


def _null_vectors(Js: np.ndarray, scale: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Right and left singular vectors of the smallest singular value of ``Js``.

    With ``scale`` (typical magnitudes of the states) the SVD is taken of ``Js D``: in
    mixed units (m, rad, N) the unscaled matrix can have several small singular values
    and the smallest need not belong to the fold. The right vector is returned unscaled,
    normalised to unit length.
    """
    if scale is None:
        u, _, vt = np.linalg.svd(Js)
        return vt[-1], u[:, -1]
    u, _, vt = np.linalg.svd(Js * scale)
    v = vt[-1] * scale
    return v / np.linalg.norm(v), u[:, -1]


def fold_quantities(system: EquationSystem, x: np.ndarray, state_idx: np.ndarray, param_index: int,
                    v: np.ndarray | None = None):
    """Right/left null vectors and the normalised quadratic coefficient at a fold.

    Returns ``(v, w, a)``: ``v`` spans ker G_s, ``w`` spans ker G_s^T, oriented so that
    ``w^T dG/dp1 > 0`` (non-zero at a fold: that is its transversality condition), and
    ``a = w^T G_ss[v, v] / |v|^2`` with ``|w| = 1``. With this orientation the sign of
    ``a`` says on which side of the fold in ``p1`` the two branches lie, and it changes
    sign exactly at a cusp.
    """
    J = system.jacobian(x)
    Js = J[:, state_idx]
    vs, w = _null_vectors(Js)
    if v is None:
        v = vs
    if w @ J[:, param_index] < 0:
        w = -w
    vf = np.zeros(len(x))
    vf[state_idx] = v
    Gvv = system.jacobian_derivative(x, vf)[:, state_idx] @ v
    a = float(w @ Gvv) / (v @ v)
    return v, w, a


def _fold_system(system, base, idx_vars, state_pos, c):
    """Residual and Jacobian of the fold system in unknowns U = (vars..., v).

    The null vector is normalised by |v| = 1 rather than by a fixed border c^T v = 1:
    along a long fold curve the null vector turns, and a fixed border would let |v|
    grow without bound (eating the arclength). ``c`` is kept for the interface.

    ``idx_vars``: full indices of the variable unknowns (states then parameters);
    ``state_pos``: positions within ``idx_vars`` of the states whose Jacobian must be
    singular.
    """
    nv = len(idx_vars)
    n = len(state_pos)
    state_idx = idx_vars[state_pos]

    def full(U):
        x = base.copy()
        x[idx_vars] = U[:nv]
        return x

    def evaluate(U):
        x = full(U)
        v = U[nv:]
        r, J = system.residual_and_jacobian(x)
        Js = J[:, state_idx]
        res = np.concatenate([r, Js @ v, [0.5 * (v @ v - 1.0)]])
        vf = np.zeros(len(x))
        vf[state_idx] = v
        H = system.jacobian_derivative(x, vf)
        out = np.zeros((2 * n + 1, nv + n))
        out[:n, :nv] = J[:, idx_vars]
        out[n:2 * n, :nv] = H[:, idx_vars]
        out[n:2 * n, nv:] = Js
        out[2 * n, nv:] = v
        return res, out

    def residual(U):
        x = full(U)
        v = U[nv:]
        r, J = system.residual_and_jacobian(x)
        return np.concatenate([r, J[:, state_idx] @ v, [0.5 * (v @ v - 1.0)]])

    def jacobian(U):
        return evaluate(U)[1]

    return full, residual, jacobian, evaluate


def refine_fold(system: EquationSystem, x: np.ndarray, states: Iterable[str], param: str, tol: float = 1e-11):
    """Polish an approximate fold in ``param`` with Newton on the square fold system.

    Returns ``(x, v)``: the full vector at the fold and the normalised null vector.
    Raises :class:`~mechcont.errors.ConvergenceError` if Newton fails.
    """
    states = list(states)
    idx_vars = np.array([system.index(n) for n in [*states, param]])
    state_pos = np.arange(len(states))
    Js = system.jacobian(x)[:, idx_vars[state_pos]]
    v0, _ = _null_vectors(Js, system.scales()[idx_vars[state_pos]])
    full, res, jac, _ = _fold_system(system, np.array(x, float), idx_vars, state_pos, v0)
    U0 = np.concatenate([np.asarray(x, float)[idx_vars], v0])
    scale = np.concatenate([system.scales()[idx_vars], np.ones(len(v0))])
    U, _ = newton_square(res, jac, U0, tol=tol, residual_tol=1e-10, max_iter=20, scale=scale)
    return full(U), U[len(idx_vars):]


class CuspEvent(Event):
    """Cusp (``CP``) on a fold curve: the quadratic coefficient of the fold changes sign."""

    label = "CP"

    def value(self, problem, state):
        return problem.quadratic_coefficient(state.u)


class FoldProblem(ContinuationProblem):
    """The fold curve of ``system`` in parameters ``(p1, p2)`` as a continuation problem.

    Unknowns ``u = (states..., p1, p2, v...)``; the continuation parameter (whose
    direction is chosen) is ``p2``.
    """

    def __init__(self, system: EquationSystem, x_fold: np.ndarray, p1: str, p2: str, states: Iterable[str],
                 v0: np.ndarray | None = None, scales=None):
        self.system = system.compile()
        states = list(states)
        for p in (p1, p2):
            if p in states:
                raise InputError(p, "is solved for; the two fold parameters must not be unknowns")
        if p1 == p2:
            raise InputError(p2, "the second parameter must differ from the fold's parameter")
        self.states = states
        self.p1, self.p2 = p1, p2
        self.idx_vars = np.array([system.index(n) for n in [*states, p1, p2]])
        self.state_idx = self.idx_vars[: len(states)]
        x_fold = np.asarray(x_fold, float)
        if v0 is None:
            v0, _ = _null_vectors(system.jacobian(x_fold)[:, self.state_idx], system.scales()[self.state_idx])
        v0 = np.asarray(v0, float) / np.linalg.norm(v0)
        self.c = v0
        self.base = x_fold.copy()
        self._full, self._res, self._jac, self._eval = _fold_system(system, self.base, self.idx_vars, np.arange(len(states)), v0)
        self.u0 = np.concatenate([x_fold[self.idx_vars], v0])
        self.names = (*states, p1, p2, *[f"v_{s}" for s in states])
        self.param_index = len(states) + 1
        sc = system.scales()
        for n, v in (scales or {}).items():
            sc[system.index(n)] = v
        self.scale = np.concatenate([sc[self.idx_vars], np.ones(len(states))])
        self.idx = self.idx_vars  # for messages

    def residual(self, u):
        return self._res(u)

    def jacobian(self, u):
        return self._jac(u)

    def evaluate(self, u):
        return self._eval(u)

    def full(self, u):
        return self._full(u)

    def quadratic_coefficient(self, u) -> float:
        """Normalised ``a = w^T G_ss[v, v]`` at the fold-curve point ``u``."""
        nv = len(self.idx_vars)
        return fold_quantities(self.system, self._full(u), self.state_idx, self.idx_vars[-2], u[nv:])[2]

    def test_functions(self):
        return [CuspEvent()]


def fold_states(system: EquationSystem, vary: str, hold=(), free=()) -> list[str]:
    """Unknown state names of a fold in ``vary`` (the lens of the equilibrium branch)."""
    return choose_unknowns(system, hold=hold, free=free, exclude=[vary])
