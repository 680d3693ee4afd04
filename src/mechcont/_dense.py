"""``numpy.linalg`` svd, eig, qr, slogdet and solve of one small real matrix, without the wrappers' per-call checks.

The continuation loop takes an SVD (stability, null vectors) and a log-determinant
(branch-point test) at every point of a branch, on matrices of a few dozen entries, where
NumPy's Python wrappers (argument conversion, dtype promotion, result tuples) cost more
than LAPACK. These call the same LAPACK kernels (NumPy's own generalised ufuncs) with the
same error handling, so they return the same bits and raise the same errors; anything but
a 2-D float64 array goes through ``numpy.linalg`` itself.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["svd", "singular_values", "eig", "qr_complete", "slogdet", "solve", "inverse", "quiet", "solve_raw", "RAW_SOLVE"]

_umath_linalg: Any
try:  # NumPy >= 2 (private names: any other NumPy falls back to the public functions)
    from numpy.linalg import _umath_linalg
    from numpy.linalg._linalg import (  # type: ignore[attr-defined]
        _raise_linalgerror_eigenvalues_nonconvergence as _eig_failed,
    )
    from numpy.linalg._linalg import _raise_linalgerror_qr as _qr_failed  # type: ignore[attr-defined]
    from numpy.linalg._linalg import _raise_linalgerror_svd_nonconvergence as _svd_failed  # type: ignore[attr-defined]
except ImportError:  # pragma: no cover
    _umath_linalg = None
_svd_errors: Any = None
_eig_errors: Any = None
_qr_errors: Any = None
try:  # the error state numpy.linalg.svd enters, made once (entering np.errstate costs a fifth of a small SVD)
    from numpy._core._ufunc_config import _extobj_contextvar, _make_extobj  # type: ignore[attr-defined]

    _svd_errors = _make_extobj(call=_svd_failed, invalid="call", over="ignore", divide="ignore", under="ignore")
    _eig_errors = _make_extobj(call=_eig_failed, invalid="call", over="ignore", divide="ignore", under="ignore")
    _qr_errors = _make_extobj(call=_qr_failed, invalid="call", over="ignore", divide="ignore", under="ignore")
    _quiet = _make_extobj(invalid="ignore", over="ignore", divide="ignore", under="ignore")
except Exception:  # noqa: BLE001  # pragma: no cover - another NumPy: np.errstate below
    _svd_errors = _quiet = None


def _plain(A: np.ndarray) -> bool:
    return _umath_linalg is not None and type(A) is np.ndarray and A.dtype == np.float64 and A.ndim == 2


def _in_state(extobj: object, gufunc: np.ufunc, *args: np.ndarray, signature: str) -> Any:
    """``gufunc(*args)`` in the floating-point error state ``extobj`` (made once: entering np.errstate
    costs a fifth of a small SVD): its output, an array or a tuple of arrays (as the kernel has one or more)."""
    token = _extobj_contextvar.set(extobj)
    try:
        return gufunc(*args, signature=signature)
    finally:
        _extobj_contextvar.reset(token)


def _svd_call(gufunc: np.ufunc, A: np.ndarray, signature: str) -> Any:
    """``gufunc(A)`` in the error state numpy.linalg.svd uses (non-convergence raises LinAlgError): the singular
    values, or ``(U, s, V^T)``, as the kernel gives them."""
    if _svd_errors is not None:
        return _in_state(_svd_errors, gufunc, A, signature=signature)
    with np.errstate(call=_svd_failed, invalid="call", over="ignore", divide="ignore", under="ignore"):
        return gufunc(A, signature=signature)


def svd(A: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``numpy.linalg.svd(A)`` (full matrices): ``(U, singular values, V^T)``; LinAlgError if it fails."""
    if not _plain(A) or 0 in A.shape:
        U, s, Vt = np.linalg.svd(A)
        return U, s, Vt
    return _svd_call(_umath_linalg.svd_f, A, "d->ddd")


def singular_values(A: np.ndarray) -> np.ndarray:
    """``numpy.linalg.svd(A, compute_uv=False)``: the singular values, largest first; LinAlgError if it fails."""
    if not _plain(A) or 0 in A.shape:
        return np.linalg.svd(A, compute_uv=False)
    return _svd_call(_umath_linalg.svd, A, "d->d")


