"""The engine's pieces: the step iterator, termination reasons with hints, pluggable solvers."""

import numpy as np
import pytest

from mechcont.continuation import (
    BranchSteps,
    ContinuationOptions,
    DenseLU,
    EngineSettings,
    MinimumNorm,
    Termination,
    continuation,
    find_equilibrium,
)
from mechcont.continuation._api import _Equilibria, _equilibrium_events
from mechcont.continuation._problem import choose_unknowns
from mechcont.errors import InputError
from mechcont.models import build_overcentre
from mechcont.models.overcentre import symmetric_folds

FOLDS = sorted(F for _, F in symmetric_folds(1.5, 1.0, 1.0, 9.81, 127.0, 0.4))


@pytest.fixture(scope="module")
def start():
    s = build_overcentre(LU=0.4)
    return s, find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])


def test_iterator_yields_the_start_then_each_step(start):
    s, x0 = start
    opts = ContinuationOptions(bounds={"theta1": (-1.2, 1.2)})
    problem = _Equilibria(s, x0, "F", choose_unknowns(s, exclude=["F"]))
    steps = BranchSteps(problem, problem.u_of(x0), +1, opts, _equilibrium_events(s, opts, []))
    points = list(steps)
    assert points[0].s == 0 and np.allclose(points[0].state.x, x0, rtol=1e-15, atol=0)
    assert np.all(np.diff([p.s for p in points]) >= 0)
    assert steps.termination is Termination.BOUND and steps.termination.status == "completed"
    assert points[-1].label == "EP" and points[-1].info["bound_of"] == "theta1"
    # the same points as the driver records
    b = continuation(s, x0, "F", direction=1, options=opts)
    assert len(b) == len(points)
    assert np.array_equal(b.values, np.array([p.state.x for p in points]))


def test_runaway_branch_names_the_growing_variable(start):
    s, x0 = start
    b = continuation(s, x0, "F", direction=-1, options=ContinuationOptions(max_steps=60, dsmax=1.0))
    assert b.status == "completed" and "max_steps=60" in b.message
    assert "may grow without bound" in b.message and "--bounds" in b.message
    assert b.special("EP")[0].info["reason"] == "max_steps"


def test_the_hint_names_what_a_user_changes(start):
    s, x0 = start
    b = continuation(s, x0, "F", direction=-1, options=ContinuationOptions(max_steps=60, dsmax=1.0))
    assert "--bounds F=LO:HI" in b.message and "bounds={'F': (LO, HI)}" in b.message
    assert "ContinuationOptions" not in b.message


def test_the_engine_settings_are_apart_from_the_options_and_still_steer_the_steps(start):
    """The engine's internals live in EngineSettings (options.engine): a smaller largest turn of the
    tangent takes more, shorter steps, and the folds, polished, do not move."""
    s, x0 = start
    with pytest.raises(TypeError):
        ContinuationOptions(max_angle=0.1)  # type: ignore[call-arg]
    with pytest.raises(InputError, match="max_contraction"):
        EngineSettings(max_contraction=1.5)
    with pytest.raises(InputError, match="engine"):
        ContinuationOptions(engine={"max_angle": 0.1})  # type: ignore[arg-type]
    bounds = {"theta1": (-1.2, 1.2)}
    coarse = continuation(s, x0, "F", options=ContinuationOptions(bounds=bounds))
    fine = continuation(s, x0, "F", options=ContinuationOptions(bounds=bounds, engine=EngineSettings(max_angle=0.02)))
    assert len(fine) > 2 * len(coarse)
    assert sorted(p["F"] for p in fine.special("LP")) == pytest.approx(FOLDS, rel=1e-9)
    assert sorted(p["F"] for p in coarse.special("LP")) == pytest.approx(FOLDS, rel=1e-9)


def test_step_underflow_is_a_failure_with_a_reason():
    assert Termination.STEP_UNDERFLOW.status == "step size underflow"
    assert Termination.BRANCHES_TOO_CLOSE.status == "step size underflow"
    assert {t.status for t in (Termination.BOUND, Termination.MAX_STEPS, Termination.STOP_EVENT)} == {"completed"}


@pytest.mark.parametrize("solver", [DenseLU(), MinimumNorm()])
def test_linear_solvers_give_the_same_folds(start, solver):
    s, x0 = start
    b = continuation(s, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}, linear_solver=solver))
    assert sorted(p["F"] for p in b.special("LP")) == pytest.approx(FOLDS, rel=1e-10)


def test_a_solver_without_solve_is_refused():
    with pytest.raises(InputError, match="linear_solver"):
        ContinuationOptions(linear_solver=object())


def test_progress_is_called_once_per_accepted_step(start):
    s, x0 = start
    calls = []
    b = continuation(s, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}), progress=calls.append)
    accepted = sum(1 for lab, si in zip(b.labels, b.s) if not lab and si != 0)
    assert calls == [1] * accepted and accepted > 10


class _Overshooting:
    """One equation ``a - c = 0`` whose Jacobian is 0.4 times the true one: each correction
    overshoots by 1.5, so the corrections grow."""

    names, param_index, scale, idx = ("a", "p"), 1, np.ones(2), None

    def __init__(self, c):
        self.c = c

    def evaluate(self, u):
        return np.array([u[0] - self.c]), np.array([[0.4, 0.0]])


def test_corrector_never_accepts_on_a_growing_correction():
    """The contraction bound |z - z*| <= q/(1-q)|dz| holds only for q < 1: an iteration whose
    corrections grow must not be accepted while they are above the rounding noise, even where the
    residual passes its tolerance (5e-11 < 1e-10): q/(1-q) < 0 there must not read as converged."""
    from mechcont.continuation import ContinuationOptions
    from mechcont.continuation._corrector import PseudoArclength

    eng = PseudoArclength(_Overshooting(1.0), ContinuationOptions())
    z, reason, _ = eng.correct(np.array([1.0 + 5e-11, 0.0]), np.array([0.0, 1.0]))
    assert z is None and ("iterations" in reason or "slowly" in reason)


def test_corrector_accepts_a_point_whose_corrections_are_rounding_noise():
    """Where the residual sits below its floating-point floor (a = 1e7: the floor is 100 eps |J a|
    = 9e-8) a correction of 1e-8 is noise, whatever its trend: the point is converged as far as
    double precision allows (here within a few units in the last place of the solution), and the
    same overshooting iteration that is refused above the floor is accepted there."""
    from mechcont.continuation import ContinuationOptions
    from mechcont.continuation._corrector import PseudoArclength

    eng = PseudoArclength(_Overshooting(1e7), ContinuationOptions())
    z, _, _ = eng.correct(np.array([1e7 + 3e-9, 0.0]), np.array([0.0, 1.0]))
    assert z is not None and abs(z[0] - 1e7) <= 8 * np.spacing(1e7)
