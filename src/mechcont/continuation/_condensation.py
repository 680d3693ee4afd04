r"""Condensation of parameters: the collocation Jacobian solved through its mesh points (AUTO's scheme).

Interval ``j``'s ``NCOL n`` collocation rows involve only its own nodes — the first (mesh point
``M_j``), the ``NCOL - 1`` inner ones ``I_j`` and the last (``M_(j+1)``) — and the period and the
parameter. With ``S_j = [A_I | A_R]`` (the columns of the inner and last nodes, square) those rows give

.. math::  [\delta I_j; \delta M_{j+1}] = S_j^{-1} (b_j - A_L \delta M_j - a_T \delta T - a_p \delta p),

so the inner nodes are eliminated interval by interval (one small dense solve each, all at once, for the
first node's, T's and p's columns and the right-hand side together),
and what is left is a system in the mesh points, ``T`` and ``p`` only: ``NTST`` block rows
``dM_(j+1) + P_j dM_j + ... = w_j`` (a block-bidiagonal matrix, as in multiple shooting: the maps
``-P_j`` are the intervals' transfer matrices, whose product is the monodromy matrix), periodicity,
and the phase and closing rows with the inner nodes' part moved onto the mesh points. That system, of
``(NTST + 1) n + 2`` rows, is factored once (dense LU); the inner nodes follow from the mesh points.
Work per factorisation: ``NTST`` solves with ``NCOL n`` square blocks and one LU of the reduced
system, against the ``(NTST NCOL + 1) n + 2`` rows of the whole.

Where the optional extension :mod:`._ccondense` was built (``_kernel.condensation()``), the same steps
run there in C loops: the blocks' LU, the reduced matrix's assembly, its factorisation by an elimination
that keeps its block structure (``O(NTST n^3)``), and the back-substitution; a Newton iteration's residual,
blocks and factors are one call there (:meth:`CondensedLU.with_residual`), and the monodromy matrix one more;
else NumPy's stacked solve and LAPACK's dense LU (also with ``MECHCONT_PURE_PYTHON=1``). The two agree to rounding
(``tests/test_condensation_kernel.py``).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from types import ModuleType

import numpy as np
import scipy.linalg.lapack

from . import _kernel
from ._collocation import Mesh

__all__ = ["Border", "CondensedLU", "collocation_blocks", "product"]

_GETRF, _GETRS, _GEEV = scipy.linalg.lapack.dgetrf, scipy.linalg.lapack.dgetrs, scipy.linalg.lapack.dgeev


@dataclass(frozen=True)
class _Pattern:
    """The reduced matrix's fixed entries (a template to copy) and the flat indices (row-major) of its interval blocks."""

    template: np.ndarray  # flat: +1 on M_(j+1) in interval j's rows and on M_NTST in the periodicity rows, -1 on M_0 there
    P: np.ndarray  # interval j's rows: M_j's columns, then T's and p's, in the order of Q[j, inner:, :]
    inner_nodes: np.ndarray  # (ntst, ncol - 1) node numbers of the inner nodes


@functools.lru_cache(maxsize=32)
def _pattern(ntst: int, m: int, n: int) -> _Pattern:
    nr = (ntst + 1) * n + 2
    j, a, b = np.meshgrid(np.arange(ntst), np.arange(n), np.arange(n + 2), indexing="ij")
    row = j * n + a
    col = np.where(b < n, j * n + b, nr - 2 + (b - n))
    r1 = np.arange(ntst * n)
    per = ntst * n + np.arange(n)
    template = np.zeros(nr * nr)
    template[np.concatenate([r1 * nr + (r1 + n), per * nr + per])] = 1.0
    template[per * nr + np.arange(n)] = -1.0
    template.flags.writeable = False
    return _Pattern(template, (row * nr + col).ravel(), np.arange(ntst)[:, None] * m + np.arange(1, m)[None, :])


def product(Phi: np.ndarray) -> np.ndarray:
    """``Phi[-1] @ ... @ Phi[1] @ Phi[0]`` of a stack of square matrices (k, n, n): neighbours multiplied
    pairwise, all pairs in one stacked product, until one is left (log2 k products instead of k)."""
    while len(Phi) > 1:
        odd = Phi[-1:] if len(Phi) % 2 else None
        Phi = Phi[1:len(Phi) - (odd is not None):2] @ Phi[0:len(Phi) - (odd is not None):2]
        if odd is not None:
            Phi = np.concatenate([Phi, odd])
    return Phi[0]


