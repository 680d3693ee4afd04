r"""Orthogonal collocation of periodic orbits (AUTO's scheme), on a mesh that adapts to the orbit.

A periodic orbit of ``dz/dt = f(z; p)`` with period ``T`` is, in the rescaled time ``t / T`` on
``[0, 1]``, a solution of the boundary-value problem

.. math::  u'(\tau) = T f(u(\tau); p), \qquad u(1) = u(0), \qquad \int_0^1 u(\tau)\cdot v'(\tau)\,d\tau = 0,

the last row (the integral phase condition) fixing the orbit's phase against a reference orbit ``v``.
The mesh ``0 = tau_0 < ... < tau_NTST = 1`` splits ``[0, 1]`` into NTST intervals; on each, ``u`` is
the polynomial of degree NCOL through its values at NCOL + 1 equally spaced nodes (Lagrange
basis), and the differential equation holds at the NCOL Gauss–Legendre points of the interval.
Neighbouring intervals share their end node, so ``u`` is continuous; the unknowns are the
``NTST * NCOL + 1`` node values. At the mesh points the error is of order ``h^(2 NCOL)``
(superconvergence of Gauss collocation), elsewhere ``h^(NCOL + 1)``.

:class:`Mesh` holds the mesh and the fixed collocation matrices; it evaluates the orbit between
nodes, forms integrals (Gauss quadrature, exact for the products of two of its polynomials), and
moves an orbit to an adapted mesh that equidistributes ``|u^(NCOL+1)|^(1/(NCOL+1))`` (de Boor's
criterion, as AUTO's IAD does).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import numpy.typing as npt

from . import _kernel

__all__ = ["Mesh", "gauss_legendre", "lagrange_matrices"]

#: The collocation degrees AUTO allows (NCOL); above 7 the equally spaced nodes' basis loses accuracy.
NCOL_RANGE = (2, 7)


def gauss_legendre(m: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``m`` Gauss–Legendre points on ``[0, 1]`` (ascending) and their quadrature weights (sum 1)."""
    x, w = np.polynomial.legendre.leggauss(m)
    return (x + 1.0) / 2.0, w / 2.0


def lagrange_matrices(nodes: np.ndarray, at: np.ndarray, derivative: int = 0) -> np.ndarray:
    """``L[k, i]``: the ``derivative``-th derivative of the Lagrange polynomial of ``nodes[i]`` at ``at[k]``."""
    nodes, at = np.asarray(nodes, float), np.asarray(at, float)
    m = len(nodes)
    out = np.empty((len(at), m))
    for i in range(m):
        others = np.delete(nodes, i)
        coef = np.poly(others) / np.prod(nodes[i] - others)  # monomial coefficients, highest first
        out[:, i] = np.polyval(np.polyder(coef, derivative) if derivative else coef, at)
    return out


_Arrays9 = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                 np.ndarray]


@functools.lru_cache(maxsize=16)
def _unit_interval(m: int) -> _Arrays9:
    """The unit interval's nodes, Gauss points and weights, the basis at the Gauss points (values,
    derivatives), the NCOL-th derivative (a constant) from the node values, the values and derivatives
    stacked (2 NCOL, NCOL + 1), and the Gauss-quadrature matrices between node values ``G[a, b] = sum_k g_k
    Lc[k, a] Lc[k, b]`` and ``P[a, b] = sum_k g_k Lc[k, a] Ld[k, b]``; read-only arrays."""
    s = np.linspace(0.0, 1.0, m + 1)
    c, g = gauss_legendre(m)
    Lc, Ld = lagrange_matrices(s, c), lagrange_matrices(s, c, 1)
    out = (s, c, g, Lc, Ld, lagrange_matrices(s, np.zeros(1), m)[0], np.vstack([Lc, Ld]),
           (Lc.T * g) @ Lc, (Lc.T * g) @ Ld)
    for a in out:
        a.flags.writeable = False
    return out


@functools.lru_cache(maxsize=16)
def _denominators(m: int) -> np.ndarray:
    """``prod over l != i of (s_i - s_l)`` for the unit interval's NCOL + 1 equally spaced nodes ``s``: the Lagrange
    basis's denominators, shape (ncol + 1,), read-only."""
    s = np.linspace(0.0, 1.0, m + 1)
    den = np.array([np.prod(s[i] - np.delete(s, i)) for i in range(m + 1)])
    den.flags.writeable = False
    return den


