"""The integrator choice on the time-simulation commands (issue 31, item 5): ``--method``, ``--rtol``, ``--atol``
on ``simulate``, ``sweep`` and ``freefall``, against closed forms.

tests/data/bar_drop.toml: a uniform bar hinged at its end falls from the horizontal onto a stop at -phi_s; it
arrives at sqrt((3 g / L) sin(phi_s)) (energy) after the elliptic fall time (tests/test_sim_stops.py).
tests/data/freefall_pendulum.toml without air (U = 0) and damper (c = 0): the leg falls from beta to -beta
and strikes the downlock at sqrt(6 g sin(beta) / L)."""

import math
import re

import pytest
from cli_helpers import make_runner, one_line_error
from test_sim_stops import PHI_S, K, fall_time

from mechcont.dynamics import simulate
from mechcont.dynamics._simulate import METHODS
from mechcont.errors import InputError
from mechcont.models import load_model

BAR, PENDULUM = "tests/data/bar_drop.toml", "tests/data/freefall_pendulum.toml"


@pytest.fixture(scope="module")
def run():
    return make_runner()


def _first_impact(output: str) -> tuple[float, float, int]:
    """(time s, speed rad/s, evaluations) of a ``simulate --stops`` output."""
    evals = int(re.search(r"(\d+) evaluations", output).group(1))
    line = next(ln for ln in output.splitlines() if " impact " in ln)
    return float(line.split()[2]), float(line.split("speed ")[1].split()[0]), evals


@pytest.mark.parametrize("method", list(METHODS))
def test_simulate_default_tolerances_meet_1e_6_with_every_method(run, method):
    """Every method at the default tolerances meets the closed-form impact to 1e-6; a loose --rtol/--atol
    (given: it reaches the integrator) does visibly worse, on fewer evaluations."""
    args = ("simulate", BAR, "--start", "theta_bar=0", "--until", 0.5, "--stops", "--no-progress", "--method", method)
    res = run(*args)
    assert res.exit_code == 0, res.output
    t, speed, evals = _first_impact(res.output)
    exact_t, exact_v = fall_time(), math.sqrt(K * math.sin(PHI_S))
    assert t == pytest.approx(exact_t, rel=1e-6) and speed == pytest.approx(exact_v, rel=2e-6)
    loose = run(*args, "--rtol", 1e-3, "--atol", 1e-4)
    t2, speed2, evals2 = _first_impact(loose.output)
    assert evals2 < evals
    assert max(abs(t2 / exact_t - 1), abs(speed2 / exact_v - 1)) > 1e-5


def test_the_method_reaches_the_integrator(run):
    counts = {m: _first_impact(run("simulate", BAR, "--start", "theta_bar=0", "--until", 0.5, "--stops",
                                   "--no-progress", "--method", m).output)[2] for m in ("RK23", "RK45", "DOP853")}
    assert len(set(counts.values())) == 3  # three integrators, three different evaluation counts


@pytest.mark.parametrize("method", ["DOP853", "Radau", "LSODA"])
def test_freefall_method_and_atol_meet_the_energy_impact_speed(run, method):
    res = run("freefall", PENDULUM, "--start", "angle=1", "--lock", "downlock", "--until", 3, "--set", "U=0",
              "--set", "c=0", "--method", method, "--atol", 1e-11)
    assert res.exit_code == 0, res.output
    (line,) = [ln for ln in res.output.splitlines() if ln.startswith("impact speed at the lock: ")]
    assert float(line.split()[5]) == pytest.approx(math.sqrt(6 * 9.81 * math.sin(1.0) / 1.0), rel=2e-6)


def test_sweep_takes_the_method_and_tolerances(run):
    """The overcentre's jump after its fold, timed where theta1 passes 0 (an event on the dense output): the same
    load with two methods and tolerances, on different numbers of evaluations."""
    out = {}
    for opts in (("--method", "RK45"), ("--method", "DOP853", "--rtol", 1e-9, "--atol", 1e-11)):
        res = run("sweep", "overcentre", "--set", "LU=0.4", "--set", "c=50", "--start", "theta1=1.2", "--ramp",
                  "F=-65:-90:1", "--watch", "theta1", "--through", 0, "--no-progress", *opts)
        assert res.exit_code == 0, res.output
        jump = next(ln for ln in res.output.splitlines() if ln.startswith("jump 1: "))
        out[opts[1]] = (float(jump.split()[4]), int(re.search(r"(\d+) evaluations", res.output).group(1)))
    assert out["RK45"][0] == pytest.approx(out["DOP853"][0], rel=1e-5)
    assert out["RK45"][1] != out["DOP853"][1]


COMMANDS = {
    "simulate": ("simulate", BAR, "--start", "theta_bar=0", "--until", 0.1, "--no-progress"),
    "sweep": ("sweep", "overcentre", "--start", "theta1=1.2", "--ramp", "F=-65:-66:1", "--watch", "theta1",
              "--no-progress"),
    "freefall": ("freefall", PENDULUM, "--start", "angle=1", "--lock", "downlock", "--until", 0.1),
}


@pytest.mark.parametrize("command", list(COMMANDS))
@pytest.mark.parametrize("option, value, words", [
    ("--method", "RK4", ["--method", "unknown integrator 'RK4'", "RK45, RK23, DOP853, Radau, BDF, LSODA"]),
    ("--method", "rk45", ["--method", "valid: RK45"]),
    ("--atol", "0", ["--atol", "between 1e-15 and 1"]),
    ("--atol", "-1e-9", ["--atol", "between 1e-15 and 1"]),
    ("--atol", "nan", ["--atol", "finite"]),
    ("--atol", "inf", ["--atol", "finite"]),
    ("--atol", "1e-300", ["--atol", "between 1e-15 and 1"]),  # cannot be met: overflowed SciPy's first step to NaN
    ("--rtol", "1e-16", ["--rtol", "between 1e-13 and 0.1"]),  # below rounding: cannot be met
    ("--rtol", "0", ["--rtol", "between 1e-13 and 0.1"]),
])
def test_bad_integrator_options_are_one_line_errors(run, command, option, value, words):
    one_line_error(run(*COMMANDS[command], option, value), *words)


def test_the_library_checks_alike():
    system = load_model(BAR)
    x0 = system.defaults()
    for kw, field in (({"method": "Euler"}, "method"), ({"atol": float("nan")}, "atol"), ({"atol": 1e-300}, "atol"),
                      ({"atol": [1e-9, 0.0]}, "atol"), ({"rtol": float("nan")}, "rtol")):
        with pytest.raises(InputError, match=f"^{field}: "):
            simulate(system, x0, (0.0, 0.1), **kw)
