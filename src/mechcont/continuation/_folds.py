"""Fold curves: the folds of equilibria continued in two parameters, with their cusps (``CP``).

The fold curve in the ``(p1, p2)`` plane is continued by the same pseudo-arclength engine on
the minimally extended system ``G = 0, det(R G_s C) / N = 0`` in ``(s, p1, p2)`` alone
(:class:`FoldProblem` says why the null vector is not an unknown there; the exact location
of a single fold is :mod:`._fold_point`).

A cusp (``CP``) is where the fold's quadratic coefficient ``a = w^T G_ss[v, v]``
changes sign (``w``: left null vector); the two folds of a hysteresis loop meet and
disappear there.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any, Protocol

import numpy as np

from .. import _dense
from ..equations import EquationSystem
from ..errors import InputError
from ._events import Event, PointState
from ._fold_point import _SOLVER, _norm, _null_vectors, _oriented_coefficient, fold_scaling
from ._newton import residual_met
from ._problem import CompiledFold, CompiledModel, ContinuationProblem, choose_unknowns

__all__ = ["FoldProblem", "CuspEvent", "fold_states"]


class _SecondDerivatives(Protocol):
    """The compiled second derivatives of a column view (``ColumnView.second_derivative_entries()[0]``)."""

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Their values at the full vector ``x``."""
        ...

    def parts(self) -> tuple[Any, int, np.ndarray] | None:
        """``(fn, n_out, src)`` for the compiled corrector (``fn`` SymEngine's), None without compiled code."""
        ...