def collocation_blocks(D: np.ndarray, Lc: np.ndarray, Fz: np.ndarray, T: float) -> tuple[np.ndarray, np.ndarray]:
    """The intervals' collocation blocks as :class:`CondensedLU` takes them: over their inner and last nodes (ntst,
    ncol n, ncol n) and over their first node (ntst, ncol n, n), ``D - T Lc Fz`` from the fixed part ``D`` (d/dtau,
    (ntst, ncol, n, ncol + 1, n)), the Lagrange basis at the Gauss points ``Lc`` (ncol, ncol + 1) and the rates'
    Jacobian ``Fz`` at them (ntst, ncol, n, n); ``T`` the period (s)."""
    ntst, m, n = D.shape[0], D.shape[1], D.shape[2]
    cc = _kernel.condensation()
    if cc is not None:
        S, L = np.empty((ntst, m * n, m * n)), np.empty((ntst, m * n, n))
        cc.collocation_blocks(np.ascontiguousarray(D, float), np.ascontiguousarray(Lc, float),
                              np.ascontiguousarray(Fz, float), float(T), S, L)
        return S, L
    C = D - (T * Lc[None, :, None, :, None]) * Fz[:, :, :, None, :]  # (ntst, ncol, n, ncol + 1, n)
    return C[:, :, :, 1:, :].reshape(ntst, m * n, m * n), C[:, :, :, 0, :].reshape(ntst, m * n, n)


class Border:
    """The phase and closing rows (over the nodes, and over all unknowns) as the condensation uses them, prepared
    once for all the factorisations of a Newton solve: the inner nodes' coefficients, per interval (ntst, 2,
    (ncol - 1) n), and the mesh points', T's and p's."""

    def __init__(self, phase: np.ndarray, closing: np.ndarray, mesh: Mesh, n: int) -> None:
        m, ntst = mesh.ncol, mesh.ntst
        #: the rows themselves (contiguous), for the residual computed with the factorisation
        self.phase, self.closing = np.ascontiguousarray(phase, float), np.ascontiguousarray(closing, float)
        # each interval's nodes but its last, side by side (slices: no gathering): its first node, then the inner ones
        rows = (self.phase[:-n].reshape(ntst, m * n), self.closing[:-2 - n].reshape(ntst, m * n))
        self.inner = np.empty((ntst, 2, (m - 1) * n))
        self.mesh_points = np.empty((2, ntst + 1, n))
        for s, (r, last) in enumerate(zip(rows, (self.phase[-n:], self.closing[-2 - n:-2]))):
            self.inner[:, s] = r[:, n:]
            self.mesh_points[s, :-1] = r[:, :n]
            self.mesh_points[s, -1] = last
        self.TP = np.array([[0.0, 0.0], self.closing[-2:]])


