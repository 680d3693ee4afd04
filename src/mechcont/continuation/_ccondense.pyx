# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""The condensation of parameters (:mod:`._condensation`), compiled (optional).

The same maths as :class:`~._condensation.CondensedLU`'s NumPy path, in C loops over the stacked
arrays: each interval's block ``S_j`` (``NCOL n`` square, a few rows) factored by LU with partial
pivoting and solved for the first node's, T's, p's columns and the right-hand side; the reduced
matrix assembled; and the reduced system factored by a structured elimination. NumPy's stacked
solve and LAPACK spend microseconds of call overhead per block or system on a few hundred flops of
arithmetic; here a factorisation is one call.

The reduced matrix (``(NTST + 1) n + 2`` rows: interval ``j``'s rows over ``M_j``, ``M_(j+1)``, T and
p; the periodicity rows over ``M_0`` and ``M_NTST``; two dense border rows) is eliminated column by
column with row pivoting among the rows that can hold the column (the pivot's interval block and the
periodicity rows), so that every row keeps its nonzeros within its own and the next interval's columns,
``M_NTST``'s and T's and p's: the work is ``O(NTST n^3)``, not ``O((NTST n)^3)``. The two border rows take
part in the choice of pivots only in the last ``n + 2`` columns (they are dense; as pivots earlier they
would fill every row), where the near-singular direction of ``I - monodromy`` is resolved; LAPACK's dense
LU pivots on them earlier, so the two paths agree to rounding, not bit for bit
(``tests/test_condensation_kernel.py``).

