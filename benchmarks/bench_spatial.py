"""Spatial mechanisms: building the equations from a description, and continuing a branch.

Cases: the overcentre and the paper's nose gear described with spatial elements, the
dual-sidestay gear (9 bodies, 63 coordinates, 128 unknowns) built from a freshly parsed
description each time (so nothing generated is reused), the spatial nose gear's
unlock branch with its fold, and the dual-sidestay unlock with its overcentre stops (three
runs through contact changes to their folds, and the joint unlock fold continued in the
lock-spring stretch to its cusp).
"""

from __future__ import annotations

from pathlib import Path

from mechcont.continuation import ContinuationOptions, continuation
from mechcont.mechanism import assemble, load_description

ROOT = Path(__file__).resolve().parent.parent
SPATIAL = ROOT / "tests" / "data" / "spatial"


def cases():
    nose = load_description(SPATIAL / "nose_gear_3d.toml").build()
    x0 = assemble(nose, hold={"theta4": 0.0}, free=["F"])
    opts = ContinuationOptions(bounds={"F": (-3e4, 3e4), "theta4": (-0.5, 0.5)})

    def nose_branch():
        b = continuation(nose, x0, "F", options=opts)
        assert len(b.special("LP")) == 1

    from mechcont.paper.dual_sidestay import generated_gear, unlock_study

    gear = generated_gear()

    def gear_unlock():
        study = unlock_study(gear)
        assert [p.label for p in study.fold_curve.special_points].count("CP") == 1

    return [
        ("spatial: parse + build overcentre (2 bodies)", lambda: load_description(SPATIAL / "overcentre_3d.toml").build(), 3),
        ("spatial: parse + build nose gear (5 bodies, 103 unknowns)",
         lambda: load_description(SPATIAL / "nose_gear_3d.toml").build(), 3),
        ("spatial: parse + build dual-sidestay gear (9 bodies, 128 unknowns)",
         lambda: load_description(ROOT / "examples" / "dual_sidestay.toml").build(), 3),
        ("spatial: nose-gear unlock branch, LP located", nose_branch, 3),
        ("spatial: dual-sidestay unlock with stops (3 runs + fold curve to its cusp)", gear_unlock, 3),
    ]