class CondensedLU:
    """The collocation Jacobian factored by condensation; :meth:`solve` solves it for any right-hand side.

    ``S``: the intervals' collocation blocks over their inner and last nodes (ntst, ncol n, ncol n); ``L``:
    over their first node (ntst, ncol n, n); ``aT``, ``ap``: the T and p columns of the collocation rows (ntst,
    ncol n); ``border``: the phase and closing rows (:class:`Border`); ``mesh``: the collocation mesh (node
    indices); ``rhs``: optionally the collocation part of a right-hand side (ntst, ncol n), eliminated in the
    same solves (its condensed form is :attr:`w`, for :meth:`solve`).
    Raises ``numpy.linalg.LinAlgError`` when a block or the reduced system is singular. ``S`` may be overwritten
    by its factors (the compiled path; the condensation owns the blocks it is given).
    """

    def __init__(self, S: np.ndarray, L: np.ndarray, aT: np.ndarray, ap: np.ndarray, border: Border, mesh: Mesh, n: int,
                 rhs: np.ndarray | None = None) -> None:
        self.mesh, self.n = mesh, n
        ntst, m = mesh.ntst, mesh.ncol
        inner = (m - 1) * n
        W = np.empty((ntst, m * n, n + 2 + (rhs is not None)))
        W[:, :, :n] = L
        W[:, :, n] = aT
        W[:, :, n + 1] = ap
        if rhs is not None:
            W[:, :, n + 2] = rhs
        nr = (ntst + 1) * n + 2
        self.nr = nr
        self._border = border.inner
        self._inner_idx = _pattern(ntst, m, n).inner_nodes
        self._cc = _kernel.condensation()
        if self._cc is not None:
            self._factor_compiled(S, W, border, rhs is not None)
            return
        Y = np.linalg.solve(S, W)  # rows = [inner nodes; last node]
        self._S = S
        self.Q = Y[:, :, :n + 2]  # (ntst, m n, n + 2): the first node's, T's and p's parts
        #: the condensed collocation right-hand side ``S_j^-1 b_j`` (ntst, m n) of ``rhs``, or None
        self.w = Y[:, :, n + 2] if rhs is not None else None
        pat = _pattern(ntst, m, n)
        K = pat.template.copy()
        K[pat.P] = self.Q[:, inner:, :].ravel()  # P_R on M_j, then the T and p columns
        K = K.reshape(nr, nr)
        # the phase and closing rows: their inner nodes' part moved to M_j, T and p
        adj = border.inner @ self.Q[:, :inner, :]  # (ntst, 2, n + 2)
        coefM = K[nr - 2:, :nr - 2].reshape(2, ntst + 1, n)
        coefM[:] = border.mesh_points
        coefM[:, :-1] -= adj[:, :, :n].transpose(1, 0, 2)
        K[nr - 2:, nr - 2:] = border.TP - adj[:, :, n:].sum(axis=0)
        # LAPACK's getrf directly: scipy's lu_factor wrapper costs as much as the LU
        lu, piv, info = _GETRF(K, overwrite_a=1)
        if info != 0 or not math.isfinite(float(lu.sum())):
            raise np.linalg.LinAlgError("singular collocation Jacobian")
        self.lu = (lu, piv)

    @classmethod
    def with_residual(cls, cc: ModuleType, Fz: np.ndarray, F: np.ndarray, Fp: np.ndarray,
                      Y: np.ndarray, X: np.ndarray, target: float, border: Border, mesh: Mesh, n: int,
                      res: np.ndarray, dX: np.ndarray, norms: np.ndarray) -> CondensedLU | None:
        """The compiled path's whole Newton iteration in one call (``_ccondense.factor_residual``): the BVP's residual
        into ``res`` and the factors of its Jacobian, as ``CondensedLU(*collocation_blocks(D, Lc, Fz, T), -F, -T Fp,
        border, mesh, n, rhs=-res's collocation part)`` gives them (``D`` the blocks' fixed part, made there from the
        mesh's ``Ld`` and ``h``). The Gauss points in the order of
        :meth:`~._collocation.Mesh.values_and_derivatives` (point ``k`` of interval ``j`` in row ``k ntst + j``):
        ``F``, ``Fp`` (ncol ntst, n) and ``Fz`` (ncol ntst, n, n) there, any strides; ``Y`` that method's product
        (the derivatives divided by the intervals' lengths here); ``X`` the unknowns (``X[-2]`` the period ``T``, s);
        ``target`` the closing row's value. The Newton correction, ``solve(-res, w)``, into ``dX`` in the same call, and
        into ``norms`` (2,) its largest ``|dX_i|`` (NaN when any is) and the largest ``|X_i + dX_i|``. Returns
        None when the residual or the rates' derivatives are not finite; raises
        ``numpy.linalg.LinAlgError`` when a block or the reduced system is singular."""
        ntst, m = mesh.ntst, mesh.ncol
        mn, nr = m * n, (ntst + 1) * n + 2
        S = np.empty((ntst, mn, mn))
        W = np.empty((ntst, mn, n + 3))
        piv = np.empty((ntst, mn), np.intc)
        K = np.empty((nr, nr))
        rpiv = np.empty(nr, np.intc)
        # the phase and closing rows' values as NumPy's path computes them (its dot products' order of summation)
        phase_value = float(border.phase @ X[:-2])
        closing_value = float(border.closing @ X) - target
        status = cc.factor_residual(mesh.Ld, mesh.Lc, Fz, F, Fp, Y, mesh.h, X, phase_value, closing_value, float(X[-2]),
                                    border.inner,
                                    border.mesh_points, border.TP, S, piv, W, K, rpiv, res, dX, norms)
        if status == 1:
            return None
        if status:
            raise np.linalg.LinAlgError("singular collocation Jacobian")
        self = cls.__new__(cls)
        self.mesh, self.n, self.nr = mesh, n, nr
        self._border, self._inner_idx, self._cc = border.inner, _pattern(ntst, m, n).inner_nodes, cc
        self._S, self._piv, self._W = S, piv, W
        self.Q, self.w = W[:, :, :n + 2], W[:, :, n + 2]
        self.lu = (K, rpiv)
        return self

    def _factor_compiled(self, S: np.ndarray, W: np.ndarray, border: Border, has_rhs: bool) -> None:
        # the same factorisation in C (:mod:`._ccondense`): the blocks' LU kept for :meth:`solve`, the reduced
        # system by the structured elimination; S is a copy of the Jacobian's values, overwritten by its factors
        cc, n, nr = self._cc, self.n, self.nr
        S = np.ascontiguousarray(S)
        piv: np.ndarray = np.empty(S.shape[:2], np.intc)
        if cc.block_factor_solve(S, piv, W) >= 0:
            raise np.linalg.LinAlgError("singular collocation Jacobian")
        self._S, self._piv, self._W = S, piv, W
        self.Q = W[:, :, :n + 2]
        self.w = W[:, :, n + 2] if has_rhs else None
        K = np.zeros((nr, nr))
        cc.reduced_matrix(W, border.inner, border.mesh_points, np.ascontiguousarray(border.TP), K, n)
        rpiv = np.empty(nr, np.intc)
        if cc.reduced_factor(K, rpiv, n) != 0:
            raise np.linalg.LinAlgError("singular collocation Jacobian")
        self.lu = (K, rpiv)

    def transfer(self) -> np.ndarray:
        """The intervals' transfer matrices ``Phi_j`` (ntst, n, n): last node from the first, T and p held."""
        inner = (self.mesh.ncol - 1) * self.n
        return -self.Q[:, inner:, :self.n]

    def multipliers(self) -> np.ndarray:
        """The eigenvalues of the monodromy matrix (the transfer matrices' product), complex, largest modulus first."""
        if self._cc is not None:
            M = np.empty((self.n, self.n))
            self._cc.transfer_product(self._W, self.n, M)  # the product in one call, in order
        else:
            M = product(self.transfer())
        # LAPACK's dgeev, as numpy.linalg.eigvals calls it, without that wrapper's checks (five times the call)
        wr, wi, _, _, info = _GEEV(M, compute_vl=0, compute_vr=0)
        if info != 0:
            raise np.linalg.LinAlgError("the monodromy matrix's eigenvalues did not converge")
        mu = wr + 1j * wi
        return mu[np.argsort(-np.abs(mu), kind="stable")]

    def solve(self, b: np.ndarray, w: np.ndarray | None = None) -> np.ndarray:
        """The solution ``dX`` of ``J dX = b`` (``b`` ordered as the residual: collocation, periodicity, phase, closing).

        ``w``: the condensed collocation part of ``b`` when it is known (:attr:`w`, for the ``rhs`` given to the
        factorisation); else it is condensed here (nothing to do when it is zero, as for a tangent).
        """
        mesh, n = self.mesh, self.n
        ntst, m = mesh.ntst, mesh.ncol
        inner = (m - 1) * n
        nc = ntst * m * n
        if w is None:
            bc = b[:nc].reshape(ntst, m * n)
            if not bc.any():
                w = np.zeros((ntst, m * n))
            elif self._cc is not None:
                w = np.array(bc)[:, :, None]
                self._cc.block_solve(self._S, self._piv, w)
                w = w[:, :, 0]
            else:
                w = np.linalg.solve(self._S, bc[:, :, None])[:, :, 0]
        if self._cc is not None:
            out = np.empty(mesh.n_nodes * n + 2)
            self._cc.expand(self._W, self._border, self.lu[0], self.lu[1], w, np.ascontiguousarray(b, float), out,
                            m, n)
            return out
        rhs = np.empty(self.nr)
        rhs[:ntst * n] = w[:, inner:].ravel()
        rhs[ntst * n:(ntst + 1) * n] = b[nc:nc + n]
        rhs[self.nr - 2:] = b[nc + n:nc + n + 2] - (self._border @ w[:, :inner, None]).sum(axis=0)[:, 0]
        red, _ = _GETRS(self.lu[0], self.lu[1], rhs)
        M = red[:-2].reshape(ntst + 1, n)
        dT, dp = red[-2], red[-1]
        Qi = self.Q[:, :inner, :]
        inner_vals = (w[:, :inner] - (Qi[:, :, :n] @ M[:-1, :, None])[:, :, 0]
                      - Qi[:, :, n] * dT - Qi[:, :, n + 1] * dp)
        out = np.empty(mesh.n_nodes * n + 2)
        nodes = out[:-2].reshape(mesh.n_nodes, n)
        nodes[::m] = M
        nodes[self._inner_idx] = inner_vals.reshape(ntst, m - 1, n)
        out[-2], out[-1] = dT, dp
        return out
