"""Words naming the two sides of a boundary curve ("stable" / "unstable"), each put where its side is emptiest.

On the laid-out axes (display pixels, so the result holds at any resolution) a grid of cells is split into
the two sides of the boundary: a cell takes the side of the nearest boundary point, by the sign of its offset
along that point's normal (the direction into the first side). A cell is taken when a curve, a marker or a
text covers it. A word may go where its whole box (with a small gap) lies on its own side, on free cells,
inside the axes (clear of the small markers too, a coarse grid of dots, where it can be: they are given up
before the word is); of those places it takes the one farthest from the curves, the large markers, the texts,
the other side and the frame: the middle of the side's largest empty area.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.text import Text

__all__ = ["label_sides"]

_CELL = 3.0            # pixels per grid cell (at the figure's dpi)
_GAP = 3.0             # pixels kept free around a word
_SMALL_MARKER = 4.0    # markers at most this size (pt) may be given up


def _taken(ax: Axes, cells: np.ndarray, shape: tuple[int, int], small: bool) -> np.ndarray:
    """Which ``cells`` (pixel centres, n x 2) a line, a marker (the small ones when ``small``) or a text of ``ax``
    covers, as a grid of ``shape``."""
    from matplotlib.backends.backend_agg import RendererAgg

    fig = ax.figure
    renderer = RendererAgg(int(fig.bbox.width), int(fig.bbox.height), fig.dpi)
    from scipy.spatial import cKDTree

    tree = cKDTree(cells)
    hit = np.zeros(len(cells), bool)

    def near(px: np.ndarray, r: float) -> None:
        for idx in tree.query_ball_point(px, r):
            hit[idx] = True

    for line in ax.get_lines():
        if not line.get_visible():
            continue
        xy = np.asarray(line.get_xydata(), float)
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if not len(xy):
            continue
        px = line.get_transform().transform(xy)
        if line.get_linestyle() not in ("None", "", " ") and len(px) > 1:
            seg = np.hypot(*np.diff(px, axis=0).T)
            pts = [px[:1]] + [a + np.linspace(0, 1, max(int(s / _CELL), 1) + 1)[1:, None] * (b - a)
                              for a, b, s in zip(px[:-1], px[1:], seg)]
            near(np.vstack(pts), 0.5 * line.get_linewidth() * fig.dpi / 72 + _CELL)
        ms = line.get_markersize()
        if line.get_marker() not in (None, "None", "", " ") and (small or ms > _SMALL_MARKER):
            near(px, 0.5 * ms * fig.dpi / 72 + _CELL)
    for t in ax.texts:
        if t.get_visible() and t.get_text().strip():
            e = t.get_window_extent(renderer)
            hit |= (cells[:, 0] >= e.x0 - _CELL) & (cells[:, 0] <= e.x1 + _CELL) \
                & (cells[:, 1] >= e.y0 - _CELL) & (cells[:, 1] <= e.y1 + _CELL)
    return hit.reshape(shape)


def label_sides(ax: Axes, points: npt.ArrayLike, normals: npt.ArrayLike, valid: npt.ArrayLike,
                words: Sequence[tuple[str, str]], *, fontsize: float = 9.0) -> list[Text]:
    """Write ``words`` = ``[(first side's word, colour), (second side's word, colour)]`` on ``ax``, each in the
    middle of the largest empty area of its side of the boundary through ``points`` (data, n x 2; ``normals``:
    n x 2 in data units, pointing into the first side; ``valid``: where the point bounds the two sides). Call
    it on the finished axes (legend and layout done). Returns the words' texts (a word with no free place is
    left out)."""
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.figure import Figure
    from scipy.ndimage import distance_transform_edt, minimum_filter
    from scipy.spatial import cKDTree

    fig = ax.figure
    assert isinstance(fig, Figure), "label_sides needs axes on a figure, not on a subfigure"
    fig.draw_without_rendering()
    frame = ax.bbox
    nx, ny = max(int(frame.width / _CELL), 2), max(int(frame.height / _CELL), 2)
    gx = frame.x0 + (np.arange(nx) + 0.5) * frame.width / nx
    gy = frame.y0 + (np.arange(ny) + 0.5) * frame.height / ny
    cells = np.column_stack([np.tile(gx, ny), np.repeat(gy, nx)])
    points, normals = np.asarray(points, float), np.asarray(normals, float)
    keep = np.all(np.isfinite(points), axis=1)
    if not np.any(keep & np.asarray(valid, bool)):
        return []
    to_px = ax.transData.transform
    p = to_px(points[keep])
    d = to_px(points[keep] + 1e-3 * np.nan_to_num(normals[keep])) - p
    ok = np.asarray(valid, bool)[keep] & (np.hypot(*d.T) > 0)
    _, nearest = cKDTree(p).query(cells)
    sign = np.einsum("ij,ij->i", d[nearest], cells - p[nearest])
    side = np.where(ok[nearest], np.sign(sign), 0.0).reshape(ny, nx)
    renderer = RendererAgg(int(fig.bbox.width), int(fig.bbox.height), fig.dpi)
    out = []
    for (word, colour), s in zip(words, (1.0, -1.0)):
        t = ax.text(0.0, 0.0, word, color=colour, fontsize=fontsize, ha="center", va="center", zorder=8,
                    bbox=dict(boxstyle="round,pad=0.2", facecolor="white", edgecolor="none", alpha=0.8))
        e = t.get_window_extent(renderer)
        t.remove()
        size = (int(np.ceil((e.height + 2 * _GAP) / _CELL)) | 1, int(np.ceil((e.width + 2 * _GAP) / _CELL)) | 1)
        # the room a place has: its distance from curves, large markers, texts, the other side and the frame
        open_ = (side == s) & ~_taken(ax, cells, (ny, nx), False)
        room = distance_transform_edt(np.pad(open_, 1))[1:-1, 1:-1]
        for free in ((side == s) & ~_taken(ax, cells, (ny, nx), True), open_):
            fits = minimum_filter(free.astype(np.uint8), size=size, mode="constant", cval=0).astype(bool)
            if fits.any():
                break
        else:
            continue
        j, i = np.unravel_index(np.argmax(np.where(fits, room, -1.0)), fits.shape)
        x, y = ax.transData.inverted().transform([gx[i], gy[j]])
        t = ax.text(x, y, word, color=colour, fontsize=fontsize, ha="center", va="center", zorder=8,
                    bbox=dict(boxstyle="round,pad=0.2", facecolor="white", edgecolor="none", alpha=0.8))
        out.append(t)
    return out
