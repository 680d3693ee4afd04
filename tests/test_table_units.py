"""Every column of the tables ``continue``, ``cycles`` and ``folds`` write carries its unit (issue 37).

The shimmy gear's cycles table headed a velocity state's extremes ``min_theta_wheel_dot``, without the rad/s the
column holds (a mechanism's velocity states are no variables of the model, so no unit was looked up for them).
Each header here is ``name [unit]`` or a name declared without a unit: a model variable declared dimensionless, or
one of :data:`UNITLESS`. The commands run on the shipped examples (an ODE file, a mechanism with velocity states,
the built-in overcentre model), in-process; about 10 s in all.
"""

from __future__ import annotations

import csv
import re
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from mechcont.models import load_model

ROOT = Path(__file__).resolve().parent.parent
#: The columns a table may leave without a unit: bookkeeping (arclength ``s``, counts, labels, the varied
#: parameter's name), multipliers (``floquet_max``), the Hopf curve's columns its code declares dimensionless
#: (``l1``; ``stable_<p>``: a direction in the parameter plane) and the orbit table's row number.
UNITLESS = {"s", "stability", "n_unstable", "label", "vary", "floquet_max", "n_unstable_dynamic", "n_unstable_other",
            "l1", "row"}
HEADER = re.compile(r"^(\w+) \[([^\]]+)\]$")
#: ``(model, [commands])``: each a ``mechcont`` argument list; ``OUT`` is replaced by the table's file name.
RUNS = [
    ("examples/ab.toml", [["continue", "examples/ab.toml", "--set", "B=17", "--vary", "D", "--bounds", "D=0:0.2",
                           "--out", "ab.csv"],
                          ["cycles", "examples/ab.toml", "--set", "B=17", "--point", "ab.csv:HB1", "--vary", "D",
                           "--bounds", "D=0:0.2", "--bounds", "period=0:40", "--ntst", "10", "--max-steps", "20",
                           "--out", "ab_cycles.csv", "--orbits", "ab_orbits.csv"],
                          ["folds", "examples/ab.toml", "--set", "B=17", "--vary", "D", "--along", "B", "--bounds",
                           "D=0:0.2", "--bounds", "B=15:20", "--out", "ab_folds.csv"],
                          ["folds", "examples/ab.toml", "--set", "B=17", "--point", "ab.csv:HB1", "--along", "B",
                           "--bounds", "D=0:0.2", "--bounds", "B=15:20", "--out", "ab_hopf.csv"]]),
    ("examples/shimmy.toml", [["continue", "examples/shimmy.toml", "--vary", "V", "--bounds", "V=1:100", "--dynamic",
                               "--out", "shimmy.csv"],
                              ["cycles", "examples/shimmy.toml", "--point", "shimmy.csv:HB1", "--vary", "V", "--bounds",
                               "V=1:30", "--ntst", "10", "--out", "shimmy_cycles.csv", "--orbits",
                               "shimmy_orbits.csv"],
                              ["folds", "examples/shimmy.toml", "--point", "shimmy.csv:HB1", "--along", "c_psi",
                               "--bounds", "V=1:100", "--bounds", "c_psi=0:40", "--out", "shimmy_hopf.csv"]]),
    ("overcentre", [["continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--bounds",
                     "F=-100:120", "--out", "overcentre.csv"],
                    ["folds", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--along", "LU",
                     "--bounds", "LU=0.1:2", "--bounds", "F=-200:200", "--out", "overcentre_folds.csv"]]),
]


def header_problems(header: list[str], dimensionless: set[str]) -> list[str]:
    """The headers of ``header`` that carry no unit and are not declared without one (``dimensionless``: the
    model's variables declared without a unit; ``min_X``/``max_X`` of such a state; ``stable_<p>``; :data:`UNITLESS`)."""
    bad = []
    for h in header:
        if HEADER.match(h):
            continue
        extreme = re.sub(r"^(min|max)_", "", h)
        if not (h in UNITLESS or h in dimensionless or h.startswith("stable_") or (h != extreme and extreme in dimensionless)):
            bad.append(h)
    return bad


def test_a_header_without_a_unit_is_found():
    """The check itself: a velocity state's extremes without their unit, a variable with a unit written bare."""
    assert header_problems(["V [m/s]", "min_theta_dot", "max_theta_dot [rad/s]", "F", "stretch", "label"],
                           {"stretch"}) == ["min_theta_dot", "F"]


@pytest.mark.parametrize("model,commands", RUNS, ids=[m for m, _ in RUNS])
def test_every_column_of_the_written_tables_carries_its_unit(model, commands, tmp_path, monkeypatch):
    from mechcont.cli._app import _register, cli

    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    _register()
    dimensionless = {v.name for v in load_model(model).variables if not v.unit}
    for args in commands:
        r = CliRunner().invoke(cli, [*args, "--quiet"])
        assert r.exit_code == 0, f"`mechcont {' '.join(args)}`: {r.output[-2000:]}"
        for k, a in enumerate(args[:-1]):
            if a in ("--out", "--orbits"):
                with open(tmp_path / args[k + 1], newline="") as f:
                    header = next(csv.reader(f))
                assert not header_problems(header, dimensionless), (args[k + 1], header_problems(header, dimensionless))
