"""A branch started on one of its bounds (exactly, or within rounding) ends there in the direction that
leaves the interval, and runs in the other. Found on another BLAS kernel: the optimum of a design map
lay 7e-17 inside a bound, the first step crossed it within 1e-6 of the step, that crossing was taken
for "the start's own special point" and skipped, and the boundary was traced far outside its bounds."""

import pytest

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.models import load_model


@pytest.fixture(scope="module")
def start():
    s = load_model("overcentre", LU=0.4)
    x0 = find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])
    return s, x0, float(x0[s.index("F")])


@pytest.mark.parametrize("inside", [0.0, 1e-16, 1e-12, 1e-9])
def test_leaving_direction_ends_at_the_start_and_the_other_runs(start, inside):
    s, x0, F0 = start
    lo = F0 - inside * abs(F0)
    out = continuation(s, x0, "F", options=ContinuationOptions(bounds={"F": (lo, 100.0)}), direction=-1)
    assert len(out) == 1 and out.labels == ["EP"] and "start lies on the bound of F" in out.message
    on = continuation(s, x0, "F", options=ContinuationOptions(bounds={"F": (lo, 100.0)}), direction=1)
    assert len(on) > 10 and "reached bound of F" in on.message
    # never past the bound by more than the start's own rounding
    assert out["F"].min() >= lo - 1e-14 * abs(lo) and on["F"].min() >= lo - 1e-14 * abs(lo)


def test_a_start_clearly_inside_still_reaches_the_bound_first(start):
    s, x0, F0 = start
    lo = F0 - 1e-3 * abs(F0)
    b = continuation(s, x0, "F", options=ContinuationOptions(bounds={"F": (lo, 100.0)}), direction=-1)
    assert len(b) == 2 and b["F"][0] == pytest.approx(lo, abs=1e-12) and "reached bound of F" in b.message
