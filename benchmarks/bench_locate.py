"""Fold location against Hopf location (issue 35: "Hopf location as fast as LP location"), CPU time.

Each case polishes one special point of a branch continued once outside the timing, from two starts: the
branch row before the point (what the branch's event does, from its secant guess's neighbourhood) and the
located point itself (the floor: the iterations that only confirm). Models, by number of unknowns (the
branch's states and the varied parameter):

* AUTO's ``ab`` (``examples/ab.toml`` with beta = 1: two folds and a Hopf point on one branch in D), 3;
* the caster wheel with a first-order tyre (``tests/data/caster_tyre.toml``, Hopf in V), 7;
* the paper's overcentre (``build_overcentre(LU=0.1)``, fold in F), 17 variables;
* the caster steered through a four-bar (``tests/data/fourbar_shimmy.toml``, Hopf in V), a closed loop;
* the shimmy gear (``examples/shimmy.toml``, Hopf in V), 23 variables.

Each model is also continued once with its events' polish calls recorded, and the polish an ``LP`` or ``HB`` event
makes from its secant guess (``polish_fold`` with the branch tangent as the null vector's guess; ``polish_hopf``,
then ``l1``) is timed from the same start with the same arguments: what the branch itself spends per point, like
for like.

Each Hopf case is timed three ways: ``locate_hopf`` as a branch's ``HB`` row carries it (the point, its frequency
and its first Lyapunov coefficient ``l1``), the location alone (the extended system's Newton polish, what
AUTO's ``HB`` location does: ``l1`` is classification) and ``l1`` alone at the located point (as a fold's
location carries its quadratic coefficient, which costs one contraction of the second derivatives).

``python benchmarks/bench_locate.py [--repeats N]`` prints a table (median and minimum CPU time of the
repeats, ``time.process_time``, after one warm-up call); ``benchmarks/run.py -k locate`` times the same
cases by wall time. ``--interleaved N`` also times, on ``ab``, the ``LP`` event's polish, the ``HB`` event's and the
``HB`` event's with ``l1`` in turn (10 calls each, ``N`` rounds) and prints the medians of the per-round ratios
``HB / LP`` and ``(HB + l1) / LP``: on a shared machine the load moves all three alike within a round, so the ratio
is steadier than the table's separate medians.
"""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _starts(branch, label: str):
    """``(row before, located)`` of the first point labelled ``label`` on ``branch``: SpecialPoints with its lens."""
    from mechcont.continuation import SpecialPoint

    sp = next(p for p in branch.special_points if p.label == label)
    before = SpecialPoint(label, 0, branch.values[sp.index - 1].copy(), sp.names, unknowns=sp.unknowns,
                          vary=sp.vary)
    return before, sp


@contextmanager
def _recording():
    """While open, every ``polish_fold`` and ``polish_hopf`` an event of a branch makes is recorded with a copy of
    its arguments and its result: ``{"fold": [(args, kwargs, result)], "hopf": [...]}``."""
    import mechcont.continuation._api as api
    import mechcont.continuation._hopf as hopf

    calls = {"fold": [], "hopf": []}
    fold, hopf_polish = api.polish_fold, hopf.polish_hopf

    def recorder(kind, fn):
        def call(*args, **kwargs):
            kept = tuple(a.copy() if hasattr(a, "copy") and hasattr(a, "shape") else a for a in args)
            out = fn(*args, **kwargs)
            calls[kind].append((kept, kwargs, out))
            return out
        return call

    api.polish_fold, hopf.polish_hopf = recorder("fold", fold), recorder("hopf", hopf_polish)
    try:
        yield calls
    finally:
        api.polish_fold, hopf.polish_hopf = fold, hopf_polish


