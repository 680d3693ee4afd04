"""Animations of mechanisms along a continuation branch (GIF, HTML page, or MP4 with ffmpeg).

The rows of a branch (a :class:`~mechcont.continuation.Branch`, its CSV table or plain
rows of full variable vectors) become :class:`BranchFrames` (:mod:`._branch_frames`); :func:`animate` draws each
with :mod:`mechcont.outputs.drawing` in one fixed view, annotated with the continuation
parameter (with units, degrees for angles), chosen variables, stability and label, and
optionally beside the bifurcation diagram with the current point marked. The parts of the
figure that every frame shares are drawn once; each frame draws only its own artists over
them (:mod:`mechcont.outputs._frames`).
"""

from __future__ import annotations

import contextlib
import math
import os
import shutil
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import TYPE_CHECKING, Literal, overload

import numpy as np

from ..errors import InputError
from ..units import display_scale, display_unit
from . import _drawing_parts as _d
from . import _frames as _f
from ._branch_frames import BranchFrames, branch_frames

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.legend import Legend
    from matplotlib.lines import Line2D
    from PIL.Image import Image

    from ..continuation import Branch
    from ..equations import EquationSystem, Model, Scene

    #: The diagram's marker of the current point and the branch's (x, y) in display units, per row.
    _Marker = tuple[Line2D, np.ndarray, np.ndarray]
    #: What :func:`animate` takes as a branch (see :func:`branch_frames`).
    _BranchSource = BranchFrames | Branch | str | os.PathLike[str] | np.ndarray | Sequence[Sequence[float]]

__all__ = ["animate", "BranchFrames", "branch_frames", "check_fps", "check_hold", "frame_rows", "default_fps",
           "ANIMATION_SUFFIXES", "FPS_RANGE", "MIN_DURATION", "MAX_FPS", "HOLD"]

ANIMATION_SUFFIXES = (".gif", ".mp4", ".html")


#: Frame rates that make sense (frames per second): a GIF stores each frame's duration in
#: hundredths of a second (at most 655.35 s), and players show at most 100 frames a second.
FPS_RANGE = (0.01, 100.0)


def check_fps(fps: object) -> float:
    """``fps`` as a float within :data:`FPS_RANGE`, else :class:`InputError`."""
    lo, hi = FPS_RANGE
    if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not math.isfinite(fps) or fps <= 0:
        raise InputError("fps", f"must be a positive number, not {fps!r}")
    if not lo <= fps <= hi:
        raise InputError("fps", f"{fps:g} frames per second is outside {lo:g}..{hi:g} (a frame lasts at most "
                                f"{1 / lo:g} s and at least {1 / hi:g} s)")
    return float(fps)


def check_hold(seconds: object, field: str = "hold") -> float:
    """``seconds`` (the extra time on each special point) as a float in 0..60, else :class:`InputError` naming ``field``."""
    if not (isinstance(seconds, (int, float)) and not isinstance(seconds, bool) and math.isfinite(seconds)
            and 0 <= seconds <= 60):
        raise InputError(field, f"must be a number of seconds between 0 and 60, not {seconds!r}")
    return float(seconds)


#: Defaults chosen for a human watching: at least this long (s) ...
MIN_DURATION = 6.0
#: ... at most this many frames a second (when ``fps`` is not given) ...
MAX_FPS = 15.0
#: ... and each special point held this long (s) on top of its frame.
HOLD = 0.6


def frame_rows(frames: BranchFrames, every: int = 1) -> list[int]:
    """Rows drawn as frames: every ``every``-th row, the last row, and every special point (``LP``,
    ``EP``...), whatever ``every`` is."""
    n = len(frames.values)
    special = {i for i, lab in enumerate(frames.labels) if lab}
    return sorted(set(range(0, n, int(every))) | {n - 1} | special)


def default_fps(n_frames: int) -> float:
    """Frames per second so that ``n_frames`` last at least :data:`MIN_DURATION` (at most :data:`MAX_FPS`)."""
    return float(min(MAX_FPS, max(n_frames / MIN_DURATION, 0.5)))


def _diagram_states(frames: BranchFrames) -> np.ndarray:
    """Per interval between rows: 1.0 stable, 0.0 unstable, nan not evaluated. A special point's own
    stability never decides (a fold is neutral): the interval takes its other end's."""
    flags = np.array([np.nan if f is None else float(f) for f in frames.stable])
    out = np.empty(max(len(flags) - 1, 0))
    for i in range(len(out)):
        a, b = flags[i], flags[i + 1]
        if frames.labels[i] and not np.isnan(b):
            out[i] = b
        elif frames.labels[i + 1] and not np.isnan(a):
            out[i] = a
        else:
            out[i] = a if (a == b or np.isnan(b)) else b if np.isnan(a) else a
    return out


