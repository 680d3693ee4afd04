"""The time simulation's cost per acceleration and per freefall: the nose gear (15 coordinates, constant mass
matrix), the dual-sidestay gear (63 coordinates, Euler parameters: the mass matrix inverted block by block per
call) and the freefall pendulum of the paper's damping study (one body).

One acceleration is one call of the Udwadia-Kalaba right-hand side (``ConstrainedDynamics.__call__``) at a state
taken half-way through a freefall, with no stop in contact and with the lock stop in contact (its row added to the
solve: the gap's gradient and curvature each call). A freefall is :func:`~mechcont.dynamics.freefall.freefall` as
the paper's freefall section runs it (the model built and cached before the timing).

``cases()`` serves ``benchmarks/run.py`` (wall-clock medians); ``python benchmarks/bench_freefall.py [repeats]``
prints a table of CPU-time medians (CPU, not wall-clock: the other jobs of a shared machine inflate it less):
microseconds per acceleration, milliseconds per freefall.
"""

from __future__ import annotations

import statistics
import sys
import time
from collections.abc import Callable

import numpy as np

#: Accelerations per timed repetition (one is too short to time alone).
CALLS = 200


def _nose_gear():
    from mechcont.models import model_from_text
    from mechcont.paper.freefall import description_text

    return model_from_text(description_text(), "nose_gear_freefall.toml")


def _nose_freefall(system, U: float = 50.0):
    from mechcont.dynamics.freefall import freefall
    from mechcont.paper.freefall import THETA_UP, UNTIL

    return freefall(system, {"fitting": THETA_UP}, lock="downlock", until=UNTIL, values={"U": U})


def _pendulum_freefall(system, U: float = 27.0, c: float = 1.0):
    """One run of the paper's damping study (ended at the lock or at rest, no energy audit, as its bisections)."""
    from mechcont.dynamics.freefall import freefall
    from mechcont.paper.freefall import PENDULUM_ATOL, PENDULUM_RTOL, PENDULUM_UNTIL

    return freefall(system, {"angle": 1.0}, lock="downlock", until=PENDULUM_UNTIL, values={"U": U, "c": c},
                    end_at_lock=True, rtol=PENDULUM_RTOL, atol=PENDULUM_ATOL, audit=False)


def accelerations(system, run, stop: str, calls: int = CALLS) -> dict[str, Callable[[], object]]:
    """``{label: callable}``: ``calls`` accelerations at the state half-way through the history of ``run`` (a
    FreefallResult of ``system``), with no stop in contact and with ``stop`` in contact."""
    from mechcont.dynamics._contact import StopConstraints
    from mechcont.dynamics._udwadia_kalaba import ConstrainedDynamics

    h = run.history
    i = len(h.t) // 2
    x = h.values[i].copy()
    for s in system.stops:
        x[system.index(s.reaction)] = 0.0
    out = {}
    for label, active in (("free", []), (f"on {stop}", [[s.name for s in system.stops].index(stop)])):
        dyn = ConstrainedDynamics(system, x)
        dyn.contacts = StopConstraints(system, dyn)
        dyn.contacts.active = active
        y = np.concatenate([x[dyn.q_index], h.qdot[i]])

        def many(dyn=dyn, y=y) -> None:
            for _ in range(calls):
                dyn(0.1, y)
        out[label] = many
    return out


def _sidestay():
    """The dual-sidestay gear, its retracted pose and a 0.05 s fall from it (for a state to time at)."""
    from mechcont.paper import freefall_sidestay as fs

    model = fs.freefall_gear()
    x = fs.retracted(model)
    return model, x, fs.sidestay_freefall(model, x, until=0.05)


def cases():
    """Benchmark cases for benchmarks/run.py (each acceleration case runs :data:`CALLS` of them)."""
    from mechcont.models import model_from_text
    from mechcont.paper.freefall import PENDULUM

    nose = _nose_gear()
    nose_acc = accelerations(nose, _nose_freefall(nose), "downlock")
    ds, _, ds_run = _sidestay()
    ds_acc = accelerations(ds, ds_run, "aft_stop", calls=CALLS // 4)
    pendulum = model_from_text(PENDULUM, "freefall_pendulum.toml")
    return [
        (f"nose_gear_{CALLS}_accelerations_free", nose_acc["free"], 20),
        (f"nose_gear_{CALLS}_accelerations_on_downlock", nose_acc["on downlock"], 20),
        (f"dual_sidestay_{CALLS // 4}_accelerations_free", ds_acc["free"], 20),
        (f"dual_sidestay_{CALLS // 4}_accelerations_on_aft_stop", ds_acc["on aft_stop"], 10),
        ("nose_gear_freefall_U50_to_lock", lambda: _nose_freefall(nose), 10),
        ("pendulum_freefall_U27_c1_to_rest", lambda: _pendulum_freefall(pendulum), 5),
    ]


def _cpu_times(fn: Callable[[], object], repeats: int) -> tuple[float, float]:
    """``(median, min)`` CPU time (s) of ``repeats`` calls after a warm-up."""
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return statistics.median(times), min(times)


def table(repeats: int = 9) -> str:
    """A Markdown table of CPU-time medians and minima: per acceleration (us) and per freefall (ms)."""
    from mechcont.models import model_from_text
    from mechcont.paper.freefall import PENDULUM

    rows = ["| case | CPU median | CPU min | unit |", "|---|---|---|---|"]
    nose = _nose_gear()
    nose_run = _nose_freefall(nose)
    ds, x_up, ds_run = _sidestay()
    for name, system, run, stop, calls in (("nose gear", nose, nose_run, "downlock", CALLS),
                                           ("dual-sidestay gear", ds, ds_run, "aft_stop", CALLS // 4)):
        for label, fn in accelerations(system, run, stop, calls).items():
            med, low = _cpu_times(fn, repeats)
            rows.append(f"| {name}: one acceleration, {label} | {1e6 * med / calls:.1f} | {1e6 * low / calls:.1f} | us |")
    pendulum = model_from_text(PENDULUM, "freefall_pendulum.toml")
    p_run = _pendulum_freefall(pendulum)
    for what, fn in ((f"nose gear freefall, U = 50 m/s, to the lock ({nose_run.history.nfev} evaluations)",
                      lambda: _nose_freefall(nose)),
                     (f"pendulum freefall, U = 27 m/s, c = 1 N s/m, to rest ({p_run.history.nfev} evaluations)",
                      lambda: _pendulum_freefall(pendulum))):
        med, low = _cpu_times(fn, repeats)
        rows.append(f"| {what} | {1e3 * med:.0f} | {1e3 * low:.0f} | ms |")
    return "\n".join(rows)


if __name__ == "__main__":
    print(table(int(sys.argv[1]) if len(sys.argv) > 1 else 9))
