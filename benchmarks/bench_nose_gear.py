"""Timing of each nose-gear analysis (the nose-gear part of ``mechcont paper``; target < 10 s in all)."""

from __future__ import annotations


def cases():
    import numpy as np

    from mechcont.analysis.design import design_region, fold_locus
    from mechcont.analysis.downlock import downlock
    from mechcont.models.nose_gear import build_nose_gear
    from mechcont.paper import nose_gear as ng

    system = build_nose_gear()
    res = ng.NoseGearResults(system=system)
    ng._fig7(res)

    def fig11():
        fold_locus(system, "l_sp1", "LU", {"l_sp1": ng.L_SP1_RANGE, "LU": ng.LU_RANGE})
        for v in np.linspace(*ng.LU_RANGE, 21):
            downlock(system, "l_sp1", {"l_sp1": ng.L_SP1_RANGE}, values={"LU": float(v)})

    return [
        ("nose_gear build (25 eq, compile)", build_nose_gear, 3),
        ("fig7 continuation in F", lambda: ng._fig7(ng.NoseGearResults(system=system)), 10),
        ("fig7 time simulation (sweep)", lambda: ng._fig7_dynamic(res), 3),
        ("downlock force by slow ramp (2 N/s)", lambda: ng._downlock_sweep(res), 3),
        ("fig8 downlock vs U (2 branches)", lambda: ng._fig8(ng.NoseGearResults(system=system)), 10),
        ("fig9 downlock vs LU and k", lambda: ng._fig9(ng.NoseGearResults(system=system)), 10),
        ("fig10 downlock vs l_sp1", lambda: ng._fig10(ng.NoseGearResults(system=system)), 10),
        ("fig11 fold locus + 21-branch surface", fig11, 5),
        ("design region (11 levels)", lambda: design_region(system, "l_sp1", "LU", x_bounds=ng.L_SP1_RANGE,
                                                            y_levels=np.linspace(*ng.LU_RANGE, 11)), 5),
        ("whole nose-gear paper section (compute)", lambda: ng.compute(), 3),
    ]
