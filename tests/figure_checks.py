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
