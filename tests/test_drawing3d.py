"""Drawings of spatial scenes: projections against 3-D vector algebra, figure checks, CLI-level dispatch
of draw/animate on the scene's dimension."""

from __future__ import annotations

import math

import matplotlib
import matplotlib.colors

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from figure_checks import check_figure  # noqa: E402
from PIL import Image  # noqa: E402

from mechcont.equations import Scene  # noqa: E402
from mechcont.errors import InputError  # noqa: E402
from mechcont.outputs.animation import MIN_DURATION, animate  # noqa: E402
from mechcont.outputs.drawing import draw  # noqa: E402
from mechcont.outputs.drawing3d import VIEWS, draw3d, draw_scene3d, project  # noqa: E402

RNG = np.random.default_rng(11)


def rot(axis, angle):
    """Rotation matrix about a unit ``axis`` by ``angle`` (Rodrigues), independent of the drawing code."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


TRUNNION = np.array([1.0, 0.0, 0.12]) / np.linalg.norm([1.0, 0.0, 0.12])


def swing_scene(theta: float) -> Scene:
    """A leg swinging about an inclined trunnion axis, braced by a spring, pushed by an actuator."""
    top = np.array([0.0, 0.0, 2.0])
    axle = top + rot(TRUNNION, theta) @ np.array([0.0, 0.3, -1.8])
    lug = top + rot(TRUNNION, theta) @ np.array([0.0, 0.1, -0.5])
    return Scene(bars=[("fitting", np.array([top, lug, axle]))], grounds=[top], anchors=[np.array([0.2, 1.0, 2.1])],
                 springs=[("spring", np.array([0.2, 1.0, 2.1]), lug)],
                 actuators=[("actuator", np.array([-0.4, 0.6, 2.2]), lug, -4.0e4)],
                 forces=[("W", axle, np.array([0.0, 0.0, -2.0e4]))],
                 moments=[("M", top, np.array([300.0, -200.0, 100.0]))],
                 joint_axes=[("trunnion", top, TRUNNION)], points=[("fitting.axle", axle)])


class Swing:
    """The smallest system the drawing code needs: names, variables, a scene."""

    name = "swing"
    names = ("theta", "F")

    class _Var:
        def __init__(self, name, unit, kind):
            self.name, self.unit, self.kind = name, unit, kind

    variables = (_Var("theta", "rad", "state"), _Var("F", "N", "parameter"))

    def index(self, name):
        if name not in self.names:
            raise InputError(name, "unknown")
        return self.names.index(name)

    def variable(self, name):
        return self.variables[self.index(name)]

    def scene(self, x):
        return swing_scene(float(x[0]))

    mechanics = None


def test_scene_dimension_and_extent():
    sc = swing_scene(0.0)
    assert sc.dimension == 3
    ext = sc.extent()
    pts = np.vstack([b for _, b in sc.bars] + [np.array([0.2, 1.0, 2.1]), np.array([-0.4, 0.6, 2.2])])
    assert np.allclose(ext, [v for k in range(3) for v in (pts[:, k].min(), pts[:, k].max())])
    assert Scene(bars=[("a", np.zeros((2, 2)))]).dimension == 2


@pytest.mark.parametrize("view", list(VIEWS))
def test_projected_moment_is_the_planar_moment_of_the_projected_force(view):
    """r x F in 3-D, projected by the view, equals the 2-D cross product of the projected r and F."""
    for _ in range(5):
        r, f = RNG.normal(size=3), RNG.normal(size=3)
        sc = Scene(bars=[("b", np.array([np.zeros(3), r]))], forces=[("F", r, f)], moments=[("M", np.zeros(3),
                                                                                                np.cross(r, f))])
        flat = project(sc, view)
        (_, p2, f2), (_, _, m2) = flat.forces[0], flat.moments[0]
        assert m2 == pytest.approx(p2[0] * f2[1] - p2[1] * f2[0], rel=1e-12, abs=1e-12)
        assert flat.dimension == 2


def test_projection_drops_the_seen_along_coordinate():
    sc = swing_scene(0.3)
    for view, (h, v, _) in VIEWS.items():
        flat = project(sc, view)
        assert np.array_equal(flat.bars[0][1], sc.bars[0][1][:, [h, v]])
        assert np.array_equal(flat.actuators[0][1], sc.actuators[0][1][[h, v]])
        assert flat.actuators[0][3] == sc.actuators[0][3]


def test_three_view_figure_has_units_labels_and_distinct_items():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 9), layout="constrained")
    axes = draw_scene3d(swing_scene(0.2), fig, title="swing")
    assert set(axes) == {"front", "side", "top", "3d"}
    check_figure(fig, "three-view")
    (legend,) = fig.legends  # the 3-D view names the bodies by their colour
    assert "fitting" in [t.get_text() for t in legend.get_texts()]
    for view, ax in axes.items():
        texts = {t.get_text() for t in ax.texts}
        assert ("fitting" in texts) == (view != "3d"), view
        if view != "3d":
            h, v, _ = VIEWS[view]
            assert (ax.get_xlabel(), ax.get_ylabel()) == (f"{'xyz'[h]} (m)", f"{'xyz'[v]} (m)")
            assert any(p.get_gid() == "actuator:actuator" for p in ax.patches), view
        else:
            assert ax.get_zlabel() == "z (m)"
            title = ax.get_title()   # the loads listed under the 3-D panel's title, not over its axes
            assert "actuator = 40 kN compression" in title and "W = 20 kN" in title
    # the trunnion axis is nearly along x: drawn in the side and top views, seen end-on in the front view
    gids = {v: [ln for ln in axes[v].get_lines() if ln.get_gid() == "joint-axis"] for v in ("front", "side", "top")}
    assert len(gids["side"]) == 1 and len(gids["top"]) == 1
    assert len(gids["front"]) == 1  # 0.12 of z: short, but not end-on


def test_unknown_view_is_an_input_error():
    with pytest.raises(InputError, match="view"):
        draw_scene3d(swing_scene(0.0), views=("front", "back"))
    with pytest.raises(InputError, match="3-D"):
        draw_scene3d(Scene(bars=[("a", np.zeros((2, 2)))]))


def test_draw_dispatches_on_the_scene_dimension(tmp_path):
    out = tmp_path / "swing.png"
    axes = draw(Swing(), np.array([0.4, 0.0]), out, annotate=("theta",))
    assert isinstance(axes, dict) and "3d" in axes
    with Image.open(out) as im:
        assert im.size[0] >= 800
    notes = [t.get_text() for t in axes["front"].texts]
    assert any("theta = 22.92°" in t for t in notes)


def test_spatial_animation_frames_duration_and_size(tmp_path):
    thetas = np.linspace(0.0, 1.2, 7)
    rows = np.column_stack([thetas, np.zeros_like(thetas)])
    out = tmp_path / "swing.gif"
    ticks = []
    n = animate(Swing(), rows, out, annotate=("theta",), on_frame=lambda: ticks.append(1), dpi=80)
    assert n == 7 and len(ticks) == 7
    with Image.open(out) as im:
        assert im.size[0] >= 800
        total = 0
        for k in range(im.n_frames):
            im.seek(k)
            total += im.info["duration"]
    assert total / 1000.0 >= MIN_DURATION - 1e-9


def test_three_view_labels_do_not_overlap_are_readable_and_panels_are_close():
    """Issue 25: bodies named without overlap inside the figure, >= 9 pt type, a legend with one entry per
    body in its colour, front and side panels against each other."""
    from figure_checks import check_labels, horizontal_gap, smallest_font

    from mechcont.paper.dual_sidestay import retraction

    ret = retraction()
    for row in (0, -1):
        axes = draw3d(ret.system, ret.branch.values[row], annotate=("theta",))
        fig = axes["front"].figure
        check_figure(fig, "sidestay")
        check_labels(fig, "sidestay")
        assert smallest_font(fig) >= 9
        assert 0 < horizontal_gap(fig, axes["front"], axes["side"]) < 0.1 * fig.bbox.width
        scene = ret.system.scene(ret.branch.values[row])
        names = list(dict.fromkeys(n for n, _ in scene.bars))
        (legend,) = fig.legends
        entries = {t.get_text(): h.get_color() for t, h in zip(legend.get_texts(), legend.legend_handles)}
        for view in ("front", "side", "top"):
            texts = {t.get_gid(): t for t in axes[view].texts if t.get_gid()}
            for n in names:  # every body named once per view, in its legend colour, as its bar is drawn
                assert matplotlib.colors.same_color(texts[f"body:{n}"].get_color(), entries[n])
                bar = next(ln for ln in axes[view].lines if ln.get_label() == n)
                assert matplotlib.colors.same_color(bar.get_color(), entries[n])
            assert not any(g.startswith("point:") for g in texts)   # points only on demand


def test_label_points_names_every_point_without_overlap():
    from figure_checks import check_labels

    sc = swing_scene(0.3)
    axes = draw_scene3d(sc, label_points=True)
    fig = axes["front"].figure
    check_labels(fig, "swing points")
    for view in ("front", "side", "top"):
        gids = {t.get_gid() for t in axes[view].texts}
        assert "point:fitting.axle" in gids and "body:fitting" in gids