#: :meth:`FoldProblem._layout`: ``(values, keep, i, pos, c, factor)``
_AdjugateLayout = tuple[_SecondDerivatives, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


class CuspEvent(Event):
    """Cusp (``CP``) on a fold curve: the quadratic coefficient of the fold changes sign."""

    label = "CP"

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        assert isinstance(problem, FoldProblem), "a cusp is an event of fold curves (FoldProblem.test_functions)"
        return problem.quadratic_coefficient(state.u, state.jac)


def curve_states(states: Iterable[str], p1: str, p2: str, pair: str, point: str) -> list[str]:
    """``states`` as a list, checked as the unknowns of a two-parameter curve in ``p1`` and ``p2`` (``pair``:
    what the two are called, ``"fold parameters"``; ``point``: what is continued, ``"fold"``): neither
    parameter solved for, the two different."""
    states = list(states)
    for p in (p1, p2):
        if p in states:
            raise InputError(p, f"is solved for; the two {pair} must not be unknowns")
    if p1 == p2:
        raise InputError(p2, f"the second parameter must differ from the {point}'s parameter")
    return states


class FoldProblem(ContinuationProblem):
    """The fold curve of ``system`` in parameters ``(p1, p2)`` as a continuation problem.

    Unknowns ``u = (states..., p1, p2)``, equations ``G = 0`` and one fold condition, the
    minimally extended system

        G(s, p1, p2) = 0,    g(s, p1, p2) = det(R G_s C) / N = 0,

    (``n + 1`` equations in ``n + 2`` unknowns) with ``R``, ``C`` the row and column scales
    read off the Jacobian at the start fold (:func:`fold_scaling`) and ``N`` the product of
    all but the smallest singular value of ``R G_s C`` there (so ``g`` starts as a signed
    smallest singular value). Its gradient is exact from the adjugate and the system's
    generated second derivatives: ``dg/dx_c = tr(adj(A) dA/dx_c) / N``, ``A = R G_s C``.

    Why not the standard augmented system ``(G, G_s v, |v| - 1)`` that :func:`polish_fold`
    uses: its null vector becomes an unknown, and near a cusp the null vector can turn
    through half a revolution within a tiny stretch of the curve. In a toggle press the
    reactions' share of ``v`` is proportional to the distance from the cusp times the spring
    stiffness, so with a stiff spring ``v`` turns from "all reactions" through "all motion"
    to "all reactions, reversed" within 1e-4 rad. Steps either shrink to nothing there or
    jump across it, and a tangent oriented by its null-vector part then points back: the
    curve retraced itself across the cusp again and again. Here the unknowns are the
    physical ones only; the curve is smooth through a cusp in them (the press's is
    ``L0 = 2 L cos^3(phi)``), arclength is measured in them, and the null vectors are
    recomputed from ``G_s`` where a test function needs them.
    """

    def __init__(self, system: EquationSystem, x_fold: np.ndarray, p1: str, p2: str, states: Iterable[str],
                 scales: Mapping[str, float] | None = None) -> None:
        self.system = system.compile()
        states = curve_states(states, p1, p2, "fold parameters", "fold")
        self.states = states
        self.p1, self.p2 = p1, p2
        self.idx_vars = np.array([system.index(n) for n in [*states, p1, p2]])
        self.state_idx = self.idx_vars[: len(states)]
        x_fold = np.asarray(x_fold, float)
        n = len(states)
        row, col = fold_scaling(system, x_fold, self.idx_vars)
        self.row, self.col = row, col[:n]
        self._rowcol = row[:, None] * self.col
        sv = _dense.singular_values(system.jacobian(x_fold)[:, self.state_idx] * self._rowcol)
        # log N: the start's singular values but the smallest (a zero one would make N meaningless)
        self._log_norm = float(np.sum(np.log(np.maximum(sv[:-1], np.finfo(float).tiny))))
        self._colrow = self.col[:, None] * row  # (R G_s C)^T = G_s^T * (col row^T)
        self._e_last = np.zeros(n + 1)
        self._e_last[n] = 1.0
        self.base = x_fold.copy()
        self.view = system.columns(self.idx_vars)
        self._adjugate_layout: _AdjugateLayout | None = None
        self.u0 = x_fold[self.idx_vars].copy()
        self.names = (*states, p1, p2)
        self.param_index = len(states) + 1
        sc = system.scales()
        for name, v in (scales or {}).items():
            sc[system.index(name)] = v
        self.scale = sc[self.idx_vars]
        self.idx = self.idx_vars  # for messages

    def full(self, u: np.ndarray) -> np.ndarray:
        """The full variable vector at ``u``."""
        x = self.base.copy()
        x[self.idx_vars] = u
        return x

    def _layout(self) -> _AdjugateLayout:
        """The view's second derivatives ``d2 G_i / ds_j dx_c`` with ``s_j`` a state: ``(values,
        keep, i, pos, c)`` (``keep`` selects them among all entries, ``pos`` is ``j``'s position
        among the states) and the factor ``R_i C_pos`` of each in ``dA/dx_c``."""
        if self._adjugate_layout is None:
            values, i, j, c = self.view.second_derivative_entries()
            at = np.full(len(self.base), -1, dtype=np.intp)
            at[self.state_idx] = np.arange(len(self.states), dtype=np.intp)
            keep = np.flatnonzero(at[j] >= 0)
            i, pos, c = i[keep], at[j[keep]], c[keep]
            self._adjugate_layout = (values, keep, i, pos, c, self.row[i] * self.col[pos])
        return self._adjugate_layout

    def _adjugate(self, A: np.ndarray) -> tuple[float, np.ndarray]:
        """``(g, adj(A) / N)``: the fold condition and the scaled adjugate of ``A = R G_s C``."""
        sign, logdet = _dense.slogdet(A)
        Ai = _dense.inverse(A) if sign != 0 else None
        if Ai is not None and np.isfinite(Ai).all():
            g = sign * math.exp(logdet - self._log_norm)
            return g, g * Ai
        # exactly singular (a converged fold can be, in the last bit): adj = det(U V) V adj(S) U^T
        U, s, Vt = _dense.svd(A)
        logs = np.log(np.maximum(s, np.finfo(float).tiny))
        others = np.exp(np.sum(logs) - logs - self._log_norm)  # prod_{j != i} s_j / N
        unitary = _dense.slogdet(U)[0] * _dense.slogdet(Vt)[0]
        return 0.0, unitary * (Vt.T * others) @ U.T

    def evaluate(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Residual (n + 1) and Jacobian (n + 1, n + 2) at ``u``."""
        x = self.base.copy()
        x[self.idx_vars] = u
        r, J = self.view.residual_and_jacobian(x)
        n = len(self.states)
        g, adj = self._adjugate(J[:, :n] * self._rowcol)
        values, keep, i, pos, c, factor = self._layout()
        # dg/dx_c = sum_ij adj_ji dA_ij/dx_c over the non-zero second derivatives
        w = values(x)[keep] * factor * adj[pos, i]
        res = np.empty(n + 1)
        res[:n] = r
        res[n] = g
        out = np.empty((n + 1, len(self.idx_vars)))
        out[:n] = J
        out[n] = np.bincount(c, weights=w, minlength=len(self.idx_vars))
        return res, out

    def compiled_model(self) -> CompiledModel | None:
        """The pieces of :meth:`evaluate` for the compiled corrector (:mod:`._kernel`), or None.

        A :class:`~._problem.CompiledModel`: the equilibrium rows as
        :meth:`EquilibriumProblem.compiled_model <._problem.EquilibriumProblem.compiled_model>`,
        and ``fold``, what the fold condition's row needs (:class:`~._problem.CompiledFold`).
        """
        gather = self.view.gather_parts()
        values, keep, i, pos, c, factor = self._layout()
        second = values.parts()
        if gather is None or second is None:
            return None
        fn2, n_out2, src2 = second
        fold = CompiledFold(self.evaluate, fn2, n_out2, src2[keep], i, pos, c, factor, self._rowcol, self._log_norm)
        fn, n_out, src = gather
        return CompiledModel(fn, n_out, src, self.base, self.idx_vars, fold)

    def residual(self, u: np.ndarray) -> np.ndarray:
        return self.evaluate(u)[0]

    def jacobian(self, u: np.ndarray) -> np.ndarray:
        return self.evaluate(u)[1]

    def solves(self, u: np.ndarray, tol: float = 1e-10) -> bool:
        """Whether ``u`` solves the fold system: equilibrium rows and the fold condition each below
        ``tol`` or their floating-point floor."""
        res, out = self.evaluate(u)
        return bool(np.isfinite(res).all() and residual_met(res, out, u, tol))

    def quadratic_coefficient(self, u: np.ndarray, jac: np.ndarray | None = None) -> float:
        """Normalised ``a = w^T G_ss[v, v]`` at the fold-curve point ``u``.

        ``jac``: the scaled Jacobian of the fold system the corrector returned with ``u``
        (``dG/du * scale``), whose first rows are ``G``'s columns; without it they are
        evaluated at ``u``.
        """
        n, nv = len(self.states), len(self.idx_vars)
        x = self.full(u)
        J = self.view.residual_and_jacobian(x)[1] if jac is None else jac[:n] / self.scale
        Js, Jp, row = J[:, :n], J[:, nv - 2], self.row
        vh = _dense.svd(Js * self._rowcol)[2][-1]
        v = self.col * vh
        vf = np.zeros(len(x))
        vf[self.state_idx] = v
        H = self.view.jacobian_derivative(x, vf)[:, :n]
        # as fold_quantities(system, x, state_idx, p1, v, scaling). The left null vector w solves
        # the bordered system [R G_s C, R G_p1; v_hat^T, 0]^T [y; s] = e, w = R y: non-singular
        # along a fold curve (G_p1 is outside the range of G_s: transversality), and
        # w^T G_p1 = 1 > 0 comes out oriented.
        M = np.empty((n + 1, n + 1))
        np.multiply(Js.T, self._colrow, out=M[:n, :n])
        M[:n, n] = vh
        np.multiply(row, Jp, out=M[n, :n])
        M[n, n] = 0.0
        y = _SOLVER.solve(M, self._e_last)
        if y is None or not math.isfinite(np.add.reduce(y, None)):
            return _oriented_coefficient(v, _null_vectors(Js, row, self.col)[1], Jp, H)[2]
        w = row * y[:n]
        return float(w @ (H @ v)) / (_norm(w) * float(v @ v))

    def test_functions(self) -> list[Event]:
        return [CuspEvent()]


def fold_states(system: EquationSystem, vary: str, hold: Iterable[str] = (), free: Iterable[str] = ()) -> list[str]:
    """Unknown state names of a fold in ``vary`` (the lens of the equilibrium branch)."""
    return choose_unknowns(system, hold=hold, free=free, exclude=[vary])
