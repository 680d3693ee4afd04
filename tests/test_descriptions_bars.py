"""No shipped or test description falls into the trap of ``length`` (issue 37, item 1): every point and centre of
gravity of a bar lies between its ends, so every drawing shows the bar where its joints are.

The descriptions fixed here (tests/data pendulums, freefall legs, spring lock, tests/corpus brace locks) were
re-measured from the bar's centre with the hinge at the bar's end ``a``; their tests, which compare against
closed forms written from the hinge, give the same numbers.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from mechcont.errors import InputError
from mechcont.mechanism._bar_points import bar_point_warnings
from mechcont.mechanism._file import load_description
from mechcont.mechanism._values import parameter_values

ROOT = Path(__file__).resolve().parent.parent
FILES = sorted(p for d in ("examples", "tests/data", "tests/corpus", "src/mechcont/models") for p in
               (ROOT / d).rglob("*.toml"))


def _mechanism(path: Path):
    try:
        return load_description(path)
    except InputError:
        return None  # not a mechanism (an ODE file) or a deliberately bad one: the check has nothing to say


def test_there_are_descriptions_to_check():
    assert sum(_mechanism(p) is not None for p in FILES) > 40


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_description_measures_a_bars_points_from_beyond_its_ends(path):
    mech = _mechanism(path)
    if mech is None:
        pytest.skip("not a readable mechanism description")
    assert bar_point_warnings(mech, parameter_values(mech, {})) == ()
