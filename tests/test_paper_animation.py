"""The paper's retraction animation (issue 25): smooth (>= 48 frames), the branch panel with the current point,
the stability and label text on every frame. The GIF itself is the one tests/test_figure_review.py reviews
(``retraction_gif``: ``dual_sidestay.retraction_animation`` run once per session); here its frames are counted."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402

from mechcont.models.dual_sidestay_geometry import DEFAULT_GEOMETRY  # noqa: E402
from mechcont.outputs import animation as _a  # noqa: E402
from mechcont.paper.dual_sidestay import ANIMATION_FRAMES, _fine, retraction  # noqa: E402


def test_retraction_animation_has_enough_frames_a_branch_panel_and_status_text(shared):
    ret = retraction()
    fine = _fine(ret.system, ret.branch, DEFAULT_GEOMETRY.retracted)
    theta = fine.values[:, ret.system.index("theta")]
    assert len(theta) >= ANIMATION_FRAMES >= 48
    assert theta[0] == 0.0 and np.all(np.diff(theta) > 0)
    assert abs(theta[-1] - DEFAULT_GEOMETRY.retracted) < 1e-9
    # every row is on the mechanism: the loop-closure equations hold (the coarse branch's own tolerance)
    worst = max(float(np.max(np.abs(ret.system.residual(x)))) for x in fine.values)
    assert worst < 1e-8
    frames = _a.branch_frames(ret.system, fine)
    renderer = _a._renderer(ret.system.scene, ret.system, frames, _a.frame_rows(frames), ("theta",), title=None,
                            show_forces=True, diagram=("theta", "aft_J_z"), figsize=None, dpi=50)
    line, xs, ys = renderer.marker
    for k in (0, len(xs) // 2, len(xs) - 1):
        renderer.render(k)
        assert (line.get_xdata()[0], line.get_ydata()[0]) == (xs[k], ys[k])   # the current point
        notes = [t.get_text() for t in renderer.axes[0].texts if "theta =" in t.get_text()]
        assert len(notes) == 1 and "kinematic: no stability" in notes[0]
    assert notes[0].endswith("EP1")
    from test_figure_review import retraction_gif

    gif = retraction_gif(shared)   # the paper's GIF: one frame per row of the fine branch
    assert gif.n == gif.frames == len(theta)
