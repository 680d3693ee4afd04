"""Animations along a continuation branch: ``animate`` of the overcentre's bounded branch (54 frames,
the README's example) to a GIF and to an HTML page, and of the dual-sidestay gear's retraction (a
three-view and a 3-D view) to a GIF. The branch is continued once in ``cases()``; each repetition draws
and writes the whole file.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.models import load_model
from mechcont.outputs.animation import animate


def cases():
    overcentre = load_model("overcentre", LU=0.4)
    x0 = find_equilibrium(overcentre, hold={"theta1": 0.3}, free=["F"])
    branch = continuation(overcentre, x0, "F", options=ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}))
    assert len(branch) == 54, len(branch)
    gear = load_model("dual_sidestay_kinematics")
    g0 = find_equilibrium(gear, hold={"theta": float(gear.vector({})[gear.index("theta")])})
    retraction = continuation(gear, g0, "theta", options=ContinuationOptions(bounds={"theta": (0.0, 0.6)}))
    out = Path(tempfile.mkdtemp(prefix="mechcont-bench-animation-"))

    def overcentre_to(suffix: str):
        def run():
            assert animate(overcentre, branch, out / f"a{suffix}", diagram=("F", "theta1")) == 54
        return run

    def gear_gif():
        animate(gear, retraction, out / "gear.gif", diagram=("theta", "delta"))

    return [
        ("animate: overcentre branch, 54 frames, GIF (with the branch panel)", overcentre_to(".gif"), 3),
        ("animate: overcentre branch, 54 frames, HTML page", overcentre_to(".html"), 3),
        (f"animate: dual-sidestay retraction, {len(retraction)} frames, GIF (three-view + 3-D)", gear_gif, 3),
    ]
