# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""The corrector and tangent of :class:`~._palc.PseudoArclength`, compiled (optional).

The same algorithm as ``PseudoArclength._correct`` and ``PseudoArclength.tangent`` (read
their docstrings for the maths), run without the Python interpreter between the model's
compiled residual/Jacobian and the linear solves. On a small model (the overcentre: six
equations) a Newton iteration in Python costs about ten times the work it does: argument
checks, small temporary arrays and the NumPy calls around a 7 x 7 solve. Here one call
takes a whole step: predictor, Newton on the bordered system, the new tangent, and the
branch-point test function from the tangent system's factors.

The model is called through the C entry point SymEngine gives every compiled function
(``Lambdify.as_ctypes``): ``void f(double *out, const double *in, void *data)``; a problem
without one (a fold curve, whose rows include a determinant) has its ``evaluate`` called
back, and the loop around it still runs here. The
bordered systems are solved by LU with partial pivoting written here, because LAPACK's
(NumPy's or SciPy's) is not reachable from C without importing ``scipy.linalg`` (0.2 s of
every process's start); it is used only for systems of at most :data:`MAX_SIZE` unknowns,
where LAPACK's blocking gains nothing. A zero pivot is singular, as LAPACK's ``dgetrf``
says it is.

Built by ``pip install`` when a C compiler is present (``setup.py``: an optional
extension); without it, or with ``MECHCONT_PURE_PYTHON=1``, the Python corrector runs,
with the same results to rounding (``tests/test_kernel.py``).
"""

from libc.math cimport fabs, sqrt, log, exp, INFINITY, isfinite
from libc.string cimport memcpy
from libc.stdlib cimport malloc, free

import numpy as np

#: largest bordered system (n + 1 unknowns) solved here; larger ones take the Python corrector
MAX_SIZE = 48

#: return codes of :meth:`BorderedNewton.step` (the Python corrector's reasons, in :mod:`._kernel`)
cdef enum:
    CONVERGED = 0
    NOT_FINITE = 1
    SINGULAR = 2
    TOO_SLOW = 3
    MAX_ITERATIONS = 4
    SINGULAR_TANGENT = 5

CODES = {"converged": CONVERGED, "not_finite": NOT_FINITE, "singular": SINGULAR, "too_slow": TOO_SLOW,
         "max_iterations": MAX_ITERATIONS, "singular_tangent": SINGULAR_TANGENT}

ctypedef void (*model_fn)(double *out, const double *inp, void *data) noexcept nogil

# the Python corrector's noise model (``_newton``): one definition for both
from ._newton import _FLOOR, _ROUNDING

cdef double EPS = _ROUNDING
cdef double FLOOR = _FLOOR


cdef int lu_factor(double *A, int *piv, int m) noexcept nogil:
    """In-place LU with partial pivoting of the m x m row-major ``A``; 1 if a pivot is exactly 0."""
    cdef int i, j, k, p
    cdef double big, t, d
    cdef int singular = 0
    for k in range(m):
        p = k
        big = fabs(A[k * m + k])
        for i in range(k + 1, m):
            t = fabs(A[i * m + k])
            if t > big:  # NaN never wins, as in LAPACK's idamax
                big = t
                p = i
        piv[k] = p
        if p != k:
            for j in range(m):
                t = A[k * m + j]
                A[k * m + j] = A[p * m + j]
                A[p * m + j] = t
        d = A[k * m + k]
        if d == 0.0:
            singular = 1
            continue
        for i in range(k + 1, m):
            A[i * m + k] /= d
            t = A[i * m + k]
            if t != 0.0:
                for j in range(k + 1, m):
                    A[i * m + j] -= t * A[k * m + j]
    return singular


cdef void lu_solve(const double *LU, const int *piv, double *b, int m) noexcept nogil:
    """Solve in place with the factors of :func:`lu_factor`."""
    cdef int i, j
    cdef double t, s
    for i in range(m):
        if piv[i] != i:
            t = b[i]
            b[i] = b[piv[i]]
            b[piv[i]] = t
    for i in range(m):
        s = b[i]
        for j in range(i):
            s -= LU[i * m + j] * b[j]
        b[i] = s
    for i in range(m - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, m):
            s -= LU[i * m + j] * b[j]
        b[i] = s / LU[i * m + i]


cdef double max_abs(const double *v, int m) noexcept nogil:
    """Largest |v_i|; NaN if any entry is NaN (as ``np.maximum.reduce(np.abs(v))``)."""
    cdef double out = 0.0, a
    cdef int i
    for i in range(m):
        a = fabs(v[i])
        if a != a:
            return a
        if a > out:
            out = a
    return out


cdef bint all_finite(const double *v, int m) noexcept nogil:
    cdef int i
    cdef double s = 0.0
    for i in range(m):
        s += v[i]
    return isfinite(s)


cdef class BorderedNewton:
    """One step of pseudo-arclength continuation on an equilibrium problem, compiled.

    Parameters: ``fn`` the SymEngine compiled function of the residual and Jacobian entries
    (kept alive here), ``n_out`` how many values it writes, ``src`` where each residual
    (first ``n``) and each Jacobian entry of the unknowns' columns (column by column) is
    read among them (``n_out``: a structural zero), ``base`` the full variable vector of the
    held values, ``idx`` the unknowns' positions in it, ``D`` their scales, and the
    corrector's options. Or, for a problem without such a function (a fold curve), ``fn``
    is its ``evaluate(u) -> (G, dG/du)`` called from here, with ``n_out``, ``src``, ``base``
    and ``idx`` None: the loop around it is still compiled.
    """

    cdef object fn
    cdef object py_evaluate
    cdef object fallback
    # fold-curve mode (see __init__'s ``fold``)
    cdef bint fold_mode
    cdef object fn2
    cdef model_fn call2
    cdef void *data2
    cdef int ns
    cdef Py_ssize_t[::1] src2_
    cdef Py_ssize_t[::1] fi_
    cdef Py_ssize_t[::1] fpos_
    cdef Py_ssize_t[::1] fc_
    cdef double[::1] factor_
    cdef double[::1] rowcol_
    cdef double[::1] vals2_
    cdef double[::1] Af_
    cdef double[::1] Ai_
    cdef double[::1] col_
    cdef double log_norm
    cdef model_fn call
    cdef void *data
    cdef int n, m, nx, n_out, max_newton
    cdef double tol, residual_tol, max_contraction
    cdef double *work
    cdef int *piv
    cdef Py_ssize_t[::1] src_
    cdef Py_ssize_t[::1] idx_
    cdef double[::1] base_
    cdef double[::1] D_
    # views into ``work``
    cdef double *x
    cdef double *vals
    cdef double *r
    cdef double *rprev
    cdef double *A
    cdef double *LU
    cdef double *b
    cdef double *z
    cdef double *zp
    cdef double *dz
    cdef double *f

    def __cinit__(self):
        self.work = NULL
        self.piv = NULL

    def __init__(self, fn, n_out, src, base, idx, D, double tol, double residual_tol, int max_newton,
                 double max_contraction, fold=None):
        """``fold`` (a fold curve's minimally extended system, ``_folds.FoldProblem``): ``(evaluate,
        fn2, n_out2, src2, i, pos, c, factor, rowcol, log_norm)``. Then ``fn``/``src`` give the
        equilibrium rows only (``n - 1`` of them), the last row is ``g = det(A) / N`` with
        ``A = rowcol * G_s`` and its gradient ``sum_k fn2[src2_k] factor_k adj(A)[pos_k, i_k] / N``
        added into column ``c_k``; ``evaluate`` is called instead where ``A`` is exactly singular."""
        import ctypes

        def entry(f):
            callback, data = f.as_ctypes()
            return <size_t>ctypes.cast(callback, ctypes.c_void_p).value, <size_t>(data.value or 0)

        cdef size_t address, user
        self.D_ = np.array(D, dtype=float)
        self.m = len(self.D_)
        self.n = self.m - 1
        self.fn = fn
        self.fold_mode = fold is not None
        self.ns = self.n - 1 if self.fold_mode else self.n
        if src is None:  # a Python evaluate(u): no compiled model, nothing to lay out
            self.py_evaluate = fn
            src, idx, base, n_out = np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp), np.zeros(0), 0
        else:
            self.py_evaluate = None
            address, user = entry(fn)
            self.call = <model_fn>address
            self.data = <void *>user
        if self.fold_mode:
            evaluate, self.fn2, n_out2, src2, fi, fpos, fc, factor, rowcol, self.log_norm = fold
            self.fallback = evaluate
            address, user = entry(self.fn2)
            self.call2 = <model_fn>address
            self.data2 = <void *>user
            self.src2_ = np.ascontiguousarray(src2, dtype=np.intp)
            self.fi_ = np.ascontiguousarray(fi, dtype=np.intp)
            self.fpos_ = np.ascontiguousarray(fpos, dtype=np.intp)
            self.fc_ = np.ascontiguousarray(fc, dtype=np.intp)
            self.factor_ = np.ascontiguousarray(factor, dtype=float)
            self.rowcol_ = np.ascontiguousarray(rowcol, dtype=float).reshape(-1)
            self.vals2_ = np.zeros(n_out2 + 1)
            self.Af_ = np.empty(self.ns * self.ns)
            self.Ai_ = np.empty(self.ns * self.ns)
            self.col_ = np.empty(self.ns)
            k = len(self.src2_)
            if not (len(self.fi_) == len(self.fpos_) == len(self.fc_) == len(self.factor_) == k) or \
                    len(self.rowcol_) != self.ns * self.ns:
                raise ValueError("BorderedNewton: inconsistent fold-curve layout")
        self.src_ = np.ascontiguousarray(src, dtype=np.intp)
        self.idx_ = np.ascontiguousarray(idx, dtype=np.intp)
        self.base_ = np.array(base, dtype=float)
        self.nx = len(self.base_)
        self.n_out = n_out
        if self.py_evaluate is None and (len(self.src_) != self.ns + self.ns * self.m or len(self.idx_) != self.m):
            raise ValueError("BorderedNewton: src must hold the residuals and their Jacobian entries, column by column")
        self.tol, self.residual_tol, self.max_newton, self.max_contraction = tol, residual_tol, max_newton, max_contraction
        cdef int m = self.m
        cdef Py_ssize_t size = self.nx + (self.n_out + 1) + 2 * m + 3 * m * m + 5 * m
        self.work = <double *>malloc(size * sizeof(double))
        self.piv = <int *>malloc(m * sizeof(int))
        if self.work == NULL or self.piv == NULL:
            raise MemoryError()
        self.x = self.work
        self.vals = self.x + self.nx
        self.r = self.vals + self.n_out + 1
        self.rprev = self.r + m
        self.A = self.rprev + m
        self.LU = self.A + m * m
        self.b = self.LU + m * m
        self.z = self.b + m
        self.zp = self.z + m
        self.dz = self.zp + m
        self.f = self.dz + m
        self.vals[self.n_out] = 0.0

    def __dealloc__(self):
        free(self.work)
        free(self.piv)

    cdef int evaluate(self, const double *z, double *jac) except -1:
        """Residual into ``self.r`` and the scaled Jacobian (n x m, row-major) into ``jac``."""
        cdef int i, c, n = self.ns, m = self.m
        if self.py_evaluate is not None:
            return self.evaluate_python(z, jac, self.py_evaluate)
        memcpy(self.x, &self.base_[0], self.nx * sizeof(double))
        for c in range(m):
            self.x[self.idx_[c]] = z[c] * self.D_[c]
        self.call(self.vals, self.x, self.data)
        for i in range(n):
            self.r[i] = self.vals[self.src_[i]]
        for c in range(m):
            for i in range(n):
                jac[i * m + c] = self.vals[self.src_[n + c * n + i]] * self.D_[c]
        if self.fold_mode:
            return self.fold_row(z, jac)
        return 0

    cdef int fold_row(self, const double *z, double *jac) except -1:
        """The fold condition ``g = det(A) / N`` and its gradient, as ``FoldProblem.evaluate``."""
        cdef int i, j, k, c, ns = self.ns, m = self.m
        cdef double *A = &self.Af_[0]
        cdef double *Ai = &self.Ai_[0]
        cdef double *col = &self.col_[0]
        cdef double *v2
        cdef double sign = 1.0, logdet = 0.0, g, w
        for i in range(ns):
            for j in range(ns):
                A[i * ns + j] = self.vals[self.src_[ns + j * ns + i]] * self.rowcol_[i * ns + j]
        if lu_factor(A, self.piv, ns):
            return self.evaluate_python(z, jac, self.fallback)  # exactly singular: its SVD adjugate
        for j in range(ns):
            if self.piv[j] != j:
                sign = -sign
            if A[j * ns + j] < 0:
                sign = -sign
            logdet += log(fabs(A[j * ns + j]))
        g = sign * exp(logdet - self.log_norm)
        for k in range(ns):  # adj(A) / N = g A^-1, column by column
            for j in range(ns):
                col[j] = 1.0 if j == k else 0.0
            lu_solve(A, self.piv, col, ns)
            for j in range(ns):
                Ai[j * ns + k] = g * col[j]
        if not all_finite(Ai, ns * ns):
            return self.evaluate_python(z, jac, self.fallback)
        self.r[ns] = g
        self.call2(&self.vals2_[0], self.x, self.data2)
        v2 = &self.vals2_[0]
        for c in range(m):
            jac[ns * m + c] = 0.0
        for k in range(self.src2_.shape[0]):
            w = v2[self.src2_[k]] * self.factor_[k] * Ai[self.fpos_[k] * ns + self.fi_[k]]
            jac[ns * m + self.fc_[k]] += w
        for c in range(m):
            jac[ns * m + c] *= self.D_[c]
        return 0

    cdef int evaluate_python(self, const double *z, double *jac, evaluate) except -1:
        cdef int i, c, n = self.n, m = self.m
        u = np.empty(m)
        cdef double[::1] uv = u
        for c in range(m):
            uv[c] = z[c] * self.D_[c]
        res, J = evaluate(u)
        cdef double[::1] rv = np.ascontiguousarray(res, dtype=float).reshape(-1)
        cdef double[:, ::1] Jv = np.ascontiguousarray(J, dtype=float)
        if rv.shape[0] != n or Jv.shape[0] != n or Jv.shape[1] != m:
            raise ValueError(f"evaluate must return {n} residuals and a ({n}, {m}) Jacobian")
        for i in range(n):
            self.r[i] = rv[i]
            for c in range(m):
                jac[i * m + c] = Jv[i, c] * self.D_[c]
        return 0

    cdef bint residual_met(self, const double *jac, const double *z) noexcept nogil:
        """``_newton.residual_met(r, jac, z, residual_tol)``."""
        cdef int i, j, n = self.n, m = self.m
        cdef double s, tol = self.residual_tol
        if max_abs(self.r, n) <= tol:
            return True
        for i in range(n):
            s = 0.0
            for j in range(m):
                s += fabs(jac[i * m + j] * z[j])
            if not fabs(self.r[i]) <= max(tol, FLOOR * s):
                return False
        return True

    cdef double step_noise(self, const double *jac, const double *z) noexcept nogil:
        """``_newton.step_noise`` with the factors in ``self.LU``: inf if they are singular."""
        cdef int i, j, n = self.n, m = self.m
        cdef double s, noise = 0.0, a
        cdef int sign_pattern
        for sign_pattern in range(2):
            for i in range(n):
                s = 0.0
                for j in range(m):
                    s += fabs(jac[i * m + j] * z[j])
                self.f[i] = EPS * s * (-1.0 if (sign_pattern and i % 2) else 1.0)
            self.f[n] = 0.0
            lu_solve(self.LU, self.piv, self.f, m)
            a = max_abs(self.f, m)
            if not isfinite(a):
                return INFINITY
            noise = max(noise, a)
        return noise

    def step(self, double[::1] z0, double[::1] t0, double sigma, z_start=None):
        """Predict ``z0 + sigma t0``, correct onto the branch, and take the new tangent there.

        Newton starts at ``z_start`` when given (a point near the hyperplane), as
        ``PseudoArclength.correct``. Returns ``(code, iterations, z, jac, tangent, det_sign,
        log_det)``: ``code`` one of the module's return codes; on :data:`CONVERGED`, ``z``
        (scaled unknowns), the scaled Jacobian ``jac`` (n x n+1), the unit ``tangent``
        oriented along ``t0``, and the sign and log of ``|det [jac; tangent]|`` (the
        branch-point test function). The arrays are None otherwise.
        """
        cdef int n = self.n, m = self.m, it, i, j, code = MAX_ITERATIONS, iters = self.max_newton
        cdef bint lag = True, started = z_start is not None
        cdef double prev = INFINITY, error = INFINITY, step, q, tol = self.tol, s, norm, logdet = 0.0, sign = 1.0
        cdef double[::1] zs
        jac_arr = np.empty((n, m))
        cdef double[:, ::1] jac_v = jac_arr
        cdef double *jac = &jac_v[0, 0]
        cdef double *A = self.A
        if z0.shape[0] != m or t0.shape[0] != m:
            raise ValueError(f"expected {m} values")
        for i in range(m):
            self.zp[i] = z0[i] + sigma * t0[i]
        if started:
            zs = np.ascontiguousarray(z_start, dtype=float)
            if zs.shape[0] != m:
                raise ValueError(f"expected {m} values")
            for i in range(m):
                self.z[i] = zs[i]
        else:
            memcpy(self.z, self.zp, m * sizeof(double))
        for it in range(1, self.max_newton + 2):
            self.evaluate(self.z, jac)
            if error < tol and self.residual_met(jac, self.z):
                code = CONVERGED if all_finite(jac, n * m) else NOT_FINITE
                iters = it - 1 - (not lag)
                break
            if it > self.max_newton:
                code = MAX_ITERATIONS if all_finite(self.r, n) else NOT_FINITE
                iters = self.max_newton if code == MAX_ITERATIONS else it
                break
            memcpy(A, jac, n * m * sizeof(double))
            for j in range(m):
                A[n * m + j] = t0[j]
            memcpy(self.LU, A, m * m * sizeof(double))
            for i in range(n):
                self.b[i] = -self.r[i]
            s = 0.0
            if it == 1 and started:
                for j in range(m):
                    s -= t0[j] * (self.z[j] - self.zp[j])
            self.b[n] = s
            if lu_factor(self.LU, self.piv, m):
                step = INFINITY * 0.0  # NaN: singular, as NumPy's NaN-filled solve
            else:
                memcpy(self.dz, self.b, m * sizeof(double))
                lu_solve(self.LU, self.piv, self.dz, m)
                step = max_abs(self.dz, m)
            if not isfinite(step):
                code = SINGULAR if (all_finite(self.r, n) and all_finite(jac, n * m)) else NOT_FINITE
                iters = it
                break
            if step < tol:
                for j in range(m):
                    self.z[j] += self.dz[j]
                code = CONVERGED if all_finite(jac, n * m) else NOT_FINITE
                iters = it - (not lag)
                break
            if step > self.max_contraction * prev:
                if self.residual_met(jac, self.z) and step <= 10 * self.step_noise(jac, self.z):
                    code = CONVERGED if all_finite(jac, n * m) else NOT_FINITE
                    iters = it - (not lag)
                    break
                if lag and max_abs(self.r, n) <= 0.1 * max_abs(self.rprev, n):
                    lag = False
                    step = INFINITY
                elif step > 1e3 * tol:
                    code = TOO_SLOW
                    iters = it
                    break
            for j in range(m):
                self.z[j] += self.dz[j]
            memcpy(self.rprev, self.r, n * sizeof(double))
            if prev < INFINITY:
                q = step / prev
                error = q / (1.0 - q) * step if q < 1.0 else INFINITY
            prev = step
        if code == CONVERGED:
            # the new tangent: [jac; t0] t = e_(n+1), normalised (t0.t = 1 > 0 orients it along t0)
            memcpy(self.LU, jac, n * m * sizeof(double))
            for j in range(m):
                self.LU[n * m + j] = t0[j]
            if lu_factor(self.LU, self.piv, m):
                code = SINGULAR_TANGENT
            else:
                for j in range(m):
                    self.b[j] = 0.0
                self.b[n] = 1.0
                lu_solve(self.LU, self.piv, self.b, m)
                s = 0.0
                for j in range(m):
                    s += self.b[j] * self.b[j]
                norm = sqrt(s)
                if not isfinite(norm):
                    code = SINGULAR_TANGENT
                else:
                    # det [jac; t] = det [jac; t0] |t_unnormalised| (matrix determinant lemma, with t0.t = 1)
                    for j in range(m):
                        if self.piv[j] != j:
                            sign = -sign
                        if self.LU[j * m + j] < 0:
                            sign = -sign
                        logdet += log(fabs(self.LU[j * m + j]))
                    logdet += log(norm)
                    s = 0.0
                    for j in range(m):
                        self.b[j] /= norm
                        s += self.b[j] * t0[j]
                    if not s > 0:
                        for j in range(m):
                            self.b[j] = -self.b[j]
                        sign = -sign
        if code != CONVERGED:
            return code, iters, None, None, None, 0.0, 0.0
        z_out = np.empty(m)
        t_out = np.empty(m)
        cdef double[::1] zo = z_out, to = t_out
        for j in range(m):
            zo[j] = self.z[j]
            to[j] = self.b[j]
        return code, iters, z_out, jac_arr, t_out, sign, logdet