def _diagram(ax: Axes, system: EquationSystem, frames: BranchFrames, names: tuple[str, str]) -> _Marker:
    """Branch projected on ``names`` (x, y): stable solid, unstable dashed, labels marked."""
    (xn, yn) = names
    xs, ys = (frames.values[:, system.index(n)] for n in names)
    conv = [display_scale(system.variable(n).unit) for n in names]
    xs, ys = xs * conv[0], ys * conv[1]
    states = _diagram_states(frames)
    if len(states) == 0 or np.isnan(states).all():
        ax.plot(xs, ys, "-", color="0.2", linewidth=1.2)
    else:
        for flag, style, width, name in ((1.0, "-", 1.4, "stable"), (0.0, "--", 1.2, "unstable"),
                                         (np.nan, ":", 1.0, "not evaluated")):
            mask = np.isnan(states) if np.isnan(flag) else states == flag
            if mask.any():
                show = np.r_[mask, False] | np.r_[False, mask]  # both ends of each interval
                ax.plot(np.where(show, xs, np.nan), np.where(show, ys, np.nan), style, color="0.2",
                        linewidth=width, label=name)
        ax.legend(fontsize=9, loc="best")
    for i, lab in enumerate(frames.numbered_labels):
        if lab:
            ax.plot(xs[i], ys[i], "k.", markersize=5)
            right = xs[i] > np.min(xs) + 0.85 * np.ptp(xs)   # near the right edge: the label to the left
            ax.annotate(lab, (xs[i], ys[i]), textcoords="offset points", xytext=(-3 if right else 3, 3), fontsize=9,
                        ha="right" if right else "left")
    units = [display_unit(system.variable(n).unit) for n in names]
    ax.set_xlabel(f"{xn} ({units[0]})" if units[0] else xn)
    ax.set_ylabel(f"{yn} ({units[1]})" if units[1] else yn)
    ax.grid(True, linewidth=0.3, alpha=0.5)
    (marker,) = ax.plot([], [], "o", color="#d62728", markersize=8, zorder=5)
    return marker, xs, ys


def _unknown(system: EquationSystem) -> str:
    """What a frame says of a row whose stability is not known: a model without a potential energy
    (a kinematic one) has none to speak of; another was continued without evaluating it."""
    from ..equations import Model

    if isinstance(system, Model) and system.mechanics is not None:
        return "stability not evaluated"
    return "kinematic: no stability"  # (a drawing-only object has no mechanics either)


def _slider_spans(scenes: Sequence[Scene], h: float) -> list[tuple[np.ndarray, np.ndarray]] | None:
    """Per slider, its guide over the whole travel of the animation (the same in every frame)."""
    if not scenes or not scenes[0].sliders:
        return None
    spans = []
    for k, (p0, direction) in enumerate(scenes[0].sliders):
        p0 = np.asarray(p0, float)
        u = np.asarray(direction, float)
        u = u / np.hypot(*u) if np.hypot(*u) > 0 else np.array([1.0, 0.0])
        t = [float((np.asarray(s.sliders[k][0], float) - p0) @ u) for s in scenes if len(s.sliders) > k]
        spans.append(_d.slider_span(p0, u, h, (min(t), max(t))))
    return spans


def _added(axes: Sequence[Axes], draw: Callable[[], object]) -> list[Artist]:
    """Call ``draw()`` and return the artists it added to ``axes``."""
    before = {id(c) for ax in axes for c in ax.get_children()}
    draw()
    return [c for ax in axes for c in ax.get_children() if id(c) not in before]


