"""The run rules the commands share, as library functions: step sizes given alone or together,
the step limit, and the first equilibrium of a run."""

from __future__ import annotations

import numpy as np
import pytest

from mechcont import InputError, load_model
from mechcont.continuation import MAX_STEPS, ContinuationOptions, check_max_steps, run_options, start_point


def test_a_step_given_alone_moves_the_other_limit():
    assert run_options(ds=0.5).dsmax == 0.5  # ds above the default largest step raises it
    assert run_options(ds=0.01).dsmax == ContinuationOptions.dsmax
    assert run_options(dsmax=0.005).ds == 0.005  # dsmax below the default first step lowers it
    both = run_options({"F": (-1.0, 1.0)}, ds=0.01, dsmax=0.05, max_steps=7)
    assert (both.ds, both.dsmax, both.max_steps, dict(both.bounds)) == (0.01, 0.05, 7, {"F": (-1.0, 1.0)})


def test_the_step_limit_names_the_field_given():
    check_max_steps(None)
    check_max_steps(MAX_STEPS)
    with pytest.raises(InputError, match=r"^--max-steps: must be a positive whole number 1\.\.100000, got 0$"):
        run_options(max_steps=0, max_steps_field="--max-steps")
    with pytest.raises(InputError, match="^max_steps:"):
        check_max_steps(MAX_STEPS + 1)


def test_the_start_holds_the_state_and_solves_for_the_varied_parameter():
    s = load_model("overcentre", LU=0.4)
    x0 = start_point(s, "F", start={"theta1": 0.3})
    assert x0[s.index("theta1")] == pytest.approx(0.3, abs=1e-12)
    assert np.linalg.norm(s.residual(x0)) < 1e-9  # an equilibrium, F solved for
    with pytest.raises(InputError, match="^--start: F is the continuation parameter"):
        start_point(s, "F", start={"F": 1.0}, start_field="--start")
    with pytest.raises(InputError, match="^free: theta1 is a state"):
        start_point(s, "F", start={"theta1": 0.3}, free=["theta1"])