def _location(model, point, vary: str):
    """What ``locate_hopf(model, point, vary)`` does before its ``l1``: the Newton polish of the extended system."""
    from mechcont.continuation._hopf_point import HopfTest, polish_hopf
    from mechcont.continuation._problem import EquilibriumProblem
    from mechcont.equations import dynamics_of

    test = HopfTest(dynamics_of(model), model)
    problem = EquilibriumProblem(model, point.x, vary, list(point.unknowns), stability=False)
    return polish_hopf(test, problem, problem.u_of(point.x))


def _l1_at(model, point, vary: str):
    """A call of what ``locate_hopf`` adds to the location at the located ``point``: its frequency, ``l1`` and
    eigenvector (``hopf_point_of``)."""
    from mechcont.continuation import locate_hopf
    from mechcont.continuation._hopf import hopf_point_of
    from mechcont.continuation._hopf_point import HopfTest
    from mechcont.equations import dynamics_of

    hb = locate_hopf(model, point, vary)
    test = HopfTest(dynamics_of(model), model)
    pair = test.pair(hb.x)
    return lambda: hopf_point_of(test, hb.x, pair, hb.residual)


def cases():
    from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium, locate_fold, locate_hopf
    from mechcont.continuation._fold_point import polish_fold
    from mechcont.continuation._hopf import hopf_point_of
    from mechcont.continuation._hopf_point import polish_hopf
    from mechcont.models import build_overcentre, load_model

    out = []

    def event_cases(name, calls, n):
        if calls["fold"]:
            fargs, fkwargs, _ = calls["fold"][0]
            out.append((f"{name}: LP event's polish from its secant guess ({n} unknowns)",
                        lambda: polish_fold(*fargs, **fkwargs), 10))
        hb = [c for c in calls["hopf"] if c[2][1].complex]  # not a neutral saddle's
        if hb:
            args, kwargs, _ = hb[0]
            out.append((f"{name}: HB event's polish from its secant guess ({n} unknowns)",
                        lambda: polish_hopf(*args, **kwargs), 10))

            def with_l1():
                u, pair, res = polish_hopf(*args, **kwargs)
                return hopf_point_of(args[0], args[1].full(u), pair, res)
            out.append((f"{name}: HB event's polish and l1 ({n} unknowns)", with_l1, 10))

    def hopf_cases(name, model, branch, vary):
        before, at = _starts(branch, "HB")
        n = len(at.unknowns) + 1
        out.append((f"{name}: locate_hopf from the row before ({n} unknowns)",
                    lambda: locate_hopf(model, before, vary), 10))
        out.append((f"{name}: locate_hopf from HB1 ({n} unknowns)", lambda: locate_hopf(model, at, vary), 10))
        out.append((f"{name}: location alone from the row before ({n} unknowns)",
                    lambda: _location(model, before, vary), 10))
        out.append((f"{name}: location alone from HB1 ({n} unknowns)", lambda: _location(model, at, vary), 10))
        out.append((f"{name}: l1 alone at HB1 ({n} unknowns)", _l1_at(model, at, vary), 10))

    def fold_cases(name, model, branch, vary):
        before, at = _starts(branch, "LP")
        n = len(at.unknowns) + 1
        out.append((f"{name}: locate_fold from the row before ({n} unknowns)",
                    lambda: locate_fold(model, before, vary), 10))
        out.append((f"{name}: locate_fold from LP1 ({n} unknowns)", lambda: locate_fold(model, at, vary), 10))

    def recorded(name, unknowns, run):
        """The branch ``run()`` continues, its events' polish calls recorded as cases."""
        with _recording() as calls:
            b = run()
        event_cases(name, calls, unknowns)
        return b

    ab = load_model(str(ROOT / "examples" / "ab.toml"), beta=1.0)
    b = recorded("ab (beta = 1)", 3, lambda: continuation(
        ab, ab.vector({}), "D", hopf=True, options=ContinuationOptions(bounds={"D": (0.0, 0.2), "u2": (-1.0, 10.0)})))
    fold_cases("ab (beta = 1)", ab, b, "D")
    hopf_cases("ab (beta = 1)", ab, b, "D")

    caster = load_model(str(ROOT / "tests" / "data" / "caster_tyre.toml"))
    b = recorded("caster_tyre", 7, lambda: continuation(
        caster, find_equilibrium(caster), "V", hopf=True, options=ContinuationOptions(bounds={"V": (0.5, 50.0)})))
    hopf_cases("caster_tyre", caster, b, "V")

    oc = build_overcentre(LU=0.1)
    b = recorded("overcentre (LU = 0.1)", 7, lambda: continuation(
        oc, find_equilibrium(oc, hold={"theta1": 0.3}, free=["F"]), "F",
        options=ContinuationOptions(bounds={"theta1": (-1.4, 1.4)})))
    fold_cases("overcentre (LU = 0.1)", oc, b, "F")

    fourbar = load_model(str(ROOT / "tests" / "data" / "fourbar_shimmy.toml"))
    b = recorded("fourbar_shimmy", 19, lambda: continuation(
        fourbar, find_equilibrium(fourbar), "V", hopf=True, options=ContinuationOptions(bounds={"V": (0.3, 20.0)})))
    hopf_cases("fourbar_shimmy", fourbar, b, "V")

    from mechcont.paper import _shimmy_analysis as an
    from mechcont.paper.shimmy import gear_at

    gear, x1 = gear_at(1.0)
    b = recorded("shimmy gear", 12, lambda: an.equilibria(gear, x1))
    hopf_cases("shimmy gear", gear, b, "V")
    return out


