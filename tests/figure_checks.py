"""Checks shared by the tests of the paper's figures: units on every axis, legends only for what is drawn,
text inside the axes."""

import re

UNIT = re.compile(r"\((?:[^()]*)\)\s*$")  # "F (N)", "theta1 (deg)", "spring attachment l_sp1 (m, + towards the knee)"


def axes_of(fig):
    return [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]


def check_figure(fig, name: str) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    for ax in axes_of(fig):
        labels = [ax.get_xlabel(), ax.get_ylabel()] + ([ax.get_zlabel()] if hasattr(ax, "get_zlabel") else [])
        for text in labels:
            if text:
                assert UNIT.search(text), f"{name}: axis label '{text}' has no unit"
        legend = ax.get_legend()
        if legend is not None and ax.name != "3d":  # a surface's sheets are named by proxy patches
            drawn = {h.get_label() for h in ax.get_lines() + ax.collections + ax.patches}
            for t in legend.get_texts():
                assert t.get_text() in drawn, f"{name}: legend entry '{t.get_text()}' names nothing drawn"
        if ax.name == "3d":
            continue
        box = ax.get_window_extent(renderer)
        for t in ax.texts:
            if t.get_text().strip():
                e = t.get_window_extent(renderer)
                assert box.x0 - 2 <= e.x0 and e.x1 <= box.x1 + 2 and box.y0 - 2 <= e.y0 and e.y1 <= box.y1 + 2, (
                    f"{name}: label '{t.get_text()}' leaves the axes")


def _extent(t, renderer):
    """Pixel extent of text ``t`` with its frame, if it has one (sized as drawn)."""
    from matplotlib import cbook
    from mpl_toolkits.mplot3d import proj3d
    from mpl_toolkits.mplot3d.art3d import Text3D

    if isinstance(t, Text3D):  # drawn at its projection, which Text3D.draw sets only while drawing
        xs, ys, _ = proj3d.proj_transform(t._x, t._y, t._z, t.axes.M)
        with cbook._setattr_cm(t, _x=xs, _y=ys):
            return _extent2d(t, renderer)
    return _extent2d(t, renderer)


def _extent2d(t, renderer):
    patch = t.get_bbox_patch()
    if patch is None:
        return t.get_window_extent(renderer)
    t.update_bbox_position_size(renderer)
    return patch.get_window_extent(renderer)


def drawn(fig):
    """Draw ``fig`` on an Agg canvas; its renderer."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    canvas.draw()
    return canvas.get_renderer()


def check_labels(fig, name: str, tolerance: float = 0.5) -> None:
    """No two texts of one 2-D axes overlap (extents with their frames, ``tolerance`` px), and every text of the
    figure lies inside it."""
    renderer = drawn(fig)
    W, H = fig.bbox.width, fig.bbox.height
    for ax in axes_of(fig):
        boxes = [(t.get_text(), _extent(t, renderer)) for t in ax.texts if t.get_visible() and t.get_text().strip()]
        if ax.name != "3d":
            for i, (a, ea) in enumerate(boxes):
                for b, eb in boxes[i + 1:]:
                    overlap = min(ea.x1, eb.x1) - max(ea.x0, eb.x0), min(ea.y1, eb.y1) - max(ea.y0, eb.y0)
                    assert min(overlap) <= tolerance, f"{name}: labels '{a}' and '{b}' overlap"
        for a, e in boxes:
            assert -1 <= e.x0 and e.x1 <= W + 1 and -1 <= e.y0 and e.y1 <= H + 1, f"{name}: label '{a}' leaves the figure"


def smallest_font(fig) -> float:
    """The smallest font size (pt) of any visible, non-empty text of ``fig`` (tick labels included)."""
    from matplotlib.text import Text

    drawn(fig)
    sizes = [t.get_fontsize() for t in fig.findobj(Text) if t.get_visible() and t.get_text().strip()]
    return min(sizes)


def horizontal_gap(fig, left, right) -> float:
    """Pixels between the right edge of axes ``left`` and the left edge of axes ``right`` as drawn."""
    drawn(fig)
    return right.get_window_extent().x0 - left.get_window_extent().x1


def gif_frames(path) -> int:
    """Number of frames of the GIF at ``path``."""
    from PIL import Image

    with Image.open(path) as im:
        return im.n_frames


# -- the figure review (issue 37): every figure of `mechcont paper` and of the documented commands ------------------

#: A unit in an axis label: a parenthesised group, "F (N)", "downlock force F (N); > 0: locks unaided".
ANY_UNIT = re.compile(r"\([^()]+\)")


def _ticklabels(axis):
    """The tick labels ``axis`` draws (within its view interval), visible and non-empty."""
    ticks = axis._update_ticks() if hasattr(axis, "_update_ticks") else axis.get_major_ticks()
    return [lab for t in ticks for lab in (t.label1, t.label2) if lab.get_visible() and lab.get_text().strip()]


def _axes_texts(ax):
    """Every text ``ax`` draws: titles, its texts and annotations, axis labels, tick labels, its legend's texts."""
    out = [t for t in (ax.title, getattr(ax, "_left_title", None), getattr(ax, "_right_title", None)) if t is not None]
    out += list(ax.texts)
    for axis in (ax.xaxis, ax.yaxis, getattr(ax, "zaxis", None)):
        if axis is not None and axis.get_visible() and ax.axison:
            out += [axis.label, *_ticklabels(axis)]
    legend = ax.get_legend()
    if legend is not None:
        out += [*legend.get_texts(), legend.get_title()]
    return out


