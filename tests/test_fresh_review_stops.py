"""A fresh user's overcentre lock (tests/data/fresh/toggle_lock.toml): links A-B-C with C on the x axis, a spring
pulling the knee B towards S, a push P on C, an unlock moment F on link 1, a lock stop at theta_l1 = -delta and an
open stop at theta_l1 = theta_open. Truth from the potential V = k/2 (|B - S| - L0)^2 + 2 a P cos(theta) (no
gravity): off the stops F(theta) = dV/dtheta; at k = 1000 N/m dF/dtheta < 0 at the lock, so the release there is
the snap (an NSF at F(-delta)) and the links land on the open stop; pushed back, they leave the open stop at
F(theta_open) (an NSF too) and land on the lock. A run that starts on the unstable free branch walks each NSF
from its unstable side: the stable mechanism on the other piece still jumps there, and lands where it lands."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mechcont.analysis import continuation_with_stops, equilibrium_on_stops
from mechcont.continuation import ContinuationOptions, find_equilibrium
from mechcont.models import load_model

FILE = Path(__file__).parent / "data" / "fresh" / "toggle_lock.toml"
A, K, SX, SY, L0, P, DELTA, OPEN = 0.4, 1000.0, 0.4, -0.25, 0.1, 300.0, 0.05, 1.0


def _F(t: float, k: float = K, p: float = P) -> float:
    """The unlock moment (N m) that holds the links free of the stops at theta_l1 = t (rad): dV/dt, with the
    spring's stiffness k (N/m) and the push p (N)."""
    bx, by = A * np.cos(t), A * np.sin(t)
    d = np.hypot(bx - SX, by - SY)
    return float(k * (d - L0) * ((bx - SX) * -by + (by - SY) * bx) / d - 2 * A * p * np.sin(t))


@pytest.fixture(scope="module")
def model():  # noqa: ANN201 (a compiled model)
    return load_model(str(FILE), k=K)


@pytest.mark.parametrize("start", ["free", "locked"])
def test_snap_and_landing_do_not_depend_on_the_start(model, start: str) -> None:  # noqa: ANN001
    """Both non-smooth folds are where the closed form puts them, both jump, and each lands on the other stop,
    whether the run starts on the lock stop or on the unstable free branch between the stops (that run reaches
    each fold along its unstable piece: on the old code it said nothing jumps there)."""
    if start == "free":   # between the stops, where the free branch is unstable
        x0 = find_equilibrium(model, hold={"theta_l1": 0.6}, free=["F"])
        assert x0[model.index("F")] == pytest.approx(_F(0.6), rel=1e-9)
    else:
        x0, contact = equilibrium_on_stops(model, {"theta_l1": -DELTA, "theta_l2": DELTA}, values={"F": 0.0})
        assert contact == ["lock"]
    opts = ContinuationOptions(bounds={"F": (-100.0, 300.0), "theta_l1": (-0.5, 1.4)})
    run = continuation_with_stops(model, x0, "F", direction=0, options=opts)
    nsf = {p.stop: p for p in run.branch.special("NSF")}
    assert set(nsf) == {"lock", "open"}
    t = model.index("theta_l1")
    for stop, here, there, land_on in (("lock", -DELTA, OPEN, "open"), ("open", OPEN, -DELTA, "lock")):
        p = nsf[stop]
        assert p["F"] == pytest.approx(_F(here), abs=1e-7 * abs(_F(here)))
        assert p["theta_l1"] == pytest.approx(here, abs=1e-9)
        fold = p.nonsmooth
        assert fold is not None and fold.jump, f"the NSF of stop {stop} does not jump (start {start})"
        land = fold.landing
        assert land is not None and land.contact == (land_on,) and land.stable
        assert land.x[t] == pytest.approx(there, abs=1e-9)
        # on the stop it lands on, the stop's reaction balances the moment: R = +-(F - dV/dtheta)/cos(theta)
        r = land.x[model.index(f"R_{land_on}")]
        assert r == pytest.approx(abs(_F(here) - _F(there)) / np.cos(there), rel=1e-7)