class _Renderer:
    """Draws frame ``k`` into a fixed figure: removes the previous frame's artists, adds this one's.

    ``render(k)`` returns the artists that differ between frames (the frame's own, the diagram's
    marker, and the legend the marker may pass under), to be drawn over the fixed image.
    ``content_axes`` are 3-D axes (see :class:`~mechcont.outputs._frames.Compositor`).
    """

    def __init__(self, fig: Figure, axes: Iterable[Axes], draw: Callable[[int], None], marker: _Marker | None = None,
                 content_axes: Iterable[Axes] = ()) -> None:
        self.fig, self.axes, self._draw, self.marker = fig, list(axes), draw, marker
        self.content_axes = list(content_axes)
        self.over: list[Artist] = []  # the artists of the frame drawn to lay the figure out
        self.legend_over_marker = True  # False once the marker is known never to pass under the legend
        self._current: list[Artist] = []

    def render(self, k: int) -> list[Artist]:
        for a in self._current:
            a.remove()
        self._current = _added(self.axes, lambda: self._draw(k))
        over = list(self._current)
        if self.marker is not None:
            legend = self.diagram_legend() if self.legend_over_marker else None
            over += [self.marker[0], *([legend] if legend is not None else [])]
        return over

    def diagram_legend(self) -> Legend | None:
        """The legend of the diagram the marker is on (None without a marker or a legend)."""
        ax = None if self.marker is None else self.marker[0].axes
        return None if ax is None else ax.get_legend()

    def marker_meets_legend(self) -> bool:
        """Whether the diagram's marker, at any row, overlaps its legend (which is then redrawn over it)."""
        legend = self.diagram_legend()
        if self.marker is None or legend is None:
            return False
        line, xs, ys = self.marker
        ax = line.axes
        assert ax is not None   # the marker was plotted on the diagram's axes
        box = legend.get_window_extent()
        r = 0.5 * line.get_markersize() * self.fig.dpi / 72.0 + 2.0  # pixels, with a margin for antialiasing
        px = ax.transData.transform(np.column_stack([xs, ys]))
        return bool(np.any((px[:, 0] > box.x0 - r) & (px[:, 0] < box.x1 + r) & (px[:, 1] > box.y0 - r)
                           & (px[:, 1] < box.y1 + r)))


def _planar_renderer(system: Model, frames: BranchFrames, rows: Sequence[int], scenes: Sequence[Scene],
                     annotate: Sequence[str], labels: Sequence[str], *, title: str | None, show_forces: bool,
                     diagram: tuple[str, str] | None, figsize: tuple[float, float] | None, dpi: int) -> _Renderer:
    """The figure of a planar mechanism and its frames (one fixed view, optional diagram)."""
    scale = _d._default_force_scale(scenes)
    limits = _d._limits(_d._union(_d._bounds(s, scale, show_forces) for s in scenes))
    h = _d._SYMBOL * max(limits[1] - limits[0], limits[3] - limits[2])
    spans = _slider_spans(scenes, h)
    corner = _d._note_corner(scenes, limits)

    from matplotlib.figure import Figure

    # the mechanism's panel as wide as its view needs at this height, the diagram's 6 in: >= 8 in (800 px) in all
    aspect = (limits[1] - limits[0]) / max(limits[3] - limits[2], 1e-12)
    mech_w = min(max(aspect * 4.8 + 1.0, 3.0), 12.0)
    if figsize is None:
        figsize = (max(mech_w + 6.2, 8.0), 5.6) if diagram else (max(aspect * 5.2 + 1.0, 8.0), 6.0)
    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    marker = None
    if diagram:
        ax, dax = fig.subplots(1, 2, width_ratios=(mech_w, 6.0))
        marker = _diagram(dax, system, frames, (diagram[0], diagram[1]))
    else:
        ax = fig.add_subplot()

    def draw(k: int) -> None:
        i = rows[k]
        _d.draw_scene(scenes[k], ax, title=title or system.name, show_forces=show_forces, force_scale=scale,
                      limits=limits, slider_spans=spans, quiet_loads=annotate)
        _d._put_note(ax, _d._note(system, frames.values[i], annotate, frames.stable[i], labels[i], _unknown(system)),
                     frames.stable[i],
                     corner)
        if marker is not None:
            marker[0].set_data([marker[1][i]], [marker[2][i]])

    return _Renderer(fig, [ax], draw, marker)