def figure_texts(fig):
    """``[(text, owner)]``: every visible, non-empty text ``fig`` draws, with the axes it belongs to (None for the
    figure's own: suptitle, figure texts, figure legends)."""
    out = []
    for ax in fig.axes:
        out += [(t, ax) for t in _axes_texts(ax)]
    out += [(t, None) for t in fig.texts]
    for legend in fig.legends:
        out += [(t, None) for t in (*legend.get_texts(), legend.get_title())]
    seen, kept = set(), []
    for t, owner in out:
        if id(t) in seen or not t.get_visible() or not t.get_text().strip():
            continue
        seen.add(id(t))
        kept.append((t, owner))
    return kept


def _overlap(a, b) -> tuple[float, float]:
    return min(a.x1, b.x1) - max(a.x0, b.x0), min(a.y1, b.y1) - max(a.y0, b.y0)


def _data_pixels(line, samples: int = 8):
    """Pixel positions along a 2-D ``line``: its vertices and ``samples`` points on each segment."""
    import numpy as np

    xy = np.asarray(line.get_xydata(), float)
    xy = xy[np.all(np.isfinite(xy), axis=1)]
    if len(xy) == 0:
        return xy.reshape(0, 2)
    px = line.get_transform().transform(xy)
    if len(px) > 1 and line.get_linestyle() not in ("None", "", " "):
        t = np.linspace(0.0, 1.0, samples, endpoint=False)[1:]
        inner = (px[:-1, None, :] + (px[1:] - px[:-1])[:, None, :] * t[None, :, None]).reshape(-1, 2)
        px = np.vstack([px, inner])
    return px


def _in_box(box, px):
    """Which pixel positions ``px`` (n, 2) lie inside ``box``."""
    return (px[:, 0] > box.x0) & (px[:, 0] < box.x1) & (px[:, 1] > box.y0) & (px[:, 1] < box.y1)


def _inside_axes(ax, px, margin: float = 0.0):
    box = ax.get_window_extent()
    return ((px[:, 0] >= box.x0 - margin) & (px[:, 0] <= box.x1 + margin)
            & (px[:, 1] >= box.y0 - margin) & (px[:, 1] <= box.y1 + margin))