@functools.lru_cache(maxsize=16)
def _layout(ntst: int, m: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A mesh's node indices per interval (ntst, ncol + 1), the same transposed (contiguous), and ones (ntst,):
    read-only, shared by the meshes of one size (an adapted mesh has its predecessor's)."""
    index = np.arange(ntst)[:, None] * m + np.arange(m + 1)[None, :]
    out = (index, np.ascontiguousarray(index.T), np.ones(ntst))
    for a in out:
        a.flags.writeable = False
    return out


class Mesh:
    """A collocation mesh: NTST intervals of ``[0, 1]``, NCOL + 1 equally spaced nodes and NCOL
    Gauss points in each.

    Attributes
    ----------
    tau:
        The mesh points, shape (ntst + 1,), ``tau[0] = 0``, ``tau[-1] = 1``.
    h:
        Interval lengths, shape (ntst,).
    Lc, Ld:
        Values and first derivatives of the interval's Lagrange basis at its Gauss points (per
        unit interval length), shape (ncol, ncol + 1).
    g:
        Gauss weights on the unit interval, shape (ncol,).
    """

    def __init__(self, ntst: int, ncol: int, tau: np.ndarray | None = None) -> None:
        self.ntst, self.ncol = int(ntst), int(ncol)
        self.tau = np.linspace(0.0, 1.0, self.ntst + 1) if tau is None else np.asarray(tau, float)
        self.h = np.diff(self.tau)
        m = self.ncol
        self.s, self.c, self.g, self.Lc, self.Ld, self.Dm, self._L2, self._G, self._P = _unit_interval(m)
        #: node index of local node i of interval j (read-only)
        self.index, self._index_t, self._ones = _layout(self.ntst, m)

    @property
    def n_nodes(self) -> int:
        """NTST * NCOL + 1 nodes (the first and last are both kept: periodicity is an equation)."""
        return self.ntst * self.ncol + 1

    def times(self) -> np.ndarray:
        """The nodes' rescaled times in ``[0, 1]``, shape (n_nodes,)."""
        t = self.tau[:-1, None] + self.h[:, None] * self.s[None, :-1]
        return np.append(t.ravel(), 1.0)

    def collocation_times(self) -> np.ndarray:
        """The Gauss points' rescaled times, shape (ntst, ncol)."""
        return self.tau[:-1, None] + self.h[:, None] * self.c[None, :]

    def blocks(self, u: np.ndarray) -> np.ndarray:
        """The node values per interval, shape (ntst, ncol + 1, n), from node values (n_nodes, n)."""
        return u[self.index]

    def at_collocation(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(u, du/dtau)`` at the Gauss points, each shape (ntst, ncol, n)."""
        both = self._local(self._L2, u)  # values and derivatives in one product
        m = self.ncol
        return both[:, :m], both[:, m:] / self.h[:, None, None]

    def values_and_derivatives(self, u: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """The orbit's values and derivatives (d/dtau per unit interval length, not yet divided by ``h``) at the Gauss
        points from its node values ``u`` (n_nodes, n): shape (2 ncol, ntst n), row ``k`` / ``ncol + k`` Gauss point
        ``k``'s, interval ``j``'s in columns ``j n .. j n + n - 1`` (:meth:`at_collocation` is this product, arranged
        per interval)."""
        return self._L2 @ u[self._index_t].reshape(self.ncol + 1, -1)

    def gauss_values(self, u: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """The orbit's values at the Gauss points from its node values ``u`` (n_nodes, n): shape (ncol, ntst, n), point
        ``k`` of interval ``j`` at ``[k, j]`` (the first half of :meth:`values_and_derivatives`)."""
        return (self.Lc @ u[self._index_t].reshape(self.ncol + 1, -1)).reshape(self.ncol, self.ntst, -1)

    def quadrature(self) -> npt.NDArray[np.float64]:
        """The Gauss quadrature's weights of the whole mesh, ``g_k h_j`` at ``[k, j]`` (ncol, ntst): the weights of
        :meth:`gauss_values`' points in the integral over [0, 1] (read-only, made once per mesh)."""
        q = getattr(self, "_quadrature", None)
        if q is None:
            q = self._quadrature = self.g[:, None] * self.h[None, :]
            q.flags.writeable = False
        return q

    def _local(self, A: np.ndarray, u: np.ndarray) -> np.ndarray:
        """``A @ (interval j's node values)`` for every interval, shape (ntst, len(A), n): one matrix product of
        ``A`` with all intervals' node values side by side (a stack of small products costs far more)."""
        n = u.shape[1]
        out = A @ u[self._index_t].reshape(self.ncol + 1, -1)  # (len(A), ntst n)
        return out.reshape(len(A), self.ntst, n).transpose(1, 0, 2)

    def gram_row(self, w: np.ndarray) -> np.ndarray:
        """``r`` with ``r . u = integral of u(tau) . w(tau) over [0, 1]`` for every orbit ``u`` on this mesh
        (node values, flattened like ``u``); ``w`` given by its node values (n_nodes, n). Gauss
        quadrature at the NCOL points: exact to degree 2 NCOL - 1, so this is the collocation's own
        inner product (as AUTO's), not the exact integral of the two degree-NCOL polynomials."""
        return self._interval_rows(self._G, self.h, w)

    def mean(self, u: np.ndarray) -> np.ndarray:
        """The orbit's time average over [0, 1] (Gauss quadrature on every interval), shape (n,)."""
        uc, _ = self.at_collocation(u)
        return np.einsum("j,k,jkn->n", self.h, self.g, uc)

    def phase_row(self, v: np.ndarray) -> np.ndarray:
        """``r`` with ``r . u = integral of u . v'`` over ``[0, 1]`` (exact: degree 2 NCOL - 1), ``v`` by its node values."""
        # int u . v' over an interval of length h: h sum_k g_k u(c_k) . (Ld v)(c_k) / h
        return self._interval_rows(self._P, self._ones, v)

    def _interval_rows(self, A: npt.NDArray[np.float64], c: npt.NDArray[np.float64],
                       w: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """``c_j A (interval j's node values of w)`` summed onto the nodes, flattened like ``w`` (n_nodes, n)."""
        cc = _kernel.condensation()
        if cc is None:
            return self._to_nodes(c[:, None, None] * self._local(A, w))
        out = np.empty((self.n_nodes, w.shape[1]))
        cc.interval_rows(A, c, w, out)
        return out.ravel()

    def _to_nodes(self, local: np.ndarray) -> np.ndarray:
        """Per-interval node rows (ntst, ncol + 1, n) summed onto the nodes (neighbours share their end node),
        flattened like the orbit's node values."""
        m, n = self.ncol, local.shape[2]
        r = np.empty((self.n_nodes, n))
        r[:-1] = local[:, :m].reshape(-1, n)  # each interval's nodes but its last: every node but the final once
        r[-1] = 0.0
        r[m::m] += local[:, m]
        return r.ravel()

    def evaluate(self, u: np.ndarray, times: np.ndarray) -> np.ndarray:
        """The orbit (node values (n_nodes, n)) at the rescaled ``times`` (wrapped into [0, 1]), shape (len(times), n)."""
        t = np.mod(np.asarray(times, float), 1.0)
        cc = _kernel.condensation()
        if cc is not None:  # the same basis and sums, one compiled call
            out = np.empty((len(t), u.shape[1]))
            cc.lagrange_values(u, self.tau, self.s, _denominators(self.ncol), t, out)
            return out
        j = np.clip(np.searchsorted(self.tau, t, side="right") - 1, 0, self.ntst - 1)
        local = (t - self.tau[j]) / self.h[j]
        # the Lagrange basis at every point at once: prod over l != i of (x - s_l) / (s_i - s_l), the products over
        # l < i and l > i by running products from either end
        d = local[:, None] - self.s[None, :]
        one = np.ones((len(t), 1))
        left = np.cumprod(np.hstack([one, d[:, :-1]]), axis=1)
        right = np.cumprod(np.hstack([one, d[:, :0:-1]]), axis=1)[:, ::-1]
        basis = left * right / _denominators(self.ncol)
        return np.einsum("pi,pin->pn", basis, u[self.index[j]])

    def extremes(self, u: npt.NDArray[np.float64]) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Each state's smallest and largest value over the orbit ``u`` (node values (n_nodes, n)): shapes (n,), (n,).

        The extremes over the nodes and Gauss points, refined: through each extreme sample and its neighbours in time a
        parabola, whose vertex's time the orbit is evaluated at (the larger, or smaller, of the two values counts).
        Between samples a distance ``d`` apart the samples alone miss a smooth extreme by up to ``|u''| d^2 / 8``,
        which depends on where the adapted mesh happens to put them (1e-4 of a relaxation orbit's amplitude at 20
        intervals); the vertex's time is off by ``O(d^2)``, the value there by the square of that."""
        n = u.shape[1]
        order, t = self._time_order()
        every = np.vstack([u[:-1], self.gauss_values(u).transpose(1, 0, 2).reshape(-1, n)])[order]  # (P, n) in time
        P = len(t)
        k = np.arange(n)
        i = np.concatenate([every.argmin(axis=0), every.argmax(axis=0)])  # (2n,): state k's min, then its max
        kk = np.concatenate([k, k])
        v0, v1, v2 = every[(i - 1) % P, kk], every[i, kk], every[(i + 1) % P, kk]
        x0 = (t[(i - 1) % P] - t[i] + 0.5) % 1.0 - 0.5  # the neighbours' times from the sample's (the orbit is periodic)
        x2 = (t[(i + 1) % P] - t[i] + 0.5) % 1.0 - 0.5
        q0, q2 = (v0 - v1) / x0, (v2 - v1) / x2  # p(x) = v1 + b x + a x^2: b + a x0 = q0, b + a x2 = q2
        a = (q2 - q0) / (x2 - x0)
        x = np.zeros(2 * n)  # the vertex, -b / (2 a), within the neighbours (the sample itself where the parabola is flat)
        np.divide(q0 - a * x0, -2.0 * a, out=x, where=a != 0)
        np.clip(x, x0, x2, out=x)
        x += t[i]
        v = self.evaluate(u, x)[np.arange(2 * n), kk]
        return np.fmin(v1[:n], v[:n]), np.fmax(v1[n:], v[n:])  # fmin, fmax: a value that is not finite never counts

    def _time_order(self) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.float64]]:
        """The nodes but the last (time 1 is time 0) and then the Gauss points (interval by interval): the order that
        sorts them in time, and their sorted times in [0, 1). Made once per mesh."""
        cached = getattr(self, "_order", None)
        if cached is None:
            times = np.concatenate([self.times()[:-1], self.collocation_times().ravel()])
            order = np.argsort(times, kind="stable")
            cached = self._order = (order, times[order])
        return cached

    def adapted(self, u: np.ndarray) -> Mesh:
        """A mesh of the same size equidistributing ``|u^(NCOL+1)|^(1/(NCOL+1))`` for the orbit ``u``.

        The NCOL-th derivative is constant on each interval; its jumps between neighbours (the orbit
        is periodic: the last interval's neighbour is the first) divided by the mean of their
        lengths estimate the (NCOL+1)-th derivative at each mesh point (de Boor, as AUTO does).
        """
        m, h = self.ncol, self.h
        dm = (self.Dm @ u[self._index_t].reshape(m + 1, -1)).reshape(self.ntst, -1) / h[:, None] ** m
        # the neighbour of each interval and mesh point by slices (np.roll's copies cost more than the arithmetic)
        diff = np.empty_like(dm)
        np.subtract(dm[1:], dm[:-1], out=diff[:-1])
        np.subtract(dm[:1], dm[-1:], out=diff[-1:])
        both = np.empty_like(h)
        np.add(h[:-1], h[1:], out=both[:-1])
        both[-1] = h[-1] + h[0]
        jump = np.sqrt(np.add.reduce(diff * diff, axis=1)) / (0.5 * both)  # at tau_(j+1)
        per = np.empty_like(jump)  # per interval: the mean of its two ends
        np.add(jump[1:], jump[:-1], out=per[1:])
        per[0] = jump[0] + jump[-1]
        per *= 0.5
        density = per ** (1.0 / (m + 1))
        density += 1e-3 * max(float(np.mean(density)), 1e-300)  # never an interval of zero weight
        cum = np.concatenate([[0.0], np.cumsum(density * self.h)])
        targets = np.linspace(0.0, cum[-1], self.ntst + 1)
        tau = np.interp(targets, cum, self.tau)
        tau[0], tau[-1] = 0.0, 1.0
        return Mesh(self.ntst, self.ncol, tau)

    def moved(self, u: np.ndarray, other: Mesh) -> np.ndarray:
        """The orbit ``u`` (node values on this mesh) at the nodes of ``other``."""
        return np.vstack([self.evaluate(u, other.times()[:-1]), u[-1:]])

    def uniformity(self) -> float:
        """Longest over shortest interval (1 for a uniform mesh)."""
        return float(self.h.max() / self.h.min()) if math.isfinite(self.h.min()) and self.h.min() > 0 else math.inf
