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