def review_problems(fig, name: str, tolerance: float = 1.0) -> list[str]:
    """What a reader would trip on in ``fig``, measured on the drawn figure (Agg, at its dpi):

    - two texts whose boxes (with their frames) overlap by more than ``tolerance`` px both ways (titles, axis and
      tick labels, annotations, legend entries; across panels too);
    - a text reaching outside the figure;
    - a legend over something drawn: a line's vertex or a point on one of its segments, a marker, a scatter point
      or a text of the same axes inside the legend's box (2-D axes);
    - a marker on the axes' frame (its centre inside the axes less than its radius from an edge: cut by the frame,
      or drawn half over the spine when not clipped);
    - an axis with tick labels but no label, or a label without a unit in parentheses (colour bars included);
    - a 3-D surface whose faces have different numbers of vertices: Matplotlib pads them with uninitialised
      memory, whose projection can overflow (a RuntimeWarning on some runs, not others).

    Returns the problems as sentences (empty: none)."""
    import numpy as np

    renderer = drawn(fig)
    W, H = fig.bbox.width, fig.bbox.height
    problems = []
    texts = [(t, owner, _extent(t, renderer)) for t, owner in figure_texts(fig)]
    for i, (a, _, ea) in enumerate(texts):
        if not (-1 <= ea.x0 and ea.x1 <= W + 1 and -1 <= ea.y0 and ea.y1 <= H + 1):
            problems.append(f"{name}: text '{a.get_text()}' leaves the figure")
        for b, _, eb in texts[i + 1:]:
            if min(_overlap(ea, eb)) > tolerance:
                problems.append(f"{name}: texts '{a.get_text()}' and '{b.get_text()}' overlap")
    for ax in fig.axes:
        if not ax.axison:
            continue
        colorbar = ax.get_label() == "<colorbar>"
        for axis in (ax.xaxis, ax.yaxis, getattr(ax, "zaxis", None)):
            if axis is None or not axis.get_visible() or not _ticklabels(axis):
                continue
            label = axis.label.get_text()
            if not ANY_UNIT.search(label):
                what = "colour bar" if colorbar else axis.axis_name + " axis"
                problems.append(f"{name}: {what} labelled '{label}', no unit")
        if ax.name == "3d":
            for coll in ax.collections:
                if np.any(getattr(coll, "_invalid_vertices", False)):
                    problems.append(f"{name}: a 3-D surface with faces of unequal vertex counts (padded with "
                                    "uninitialised memory)")
        if ax.name == "3d" or colorbar:
            continue
        legend = ax.get_legend()
        if legend is not None and legend.get_visible():
            box = legend.get_window_extent(renderer).padded(-1)
            for line in ax.get_lines():
                if not line.get_visible():
                    continue
                px = _data_pixels(line)
                px = px[_inside_axes(ax, px)]
                if np.any(_in_box(box, px)):
                    problems.append(f"{name}: the legend hides part of line '{line.get_label()}'")
            for coll in ax.collections:
                offsets = getattr(coll, "get_offsets", lambda: [])()
                if len(offsets) and coll.get_visible() and coll.get_offset_transform() is not None \
                        and coll.get_label() != "" and not hasattr(coll, "levels"):
                    px = coll.get_offset_transform().transform(np.asarray(offsets, float))
                    px = px[_inside_axes(ax, px)]
                    if np.any(_in_box(box, px)):
                        problems.append(f"{name}: the legend hides points of '{coll.get_label()}'")
            for t in ax.texts:
                if t.get_visible() and t.get_text().strip() and min(_overlap(box, _extent(t, renderer))) > 0:
                    problems.append(f"{name}: the legend hides text '{t.get_text()}'")
        labels = [(t, _extent(t, renderer)) for t in ax.texts if t.get_visible() and t.get_text().strip()]
        for line in ax.get_lines():   # a label's leader line (gid "leader:<label's gid>") through another label
            gid = str(line.get_gid() or "")
            if not gid.startswith("leader"):
                continue
            px = line.get_transform().transform(np.asarray(line.get_xydata(), float))
            seg = px[0] + np.linspace(0.1, 0.9, 17)[:, None] * (px[-1] - px[0])
            for t, e in labels:
                if f"leader:{t.get_gid()}" != gid and np.any(_in_box(e, seg)):
                    problems.append(f"{name}: a leader line ({gid}) crosses the label '{t.get_text()}'")
        frame = ax.get_window_extent(renderer)
        for line in ax.get_lines():
            if line.get_marker() in (None, "None", "", " ") or not line.get_visible():
                continue   # (clipped, a marker on the frame is cut; unclipped, it lies half over the spine)
            r = 0.5 * line.get_markersize() * fig.dpi / 72.0
            px = line.get_transform().transform(np.asarray(line.get_xydata(), float))
            inside = _inside_axes(ax, px)
            near = (np.minimum.reduce([px[:, 0] - frame.x0, frame.x1 - px[:, 0], px[:, 1] - frame.y0,
                                       frame.y1 - px[:, 1]]) < r - 1.0) & inside
            if np.any(near):
                problems.append(f"{name}: markers of '{line.get_label()}' cut by the axes' frame")
    return problems


def review(fig, name: str, tolerance: float = 1.0) -> None:
    """Assert :func:`review_problems` finds nothing in ``fig``."""
    problems = review_problems(fig, name, tolerance)
    assert not problems, "\n".join(problems)
