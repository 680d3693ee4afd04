"""``mechcont._dense``: NumPy's SVD, singular values and log-determinant without the wrappers,
bit for bit, with the same errors."""

import numpy as np
import pytest

from mechcont import _dense


@pytest.mark.parametrize("shape", [(1, 1), (3, 3), (5, 6), (6, 5), (13, 14), (30, 30)])
def test_same_bits_as_numpy(shape):
    rng = np.random.default_rng(sum(shape))
    for _ in range(20):
        A = rng.normal(size=shape) * 10.0 ** rng.uniform(-5, 5, size=(shape[0], 1))
        for got, expected in zip(_dense.svd(A), np.linalg.svd(A)):
            assert np.array_equal(got, expected)
        assert np.array_equal(_dense.singular_values(A), np.linalg.svd(A, compute_uv=False))
        if shape[0] == shape[1]:
            assert _dense.slogdet(A) == tuple(np.linalg.slogdet(A))


def test_non_finite_and_other_inputs():
    A = np.eye(3)
    A[1, 1] = np.nan
    for f in (_dense.svd, _dense.singular_values):
        with pytest.raises(np.linalg.LinAlgError):
            f(A)
    # lists, integer arrays and empty matrices go through numpy.linalg itself
    assert np.array_equal(_dense.singular_values([[3, 0], [0, 4]]), [4.0, 3.0])
    assert _dense.singular_values(np.zeros((0, 3))).shape == (0,)


@pytest.mark.parametrize("n", [1, 2, 3, 7, 20])
def test_eig_and_complex_inverse_same_bits_as_numpy(n):
    """``_dense.eig`` is ``numpy.linalg.eig`` always complex (NumPy's turns both outputs real where every eigenvalue
    is); ``_dense.inverse`` of the complex eigenvectors is ``numpy.linalg.inv``'s; a singular matrix gives None and a
    matrix with a NaN raises, as numpy.linalg.eig does."""
    rng = np.random.default_rng(n)
    for _ in range(20):
        A = rng.normal(size=(n, n)) * 10.0 ** rng.uniform(-5, 5, size=(n, 1))
        lam, V = _dense.eig(A)
        lam_np, V_np = np.linalg.eig(A)
        assert lam.dtype == V.dtype == np.complex128
        assert np.array_equal(lam, lam_np.astype(complex)) and np.array_equal(V, V_np.astype(complex))
        assert np.array_equal(_dense.inverse(V), np.linalg.inv(V))
    assert _dense.inverse(np.ones((2, 2), complex)) is None
    A = np.eye(3)
    A[1, 1] = np.nan
    with pytest.raises(np.linalg.LinAlgError):
        _dense.eig(A)


@pytest.mark.parametrize("shape", [(2, 1), (7, 6), (20, 19), (5, 2)])
def test_complete_qr_same_bits_as_numpy(shape):
    rng = np.random.default_rng(shape[0])
    for _ in range(10):
        A = rng.normal(size=shape) * 10.0 ** rng.uniform(-5, 5, size=(1, shape[1]))
        for got, expected in zip(_dense.qr_complete(A), np.linalg.qr(A, mode="complete")):
            assert np.array_equal(got, expected)