Built by ``pip install`` beside :mod:`._ckernel` (``setup.py``: an optional extension); without it, or
with ``MECHCONT_PURE_PYTHON=1``, :mod:`._condensation` runs NumPy and LAPACK.
"""

from libc.math cimport fabs, isfinite
from libc.stdlib cimport free, malloc
from libc.string cimport memset

import numpy as np


cdef int _lu(double *A, int *piv, Py_ssize_t m) noexcept nogil:
    """LU with partial pivoting of the square ``A`` (m x m, row-major) in place (LAPACK's layout: unit L below);
    0, or 1 if singular."""
    cdef Py_ssize_t k, i, c, p
    cdef double big, t, pivot
    cdef double *rk
    cdef double *ri
    for k in range(m):
        p = k
        big = fabs(A[k * m + k])
        for i in range(k + 1, m):
            if fabs(A[i * m + k]) > big:
                big = fabs(A[i * m + k])
                p = i
        piv[k] = <int>p
        if big == 0.0:
            return 1
        rk = A + k * m
        if p != k:
            ri = A + p * m
            for c in range(m):
                t = rk[c]
                rk[c] = ri[c]
                ri[c] = t
        pivot = rk[k]
        for i in range(k + 1, m):
            ri = A + i * m
            t = ri[k] / pivot
            ri[k] = t
            if t != 0.0:
                for c in range(k + 1, m):
                    ri[c] -= t * rk[c]
    return 0


cdef void _lu_solve(const double *A, const int *piv, double *B, Py_ssize_t m, Py_ssize_t r) noexcept nogil:
    """``B`` (m x r, row-major) overwritten by ``A^-1 B`` from :func:`_lu`'s factors."""
    cdef Py_ssize_t k, i, c, p
    cdef double t
    cdef double *bk
    cdef double *bi
    for k in range(m):
        p = piv[k]
        if p != k:
            bk = B + k * r
            bi = B + p * r
            for c in range(r):
                t = bk[c]
                bk[c] = bi[c]
                bi[c] = t
    for k in range(m):
        bk = B + k * r
        for i in range(k + 1, m):
            t = A[i * m + k]
            if t != 0.0:
                bi = B + i * r
                for c in range(r):
                    bi[c] -= t * bk[c]
    for k in range(m - 1, -1, -1):
        bk = B + k * r
        for i in range(k + 1, m):
            t = A[k * m + i]
            if t != 0.0:
                bi = B + i * r
                for c in range(r):
                    bk[c] -= t * bi[c]
        t = 1.0 / A[k * m + k]
        for c in range(r):
            bk[c] *= t


def collocation_blocks(const double[:, :, :, :, ::1] D, const double[:, ::1] Lc, const double[:, :, :, ::1] Fz, double T,
                       double[:, :, ::1] S, double[:, :, ::1] L):
    """The intervals' collocation blocks into ``S`` (ntst, ncol n, ncol n: inner and last nodes) and ``L`` (ntst,
    ncol n, n: first node): ``D[j, k, a, i, b] - T Lc[k, i] Fz[j, k, a, b]`` for Gauss point ``k``, node ``i``
    (``D`` the fixed part d/dtau, (ntst, ncol, n, ncol + 1, n); ``Lc`` the basis at the Gauss points; ``Fz`` the
    rates' Jacobian at them, (ntst, ncol, n, n))."""
    cdef Py_ssize_t ntst = D.shape[0], m = D.shape[1], n = D.shape[2], j, k, a, i, b
    cdef double c
    if (D.shape[3] != m + 1 or D.shape[4] != n or Lc.shape[0] != m or Lc.shape[1] != m + 1
            or Fz.shape[0] != ntst or Fz.shape[1] != m or Fz.shape[2] != n or Fz.shape[3] != n
            or S.shape[0] != ntst or S.shape[1] != m * n or S.shape[2] != m * n
            or L.shape[0] != ntst or L.shape[1] != m * n or L.shape[2] != n):
        raise ValueError("collocation block shapes disagree")
    with nogil:
        for j in range(ntst):
            for k in range(m):
                for a in range(n):
                    for i in range(m + 1):
                        c = T * Lc[k, i]
                        for b in range(n):
                            if i == 0:
                                L[j, k * n + a, b] = D[j, k, a, 0, b] - c * Fz[j, k, a, b]
                            else:
                                S[j, k * n + a, (i - 1) * n + b] = D[j, k, a, i, b] - c * Fz[j, k, a, b]


def block_factor_solve(double[:, :, ::1] S, int[:, ::1] piv, double[:, :, ::1] W):
    """Each block ``S[j]`` (square) LU-factored in place (pivots in ``piv[j]``) and ``W[j]`` overwritten by
    ``S[j]^-1 W[j]``. Returns -1, or the first singular block's index."""
    cdef Py_ssize_t j, m = S.shape[1], r = W.shape[2], bad = -1
    if S.shape[2] != m or W.shape[1] != m or piv.shape[1] != m or W.shape[0] != S.shape[0] or piv.shape[0] < S.shape[0]:
        raise ValueError("block shapes disagree")
    with nogil:
        for j in range(S.shape[0]):
            if _lu(&S[j, 0, 0], &piv[j, 0], m):
                bad = j
                break
            _lu_solve(&S[j, 0, 0], &piv[j, 0], &W[j, 0, 0], m, r)
    return bad


def block_solve(double[:, :, ::1] S, int[:, ::1] piv, double[:, :, ::1] B):
    """``B[j]`` (ncol n, r) overwritten by ``S[j]^-1 B[j]`` from :func:`block_factor_solve`'s factors."""
    cdef Py_ssize_t j, m = S.shape[1], r = B.shape[2]
    if B.shape[1] != m or B.shape[0] != S.shape[0]:
        raise ValueError("block shapes disagree")
    with nogil:
        for j in range(S.shape[0]):
            _lu_solve(&S[j, 0, 0], &piv[j, 0], &B[j, 0, 0], m, r)


def reduced_matrix(double[:, :, ::1] Y, double[:, :, ::1] binner, double[:, :, ::1] mesh_points,
                   double[:, ::1] TP, double[:, ::1] K, int n):
    """The reduced matrix into ``K`` (zeros, ``(ntst + 1) n + 2`` square) from ``Y`` (ntst, ncol n, >= n + 2), the
    condensed first node's, T's and p's columns, and the border rows (:class:`~._condensation.Border`'s ``inner``,
    ``mesh_points``, ``TP``)."""
    with nogil:
        _reduced_matrix(Y, binner, mesh_points, TP, K, n)


cdef void _reduced_matrix(const double[:, :, ::1] Y, const double[:, :, ::1] binner, const double[:, :, ::1] mesh_points,
                          const double[:, ::1] TP, double[:, ::1] K, Py_ssize_t n) noexcept nogil:
    cdef Py_ssize_t ntst = Y.shape[0], mn = Y.shape[1], inner = mn - n, nr = K.shape[0]
    cdef Py_ssize_t j, a, b, s, i
    cdef double t
    if True:
        for j in range(ntst):
            for a in range(n):
                for b in range(n):
                    K[j * n + a, j * n + b] = Y[j, inner + a, b]
                K[j * n + a, (j + 1) * n + a] = 1.0
                K[j * n + a, nr - 2] = Y[j, inner + a, n]
                K[j * n + a, nr - 1] = Y[j, inner + a, n + 1]
        for a in range(n):
            K[ntst * n + a, a] = -1.0
            K[ntst * n + a, ntst * n + a] = 1.0
        for s in range(2):
            for b in range(n):
                K[nr - 2 + s, ntst * n + b] = mesh_points[s, ntst, b]
            K[nr - 2 + s, nr - 2] = TP[s, 0]
            K[nr - 2 + s, nr - 1] = TP[s, 1]
            for j in range(ntst):
                for b in range(n + 2):
                    t = 0.0
                    for i in range(inner):
                        t += binner[j, s, i] * Y[j, i, b]
                    if b < n:
                        K[nr - 2 + s, j * n + b] = mesh_points[s, j, b] - t
                    else:
                        K[nr - 2 + s, nr - 2 + b - n] -= t


cdef inline Py_ssize_t _band_end(Py_ssize_t k, Py_ssize_t n, Py_ssize_t last, Py_ssize_t blocks) noexcept nogil:
    # the end of column k's band: the end of its interval block's rows (``blocks`` = 1), or of the next
    # block's columns (``blocks`` = 2), never past the periodicity rows / M_NTST's columns (``last``)
    cdef Py_ssize_t e = (k // n + blocks) * n
    return e if e < last else last


def reduced_factor(double[:, ::1] K, int[::1] piv, int n):
    """The reduced matrix ``K`` factored in place by the structured elimination (see the module docstring).
    Returns 0, 1 if singular, 2 if not finite."""
    cdef int status
    if K.shape[1] != K.shape[0] or piv.shape[0] != K.shape[0] or n < 1 or (K.shape[0] - 2) % n or K.shape[0] < 2 * n + 2:
        raise ValueError("not a reduced matrix of n-row blocks")
    with nogil:
        status = _reduced_factor(K, piv, n)
    return status


cdef int _reduced_factor(double[:, ::1] K, int[::1] piv, Py_ssize_t n) noexcept nogil:
    cdef Py_ssize_t nr = K.shape[0], last = nr - 2 - n, k, i, c, p, re, ce, lo
    cdef double big, t, pivot, total = 0.0
    if True:
        for k in range(nr):
            re = _band_end(k, n, last, 1) if k < last else k
            ce = _band_end(k, n, last, 2) if k < last else k
            lo = last if last > k else k  # the bottom rows, or the rest once the band is done
            p = k
            big = fabs(K[k, k])
            for i in range(k + 1, re):
                if fabs(K[i, k]) > big:
                    big = fabs(K[i, k])
                    p = i
            # the periodicity rows always; the border rows only in the last columns (they are dense)
            for i in range(lo if lo > k else k + 1, nr if k >= last else nr - 2):
                if fabs(K[i, k]) > big:
                    big = fabs(K[i, k])
                    p = i
            piv[k] = <int>p
            if big == 0.0:
                return 1
            if p != k:
                for c in range(k, ce):
                    t = K[k, c]
                    K[k, c] = K[p, c]
                    K[p, c] = t
                for c in range(lo, nr):
                    t = K[k, c]
                    K[k, c] = K[p, c]
                    K[p, c] = t
            pivot = K[k, k]
            for c in range(k, ce):
                total += K[k, c]
            for c in range(lo, nr):
                total += K[k, c]
            for i in range(k + 1, re):
                _eliminate(K, i, k, pivot, ce, lo, nr)
            for i in range(lo if lo > k else k + 1, nr):
                _eliminate(K, i, k, pivot, ce, lo, nr)
            # the multipliers too: every entry of the factors has been summed
            for i in range(k + 1, re):
                total += K[i, k]
            for i in range(lo if lo > k else k + 1, nr):
                total += K[i, k]
    return 0 if isfinite(total) else 2


cdef inline void _eliminate(double[:, ::1] K, Py_ssize_t i, Py_ssize_t k, double pivot, Py_ssize_t ce,
                            Py_ssize_t lo, Py_ssize_t nr) noexcept nogil:
    cdef double t = K[i, k] / pivot
    cdef Py_ssize_t c
    K[i, k] = t
    if t == 0.0:
        return
    for c in range(k + 1, ce):
        K[i, c] -= t * K[k, c]
    for c in range(lo if lo > k else k + 1, nr):
        K[i, c] -= t * K[k, c]


def reduced_solve(double[:, ::1] K, int[::1] piv, int n, double[::1] b):
    """``b`` overwritten by the solution of the reduced system from :func:`reduced_factor`'s factors."""
    with nogil:
        _reduced_solve(K, piv, n, &b[0])


cdef void _reduced_solve(double[:, ::1] K, int[::1] piv, Py_ssize_t n, double *b) noexcept nogil:
    cdef Py_ssize_t nr = K.shape[0], last = nr - 2 - n, k, i, c, p, re, ce, lo
    cdef double t
    if True:
        for k in range(nr):
            re = _band_end(k, n, last, 1) if k < last else k
            lo = last if last > k else k
            p = piv[k]
            if p != k:
                t = b[k]
                b[k] = b[p]
                b[p] = t
            t = b[k]
            if t != 0.0:
                for i in range(k + 1, re):
                    b[i] -= K[i, k] * t
                for i in range(lo if lo > k else k + 1, nr):
                    b[i] -= K[i, k] * t
        for k in range(nr - 1, -1, -1):
            ce = _band_end(k, n, last, 2) if k < last else k
            lo = last if last > k else k
            t = b[k]
            for c in range(k + 1, ce):
                t -= K[k, c] * b[c]
            for c in range(lo if lo > k else k + 1, nr):
                t -= K[k, c] * b[c]
            b[k] = t / K[k, k]


def expand(double[:, :, ::1] Y, double[:, :, ::1] binner, double[:, ::1] K, int[::1] piv, double[:, :] w,
           double[::1] b, double[::1] out, int ncol, int n):
    """The whole solution into ``out`` (nodes, then T, p) of ``J x = b`` from the factors: the reduced right-hand side
    from ``w`` (the condensed collocation part, ntst x ncol n) and ``b``'s periodicity, phase and closing rows,
    the reduced solve, and the inner nodes from the mesh points."""
    cdef double[::1] red = np.empty(K.shape[0])
    with nogil:
        _expand(Y, binner, K, piv, w, b, 1.0, out, ncol, n, &red[0])


cdef void _expand(const double[:, :, ::1] Y, const double[:, :, ::1] binner, double[:, ::1] K, int[::1] piv,
                  const double[:, :] w, const double[::1] b, double sign, double[::1] out, Py_ssize_t ncol,
                  Py_ssize_t n, double *red) noexcept nogil:
    # expand's work for the right-hand side ``sign b`` (sign +-1: exact), ``red`` the reduced system's scratch
    cdef Py_ssize_t ntst = Y.shape[0], mn = Y.shape[1], inner = mn - n, nr = K.shape[0]
    cdef Py_ssize_t nc = ntst * mn, j, a, s, i
    cdef double dT, dp, t
    for j in range(ntst):
        for a in range(n):
            red[j * n + a] = w[j, inner + a]
    for a in range(n):
        red[ntst * n + a] = sign * b[nc + a]
    for s in range(2):
        t = sign * b[nc + n + s]
        for j in range(ntst):
            for i in range(inner):
                t -= binner[j, s, i] * w[j, i]
        red[nr - 2 + s] = t
    _reduced_solve(K, piv, n, red)
    dT = red[nr - 2]
    dp = red[nr - 1]
    for j in range(ntst):
        for a in range(n):
            out[j * ncol * n + a] = red[j * n + a]
        for i in range(inner):
            t = w[j, i] - Y[j, i, n] * dT - Y[j, i, n + 1] * dp
            for a in range(n):
                t -= Y[j, i, a] * red[j * n + a]
            out[j * ncol * n + n + i] = t
    for a in range(n):
        out[ntst * ncol * n + a] = red[ntst * n + a]
    out[out.shape[0] - 2] = dT
    out[out.shape[0] - 1] = dp


def factor_residual(const double[:, ::1] Ld, const double[:, ::1] Lc, const double[:, :, :] Fz,
                    const double[:, :] F, const double[:, :] Fp, const double[:, :] Y, const double[::1] h,
                    const double[::1] X,
                    double phase_value, double closing_value, double T, double[:, :, ::1] binner,
                    double[:, :, ::1] mesh_points, double[:, ::1] TP,
                    double[:, :, ::1] S, int[:, ::1] piv, double[:, :, ::1] W, double[:, ::1] K, int[::1] rpiv,
                    double[::1] res, double[::1] dX, double[::1] norms):
    """One Newton iteration's linear algebra in one call: the BVP's residual into ``res`` (collocation ``du - T F``,
    periodicity ``X``'s last node minus its first, the phase and closing rows' values as given), the collocation
    blocks (as :func:`collocation_blocks`, their fixed part ``Ld[k, i] / h[j]`` on the diagonal of the n x n block
    of Gauss point ``k`` and node ``i`` of interval ``j``: ``Ld`` the basis's derivatives at the Gauss points (ncol,
    ncol + 1), ``h`` the intervals' lengths) into ``S`` and ``W[:, :, :n]``, ``W``'s T, p and right-hand-side columns
    (``-F``, ``-T Fp``, ``-res``), the blocks factored and solved (:func:`block_factor_solve`), the reduced matrix
    (:func:`reduced_matrix`, ``K`` zeroed here) factored (:func:`reduced_factor`). The Gauss points in the order of
    :meth:`~._collocation.Mesh.values_and_derivatives` (point ``k`` of interval ``j`` in row ``k ntst + j``):
    ``F``, ``Fp`` (ncol ntst, n) and ``Fz`` (ncol ntst, n, n) there, any strides; ``Y`` that method's values and
    derivatives (2 ncol, ntst n), ``du = Y[ncol + k, j n + a] / h[j]``. The Newton correction, the solution of
    ``J dX = -res`` (:func:`expand`), into ``dX``; into ``norms`` (2,) the correction's largest ``|dX_i|`` (NaN when
    any is) and the corrected unknowns' largest ``|X_i + dX_i|`` (the Newton loop's tests). Returns 0, 1 when the
    residual or the rates' derivatives are not finite (nothing factored), 2 when a block or the reduced system is
    singular (or its factors not finite)."""
    cdef Py_ssize_t ntst = h.shape[0], m = Ld.shape[0], n = F.shape[1], mn = m * n, nc = ntst * mn
    cdef Py_ssize_t nr = K.shape[0], size = X.shape[0]
    cdef int status
    cdef double *red
    if (Ld.shape[1] != m + 1 or Lc.shape[0] != m or Lc.shape[1] != m + 1
            or Fz.shape[0] != ntst * m or Fz.shape[1] != n or Fz.shape[2] != n or F.shape[0] != ntst * m
            or Fp.shape[0] != ntst * m or Fp.shape[1] != n or Y.shape[0] != 2 * m
            or Y.shape[1] != ntst * n or S.shape[0] != ntst or S.shape[1] != mn
            or S.shape[2] != mn or W.shape[0] != ntst or W.shape[1] != mn or W.shape[2] != n + 3
            or piv.shape[0] != ntst or piv.shape[1] != mn or nr != (ntst + 1) * n + 2 or K.shape[1] != nr
            or rpiv.shape[0] != nr or res.shape[0] != size or size != (ntst * m + 1) * n + 2
            or dX.shape[0] != size or norms.shape[0] != 2):
        raise ValueError("collocation system shapes disagree")
    cdef const double[:, :] w = W[:, :, n + 2]
    cdef Py_ssize_t i
    cdef double a, step = 0.0, big = 0.0
    with nogil:
        status = _residual_blocks(Ld, Lc, Fz, F, Fp, Y, h, X, phase_value, closing_value, T, S, piv, W, K, res)
        if status == 0:
            _reduced_matrix(W, binner, mesh_points, TP, K, n)
            if _reduced_factor(K, rpiv, n) != 0:
                status = 2
            else:
                red = <double *> malloc(nr * sizeof(double))
                if red == NULL:
                    status = 3
                else:
                    _expand(W, binner, K, rpiv, w, res, -1.0, dX, m, n, red)
                    free(red)
                    for i in range(size):
                        a = fabs(dX[i])
                        if not a <= step:  # larger, or NaN (which then stays)
                            step = a
                            if a != a:
                                break
                        a = fabs(X[i] + dX[i])
                        if a > big:
                            big = a
                    norms[0] = step
                    norms[1] = big
    if status == 3:
        raise MemoryError()
    return status


cdef int _residual_blocks(const double[:, ::1] Ld, const double[:, ::1] Lc, const double[:, :, :] Fz,
                          const double[:, :] F, const double[:, :] Fp, const double[:, :] Y, const double[::1] h,
                          const double[::1] X,
                          double phase_value, double closing_value, double T, double[:, :, ::1] S,
                          int[:, ::1] piv, double[:, :, ::1] W, double[:, ::1] K, double[::1] res) noexcept nogil:
    # factor_residual's work up to the reduced matrix: 0, 1 (not finite) or 2 (a singular block)
    cdef Py_ssize_t ntst = h.shape[0], m = Ld.shape[0], n = F.shape[1], mn = m * n, nc = ntst * mn
    cdef Py_ssize_t nr = K.shape[0], size = X.shape[0], nn = size - 2, j, k, a, i, b, r, q
    cdef double c, d, total = 0.0, t
    cdef double *row
    for j in range(ntst):
        for k in range(m):
            q = k * ntst + j
            for a in range(n):
                r = k * n + a
                t = Y[m + k, j * n + a] / h[j] - T * F[q, a]
                res[j * mn + r] = t
                total += t + Fp[q, a]
                W[j, r, n] = -F[q, a]
                W[j, r, n + 1] = -T * Fp[q, a]
                W[j, r, n + 2] = -t
                for b in range(n):
                    total += Fz[q, a, b]
    for a in range(n):
        res[nc + a] = X[nn - n + a] - X[a]
        total += res[nc + a]
    res[size - 2] = phase_value
    res[size - 1] = closing_value
    total += phase_value + closing_value
    if not isfinite(total):
        return 1
    # the blocks D - T Lc Fz, D the fixed part d/dtau: Ld[k, i] / h[j] times the identity (its off-diagonal zeros
    # minus T Lc Fz as NumPy's broadcast of the identity gives them)
    for j in range(ntst):
        for k in range(m):
            q = k * ntst + j
            for a in range(n):
                r = k * n + a
                for i in range(m + 1):
                    c = T * Lc[k, i]
                    d = Ld[k, i] / h[j]
                    row = &W[j, r, 0] if i == 0 else &S[j, r, (i - 1) * n]
                    for b in range(n):
                        row[b] = (d if a == b else 0.0) - c * Fz[q, a, b]
    for j in range(ntst):
        if _lu(&S[j, 0, 0], &piv[j, 0], mn):
            return 2
        _lu_solve(&S[j, 0, 0], &piv[j, 0], &W[j, 0, 0], mn, n + 3)
    memset(&K[0, 0], 0, nr * nr * sizeof(double))
    return 0


def interval_rows(const double[:, ::1] A, const double[::1] c, const double[:, :] w, double[:, ::1] out):
    """``out`` (ntst ncol + 1, n) = the per-interval rows ``c_j A (interval j's node values of w)`` summed onto the
    nodes (neighbours share their end node): :meth:`~._collocation.Mesh.gram_row` and ``phase_row``'s sums, with
    ``A`` (ncol + 1 square) their quadrature matrix."""
    cdef Py_ssize_t ntst = c.shape[0], m = A.shape[0] - 1, n = w.shape[1], j, a, b, q
    cdef double s
    if A.shape[1] != m + 1 or w.shape[0] != ntst * m + 1 or out.shape[0] != w.shape[0] or out.shape[1] != n:
        raise ValueError("interval rows' shapes disagree")
    with nogil:
        for q in range(n):
            for a in range(w.shape[0]):
                out[a, q] = 0.0
        for j in range(ntst):
            for a in range(m + 1):
                for q in range(n):
                    s = 0.0
                    for b in range(m + 1):
                        s += A[a, b] * w[j * m + b, q]
                    out[j * m + a, q] += c[j] * s


def transfer_product(const double[:, :, ::1] Y, int n, double[:, ::1] M):
    """``M`` (n, n) = ``Phi_(ntst-1) ... Phi_0``, the monodromy matrix, from the condensed first-node columns ``Y``
    (ntst, ncol n, >= n): ``Phi_j = -Y[j, last node's rows, :n]``."""
    cdef Py_ssize_t ntst = Y.shape[0], inner = Y.shape[1] - n, j, a, b, k
    cdef double s
    cdef double[:, ::1] tmp = np.empty((n, n))
    if M.shape[0] != n or M.shape[1] != n or Y.shape[2] < n or inner < 0:
        raise ValueError("transfer shapes disagree")
    with nogil:
        for a in range(n):
            for b in range(n):
                M[a, b] = -Y[0, inner + a, b]
        for j in range(1, ntst):
            for a in range(n):
                for b in range(n):
                    s = 0.0
                    for k in range(n):
                        s -= Y[j, inner + a, k] * M[k, b]
                    tmp[a, b] = s
            for a in range(n):
                for b in range(n):
                    M[a, b] = tmp[a, b]


def lagrange_values(const double[:, :] u, const double[::1] tau, const double[::1] s, const double[::1] den,
                    const double[::1] t, double[:, ::1] out):
    """The orbit ``u`` (node values, ntst ncol + 1 rows) at the rescaled times ``t`` (in [0, 1]) into ``out`` (len(t),
    n): :meth:`~._collocation.Mesh.evaluate`'s sums, ``tau`` the mesh, ``s`` the unit interval's nodes and ``den``
    the basis's denominators (:func:`~._collocation._denominators`)."""
    cdef Py_ssize_t ntst = tau.shape[0] - 1, m = s.shape[0] - 1, n = u.shape[1], p, j, lo, hi, mid, i, l, a
    cdef double x, local, left, right, v
    cdef double b[16]
    if m + 1 > 16 or den.shape[0] != m + 1 or u.shape[0] != ntst * m + 1 or out.shape[0] != t.shape[0] \
            or out.shape[1] != n or ntst < 1:
        raise ValueError("evaluation shapes disagree")
    with nogil:
        for p in range(t.shape[0]):
            x = t[p]
            lo = 0  # the first mesh point above x (numpy's searchsorted, side="right")
            hi = ntst + 1
            while lo < hi:
                mid = (lo + hi) // 2
                if tau[mid] <= x:
                    lo = mid + 1
                else:
                    hi = mid
            j = lo - 1
            if j < 0:
                j = 0
            elif j > ntst - 1:
                j = ntst - 1
            local = (x - tau[j]) / (tau[j + 1] - tau[j])
            for i in range(m + 1):
                left = 1.0
                for l in range(i):
                    left = left * (local - s[l])
                right = 1.0
                for l in range(m, i, -1):
                    right = right * (local - s[l])
                b[i] = left * right / den[i]
            for a in range(n):
                v = 0.0
                for i in range(m + 1):
                    v += b[i] * u[j * m + i, a]
                out[p, a] = v
