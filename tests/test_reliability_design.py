"""Reliability-based design: ``optimize`` under ``P(not locking) <= p`` against closed forms (a downlock moment
linear in normal variables), on the nose gear checked by an independent reliability analysis, and its CLI."""

import json

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from scipy.stats import norm

from mechcont.analysis.optimize import BETA, NOT_LOCKING, Constraint, optimize
from mechcont.analysis.reliability import downlock_reliability
from mechcont.analysis.study import Distribution, StudySpec
from mechcont.errors import InputError
from mechcont.models import load_model

run = make_runner()
PENDULUM = "tests/data/pendulum_downlock.toml"
C = 9.81 * 0.5 * np.cos(0.3)  # the downlock moment is M0 - C m
M_DIST = Distribution("normal", (2.0, 0.1))


@pytest.mark.parametrize("text, sense, bound", [("P(not locking) <= 1e-6", "<=", 1e-6),
                                                (" P( not  locking unaided )<=.001 ", "<=", 1e-3),
                                                ("P(not locking) >= 0.5", ">=", 0.5)])
def test_probability_constraint_parses(text, sense, bound):
    c = Constraint.parse(text)
    assert (c.quantity, c.sense, c.bound) == (NOT_LOCKING, sense, bound)


@pytest.mark.parametrize("text", ["P(not locking) <= 0", "P(not locking) <= 1", "P(not locking) <= -1e-6",
                                  "P(locking) <= 1e-6", "P(not locking) <= 1e-6 or 1", "P(not locking) < 1e-6",
                                  "P(__import__('os')) <= 1e-6"])
def test_probability_constraint_refuses_anything_else(text):
    with pytest.raises(InputError, match="constraint"):
        Constraint.parse(text)


@pytest.mark.parametrize("toleranced", [False, True])
def test_linear_limit_state_optimum_in_closed_form(toleranced):
    """Smallest lock moment M0 with P(M0 - C m <= 0) <= 1e-6, m ~ N(2, 0.1): M0* = C mean_m + z sd, z = Phi^-1(1 - 1e-6),
    sd = C sd_m for a deterministic M0, hypot(sd_M0, C sd_m) for a toleranced one (its distribution moves with it).
    The multiplier is dM0*/dbeta = sd."""
    random = {"m": M_DIST, **({"M0": Distribution("normal", (15.0, 0.5))} if toleranced else {})}
    r = optimize(load_model(PENDULUM), "M0", {"M0": (5.0, 30.0)}, constraints=[Constraint.parse("P(not locking) <= 1e-6")],
                 random=random)
    sd = np.hypot(0.5, C * 0.1) if toleranced else C * 0.1
    assert r.success
    assert r.design["M0"] == pytest.approx(C * 2.0 + norm.isf(1e-6) * sd, rel=1e-9)
    assert r.quantities[NOT_LOCKING] == pytest.approx(1e-6, rel=1e-6)
    [(what, mu)] = r.active
    assert what.startswith(BETA) and mu == pytest.approx(sd, rel=1e-6)


def test_nose_gear_longest_free_length_at_one_in_a_million():
    """The longest spring free length (nominal, 10 mm tolerance) with P(not locking) <= 1e-6; the reliability of
    the optimum analysed again on its own gives 1e-6, and importance sampling agrees within 10 %."""
    tol = {"LU": Distribution("normal", (1.3, 0.01)), "l_sp1": Distribution("truncnormal", (0.1, 0.005, 0.09, 0.11))}
    r = optimize(load_model("nose_gear"), "LU", {"LU": (1.2, 1.4)}, maximize=True,
                 constraints=[Constraint.parse("P(not locking) <= 1e-6")], random=tol)
    LU = r.design["LU"]
    spec = StudySpec("nose_gear", "mc", (("LU", Distribution("normal", (LU, 0.01))), ("l_sp1", tol["l_sp1"])), n=4000)
    check = downlock_reliability(spec, seed=2)
    assert check.probability == pytest.approx(1e-6, rel=1e-5)
    assert check.sampling.probability == pytest.approx(1e-6, rel=0.1)


def test_cli_probability_constraint(tmp_path):
    out = tmp_path / "o.json"
    r = run("optimize", PENDULUM, "--minimize", "M0", "--design", "M0=5:30", "--dist", "m=normal:2:0.1",
            "--constraint", "P(not locking) <= 1e-6", "--out", out)
    assert r.exit_code == 0, r.output
    doc = json.loads(out.read_text())
    assert doc["design"]["M0"] == pytest.approx(C * (2.0 + norm.isf(1e-6) * 0.1), rel=1e-9)
    assert doc["quantities"][NOT_LOCKING] == pytest.approx(1e-6, rel=1e-6)
    assert "P(not locking) = 1e-06" in r.output


@pytest.mark.parametrize("args, words", [
    (("--constraint", "P(not locking) <= 1e-6"), ["--dist", "tolerances"]),
    (("--dist", "m=normal:2:0.1"), ["--dist", "P(not locking)"]),
    (("--dist", "m=normal:2:-1", "--constraint", "P(not locking) <= 1e-6"), ["--dist m", "sd"]),
    (("--dist", "m=normal:2:0.1", "--constraint", "P(not locking) <= 2"), ["--constraint", "between 0 and 1"]),
    (("--dist", "x_bar=normal:2:0.1", "--constraint", "P(not locking) <= 1e-6"), ["x_bar", "parameters"]),
])
def test_cli_bad_probability_input_is_one_line(tmp_path, args, words):
    out = tmp_path / "o.json"
    r = run("optimize", PENDULUM, "--minimize", "M0", "--design", "M0=5:30", *args, "--out", out)
    one_line_error(r, *words)
    assert not out.exists()
