"""First equilibria (``find_equilibrium``, the square Newton solve) from a model's guess: the overcentre and the
nose gear (a few unknowns, where Python's overhead per iteration counts) and the locked dual-sidestay gear of
``examples/dual_sidestay.toml`` (63 coordinates and their reactions, where the linear algebra per iteration
counts). Models are built (through the disk cache) before timing.
"""

from __future__ import annotations

from pathlib import Path

from mechcont.continuation import find_equilibrium
from mechcont.models import load_model

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def cases():
    overcentre = load_model("overcentre", LU=0.4)
    nose = load_model("nose_gear")
    gear = load_model(EXAMPLES / "dual_sidestay.toml")
    locks = {"fwd_lock": 0.0, "aft_lock": 0.0}
    return [
        ("find_equilibrium: overcentre, theta1 held, F freed", lambda: find_equilibrium(
            overcentre, hold={"theta1": 0.3}, free=["F"]), 50),
        ("find_equilibrium: nose gear from its guess", lambda: find_equilibrium(nose), 50),
        (f"find_equilibrium: dual-sidestay locked, {gear.n_equations} unknowns", lambda: find_equilibrium(
            gear, hold=locks, free=["F_fwd", "F_aft"]), 50),
    ]
