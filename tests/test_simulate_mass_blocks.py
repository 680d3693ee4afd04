"""The block-by-block mass matrix inverses of the time simulation (spatial bodies in Euler parameters)."""

import numpy as np
import pytest

from mechcont.dynamics._udwadia_kalaba import MassBlocks, fundamental_equation, inverse_sqrt


def _block_diagonal(rng, sizes):
    n = sum(sizes)
    M, start = np.zeros((n, n)), 0
    for s in sizes:
        A = rng.normal(size=(s, s))
        M[start:start + s, start:start + s] = A @ A.T + s * np.eye(s)
        start += s
    perm = rng.permutation(n)  # the blocks' coordinates interleaved, as the pattern finds them
    return M[np.ix_(perm, perm)]


def test_blocks_give_the_dense_inverse_and_inverse_square_root():
    rng = np.random.default_rng(3)
    M = _block_diagonal(rng, [7, 7, 3, 7, 1])
    blocks = MassBlocks(len(M), np.argwhere(M != 0).tolist())
    assert sorted(g.shape for g in blocks.groups) == [(1, 1), (1, 3), (3, 7)]
    assert np.allclose(blocks.inverse(M), np.linalg.inv(M), rtol=0, atol=1e-13)
    assert np.allclose(blocks.inverse_sqrt(M), inverse_sqrt(M), rtol=0, atol=1e-13)


def test_the_fundamental_equation_through_the_inverse_is_the_pseudo_inverse_one():
    """``M^-1 A^T (A M^-1 A^T)^-1 r`` (the simulation's path for block-diagonal M) equals
    ``M^-1/2 (A M^-1/2)^+ r`` (the fundamental equation) for full-rank A."""
    from mechcont.dynamics._udwadia_kalaba import ConstrainedDynamics

    rng = np.random.default_rng(4)
    M = _block_diagonal(rng, [7, 7, 7])
    A, Q, b = rng.normal(size=(9, 21)), rng.normal(size=21), rng.normal(size=9)
    dyn = object.__new__(ConstrainedDynamics)
    dyn._blocks = MassBlocks(21, np.argwhere(M != 0).tolist())
    dyn.mech = type("Mech", (), {"mass": staticmethod(lambda x: M)})()
    got = dyn._by_inverse(np.zeros(1), Q, A, b)
    assert got == pytest.approx(fundamental_equation(inverse_sqrt(M), Q, A, b), rel=1e-10, abs=1e-12)
    assert dyn._by_inverse(np.zeros(1), Q, np.vstack([A, A[:1]]), np.append(b, b[0])) is None  # rank deficient


def test_a_non_positive_block_is_refused():
    from mechcont.errors import InputError

    M = np.diag([1.0, 2.0, -1.0])
    M[0, 1] = M[1, 0] = 0.1
    with pytest.raises(InputError, match="mass_matrix"):
        MassBlocks(3, np.argwhere(M != 0).tolist()).inverse_sqrt(M)
