"""Comparing text that holds computed numbers: the words exactly, the numbers to a tolerance.

Generated files and printed summaries hold floats whose last bits depend on the CPU and BLAS
kernel (a norm, a cross product, an eigenvalue). Comparing such text byte for byte passes only
on the machine that wrote it; these helpers compare the text around the numbers exactly and
each number to a tolerance that the caller justifies.
"""

import math
import re

# a number standing alone: not part of a name such as ``e1_fitting`` or ``fwd_L1``
_NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?(?![\w.])")


def split_numbers(text):
    """(the text with each number replaced by ``#``, the numbers as floats in order)."""
    numbers = [float(m.group()) for m in _NUMBER.finditer(text)]
    return _NUMBER.sub("#", text), numbers


def assert_text_close(actual, expected, *, rtol, atol=0.0):
    """The same text but for numbers, each within ``atol + rtol*|expected|`` of the expected one."""
    skeleton_a, numbers_a = split_numbers(actual)
    skeleton_e, numbers_e = split_numbers(expected)
    if skeleton_a != skeleton_e:
        for i, (la, le) in enumerate(zip(skeleton_a.splitlines(), skeleton_e.splitlines(), strict=False)):
            assert la == le, f"line {i + 1} differs beyond its numbers:\n  {la}\n  {le}"
        raise AssertionError("the texts differ in their number of lines")
    assert len(numbers_a) == len(numbers_e)
    for k, (a, e) in enumerate(zip(numbers_a, numbers_e, strict=True)):
        assert math.isclose(a, e, rel_tol=rtol, abs_tol=atol), f"number {k + 1}: {a!r} against {e!r}"


def assert_frames_close(actual, expected, *, rtol, atol=0.0):
    """Two DataFrames with the same columns, index and non-float cells, and float cells within
    ``atol + rtol*|expected|`` (NaN where the other is NaN): for results computed in other processes."""
    import numpy as np
    import pandas as pd

    assert list(actual.columns) == list(expected.columns) and actual.index.equals(expected.index)
    for name in expected.columns:
        a, e = actual[name], expected[name]
        assert a.dtype == e.dtype, name
        if pd.api.types.is_float_dtype(e.dtype):
            np.testing.assert_allclose(a.to_numpy(), e.to_numpy(), rtol=rtol, atol=atol, equal_nan=True, err_msg=name)
        else:
            assert a.equals(e), name
