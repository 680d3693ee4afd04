"""A fresh user's overcentre lock (tests/data/fresh/toggle_lock.toml) whose unlock force F is a moment (N m):
``optimize`` chooses the push P that minimises it at k = 2000 N/m. Truth from the potential
V = k/2 (|B - S| - L0)^2 + 2 a P cos(theta) (tests/test_fresh_review_stops.py): off the stops F(theta) = dV/dtheta,
the unlock force its largest value past the lock (a smooth fold), dF*/dP = -2 a sin(theta*) there, and the downlock
force (the links held in line) F(0). The optimum's quantities carry the force parameter's unit (the old code called
every force N)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import minimize_scalar
from test_fresh_review_stops import _F, FILE

from mechcont.analysis.optimize import Constraint, optimize
from mechcont.models import load_model


def _unlock(P: float) -> tuple[float, float]:
    """The unlock moment (N m) at k = 2000 N/m and push P (N): the largest F(theta) past the lock, and its theta."""
    r = minimize_scalar(lambda th: -_F(th, 2000.0, P), bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-12})
    return -float(r.fun), float(r.x)


def test_unlock_optimum_in_the_force_unit() -> None:
    """The optimum sits on the bound P = 350 N with the closed-form unlock moment, its multiplier the closed-form
    slope, the downlock constraint at its closed-form value, and both printed in N m (the force's unit)."""
    system = load_model(str(FILE), k=2000.0)
    res = optimize(system, "unlock_force", {"P": (200.0, 350.0)}, constraints=[Constraint.parse("downlock_force >= 100")])
    f_star, th = _unlock(350.0)
    assert res.design["P"] == pytest.approx(350.0, abs=1e-9)
    assert res.value == pytest.approx(f_star, rel=1e-8)
    assert res.quantities["downlock_force"] == pytest.approx(_F(0.0, 2000.0), rel=1e-10)
    (what, mult), = res.active
    assert "P" in what and abs(mult) == pytest.approx(2 * 0.4 * np.sin(th), rel=1e-5)
    assert res.units["unlock_force"] == "N m" and res.units["downlock_force"] == "N m"
