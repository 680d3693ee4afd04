"""`downlock` on a fresh user's retracting strut whose lock is its stop: what the release run's notes claim.

The strut (tests/data/fresh_user/strut.toml: a leg, a two-link brace closing the loop, a preloaded lock spring, a
damper, an offset cg, a downlock stop on the brace's alignment) has no unlock fold: pushed either way from the lock,
the brace either rests harder on its stop or, released, runs towards its straight toggle, where the force holding
it grows without bound. The release run therefore uses up its steps before the force has moved by its span; the
note must say where it ended, not where it aimed.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from cli_helpers import make_runner

from mechcont.analysis import equilibrium_on_stops
from mechcont.analysis.stop_lock import stop_unlock
from mechcont.analysis.unlock import RELEASE_FORCE_SPAN
from mechcont.models import load_model

STRUT = Path(__file__).parent / "data" / "fresh_user" / "strut.toml"


def test_release_run_that_ends_early_says_where():
    # before: "no fold increasing F within the release run (F moved by 50 of its scales, to 800000 N ...)" while
    # the run had stopped at F = 377135 N (its warning said so on stderr)
    run = make_runner()
    res = run("downlock", STRUT, "--vary", "k", "--bounds", "k=7000:9000")
    assert res.exit_code == 0, res.output
    notes = {side: line for line in res.stdout.splitlines()
             for side in ("decreasing", "increasing") if line.strip().startswith(f"no fold {side} F")}
    assert set(notes) == {"decreasing", "increasing"}, res.stdout
    m = load_model(str(STRUT))
    x, _ = equilibrium_on_stops(m, m.defaults())
    unlock = stop_unlock(m, x, "F")
    forces = unlock.branch.values[:, unlock.branch.names.index("F")]
    span = RELEASE_FORCE_SPAN * m.variable("F").scale
    for side, reached in (("increasing", forces.max()), ("decreasing", forces.min())):
        assert abs(reached) < 0.9 * span  # the run did end early: the toggle holds it back
        said = float(re.search(r"ended early at F = (-?[\d.e+]+) N", notes[side]).group(1))
        assert np.isclose(said, reached, rtol=1e-5), (notes[side], reached)
        assert f"to {span:.6g}" not in notes[side] and f"to {-span:.6g}" not in notes[side]
