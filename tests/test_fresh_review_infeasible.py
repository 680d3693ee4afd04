"""`optimize` with a constraint no design within the bounds meets: the result says so instead of printing a design.

Truth: the overcentre lock of tests/data/fresh/toggle_lock.toml has the closed-form downlock force F(0; k, P)
(tests/test_fresh_review_stops.py); over the push P in 200..350 N its largest value is far below 1e6 N m, so
``downlock_force >= 1e6`` is infeasible.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_fresh_review_stops import _F, FILE

from mechcont.analysis.optimize import Constraint, optimize
from mechcont.models import load_model


def test_infeasible_constraint_is_reported_violated() -> None:
    # before: 'NOT converged: Positive directional derivative for linesearch' and a design printed as the optimum,
    # with nothing saying that its downlock force is far below the bound asked for
    largest = max(_F(0.0, 2000.0, P) for P in np.linspace(200.0, 350.0, 301))
    assert largest < 1e5  # the closed form: no P within the bounds reaches the bound
    system = load_model(str(FILE), k=2000.0)
    res = optimize(system, "unlock_force", {"P": (200.0, 350.0)}, constraints=[Constraint.parse("downlock_force >= 1e6")])
    assert res.quantities["downlock_force"] == pytest.approx(_F(0.0, 2000.0, res.design["P"]), rel=1e-8)
    assert len(res.violated) == 1 and res.violated[0].startswith("downlock_force >= 1e+06"), res.violated
    assert "VIOLATED" in res.summary() and res.to_dict()["violated"] == res.violated


def test_feasible_optimum_violates_nothing() -> None:
    system = load_model(str(FILE), k=2000.0)
    res = optimize(system, "unlock_force", {"P": (200.0, 350.0)}, constraints=[Constraint.parse("downlock_force >= 100")])
    assert res.violated == [] and "VIOLATED" not in res.summary()
    assert res.quantities["downlock_force"] >= 100 * (1 - 1e-9)
