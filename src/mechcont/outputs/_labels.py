"""Labels placed beside what they name, never over each other and never outside the axes.

A greedy pass on a laid-out figure (positions in display pixels, so the result holds at any
resolution): each label in turn goes to the candidate position of least cost on rings of
directions around its anchor. A candidate is refused when its box leaves the axes, meets a
text already there or covers another label's anchor or a leader line drawn before it; its cost is
its distance from the anchor plus a penalty for every drawn point (bars, springs, pins) it would
cover and a large one when its own leader line would cross a label already placed. The labels
with the most anchors near theirs go first (they have the fewest free places). A label that ends
up away from its anchor gets a thin leader line in its colour.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ._symbols import _LABEL_BOX

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.backend_bases import RendererBase
    from matplotlib.text import Text
    from matplotlib.typing import ColorType

__all__ = ["Label", "place_labels", "text_boxes"]

_DIRECTIONS = 32
_COVER_PENALTY = 20.0  # pixels of distance one covered drawn point is worth (away from a crowded drawing)
_GAP = 2.0             # pixels kept free around every label


@dataclass(frozen=True)
class Label:
    """One label: its ``text``, the data point ``anchor`` (x, y) it names, ``colour``, ``bold``, and a ``gid``."""

    text: str
    anchor: tuple[float, float]
    colour: ColorType = "0.15"
    bold: bool = False
    gid: str | None = None


def text_boxes(ax: Axes, renderer: RendererBase) -> list[np.ndarray]:
    """Pixel boxes ``[x0, y0, x1, y1]`` of the non-empty visible texts on ``ax`` (with their frames)."""
    return [_box(t, renderer) for t in ax.texts if t.get_visible() and t.get_text().strip()]


def _box(t: Text, renderer: RendererBase) -> np.ndarray:
    """Pixel box ``[x0, y0, x1, y1]`` of text ``t`` with its frame (sized now: a frame is sized when drawn)."""
    patch = t.get_bbox_patch()
    if patch is None:
        e = t.get_window_extent(renderer)
    else:
        t.update_bbox_position_size(renderer)
        e = patch.get_window_extent(renderer)
    return np.array([e.x0, e.y0, e.x1, e.y1])


def _inside_count(boxes: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """How many of ``pts`` (k, 2) fall in each of ``boxes`` (m, 4)."""
    if len(pts) == 0:
        return np.zeros(len(boxes))
    x, y = pts[:, 0][None, :], pts[:, 1][None, :]
    inside = (x > boxes[:, [0]]) & (x < boxes[:, [2]]) & (y > boxes[:, [1]]) & (y < boxes[:, [3]])
    return inside.sum(axis=1)


def _meets(boxes: np.ndarray, others: Sequence[np.ndarray]) -> np.ndarray:
    """Whether each of ``boxes`` (m, 4) intersects any of ``others``."""
    hit = np.zeros(len(boxes), bool)
    for o in others:
        hit |= (boxes[:, 0] < o[2]) & (boxes[:, 2] > o[0]) & (boxes[:, 1] < o[3]) & (boxes[:, 3] > o[1])
    return hit


def _crosses(anchor: np.ndarray, ends: np.ndarray, others: Sequence[np.ndarray]) -> np.ndarray:
    """Whether the leader line from ``anchor`` to each of ``ends`` (m, 2) would cross any of ``others``."""
    seg = anchor[None, None, :] + np.linspace(0.05, 0.95, 19)[None, :, None] * (ends - anchor)[:, None, :]
    hit = np.zeros(len(ends), bool)
    for o in others:
        hit |= ((seg[..., 0] > o[0]) & (seg[..., 0] < o[2]) & (seg[..., 1] > o[1]) & (seg[..., 1] < o[3])).any(axis=1)
    return hit


def _candidates(anchor: np.ndarray, w: float, h: float, step: float, reach: float) -> tuple[np.ndarray, np.ndarray]:
    """Centres (m, 2) of boxes ``w`` x ``h`` px on rings around ``anchor`` (the box edge at the ring) and their
    distances from it, out to ``reach`` px; the first candidate is centred on the anchor itself."""
    phi = np.linspace(0.0, 2 * np.pi, _DIRECTIONS, endpoint=False)
    u = np.column_stack([np.cos(phi), np.sin(phi)])
    radii = step * np.arange(1, max(int(reach / step), 1) + 1)
    centres = [anchor[None, :]]
    dist = [np.zeros(1)]
    for r in radii:
        centres.append(anchor + r * u + 0.5 * np.column_stack([w * u[:, 0], h * u[:, 1]]))
        dist.append(np.full(len(u), r))
    return np.vstack(centres), np.concatenate(dist)


def place_labels(ax: Axes, labels: Sequence[Label], renderer: RendererBase, avoid: npt.ArrayLike | None = None, *,
                 fontsize: float = 9.0) -> list[Text]:
    """Put ``labels`` on the laid-out axes ``ax``: each beside its anchor, clear of the texts already on ``ax``
    and of the labels placed before it, inside the axes, covering as few of the ``avoid`` data points (k, 2)
    as it can; a label away from its anchor is joined to it by a leader line.

    Returns the :class:`matplotlib.text.Text` artists, in the order of ``labels``.
    """
    from matplotlib.lines import Line2D

    frame = ax.get_window_extent(renderer)
    limit = np.array([frame.x0, frame.y0, frame.x1, frame.y1])
    to_px = ax.transData.transform
    to_data = ax.transData.inverted().transform
    pts = to_px(np.asarray(avoid, float).reshape(-1, 2)) if avoid is not None else np.zeros((0, 2))
    placed = text_boxes(ax, renderer)
    # what no label may cover: every label's anchor (what it names) and the leader lines drawn so far
    kept = to_px(np.array([lab.anchor for lab in labels], float).reshape(-1, 2))
    # the most crowded anchors first: they have the fewest free places, which later labels would take
    near = np.linalg.norm(kept[:, None, :] - kept[None, :, :], axis=2) < 0.15 * max(frame.width, frame.height)
    order = sorted(range(len(labels)), key=lambda i: -int(near[i].sum()))
    out: dict[int, Text] = {}
    for i in order:
        lab = labels[i]
        t = ax.text(*lab.anchor, lab.text, ha="center", va="center", fontsize=fontsize, color=lab.colour,
                    fontweight="bold" if lab.bold else "normal", zorder=9, bbox=_LABEL_BOX, gid=lab.gid,
                    clip_on=False)
        t.set_in_layout(False)
        e = _box(t, renderer)
        w, h = e[2] - e[0] + 2 * _GAP, e[3] - e[1] + 2 * _GAP
        a = to_px(np.asarray(lab.anchor, float).reshape(1, 2))[0]
        centres, dist = _candidates(a, w, h, step=0.5 * h, reach=max(frame.width, frame.height))
        boxes = np.column_stack([centres[:, 0] - w / 2, centres[:, 1] - h / 2, centres[:, 0] + w / 2,
                                 centres[:, 1] + h / 2])
        own = np.all(np.isclose(kept, a), axis=1)   # its own anchor it may sit on
        ok = ((boxes[:, 0] >= limit[0]) & (boxes[:, 2] <= limit[2]) & (boxes[:, 1] >= limit[1])
              & (boxes[:, 3] <= limit[3]) & ~_meets(boxes, placed) & (_inside_count(boxes, kept[~own]) == 0))
        leader_ends = centres + np.clip(a - centres, -np.array([w / 2 - _GAP, h / 2 - _GAP]),
                                        np.array([w / 2 - _GAP, h / 2 - _GAP]))   # as drawn below
        cost = dist + _COVER_PENALTY * _inside_count(boxes, pts) + 1e3 * _crosses(a, leader_ends, placed)
        if not ok.any():  # nowhere free near the anchor: the least crowded place inside the axes
            ok = (boxes[:, 0] >= limit[0]) & (boxes[:, 2] <= limit[2]) & (boxes[:, 1] >= limit[1]) & (
                boxes[:, 3] <= limit[3])
            cost = cost + 1e6 * _meets(boxes, placed)
            ok = ok if ok.any() else np.ones(len(boxes), bool)
        k = int(np.argmin(np.where(ok, cost, np.inf)))
        c = centres[k]
        x, y = lab.anchor if dist[k] == 0 else to_data(c.reshape(1, 2))[0]
        t.set_position((float(x), float(y)))
        placed.append(boxes[k])
        if dist[k] > 0:
            half = np.array([w / 2 - _GAP, h / 2 - _GAP])
            end = c + np.clip(a - c, -half, half)      # the nearest point of the label's box
            ends = to_data(np.array([a, end]))
            n = max(int(np.linalg.norm(end - a) / 3.0), 2)   # a point every 3 px: no label slips between them
            kept = np.vstack([kept, a + np.linspace(0.05, 0.95, n)[:, None] * (end - a)])
            ax.add_line(Line2D(ends[:, 0], ends[:, 1], color=lab.colour, linewidth=0.8, zorder=8.5,
                               gid=f"leader:{lab.gid}" if lab.gid else "leader"))
        out[i] = t
    return [out[i] for i in range(len(labels))]
