"""Generated mechanisms: time to build the equations, and the cost of one Newton step.

Targets (issue 3): build under 1 s (overcentre, five-bar); a Newton step (residual +
Jacobian + linear solve) under 100 us for the five-bar.
"""

from __future__ import annotations

import numpy as np

from mechcont.mechanism import assemble, load_description


def cases():
    over = load_description("overcentre")
    five = load_description("fivebar")
    system = five.build()
    x = assemble(system, hold={"theta_b1": 1.9, "theta_b4": 1.2}, free=["T1", "T2"])
    unknowns = [n for n in system.state_names if n not in ("theta_b1", "theta_b4")] + ["T1", "T2"]
    idx = np.array([system.index(n) for n in unknowns])
    x = x.copy()
    x[system.index("theta_b1")] += 1e-3  # a genuine correction to make

    def newton_step():
        r = system.residual(x)
        J = system.jacobian(x)[:, idx]
        return np.linalg.solve(J, -r)

    return [
        ("build overcentre (full)", over.build, 3),
        ("build overcentre (reduced)", over.build_reduced, 3),
        ("build five-bar (full)", five.build, 3),
        ("build five-bar (reduced)", five.build_reduced, 3),
        ("parse + build five-bar", lambda: load_description("fivebar").build(), 3),
        ("Newton step five-bar (residual + Jacobian + solve)", newton_step, 2000),
    ]
