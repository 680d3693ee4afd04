"""The release runs' long steps find the unlock folds that fine steps and an independent polish find.

:func:`~mechcont.analysis.unlock.with_unlock_columns` runs one release run per downlocked point
with long steps where the run is straight (see ``RELEASE_DSMAX``). Here every column value is
compared with the fold found independently: a release run with the fine steps used before
(``ds`` 0.02, ``dsmax`` 0.5, the engine's own fold detection, not stopped at the first fold),
its first fold each way polished to machine precision by :func:`refine_fold`. Where that run
meets no fold within the same bounds, the column must say none (nan).
"""

from pathlib import Path

import numpy as np
import pytest

from mechcont.analysis.downlock import downlock
from mechcont.analysis.unlock import RELEASE_FORCE_SPAN, RELEASE_STATE_SPAN, with_unlock_columns
from mechcont.continuation import ContinuationOptions, continuation
from mechcont.continuation._fold_point import refine_fold
from mechcont.models import load_model

CLAMP = Path(__file__).parent / "data" / "toggle_clamp.toml"


def reference_folds(system, x, force, released):
    """(below, above): the polished first fold decreasing / increasing ``force`` from ``x`` (nan if none)."""
    bounds = {n: (x[system.index(n)] - span * system.variable(n).scale, x[system.index(n)] + span * system.variable(n).scale)
              for n, span in ((force, RELEASE_FORCE_SPAN), *((r, RELEASE_STATE_SPAN) for r in released))}
    fine = ContinuationOptions(ds=0.02, dsmax=0.5, max_steps=2000, bounds=bounds, detect_branch_points=False,
                               stability=False)
    F0, out = x[system.index(force)], []
    for direction in (-1, 1):
        run = continuation(system, x, force, options=fine, direction=direction)
        folds = sorted(run.special("LP"), key=lambda p: abs(run.s[p.index]))
        if not folds:
            out.append(np.nan)
            continue
        states = [n for n in run.unknowns if n != force]
        xf, _ = refine_fold(system, folds[0].x, states, force)
        assert (xf[system.index(force)] - F0) * direction > 0
        out.append(xf[system.index(force)])
    return tuple(out)


@pytest.fixture(scope="module")
def clamp_table():
    s = load_model(CLAMP)
    branch = downlock(s, "l0", {"l0": (0.55, 0.8)}, condition="toggle", force="F")
    return s, with_unlock_columns(s, branch, "F", released=["toggle"]).branch


def test_unlock_columns_are_the_independently_polished_folds(clamp_table):
    s, table = clamp_table
    above, below = table["unlock_F"], table["unlock_F_decreasing"]
    assert np.isfinite(above).any() and np.isnan(above).any()  # folds at some points, none at others
    for i in sorted({0, len(table) // 3, len(table) // 2, len(table) - 1}):
        lo, hi = reference_folds(s, table.values[i, : len(s.names)], "F", ["toggle"])
        for got, want in ((above[i], hi), (below[i], lo)):
            if np.isnan(want):
                assert np.isnan(got), (i, got)
            else:
                assert got == pytest.approx(want, rel=1e-9), (i, got, want)