def _table(repeats: int) -> str:
    import statistics
    import time

    rows = []
    for name, fn, _ in cases():
        fn()  # warm-up: the compiled second derivatives, the partition
        times = []
        for _ in range(repeats):
            t = time.process_time()
            fn()
            times.append(time.process_time() - t)
        rows.append((name, statistics.median(times), min(times)))
    w = max(len(r[0]) for r in rows)
    lines = [f"| {'case':<{w}} | median (ms) | min (ms) |", f"|{'-' * (w + 2)}|-------------|----------|"]
    lines += [f"| {n:<{w}} | {med * 1e3:>11.2f} | {mn * 1e3:>8.2f} |" for n, med, mn in rows]
    return "\n".join(lines)


def _interleaved(rounds: int) -> str:
    """The medians of the per-round ratios of the ``ab`` events' polishes (``--interleaved``)."""
    import statistics
    import time

    fns = {name: fn for name, fn, _ in cases() if name.startswith("ab (beta = 1):") and "event" in name}
    lp, hb, hb_l1 = (next(f for n, f in fns.items() if key in n) for key in
                     ("LP event's polish", "HB event's polish from", "HB event's polish and l1"))
    times: dict[str, list[float]] = {"LP": [], "HB": [], "HB + l1": []}
    for f in (lp, hb, hb_l1):
        f()
    for _ in range(rounds):
        for key, f in (("LP", lp), ("HB", hb), ("HB + l1", hb_l1)):
            t = time.process_time()
            for _ in range(10):
                f()
            times[key].append((time.process_time() - t) / 10)
    ratio = statistics.median(h / l for h, l in zip(times["HB"], times["LP"]))
    ratio_l1 = statistics.median(h / l for h, l in zip(times["HB + l1"], times["LP"]))
    lines = [f"ab, interleaved ({rounds} rounds of 10 calls each): " + ", ".join(
        f"{k} median {statistics.median(v) * 1e3:.3f} ms (min {min(v) * 1e3:.3f})" for k, v in times.items())]
    lines.append(f"HB / LP {ratio:.2f}, (HB + l1) / LP {ratio_l1:.2f} (medians of the per-round ratios)")
    return "\n".join(lines)


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--interleaved", type=int, default=0, metavar="ROUNDS")
    args = ap.parse_args()
    print(_table(args.repeats))
    if args.interleaved:
        print(_interleaved(args.interleaved))
