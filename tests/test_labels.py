"""The label-placement pass (outputs/_labels.py): no two labels overlap, all stay in the axes, a displaced
label has a leader line to its anchor, a free anchor keeps its label."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from figure_checks import check_labels, drawn  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from mechcont.outputs._labels import Label, place_labels  # noqa: E402


def _axes():
    fig = Figure(figsize=(6, 5), layout="constrained")
    ax = fig.add_subplot()
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 10)
    return fig, ax, drawn(fig)


def test_crowded_labels_spread_out_without_overlap_inside_the_axes_with_leaders():
    fig, ax, renderer = _axes()
    labels = [Label(f"body number {k}", (9.5, 9.5), gid=f"b{k}") for k in range(25)]  # one anchor, a corner
    texts = place_labels(ax, labels, renderer)
    check_labels(fig, "crowded")
    box = ax.get_window_extent(renderer)
    for t in texts:
        e = t.get_window_extent(renderer)
        assert box.x0 - 1 <= e.x0 and e.x1 <= box.x1 + 1 and box.y0 - 1 <= e.y0 and e.y1 <= box.y1 + 1
    leaders = {ln.get_gid(): ln for ln in ax.get_lines()}
    for t in texts[1:]:   # all but the first are displaced: each has a leader from its anchor to its box
        ln = leaders[f"leader:{t.get_gid()}"]
        start, end = ln.get_xydata()
        assert np.allclose(start, (9.5, 9.5))
        e = t.get_window_extent(renderer).padded(4)
        assert e.contains(*ax.transData.transform(end))


def test_a_free_anchor_keeps_its_label_and_drawn_points_are_avoided():
    fig, ax, renderer = _axes()
    (t,) = place_labels(ax, [Label("alone", (5.0, 5.0), gid="a")], renderer)
    assert t.get_position() == (5.0, 5.0) and not ax.get_lines()
    # a bar drawn through the anchor: the label moves off it (leader drawn), covering none of its points
    bar = np.column_stack([np.linspace(0, 10, 201), np.full(201, 2.0)])
    (t2,) = place_labels(ax, [Label("bar", (5.0, 2.0), gid="bar")], renderer, avoid=bar)
    e = t2.get_window_extent(renderer)
    px = ax.transData.transform(bar)
    assert not np.any((px[:, 0] > e.x0) & (px[:, 0] < e.x1) & (px[:, 1] > e.y0) & (px[:, 1] < e.y1))
    assert any(ln.get_gid() == "leader:bar" for ln in ax.get_lines())
