"""Continuation core on the paper's overcentre (model built before timing)."""

from __future__ import annotations

import tempfile
from pathlib import Path


def cases():
    from mechcont.continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium
    from mechcont.models import build_overcentre
    from mechcont.paper import overcentre as paper_overcentre

    s = build_overcentre(LU=0.4)
    x0 = find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])
    opts = ContinuationOptions(bounds={"theta1": (-1.2, 1.2)})

    def branch():
        b = continuation(s, x0, "F", options=opts)
        assert len(b.special("LP")) == 2

    s01 = build_overcentre(LU=0.1)
    x01 = find_equilibrium(s01, hold={"theta1": 0.3}, free=["F"])
    lp = min(continuation(s01, x01, "F", options=ContinuationOptions(bounds={"theta1": (-1.4, 1.4)})).special("LP"),
             key=lambda p: p["F"])
    fopts = ContinuationOptions(bounds={"LU": (0.1, 2.0)})

    def fold_curve():
        fc = continue_folds(s01, lp, "F", "LU", options=fopts, direction=1, stop_at_cusp=True)
        assert fc.labels[-1] == "CP"

    tmp = Path(tempfile.mkdtemp())

    def paper_part():
        # the section keeps its branches and sweeps for the dynamics section: start each run afresh
        for f in (paper_overcentre.system, paper_overcentre._start, paper_overcentre.branch):
            f.cache_clear()
        paper_overcentre._SWEEPS.clear()
        paper_overcentre.run(tmp, quiet=True)

    return [
        ("overcentre branch, both LP located", branch, 20),
        ("overcentre fold curve LU=0.1 -> cusp", fold_curve, 20),
        ("paper overcentre part (two time simulations, figures incl.)", paper_part, 3),
    ]
