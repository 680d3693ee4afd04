"""Folds located exactly: the standard augmented system and its Newton polish.

A fold (limit point) of equilibria in parameter ``p1`` satisfies, with ``G_s`` the
Jacobian with respect to the unknown states ``s``,

    G(s, p1, p2) = 0,    G_s v = 0,    (v^T v - 1) / 2 = 0,

(``2n + 1`` equations). With ``p2`` held this is square in ``(s, p1, v)`` and Newton
polishes a fold found by a sign change to machine precision (:func:`polish_fold`), in
equilibrated variables so that the result does not depend on units. Its Jacobian needs
second derivatives of ``G``, contracted with ``v``: exact, from the system's generated Hessian.
The fold curve in two parameters is :mod:`._folds`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from .. import _dense
from ..equations import EquationSystem
from ..errors import ConvergenceError
from ._linalg import DenseLU
from ._newton import residual_met, step_noise
from ._scaling import equilibrate

_SOLVER = DenseLU()

__all__ = ["FoldPoint", "fold_quantities", "fold_scaling", "polish_fold", "refine_fold"]


def _norm(a: np.ndarray) -> float:
    """``np.linalg.norm(a)`` (2-norm of the entries, the same bits: it computes exactly this) without its overhead."""
    a = a.ravel(order="K")
    return math.sqrt(a.dot(a))


def _reference_columns(system: EquationSystem, idx: np.ndarray) -> np.ndarray:
    """Mask of the columns ``idx`` measured in radians (the reference of :func:`equilibrate`)."""
    return np.array([system.variables[i].unit == "rad" for i in idx], dtype=bool)


def fold_scaling(system: EquationSystem, x: np.ndarray, idx_vars: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Row scales of the equations and column scales of the unknowns ``idx_vars`` at ``x``.

    Read off the Jacobian (see :func:`equilibrate`), so they do not depend on the units the
    user chose nor on ``scale`` hints: the fold polish and the fold curve use them.
    """
    return _scaling_of(system, system.jacobian(x)[:, idx_vars], idx_vars)


