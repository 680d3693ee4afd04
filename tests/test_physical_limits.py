"""Physical ranges everywhere: impossible values refused, continuation ends at the range's edge."""

import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium
from mechcont.errors import InputError
from mechcont.mechanism import load
from mechcont.models import build_overcentre
from mechcont.models.nose_gear import build_nose_gear


@pytest.mark.parametrize("name, value, words", [
    ("L1", -1.0, "length of bar 1 (m) must be positive, got -1"),
    ("m2", 0.0, "mass of bar 2 (kg) must be positive, got 0"),
    ("k", -5.0, "spring stiffness (N/m) must be non-negative, got -5"),
    ("LU", 0.0, "unstrained spring length (m) must be positive"),
])
def test_built_in_overcentre_refuses_impossible_values(name, value, words):
    with pytest.raises(InputError, match=rf"^{name}: ") as exc:
        build_overcentre(**{name: value})
    assert words in str(exc.value)
    s = build_overcentre()
    with pytest.raises(InputError, match=rf"^{name}: "):  # also when given to a solve
        find_equilibrium(s, values={name: value}, hold={"theta1": 0.3}, free=["F"])


def test_built_in_nose_gear_refuses_a_negative_length():
    with pytest.raises(InputError, match=r"^L3: must be positive"):
        build_nose_gear(L3=-2.0)


@pytest.mark.parametrize("model, field", [("overcentre", "L1"), ("overcentre.toml", "bodies.1.length"),
                                          ("nose_gear", "L1")])
def test_cli_refuses_a_negative_length(model, field):
    r = make_runner()("continue", model, "--set", "L1=-1", "--start", "theta1=0.3" if "over" in model else "theta4=0",
                      "--vary", "F", "--bounds", "F=-100:100")
    one_line_error(r, field, "must be positive")


def _held(system, vary, bounds):
    x0 = find_equilibrium(system, hold={"theta1": 0.3}, free=["F"])
    return continuation(system, x0, vary, hold=["theta1"], free=["F"],
                        options=ContinuationOptions(bounds={vary: bounds}))


def test_continuation_in_stiffness_ends_where_it_reaches_zero():
    b = _held(build_overcentre(LU=0.4), "k", (-100.0, 300.0))
    ends = b.special("EP")
    low = min(ends, key=lambda p: p["k"])
    assert low["k"] == 0.0 or abs(low["k"]) < 1e-10
    assert low.info["limit"] == "k" and "physical limit" in low.info["reason"]
    assert "physical limit: k" in b.message
    assert b.column("k").min() >= -1e-10


@pytest.mark.parametrize("vary, field", [("LU", "springs.spring.free_length"), ("m1", "bodies.1.mass")])
def test_generated_model_stops_at_its_physical_limit(vary, field):
    s = load("overcentre", LU=0.4)
    b = _held(s, vary, (-1.0, 3.0))
    low = min(b.special("EP"), key=lambda p: p[vary])
    assert abs(low[vary]) < 1e-10 and low.info["limit"] == field
    assert b.column(vary).min() > -1e-10


def test_fold_curve_stops_at_a_physical_limit():
    s = build_overcentre(LU=0.4)
    x0 = find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])
    b = continuation(s, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}))
    curve = continue_folds(s, b["LP1"], "F", "k", options=ContinuationOptions(bounds={"k": (-50.0, 500.0)}))
    low = min(curve.special("EP"), key=lambda p: p["k"])
    assert abs(low["k"]) < 1e-9 and low.info["limit"] == "k"


@pytest.mark.parametrize("where", ["fourbar", "tests/data/spatial/fourbar_3d.toml", "examples/dual_sidestay.toml"])
def test_the_compiled_value_screen_agrees_with_the_exact_check(where):
    """A description's value check (run by every solve) decides as its exact SymPy check does, with the
    same one-line error, for each parameter at its default, zero, negated, tiny, large, inf and nan;
    clearly valid values never reach the exact check (that is what keeps SymPy out of a solve)."""
    from pathlib import Path

    import numpy as np

    from mechcont.errors import InputError
    from mechcont.mechanism._compiled import ValueCheck
    from mechcont.models import load_model

    path = Path(__file__).resolve().parent.parent / where if where.endswith(".toml") else where
    check = load_model(path).check_values  # (the dual-sidestay gear's has perpendicular axes)
    assert isinstance(check, ValueCheck) and check.screen is not None
    exact = check.exact
    calls = []
    check.exact = lambda values: (calls.append(values), exact(values))

    def outcome(fn, values):
        try:
            fn(values)
        except InputError as exc:
            return str(exc)
        return None

    check({})
    assert calls == []  # the defaults pass on the screen alone
    refused = 0
    for name, default in zip(check.names, check.defaults):
        for value in (default, 0.0, -default, 1e-12, -1e-12, 3 * default + 1, np.inf, np.nan):
            values = {name: value}
            expected = outcome(exact, {**dict(zip(check.names, check.defaults)), **values})
            assert outcome(check, values) == expected, (name, value)
            refused += expected is not None
    assert calls and refused  # the doubtful values went to the exact check, some were refused
