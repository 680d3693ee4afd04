r"""The periodic boundary-value problem on a collocation mesh: residual, sparse Jacobian, Newton, tangent, Floquet.

Unknowns ``X = (u_0, ..., u_N, T, p)``: the orbit's node values (:class:`~._collocation.Mesh`), the
period (s) and the continuation parameter. Equations: collocation ``u'(tau_jk) = T f(u(tau_jk); p)``
at every Gauss point, periodicity ``u_N = u_0``, the integral phase condition against a reference
orbit, and one more row that closes the system: the pseudo-arclength hyperplane
``<t0, X - X_pred> = 0`` in the inner product ``<a, b> = int a_u . W b_u dtau + w_p a_p b_p`` (the period
has weight 0, as AUTO's default THL(11) = 0), or ``p = p0`` to correct an orbit at a fixed parameter.

Linear algebra: Newton's systems are solved by condensation of parameters (AUTO's scheme,
:mod:`._condensation`): each interval's inner nodes are eliminated by one small dense solve
(``NCOL n`` square, all intervals stacked, the residual with them), leaving a block-bidiagonal system in
the ``NTST + 1`` mesh points, ``T`` and ``p`` (``(NTST + 1) n + 2`` rows, one dense LU). Cost per factorisation
``O(NTST (NCOL n)^3 + (NTST n)^3)``; for the sizes of a cycle of a small system (NTST 20-100, n up to ~10) the
first term dominates. :meth:`linearise` assembles the whole sparse Jacobian (compressed columns) for checking it against SuperLU.

Floquet multipliers: the same collocation blocks, for fixed ``T`` and ``p``, map an interval's first
node to its last (eliminating its inner nodes: ``Phi_j``, one small dense solve per interval); their
product ``M = Phi_(NTST-1) ... Phi_0`` is the collocation's monodromy matrix, whose eigenvalues
approximate the multipliers to the scheme's order. The one nearest 1 is the trivial multiplier (the
orbit's own direction) and is excluded.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from types import ModuleType
from typing import TYPE_CHECKING, Protocol, cast

import numpy as np

from ..errors import ConvergenceError
from . import _kernel
from ._collocation import Mesh
from ._condensation import Border, CondensedLU, collocation_blocks, product

if TYPE_CHECKING:
    import scipy.sparse

    from ..equations import Dynamics, Model

__all__ = ["RateFunction", "CycleSystem", "NewtonFailure", "nontrivial_multipliers", "split_multipliers"]

#: :meth:`CycleSystem.collocation`'s ``(u, T, p, uc, du, F, Fz, Fp)``
Collocation = tuple[np.ndarray, float, float, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


class _BatchDynamics(Protocol):
    """Dynamics that evaluate at many states at once (a mechanism's)."""

    def rates_batch(self, Z: np.ndarray, x: np.ndarray) -> np.ndarray: ...

    def rates_jacobian_batch(self, Z: np.ndarray, x: np.ndarray) -> np.ndarray: ...

    def parameter_rates_batch(self, Z: np.ndarray, x: np.ndarray, names: Sequence[str]) -> np.ndarray: ...


_NOT_FINITE = "rates not finite along the orbit (outside the model's domain)"


class NewtonFailure(Exception):
    """The collocation corrector failed; the message says why."""


class RateFunction:
    """``f``, ``df/dz`` and ``df/dp`` at many states at once, for a model's :class:`~mechcont.equations.Dynamics`.

    ``x_base``: the full vector giving every other parameter; ``vary``: the continuation parameter.
    An ODE model (``OdeDynamics``) is evaluated in one call of its compiled batch function; any other
    dynamics through the protocol: all states at once where it offers ``rates_batch``,
    ``rates_jacobian_batch`` and ``parameter_rates_batch`` (a mechanism's), else point by point.
    """

    def __init__(self, model: Model, dynamics: Dynamics, vary: str, x_base: np.ndarray) -> None:
        from ..equations import OdeDynamics

        self.model, self.dynamics, self.vary = model, dynamics, vary
        self.x_base = np.array(x_base, dtype=float)
        self.p_index = model.index(vary)
        self.n = len(dynamics.state_names)
        self._batch = isinstance(dynamics, OdeDynamics) and hasattr(model, "residual_and_jacobian_batch")
        if self._batch:
            self._cols = np.array([model.index(s) for s in dynamics.state_names], dtype=np.intp)
            first = int(self._cols[0]) if self.n else 0
            # the states as a slice where they are consecutive variables (as an ODE's are): the Jacobian's
            # columns a view, not a copy
            self._cols_slice: slice | None = (slice(first, first + self.n)
                                              if np.array_equal(self._cols, np.arange(first, first + self.n)) else None)
            self._rows = np.zeros((0, len(self.x_base)))  # the full vectors at the states of the last call
        self._dyn_batch = all(hasattr(dynamics, m) for m in
                              ("rates_batch", "rates_jacobian_batch", "parameter_rates_batch"))

    def x_at(self, p: float) -> np.ndarray:
        """The full vector with the continuation parameter at ``p``."""
        x = self.x_base.copy()
        x[self.p_index] = p
        return x

    def __call__(self, Z: np.ndarray, p: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(f, df/dz, df/dp)`` at the states ``Z`` (shape (P, n)): shapes (P, n), (P, n, n), (P, n)."""
        Z = np.asarray(Z, float)
        x = self.x_at(p)
        if self._batch:
            X = self._rows
            if X.shape[0] != len(Z):
                X = self._rows = np.empty((len(Z), len(x)))
            X[:] = x
            cols = self._cols if self._cols_slice is None else self._cols_slice
            X[:, cols] = Z
            F, J = self.model.residual_and_jacobian_batch(X)
            return F, J[:, :, cols], J[:, :, self.p_index]
        dyn = self.dynamics
        if self._dyn_batch:
            bd = cast(_BatchDynamics, dyn)
            return (bd.rates_batch(Z, x), bd.rates_jacobian_batch(Z, x),
                    bd.parameter_rates_batch(Z, x, [self.vary])[:, :, 0])
        F = np.array([dyn.rates(z, x) for z in Z])
        Fz = np.array([dyn.rates_jacobian(z, x) for z in Z])
        Fp = np.array([dyn.parameter_rates(z, x, [self.vary])[:, 0] for z in Z])
        return F, Fz, Fp


class CycleSystem:
    """The periodic BVP of ``rates`` on ``mesh``, with state weights ``weights`` (n,) and parameter weight ``p_weight``."""

    def __init__(self, rates: RateFunction, mesh: Mesh, weights: np.ndarray, p_weight: float) -> None:
        self.rates, self.mesh = rates, mesh
        self.n = rates.n
        self.weights = np.asarray(weights, float)
        self.p_weight = float(p_weight)
        self.size = mesh.n_nodes * self.n + 2
        self._indices: np.ndarray | None = None  # the sparse Jacobian's pattern, made by linearise when first asked
        self._ncol_n = mesh.ncol * self.n
        self._D_array: np.ndarray | None = None

    @property
    def _D(self) -> np.ndarray:
        """The collocation blocks' fixed part d/dtau in the condensation's layout (ntst, ncol, n, ncol + 1, n), made
        when first asked (the compiled Newton iteration makes it from the mesh itself: a remeshed system never needs
        it there)."""
        if self._D_array is None:
            me = self.mesh
            self._D_array = (me.Ld[None, :, None, :, None] / me.h[:, None, None, None, None]
                             * np.eye(self.n)[None, None, :, None, :])
        return self._D_array

    # -- layout ------------------------------------------------------------------------------
    def split(self, X: np.ndarray) -> tuple[np.ndarray, float, float]:
        """``(u (n_nodes, n), T, p)`` of the unknowns."""
        return X[:-2].reshape(self.mesh.n_nodes, self.n), float(X[-2]), float(X[-1])

    @staticmethod
    def pack(u: np.ndarray, T: float, p: float) -> np.ndarray:
        """The unknowns from an orbit's node values, its period and the parameter."""
        return np.concatenate([np.asarray(u, float).ravel(), [T, p]])

    def row(self, t: np.ndarray) -> np.ndarray:
        """``r`` with ``r . X = <t, X>`` (the weighted inner product; the period weighs 0)."""
        tu, _, tp = self.split(t)
        return np.concatenate([self.mesh.gram_row(tu * self.weights), [0.0, self.p_weight * tp]])

    def norm(self, t: np.ndarray) -> float:
        """``sqrt(<t, t>)``."""
        return math.sqrt(max(float(self.row(t) @ t), 0.0))

    def _pattern(self) -> None:
        """Row and column indices of the sparse Jacobian's entries, fixed for a mesh size."""
        m, n, ntst = self.mesh.ncol, self.n, self.mesh.ntst
        nN = self.mesh.n_nodes * n
        j, k, i, a, b = np.meshgrid(np.arange(ntst), np.arange(m), np.arange(m + 1), np.arange(n), np.arange(n),
                                    indexing="ij")
        rows = [((j * m + k) * n + a).ravel()]
        cols = [((j * m + i) * n + b).ravel()]
        colloc_rows = np.arange(ntst * m * n)
        rows += [colloc_rows, colloc_rows]  # the T and p columns
        cols += [np.full(ntst * m * n, nN), np.full(ntst * m * n, nN + 1)]
        base = ntst * m * n
        rows += [base + np.arange(n), base + np.arange(n)]  # periodicity: u_N - u_0
        cols += [nN - n + np.arange(n), np.arange(n)]
        rows += [np.full(nN, base + n), np.full(self.size, base + n + 1)]  # phase row, closing row (dense)
        cols += [np.arange(nN), np.arange(self.size)]
        r, c = np.concatenate(rows), np.concatenate(cols)
        # every entry has its own (row, column): the CSC arrays are the entries in column-major order
        self._order = np.lexsort((r, c))
        self._indices = r[self._order].astype(np.int32)
        self._indptr = np.concatenate([[0], np.cumsum(np.bincount(c, minlength=self.size))]).astype(np.int32)

    # -- evaluation ---------------------------------------------------------------------------
    def collocation(self, X: np.ndarray) -> Collocation:
        """``(u, T, p, uc, du, F, Fz, Fp)`` at the Gauss points (arrays (ntst, ncol, ...))."""
        u, T, p = self.split(X)
        uc, du = self.mesh.at_collocation(u)
        sh = uc.shape
        F, Fz, Fp = self.rates(uc.reshape(-1, self.n), p)
        return u, T, p, uc, du, F.reshape(sh), Fz.reshape(*sh, self.n), Fp.reshape(sh)

    def blocks(self, T: float, Fz: np.ndarray) -> np.ndarray:
        """``d(collocation)/d(nodes)`` per interval: shape (ntst, ncol, ncol + 1, n, n)."""
        me = self.mesh
        return (me.Ld[None, :, :, None, None] / me.h[:, None, None, None, None] * np.eye(self.n)
                - T * me.Lc[None, :, :, None, None] * Fz[:, :, None, :, :])

    def condensation_blocks(self, T: float, Fz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The intervals' collocation blocks as the condensation takes them: over their inner and last nodes
        (ntst, ncol n, ncol n), and over their first node (ntst, ncol n, n)."""
        return collocation_blocks(self._D, self.mesh.Lc, Fz, T)

    def residual(self, X: np.ndarray, phase: np.ndarray, closing: np.ndarray, target: float,
                 colloc: Collocation) -> np.ndarray:
        """The BVP's residual from ``colloc = self.collocation(X)``: collocation, periodicity, phase, closing."""
        u, T, p, uc, du, F, Fz, Fp = colloc
        nc = self.mesh.ntst * self._ncol_n
        res = np.empty(self.size)
        np.subtract(du, T * F, out=res[:nc].reshape(du.shape))
        res[nc:nc + self.n] = u[-1] - u[0]
        res[-2] = phase @ X[:-2]
        res[-1] = closing @ X - target
        return res

    def linearise(self, X: np.ndarray, phase: np.ndarray, closing: np.ndarray,
                  target: float) -> tuple[np.ndarray, scipy.sparse.csc_matrix]:
        """Residual and sparse (CSC) Jacobian of the BVP closed by ``closing . X = target``; ``phase`` the
        phase condition's row over the nodes."""
        import scipy.sparse as sps

        if self._indices is None:
            self._pattern()
        colloc = self.collocation(X)
        u, T, p, uc, du, F, Fz, Fp = colloc
        n = self.n
        res = self.residual(X, phase, closing, target, colloc)
        vals = np.concatenate([self.blocks(T, Fz).ravel(), -F.ravel(), -T * Fp.ravel(), np.ones(n), -np.ones(n),
                               phase, closing])
        J = sps.csc_matrix((vals[self._order], self._indices, self._indptr), shape=(self.size, self.size))
        return res, J

    def factored(self, X: np.ndarray, phase: np.ndarray, closing: np.ndarray, target: float,
                 border: Border | None = None) -> tuple[np.ndarray, CondensedLU]:
        """Residual and the factored Jacobian (:class:`~._condensation.CondensedLU`) of the BVP closed by
        ``closing . X = target``, the residual's collocation part already condensed (``lu.w`` for ``-res``);
        ``border``: the rows ``phase`` and ``closing`` prepared (:class:`~._condensation.Border`), when known.
        Raises :class:`NewtonFailure` when not finite or singular, or where the rates cannot be evaluated (a
        closed loop that does not assemble at a state of the orbit)."""
        if border is None:
            border = Border(phase, closing, self.mesh, self.n)
        cc = _kernel.condensation()
        try:
            if cc is not None:
                res, lu, _, _ = self._factored_compiled(cc, X, target, border)
                return res, lu
            colloc = self.collocation(X)
        except (ConvergenceError, np.linalg.LinAlgError) as exc:
            # a mechanism's dependent coordinates not closing its loops (past a toggle position) at an orbit the
            # predictor proposed: a failed correction, which the step control answers with a shorter step
            raise NewtonFailure(f"the rates fail along the orbit: {exc}") from None
        u, T, p, uc, du, F, Fz, Fp = colloc
        ntst, mn = self.mesh.ntst, self._ncol_n
        res = self.residual(X, phase, closing, target, colloc)
        # one sum is not finite when any term is not (or when they overflow it, which is no orbit either)
        if not math.isfinite(float(res.sum() + Fz.sum() + Fp.sum())):
            raise NewtonFailure(_NOT_FINITE)
        S, L = self.condensation_blocks(T, Fz)
        try:
            lu = CondensedLU(S, L, -F.reshape(ntst, mn), -T * Fp.reshape(ntst, mn), border, self.mesh, self.n,
                             rhs=-res[:ntst * mn].reshape(ntst, mn))
        except np.linalg.LinAlgError:
            raise NewtonFailure("singular collocation Jacobian") from None
        return res, lu

    def _factored_compiled(self, cc: ModuleType, X: np.ndarray, target: float,
                           border: Border) -> tuple[np.ndarray, CondensedLU, np.ndarray, np.ndarray]:
        """:meth:`factored` by the compiled condensation, the Newton correction ``dX`` and ``(max |dX_i|, max |X_i +
        dX_i|)`` (:meth:`~._condensation.CondensedLU.with_residual`'s ``norms``): the orbit at the Gauss
        points, the rates there, then residual, blocks, factors and correction in one call
        (:meth:`~._condensation.CondensedLU.with_residual`).

        The Gauss points are taken in the order of the basis's product (point, then interval), the rates evaluated
        in that order and handed over as strided views, without copies; the values are those of
        :meth:`collocation` (the same product, and the rates row by row)."""
        me, n = self.mesh, self.n
        Y = me.values_and_derivatives(X[:-2].reshape(me.n_nodes, n))  # (2 ncol, ntst n)
        F, Fz, Fp = self.rates(Y[:me.ncol].reshape(-1, n), float(X[-1]))
        res, dX, norms = np.empty(self.size), np.empty(self.size), np.empty(2)
        try:
            lu = CondensedLU.with_residual(cc, Fz, F, Fp, Y, X, target, border, me, n, res, dX, norms)
        except np.linalg.LinAlgError:
            raise NewtonFailure("singular collocation Jacobian") from None
        if lu is None:
            raise NewtonFailure(_NOT_FINITE)
        return res, lu, dX, norms

    def _iterate_compiled(self, cc: ModuleType, X: np.ndarray, target: float,
                          border: Border) -> tuple[np.ndarray, CondensedLU, np.ndarray, np.ndarray]:
        """:meth:`_factored_compiled` with :meth:`factored`'s failures (the rates not evaluable along the orbit)."""
        try:
            return self._factored_compiled(cc, X, target, border)
        except (ConvergenceError, np.linalg.LinAlgError) as exc:
            raise NewtonFailure(f"the rates fail along the orbit: {exc}") from None

    def newton(self, X0: np.ndarray, phase: np.ndarray, closing: np.ndarray, target: float, tol: float,
               max_iter: int) -> tuple[np.ndarray, CondensedLU, int]:
        """Newton from ``X0`` on the BVP closed by ``closing . X = target``.

        Converged when a correction is below ``tol`` (relative to the largest unknown). Returns ``(X, lu,
        iterations)`` (``lu`` the factors of the last Jacobian, for the tangent and the multipliers: of a point
        within ``tol`` of ``X``).
        Raises :class:`NewtonFailure` saying why when it does not converge.
        """
        X = np.array(X0, float)
        prev = math.inf
        border = Border(phase, closing, self.mesh, self.n)
        cc = _kernel.condensation()
        for it in range(1, max_iter + 1):
            if cc is None:
                res, lu = self.factored(X, phase, closing, target, border)
                dX = lu.solve(-res, lu.w)
                step = float(np.abs(dX).max())  # nan when any entry is
                big = float(np.abs(X + dX).max())
            else:
                _, lu, dX, norms = self._iterate_compiled(cc, X, target, border)
                step, big = float(norms[0]), float(norms[1])
            if not math.isfinite(step):
                raise NewtonFailure("singular collocation Jacobian")
            X += dX
            tol_x = tol * max(1.0, big)
            if step <= tol_x:
                return X, lu, it
            if it > 2 and step > prev:
                raise NewtonFailure(f"corrector diverging (correction {step:.3g} after {prev:.3g})")
            prev = step
        raise NewtonFailure(f"corrector needed more than {max_iter} iterations")

    def tangent(self, lu: CondensedLU, t_old: np.ndarray | None = None) -> np.ndarray:
        """The unit tangent from the factors of ``[BVP Jacobian; closing row]``: the solution of ``A t = e_last``
        normalised (for the arclength row ``<t_old, .>``, it points the way of ``t_old``)."""
        return self.tangent_and_row(lu, None if t_old is None else self.row(t_old))[0]

    def tangent_and_row(self, lu: CondensedLU, row_old: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`tangent` and its :meth:`row` (one Gram product for both); ``row_old``: the previous tangent's row,
        whose direction the tangent keeps."""
        e = np.zeros(self.size)
        e[-1] = 1.0
        t = lu.solve(e)
        r = self.row(t)
        scale = 1.0 / math.sqrt(max(float(r @ t), 0.0))
        t *= scale
        r *= scale
        if row_old is not None and row_old @ t < 0:
            t, r = -t, -r
        return t, r

    # -- stability ------------------------------------------------------------------------------
    def monodromy(self, X: np.ndarray) -> np.ndarray:
        """The collocation's monodromy matrix (n, n) at the orbit ``X`` (see the module docstring)."""
        u, T, p, uc, du, F, Fz, Fp = self.collocation(X)
        S, L = self.condensation_blocks(T, Fz)
        n = self.n
        return product(-np.linalg.solve(S, L)[:, -n:, :])  # the last node from the first, per interval

    def multipliers(self, X: np.ndarray) -> np.ndarray:
        """All ``n`` Floquet multipliers (complex), largest modulus first."""
        mu = np.linalg.eigvals(self.monodromy(X))
        return mu[np.argsort(-np.abs(mu), kind="stable")]


def nontrivial_multipliers(mu: np.ndarray | Sequence[complex]) -> np.ndarray:
    """The multipliers without the trivial one (the one nearest 1), in their given order."""
    arr = np.asarray(mu, complex)
    return arr if len(arr) == 0 else split_multipliers(arr)[1]


def split_multipliers(mu: np.ndarray) -> tuple[complex, np.ndarray]:
    """``(trivial, others)``: of the (non-empty) multipliers ``mu``, the one nearest 1 and the rest in their order."""
    k = int(np.argmin(np.abs(mu - 1.0)))
    return complex(mu[k]), np.concatenate((mu[:k], mu[k + 1:]))


def phase_reference(system: CycleSystem, X: np.ndarray) -> np.ndarray:
    """The phase condition's row for the reference orbit ``X`` (its node values)."""
    u, _, _ = system.split(X)
    return system.mesh.phase_row(u)