def eig(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``numpy.linalg.eig(A)`` of a square real matrix, always complex: ``(eigenvalues, right eigenvectors as
    columns)`` (NumPy's own result turns both real where every eigenvalue is; the values are the same);
    LinAlgError if it fails or ``A`` is not finite."""
    if _eig_errors is None or not _plain(A) or A.shape[0] != A.shape[1]:
        lam, V = np.linalg.eig(A)
        return lam.astype(complex), V.astype(complex)
    if not np.isfinite(np.add.reduce(A, None)):
        raise np.linalg.LinAlgError("Array must not contain infs or NaNs")
    out: tuple[np.ndarray, np.ndarray] = _in_state(_eig_errors, _umath_linalg.eig, A, signature="d->DD")
    return out


def qr_complete(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``numpy.linalg.qr(A, mode="complete")`` of a real matrix with more rows than columns: ``(Q, R)``, ``Q`` square
    and orthogonal, ``R`` upper triangular with ``A``'s shape; LinAlgError if it fails."""
    if _qr_errors is None or not _plain(A) or A.shape[0] <= A.shape[1]:
        Q, R = np.linalg.qr(A, mode="complete")
        return Q, R
    a = A.copy()  # overwritten by the Householder vectors and R
    tau = _in_state(_qr_errors, _umath_linalg.qr_r_raw, a, signature="d->d")
    Q = _in_state(_qr_errors, _umath_linalg.qr_complete, a, tau, signature="dd->d")
    return Q, np.triu(a)


def slogdet(A: np.ndarray) -> tuple[float, float]:
    """``numpy.linalg.slogdet(A)`` of a square matrix: ``(sign, log |det A|)``."""
    if not _plain(A) or A.shape[0] != A.shape[1]:
        sign, logdet = np.linalg.slogdet(A)
        return sign, logdet
    return _umath_linalg.slogdet(A, signature="d->dd")


def solve(A: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """``numpy.linalg.solve(A, b)`` for a square ``A`` and a vector ``b`` (LAPACK ``dgesv``, NumPy's
    own kernel), or None when it is singular (an exact zero pivot) or the result is not finite.

    NumPy's kernel fills the result with NaN where the factorisation meets a zero pivot; that
    is how a singular matrix is told here. SciPy's LAPACK wrappers would do the same job, but
    importing ``scipy.linalg`` costs a start-up 0.2 s that a short run never earns back.
    """
    if _quiet is None or not _plain(A) or type(b) is not np.ndarray or b.dtype != np.float64 or b.ndim != 1:
        try:
            x = np.linalg.solve(np.asarray(A, float), np.asarray(b, float))
        except np.linalg.LinAlgError:
            return None
    else:
        x = _in_state(_quiet, _umath_linalg.solve1, A, b, signature="dd->d")
    return x if np.isfinite(np.add.reduce(x, None)) else None


class quiet:
    """``with quiet(): ...``: the floating-point error state of :func:`solve`, entered once for many
    :func:`solve_raw` calls (a loop of small solves: entering it per solve costs half a solve)."""

    __slots__ = ("_token",)

    def __enter__(self) -> None:
        self._token = _extobj_contextvar.set(_quiet) if _quiet is not None else None

    def __exit__(self, *exc: object) -> None:
        if self._token is not None:
            _extobj_contextvar.reset(self._token)


#: Whether :func:`solve_raw` may be used (this NumPy has the kernel and the error state).
RAW_SOLVE = _umath_linalg is not None and _quiet is not None


def solve_raw(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """:func:`solve` without its checks, for callers that made ``A`` (square) and ``b`` (a vector)
    float64 NumPy arrays themselves and test the result's finiteness anyway: NaN where ``A`` is
    singular. Only where :data:`RAW_SOLVE`, and inside :class:`quiet` (else a singular ``A`` warns)."""
    return _umath_linalg.solve1(A, b, signature="dd->d")


def inverse(A: np.ndarray) -> np.ndarray | None:
    """``numpy.linalg.inv(A)`` of a square real or complex matrix, or None when it is singular or not finite: for a
    Newton iteration that solves with one matrix several times (a product per solve), or the left eigenvectors
    from the right ones."""
    if type(A) is np.ndarray and A.dtype == np.complex128 and A.ndim == 2 and _umath_linalg is not None \
            and _quiet is not None:
        Ai = _in_state(_quiet, _umath_linalg.inv, A, signature="D->D")
    elif _quiet is None or not _plain(A):
        try:
            Ai = np.linalg.inv(np.asarray(A, float) if not np.iscomplexobj(A) else np.asarray(A, complex))
        except np.linalg.LinAlgError:
            return None
    else:
        Ai = _in_state(_quiet, _umath_linalg.inv, A, signature="d->d")
    return Ai if np.isfinite(np.add.reduce(Ai, None)) else None