def _spatial_renderer(system: Model, frames: BranchFrames, rows: Sequence[int], scenes: Sequence[Scene],
                      annotate: Sequence[str], labels: Sequence[str], *, title: str | None, show_forces: bool,
                      diagram: tuple[str, str] | None, figsize: tuple[float, float] | None, dpi: int) -> _Renderer:
    """The figure of a spatial mechanism and its frames: front, side, top and 3-D views (fixed for every
    frame) and, with ``diagram``, the branch with the current point in place of the top view."""
    from matplotlib.figure import Figure

    from . import drawing3d as _d3

    views = ("front", "side", "diagram", "3d") if diagram else ("front", "side", "top", "3d")
    frame = _d3._Frame(scenes, [v for v in views if v != "diagram"], show_forces)
    wide = max(8.5, 800.0 / dpi)   # at least 800 pixels wide
    fig = Figure(figsize=figsize or _d3.layout_size(frame.limits, (wide, max(wide, 13.0)), max(9.5, 950.0 / dpi)),
                 dpi=dpi, layout="constrained")
    axes = _d3.spatial_layout(fig, views, frame.limits)
    marker = _diagram(axes.pop("diagram"), system, frames, (diagram[0], diagram[1])) if diagram else None
    fig.suptitle(title or system.name)  # once: the layout places it
    _d3.legend(fig, frame.colours, scenes[0])   # bodies named by colour: the same in every frame
    corner = _d._note_corner([_d3.project(s, "front") for s in scenes], frame.limits["front"])

    def draw(k: int) -> None:
        i = rows[k]
        frame.render(axes, scenes[k], title=None, quiet_loads=annotate, clear=False)
        _d._put_note(axes["front"], _d._note(system, frames.values[i], annotate, frames.stable[i], labels[i],
                                             _unknown(system)),
                     frames.stable[i], corner)
        if marker is not None:
            marker[0].set_data([marker[1][i]], [marker[2][i]])

    return _Renderer(fig, axes.values(), draw, marker, content_axes=[axes["3d"]])


def animate(system: Model, branch: _BranchSource, path: str | os.PathLike[str], fps: float | None = None, every: int = 1,
            annotate: Sequence[str] = _d._DEFAULT_ANNOTATE, *, vary: str | None = None, title: str | None = None,
            show_forces: bool = True,
            diagram: tuple[str, str] | None = None, figsize: tuple[float, float] | None = None,
            dpi: int = 100, on_frame: Callable[[], None] | None = None, hold: float = HOLD) -> int:
    """Animate ``system`` along a branch and write a GIF, an MP4 or an HTML page.

    Frames are every ``every``-th row of the branch plus, always, every special point
    (``LP``, ``EP``, ...) and the last row; each special point is held ``hold`` seconds
    longer. By default the frame rate makes the animation last at least
    :data:`MIN_DURATION` seconds (:func:`default_fps`). All frames share one view and one
    force scale (m/N), so motion and load changes are comparable; a slider's guide spans
    its whole travel and ground symbols are drawn only where the mechanism is grounded.
    Each frame prints the continuation parameter, then the ``annotate`` variables (with
    units; angles in degrees), the stability (``fold`` at a fold) and the special-point
    label of its row; forces printed there are drawn without a label on the mechanism.

    Parameters
    ----------
    system:
        A :class:`~mechcont.equations.Model` with a ``scene``.
    branch:
        Anything :func:`branch_frames` accepts (Branch, CSV path, array of rows).
    path:
        Output ``.gif`` (Pillow), ``.mp4`` (needs ffmpeg) or ``.html`` (a page with the frames
        embedded and play controls, for notebooks and browsers).
    fps:
        Frames per second (> 0); default: :func:`default_fps` of the number of frames.
    every:
        Use every N-th row (integer >= 1); special points are always used.
    annotate:
        Variable names printed on each frame; the default is :func:`_d.default_annotate`.
    vary:
        The continuation parameter, printed first; by default the branch's (see
        :attr:`BranchFrames.vary`). Without one, the first ``annotate`` name leads.
    title, show_forces:
        As for :func:`_d.draw_scene`.
    diagram:
        Optional pair of variable names ``(x, y)``: a second panel shows the branch in that
        plane with a marker at the current point.
    figsize, dpi:
        Figure size in inches and resolution (default: at least 8 in wide at 100 dpi, so at
        least 800 pixels; the mechanism's panel as wide as its view needs).
    on_frame:
        Called with no argument after each frame is written (progress bars).
    hold:
        Extra seconds each special point stays on screen.

    Returns
    -------
    int
        The number of frames drawn (one per row used).

    Raises
    ------
    InputError
        Unknown suffix, MP4 without ffmpeg, no scene, bad ``fps``/``every``, an unknown
        name, or a branch that does not fit the model.
    """
    out = _d._check_out(path, ANIMATION_SUFFIXES)
    scene_fn = _d._scene_of(system)
    if fps is not None:
        check_fps(fps)
    if isinstance(every, bool) or not isinstance(every, (int, np.integer)) or every < 1:
        raise InputError("every", f"must be an integer >= 1, not {every!r}")
    check_hold(hold)
    if tuple(annotate) == _d._DEFAULT_ANNOTATE:
        annotate = _d.default_annotate(system)
    for name in (*annotate, *(diagram or ()), *([vary] if vary is not None else [])):
        system.index(name)
    if diagram is not None and len(diagram) != 2:
        raise InputError("diagram", "give exactly two variable names (x, y)")
    suffix = out.suffix.lower()
    if suffix == ".mp4" and (shutil.which("ffmpeg") is None or not _ffmpeg_available()):
        raise InputError("out", "writing .mp4 needs ffmpeg, which is not installed; write a .gif (or .html) instead")
    frames = branch_frames(system, branch)
    rows = frame_rows(frames, every)
    fps = default_fps(len(rows)) if fps is None else float(fps)
    renderer = _renderer(scene_fn, system, frames, rows, _d._with_vary(vary or frames.vary, annotate), title=title,
                         show_forces=show_forces, diagram=diagram, figsize=figsize, dpi=dpi)
    held = [bool(lab) for lab in (frames.labels[i] for i in rows)]

    def write(tmp: str) -> None:
        sink = None if suffix == ".gif" else _f.html_sink(fps) if suffix in (".html", ".htm") else _f.mp4_sink(fps)
        images: list[Image] = []
        # sink.setup may round an MP4's size to even pixels: before the fixed image is drawn
        with contextlib.nullcontext() if sink is None else sink.saving(renderer.fig, tmp, dpi):
            for k, rgba in enumerate(_frame_pixels(renderer, len(rows))):
                if sink is None:  # a GIF holds a frame by its duration
                    images.append(_f.gif_frame(rgba))
                else:  # HTML and MP4 have one frame rate: a held frame is repeated
                    sink.add(rgba, 1 + (int(round(hold * fps)) if held[k] else 0))
                if on_frame is not None:
                    on_frame()
        if sink is None:
            _f.write_gif(tmp, images, [_f.gif_duration_ms(fps, hold if h else 0.0) for h in held])

    _d._atomic_write(out, write)
    return len(rows)