def _scaling_of(system: EquationSystem, J: np.ndarray, idx_vars: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`fold_scaling` from the Jacobian's columns ``J = dG/dx[:, idx_vars]``, already evaluated."""
    return equilibrate(J, _reference_columns(system, idx_vars))


def _null_vectors(Js: np.ndarray, row: np.ndarray | None = None,
                  col: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Right and left null vectors (smallest singular value) of ``Js``, found on ``R Js C``.

    In mixed units (m, rad, N beside a kN/m spring) the unscaled matrix can have several
    small singular values and the smallest need not belong to the fold; on the equilibrated
    matrix it does. Returned in the unscaled variables and equations, each of unit length.
    """
    row = np.ones(Js.shape[0]) if row is None else row
    col = np.ones(Js.shape[1]) if col is None else col
    u, _, vt = _dense.svd(Js * row[:, None] * col)
    v = vt[-1] * col
    w = u[:, -1] * row
    return v / _norm(v), w / _norm(w)


def fold_quantities(system: EquationSystem, x: np.ndarray, state_idx: np.ndarray, param_index: int,
                    v: np.ndarray | None = None,
                    scaling: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray, float]:
    """Right/left null vectors and the normalised quadratic coefficient at a fold.

    Returns ``(v, w, a)``: ``v`` spans ker G_s, ``w`` spans ker G_s^T, oriented so that
    ``w^T dG/dp1 > 0`` (non-zero at a fold: that is its transversality condition), and
    ``a = w^T G_ss[v, v] / |v|^2`` with ``|w| = 1``. With this orientation the sign of
    ``a`` says on which side of the fold in ``p1`` the two branches lie, and it changes
    sign exactly at a cusp. The null vectors come from the equilibrated Jacobian, so they
    do not depend on units.
    """
    J = system.jacobian(x)
    Js = J[:, state_idx]
    # scaling = (row, col) of the states: reuse known scales (a fold curve's, fixed at its start)
    row, col = equilibrate(Js, _reference_columns(system, state_idx)) if scaling is None else scaling
    vs, w = _null_vectors(Js, row, col)
    if v is None:
        v = vs
    vf = np.zeros(len(x))
    vf[state_idx] = v
    return _oriented_coefficient(v, w, J[:, param_index], system.jacobian_derivative(x, vf)[:, state_idx])


def _oriented_coefficient(v: np.ndarray, w: np.ndarray, Jp: np.ndarray,
                          Hs: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """``(v, w, a)`` of :func:`fold_quantities` from ``w``, ``dG/dp1`` and ``Hs = d(G_s v)/ds``."""
    if w @ Jp < 0:
        w = -w
    a = float(w @ (Hs @ v)) / (v @ v)
    return v, w, a


#: :meth:`_FoldSystem._second_derivative_layout`: the compiled second derivatives ``values(x)``, where each
#: reads the null vector, where it adds in the flattened output, and that output's size
_SecondLayout = tuple[Callable[[np.ndarray], np.ndarray], np.ndarray, np.ndarray, int]


class _FoldSystem:
    """Residual and Jacobian of the fold system in unknowns ``U = (vars..., v_hat)``.

    The null vector is carried in equilibrated coordinates, ``v = col_states * v_hat``,
    normalised by ``|v_hat| = 1``: in SI units a null vector mixes radians and newtons and
    ``|v| = 1`` would make it all reaction components (an ill-conditioned system whose
    Newton iteration stalls). A fixed border ``c^T v = 1`` is not used either: along a long
    fold curve the null vector turns and ``|v|`` would grow without bound.

    ``idx_vars``: full indices of the variable unknowns (states then parameters);
    ``state_pos``: positions within ``idx_vars`` of the states whose Jacobian must be
    singular; ``col_states``: the column scales of those states. The Jacobian's blocks are
    ``G``'s columns (rows ``:n``, columns ``:nv``) and those of ``d(G_s v)/dx`` (rows
    ``n:2n``): a test function at a converged point (the cusp's) reads them there instead of
    evaluating the point again.
    """

    def __init__(self, system: EquationSystem, base: np.ndarray, idx_vars: np.ndarray, state_pos: np.ndarray,
                 col_states: np.ndarray) -> None:
        self.base, self.idx_vars = base, idx_vars
        self.nv, self.n = len(idx_vars), len(state_pos)
        # the states' columns: a slice when they come first (always, here): the same values and
        # layout as fancy indexing, one copy fewer per evaluation
        pos = np.asarray(state_pos, dtype=np.intp)
        self.state_pos: slice | np.ndarray = slice(0, len(pos)) if np.array_equal(pos, np.arange(len(pos))) else pos
        self.state_idx = idx_vars[pos]
        self.col = np.asarray(col_states, dtype=float)
        self.view = system.columns(idx_vars)  # only the unknowns' columns of J and of d(J v)/dx are formed
        self._second: _SecondLayout | None = None

    def full(self, U: np.ndarray) -> np.ndarray:
        """The full variable vector at ``U``."""
        x = self.base.copy()
        x[self.idx_vars] = U[:self.nv]
        return x

    def evaluate(self, U: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Residual (2n+1) and Jacobian (2n+1, nv+n) at ``U``."""
        nv, n, col = self.nv, self.n, self.col
        x = self.base.copy()  # self.full(U), inline: this runs at every Newton iteration
        x[self.idx_vars] = U[:nv]
        vh = U[nv:]
        r, J = self.view.residual_and_jacobian(x)
        Jv = J[:, self.state_pos] * col
        res = np.empty(2 * n + 1)
        res[:n] = r
        res[n:2 * n] = Jv @ vh
        res[2 * n] = 0.5 * (vh @ vh - 1.0)
        # d(G_s v)/dx scattered straight into its block of the output: the same sums as
        # view.jacobian_derivative(x, v) (entries added in the same order), one array fewer
        if self._second is None:
            self._second = self._second_derivative_layout()
        values, v_at, bins, size = self._second
        cv = np.empty(n + 1)
        np.multiply(col, vh, out=cv[:n])
        cv[n] = 0.0
        w = values(x)
        w *= cv[v_at]
        out = np.bincount(bins, weights=w, minlength=size).reshape(2 * n + 1, nv + n)
        out[:n, :nv] = J
        out[n:2 * n, nv:] = Jv
        out[2 * n, nv:] = vh
        return res, out

    def _second_derivative_layout(self) -> _SecondLayout:
        """``(values, v_at, bins, size)``: the view's second derivatives, where each entry reads
        the null vector (``v_at``: position among the states, ``n`` for a zero) and where it
        adds in the flattened output (row ``n + i``, column ``c``)."""
        values, i, j, c = self.view.second_derivative_entries()
        n, nv = self.n, self.nv
        at = np.full(len(self.base), n, dtype=np.intp)
        at[self.state_idx] = np.arange(n, dtype=np.intp)
        return values, at[j], (n + i) * (nv + n) + c, (2 * n + 1) * (nv + n)

    def residual(self, U: np.ndarray) -> np.ndarray:
        """Residual (2n+1) at ``U``."""
        x = self.full(U)
        vh = U[self.nv:]
        r, J = self.view.residual_and_jacobian(x)
        return np.concatenate([r, (J[:, self.state_pos] * self.col) @ vh, [0.5 * (vh @ vh - 1.0)]])

    def jacobian(self, U: np.ndarray) -> np.ndarray:
        """Jacobian (2n+1, nv+n) at ``U``."""
        return self.evaluate(U)[1]


@dataclass(frozen=True)
class FoldPoint:
    """A fold polished by :func:`polish_fold`.

    Attributes
    ----------
    x:
        Full variable vector at the fold (SI units).
    v:
        Null vector over the unknown states (unscaled, unit length).
    v_hat:
        The same in equilibrated coordinates (``v ∝ col * v_hat``, ``|v_hat| = 1``).
    col:
        Column scales of the unknowns (states then parameter), from :func:`fold_scaling`.
    residual:
        Largest equation residual relative to the size of its terms (dimensionless).
    singular_value:
        Smallest singular value of the equilibrated state Jacobian over the norm of the
        whole equilibrated Jacobian (dimensionless; 0 at an exact fold).
    iterations:
        Newton iterations used.
    """

    x: np.ndarray
    v: np.ndarray
    v_hat: np.ndarray
    col: np.ndarray
    residual: float
    singular_value: float
    iterations: int

    def precision(self) -> dict[str, float]:
        """``{"residual": ..., "singular_value": ...}`` for a special point's info."""
        return {"residual": self.residual, "singular_value": self.singular_value}


def _relative_residual(r: np.ndarray, J: np.ndarray, u: np.ndarray) -> float:
    terms = np.abs(J * u).sum(axis=1)
    return float(np.max(np.abs(r) / np.maximum(terms, np.finfo(float).tiny), initial=0.0))


class _InverseSolve:
    """``solve(A, b)`` with ``A``'s inverse already computed (``A`` is ignored): for :func:`step_noise`."""

    def __init__(self, inverse: np.ndarray) -> None:
        self.inverse = inverse

    def __call__(self, _A: np.ndarray, b: np.ndarray) -> np.ndarray:
        x: np.ndarray = self.inverse @ b
        return x


def polish_fold(system: EquationSystem, x: np.ndarray, states: Iterable[str], param: str, tol: float = 1e-11,
                max_iter: int = 30, residual_tol: float = 1e-10, v0: np.ndarray | None = None) -> FoldPoint:
    """Locate a fold in ``param`` near ``x`` to machine precision, whatever the units.

    Newton on the standard augmented system ``G = 0, G_s C v_hat = 0, |v_hat| = 1`` in
    equilibrated variables: unknowns divided by the column scales ``C`` and equations
    multiplied by the row scales ``R`` of :func:`fold_scaling`. Newton's iterates are
    invariant under a change of variables, so with scales read off the Jacobian the result
    does not depend on the units or on ``scale`` hints; only the stopping test is measured
    in those scales (residuals below ``residual_tol`` or their floating-point floor, and the
    step below ``tol``, or stalled at the noise that floor causes in it,
    :func:`~._newton.step_noise`: a very stiff compliance makes the system so
    ill-conditioned that the step stalls there). A backtracking line search on the equilibrated residual keeps
    a rough start (a secant guess) from overshooting.

    ``v0`` (optional, in the states' units): a guess of the null vector, e.g. the states'
    part of the branch tangent at ``x`` (at a fold the tangent's parameter component
    vanishes and its states' part spans ker G_s). Without it the guess is the singular
    vector of the smallest singular value at ``x``, which near a stiff joint compliance can
    belong to the compliance (singular values ~1/k) rather than to the fold.

    Returns a :class:`FoldPoint`. Raises :class:`~mechcont.errors.ConvergenceError`
    (``partial``: the last full vector) when Newton fails.
    """
    states = list(states)
    x = np.array(x, dtype=float)
    idx_vars = np.array([system.index(n) for n in [*states, param]])
    n = len(states)
    J0 = system.jacobian(x)  # evaluated once for the scales and the first null vector
    row, col = _scaling_of(system, J0[:, idx_vars], idx_vars)
    if v0 is None:
        _, _, vt = _dense.svd(J0[:, idx_vars[:n]] * row[:, None] * col[:n])
        vh0 = vt[-1]
    else:
        vh0 = np.asarray(v0, float) / col[:n]
        vh0 /= _norm(vh0)
    fs = _FoldSystem(system, x, idx_vars, np.arange(n), col[:n])
    full, evaluate = fs.full, fs.evaluate
    U = np.concatenate([x[idx_vars], vh0])
    rows = np.concatenate([row, row, [1.0]])
    cols = np.concatenate([col, np.ones(n)])
    F, JF = evaluate(U)
    step = np.inf
    for it in range(1, max_iter + 1):
        A = JF * rows[:, None] * cols
        # one inverse for the Newton step, the line search's simplified corrections and the noise
        # estimate (a product per solve; LU factors are not reachable without scipy.linalg's start-up)
        Ai = _dense.inverse(A)
        dU = Ai @ (-rows * F) if Ai is not None else None
        if Ai is None or dU is None or not np.isfinite(dU).all():
            raise ConvergenceError(f"fold polish: singular fold system at iteration {it} (the fold may be degenerate "
                                   "or a branch point)", partial=full(U))
        # Deuflhard's natural monotonicity test: the simplified Newton correction at the
        # trial point must be shorter than the Newton step. Unlike the residual norm it is
        # affine invariant, and it accepts a long step along the null direction that a
        # residual already at its noise floor would wrongly reject.
        size, lam = _norm(dU), 1.0
        while True:
            trial = U + lam * cols * dU
            F_t, JF_t = evaluate(trial)
            bar = Ai @ (-rows * F_t)
            if (np.isfinite(bar).all() and _norm(bar) <= (1 - lam / 4) * size) or lam < 1 / 64:
                break
            lam *= 0.5
        U, F, JF = trial, F_t, JF_t
        prev_step, step = step, float(np.abs(lam * dU).max())
        r_eq, J_eq = F[:len(row)], JF[:len(row), :len(idx_vars)]
        null_rows = F[len(row):2 * len(row)]
        J_null = JF[len(row):2 * len(row)]
        if (residual_met(r_eq, J_eq, U[:len(idx_vars)], residual_tol)
                and residual_met(row * null_rows, J_null * row[:, None], U * cols, residual_tol)
                and (step < tol or (step > 0.5 * prev_step  # stalled, no longer converging
                                    and step <= 10 * step_noise(_InverseSolve(Ai), A, A, U / cols)))):
            xf = full(U)
            # the columns at xf, from its evaluation above (the same values as system.jacobian(xf)[:, idx_vars])
            Jf = J_eq * row[:, None] * col
            # relative to the whole equilibrated Jacobian (G_p is non-zero at a fold)
            smallest = _dense.singular_values(Jf[:, :n])[-1] / _norm(Jf)
            v = col[:n] * U[len(idx_vars):]
            return FoldPoint(xf, v / _norm(v), U[len(idx_vars):].copy(), col,
                             _relative_residual(r_eq, J_eq, U[:len(idx_vars)]), float(smallest), it)
    raise ConvergenceError(f"fold polish did not converge in {max_iter} iterations (equilibrated residual "
                           f"{np.linalg.norm(rows * F):.3g})", partial=full(U))


def refine_fold(system: EquationSystem, x: np.ndarray, states: Iterable[str], param: str,
                tol: float = 1e-11) -> tuple[np.ndarray, np.ndarray]:
    """Polish an approximate fold in ``param``: ``(x, v)`` of :func:`polish_fold`.

    Returns the full vector at the fold and the normalised null vector over the states.
    Raises :class:`~mechcont.errors.ConvergenceError` if Newton fails.
    """
    fp = polish_fold(system, x, states, param, tol=tol)
    return fp.x, fp.v
