"""The shimmy section's parts (``mechcont paper --only shimmy``), timed piece by piece.

The gear of ``examples/shimmy.toml`` (its model built once, outside the timing): one call of the
minimal-coordinate rates (a time simulation's inner loop), the rates at the 40 Gauss points of a
periodic orbit (10 intervals of degree 4) with their Jacobians and parameter derivatives (one Newton
iteration of the cycles), the first Lyapunov coefficient at the Hopf point, the Hopf curve in (V, c_psi),
the limit cycles from HB1, and 0.2 s of the time simulation at 60 m/s (the section simulates 2 s at two
speeds: ten times this case). The dynamics' batch calls are used where the code has them, so the same file
times the code before and after they were added. ``python benchmarks/bench_shimmy.py`` prints the table
(median of the repeats, wall time).
"""

from __future__ import annotations


def cases():
    import numpy as np

    from mechcont.continuation._cycle_system import RateFunction
    from mechcont.continuation._hopf_point import first_lyapunov
    from mechcont.equations import dynamics_of
    from mechcont.paper import _shimmy_analysis as an
    from mechcont.paper.shimmy import gear_at, shimmy_mechanism

    mech = shimmy_mechanism()
    model, x1 = gear_at(1.0, mech)
    branch = an.equilibria(model, x1)
    hopf = next(p for p in branch.special_points if p.label == "HB")
    dyn = dynamics_of(model)
    z = dyn.state_at(hopf.x)
    z[dyn.state_names.index(an.TORSION)] = 0.1
    Z = z + 0.05 * np.random.default_rng(0).standard_normal((40, len(z)))
    rates = RateFunction(model, dyn, "V", hopf.x)
    omega = hopf.extra["hopf"].frequency

    def rates_1000():
        for _ in range(1000):
            dyn.rates(z, hopf.x)

    return [
        ("shimmy: 1000 rates calls", rates_1000, 5),
        ("shimmy: rates + Jacobians at 40 points", lambda: rates(Z, float(hopf["V"])), 5),
        ("shimmy: l1 at the Hopf point", lambda: first_lyapunov(dyn, hopf.x, omega), 5),
        ("shimmy: equilibria in V with Hopf", lambda: an.equilibria(model, x1), 3),
        ("shimmy: Hopf curve in (V, c_psi)", lambda: an.hopf_curve(model, hopf, "c_psi"), 3),
        ("shimmy: limit cycles from HB1", lambda: an.shimmy_cycles(model, hopf), 3),
        ("shimmy: 0.2 s simulation at 60 m/s", lambda: an.simulate_onto(60.0, mech, until=0.2), 3),
    ]


if __name__ == "__main__":
    import statistics
    import time

    for name, fn, repeats in cases():
        times = []
        for _ in range(repeats):
            t = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t)
        print(f"{statistics.median(times):9.4f} s  {name}  (median of {repeats})")