def _ffmpeg_available() -> bool:
    from matplotlib import animation

    return bool(animation.writers.is_available("ffmpeg"))


def _renderer(scene_fn: Callable[[np.ndarray], Scene], system: Model, frames: BranchFrames, rows: Sequence[int],
              annotate: Sequence[str], *, title: str | None, show_forces: bool, diagram: tuple[str, str] | None,
              figsize: tuple[float, float] | None, dpi: int) -> _Renderer:
    """The laid-out figure of an animation and its frames (planar or spatial), first frame drawn."""
    scenes = [scene_fn(frames.values[i]) for i in rows]
    from .drawing3d import is_spatial

    make = _spatial_renderer if is_spatial(scenes[0]) else _planar_renderer
    renderer = make(system, frames, rows, scenes, annotate, frames.numbered_labels, title=title,
                    show_forces=show_forces, diagram=diagram, figsize=figsize, dpi=dpi)
    # Lay the figure out once (the view is fixed, so every frame has the same layout).
    renderer.over = renderer.render(0)
    renderer.fig.draw_without_rendering()
    renderer.fig.set_layout_engine("none")
    for ax in renderer.fig.axes:
        _pin_legend(ax)
    if renderer.marker is not None and not renderer.marker_meets_legend():  # the legend stays in the fixed image
        renderer.legend_over_marker = False
        renderer.over = [a for a in renderer.over if a is not renderer.diagram_legend()]
    return renderer


def _pin_legend(ax: Axes) -> None:
    """Keep ``ax``'s legend where ``loc="best"`` put it: searching the best place again costs more
    than drawing the rest of a frame, and the branch it avoids does not change."""
    legend = ax.get_legend()
    if legend is None:
        return
    box, anchor = legend.get_window_extent(), legend.get_bbox_to_anchor()
    legend.set_loc(((box.x0 - anchor.x0) / anchor.width, (box.y0 - anchor.y0) / anchor.height))


@overload
def _frame_pixels(renderer: _Renderer, n: int, *, check: Literal[False] = False) -> Iterator[np.ndarray]: ...
@overload
def _frame_pixels(renderer: _Renderer, n: int, *, check: Literal[True]) -> Iterator[tuple[np.ndarray, np.ndarray]]: ...
def _frame_pixels(renderer: _Renderer, n: int, *,
                  check: bool = False) -> Iterator[np.ndarray] | Iterator[tuple[np.ndarray, np.ndarray]]:
    """RGBA pixels of frames ``0..n-1`` (each valid until the next is drawn): the fixed parts drawn once,
    each frame's own artists over them. With ``check``, pairs ``(blitted, full redraw)`` instead (tests)."""
    comp = _f.Compositor(renderer.fig, renderer.content_axes)
    comp.draw_background(renderer.over)
    for k in range(n):
        rgba = comp.frame(renderer.render(k))
        yield (rgba.copy(), comp.full_frame()) if check else rgba
