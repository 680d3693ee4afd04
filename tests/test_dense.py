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
