"""Drawings of spatial mechanisms: an orthographic three-view and a Matplotlib 3-D view.

A spatial :class:`~mechcont.equations.Scene` holds 3-vectors (x, y, z in metres) in the
fields a planar one holds 2-vectors in. Each orthographic view is the scene projected onto a
coordinate plane (:func:`project`) and drawn by :func:`mechcont.outputs.drawing.draw_scene`, so
bodies, pins, grounds, springs, dampers, actuators and loads look as they do in planar
drawings (a load's arrow is its projection, its value is printed in the 3-D view, where the
whole vector is drawn); the 3-D view draws the same primitives in 3-D axes. Joint axes
(``Scene.joint_axes``) are drawn as short dash-dot lines through their pins.

Views (right-handed x, y, z; for a landing gear x aft, y outboard, z up):

========  ==========  ========  ============
view      horizontal  vertical  seen along
========  ==========  ========  ============
front     y           z         x
side      x           z         y
top       x           y         z
========  ==========  ========  ============

Matplotlib is imported lazily and only the non-interactive Agg canvas is used.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ..equations import Scene
from ..errors import InputError
from . import _drawing_parts as _d

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d import Axes3D

    from ..continuation import SpecialPoint
    from ..equations import EquationSystem

__all__ = ["VIEWS", "is_spatial", "project", "draw_scene3d", "draw3d", "spatial_layout", "layout_size", "legend",
           "label_views"]

#: View name -> (horizontal axis index, vertical axis index, axis seen along).
VIEWS: dict[str, tuple[int, int, int]] = {"front": (1, 2, 0), "side": (0, 2, 1), "top": (0, 1, 2)}
_AXIS = "xyz"
_DEFAULT_VIEWS = ("front", "side", "top", "3d")
_FONT = 9   # pt: the smallest type of a drawing


def is_spatial(scene: Scene) -> bool:
    """True when ``scene`` holds 3-D coordinates: the scenes this module draws (the one place the
    drawings ask which kind a scene is)."""
    return scene.dimension == 3


def _check_view(view: str) -> tuple[int, int, int]:
    if view not in VIEWS:
        raise InputError("view", f"unknown view '{view}'; valid: {', '.join(VIEWS)} (or 3d)")
    return VIEWS[view]


def project(scene: Scene, view: str) -> Scene:
    """The planar :class:`Scene` seen in an orthographic ``view`` (``front``, ``side`` or ``top``).

    Positions and force vectors keep their two in-view components (m, N); a moment vector
    becomes its component along the viewing direction, counter-clockwise positive in the view
    (N m). Joint axes seen end-on (within 1e-9) become pins only.
    """
    h, v, n = _check_view(view)
    sign = 1.0 if (h, v, n) in ((1, 2, 0), (2, 0, 1), (0, 1, 2)) else -1.0   # e_h x e_v = sign * e_n

    def p2(p: npt.ArrayLike) -> np.ndarray:
        p = np.asarray(p, float)
        return p[..., [h, v]].copy()

    out = Scene(units=scene.units)
    out.bars = [(name, p2(pts)) for name, pts in scene.bars]
    out.pins = [p2(p) for p in scene.pins]
    out.grounds = [p2(p) for p in scene.grounds]
    out.sliders = [(p2(p), p2(d)) for p, d in scene.sliders]
    out.springs = [(name, p2(a), p2(b)) for name, a, b in scene.springs]
    out.dampers = [(name, p2(a), p2(b)) for name, a, b in scene.dampers]
    out.coils = [(name, p2(p), kind) for name, p, kind in scene.coils]
    out.actuators = [(name, p2(a), p2(b), t) for name, a, b, t in scene.actuators]
    out.forces = [(name, p2(p), p2(f)) for name, p, f in scene.forces]
    out.moments = [(name, p2(p), sign * float(np.asarray(m, float)[n])) for name, p, m in scene.moments]
    out.anchors = [p2(p) for p in scene.anchors]
    out.points = [(name, p2(p)) for name, p in scene.points]
    return out


def _norm(v: npt.ArrayLike) -> float:
    return float(np.linalg.norm(np.asarray(v, float)))


def _force_scale(scenes: Sequence[Scene]) -> float:
    """m/N so that the largest force of all ``scenes`` is drawn ``_ARROW`` of their size."""
    fmax = max((_norm(f) for s in scenes for _, _, f in s.forces), default=0.0)
    box = np.array([s.extent() for s in scenes]).reshape(len(scenes), 3, 2)
    size = float(np.max(box[:, :, 1].max(axis=0) - box[:, :, 0].min(axis=0)))
    return _d._ARROW * max(size, 1e-12) / fmax if fmax > 0 else 0.0


def _view_limits(scenes: Sequence[Scene], view: str, scale: float,
                 show_forces: bool) -> tuple[float, float, float, float]:
    return _d._limits(_d._union(_d._bounds(project(s, view), scale, show_forces) for s in scenes))


def _box3d(scenes: Sequence[Scene], scale: float, show_forces: bool) -> np.ndarray:
    """(3, 2) box (m) around every primitive and force tip of ``scenes``, with a margin."""
    pts = [np.asarray(p, float) for s in scenes for p in s._positions()]
    if show_forces:
        pts += [np.asarray(p, float) + scale * np.asarray(f, float) for s in scenes for _, p, f in s.forces]
    arr = np.array(pts).reshape(-1, 3)
    lo, hi = arr.min(axis=0), arr.max(axis=0)
    pad = _d._PAD * max(float(np.max(hi - lo)), 1e-12)
    return np.column_stack([lo - pad, hi + pad])


def _axis_lines(scene: Scene, view: str | None, length: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """Segments (a, b) of the joint axes, projected into ``view`` (or 3-D when None); end-on ones dropped."""
    out = []
    for _, p, axis in scene.joint_axes:
        p, u = np.asarray(p, float), np.asarray(axis, float)
        if _norm(u) == 0:
            continue
        u = u / _norm(u)
        a, b = p - 0.5 * length * u, p + 0.5 * length * u
        if view is not None:
            h, v, _ = VIEWS[view]
            a, b = a[[h, v]], b[[h, v]]
            if _norm(b - a) < 1e-9 * length:
                continue
        out.append((a, b))
    return out


def _label_3d(text: str, scene: Scene) -> str:
    return f"{text} ({scene.units.label('m')})"


def _zigzag3d(a: np.ndarray, b: np.ndarray, width: float, coils: int = 6) -> np.ndarray:
    """A spring's polyline in 3-D: coils across a direction normal to the spring."""
    d = b - a
    length = _norm(d)
    if length < 1e-12:
        return np.array([a, b])
    t = d / length
    trial = np.array([0.0, 0.0, 1.0]) if abs(t[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    nrm = np.cross(t, trial)
    nrm /= _norm(nrm)
    s = np.linspace(0.2, 0.8, 2 * coils + 1)
    off = np.zeros_like(s)
    off[1:-1:2], off[2:-1:2] = width, -width
    return np.vstack([a, a + np.outer(s * length, t) + np.outer(off, nrm), b])


def _loads_text(scene: Scene, show_forces: bool) -> str:
    """The loads of ``scene`` as text lines (``W = 11.3 kN``, ``actuator = 17.3 kN compression``)."""
    if not show_forces:
        return ""
    force, moment = scene.units.label("N"), scene.units.label("N m")
    lines = [f"{name} = {_d.load_text(_norm(f), force)}" for name, _, f in scene.forces]
    lines += [f"{name} = {_d.load_text(_norm(m), moment)}" for name, _, m in scene.moments]
    for name, _, _, tension in scene.actuators:
        sense = "tension" if tension > 0 else ("compression" if tension < 0 else "unloaded")
        lines.append(f"{name} = {_d.load_text(abs(tension), force)} {sense}")
    return "\n".join(lines)


def _draw_3d(ax: Axes3D, scene: Scene, box: np.ndarray, scale: float, show_forces: bool, title: str | None,
             colours: dict[str, str]) -> None:
    """Scene in Matplotlib 3-D axes ``ax`` within ``box`` (3, 2) m, equal scale on the three axes. Bodies are
    named by their colour (the figure's legend); the loads' values are listed under the panel's title."""
    size = float(np.max(box[:, 1] - box[:, 0]))
    h = _d._SYMBOL * size
    for name, pts in scene.bars:
        pts = np.atleast_2d(np.asarray(pts, float))
        ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], color=colours[name], linewidth=4, solid_capstyle="round", label=name)
    for name, a, b in scene.springs:
        line = _zigzag3d(np.asarray(a, float), np.asarray(b, float), 0.7 * h)
        ax.plot(*line.T, color="#ff7f0e", linewidth=1.3, label=name)
    for name, a, b in scene.dampers:
        ax.plot(*np.array([a, b], float).T, color="#8c564b", linewidth=2.0, linestyle="--", label=name)
    for name, a, b, _ in scene.actuators:
        a, b = np.asarray(a, float), np.asarray(b, float)
        mid = a + 0.55 * (b - a)
        ax.plot(*np.array([a, mid]).T, color="#6a3d9a", linewidth=7, alpha=0.55, solid_capstyle="butt", label=name)
        ax.plot(*np.array([a, b]).T, color="#6a3d9a", linewidth=2.4)
    for a, b in _axis_lines(scene, None, 6 * h):
        ax.plot(*np.array([a, b]).T, color="0.3", linewidth=1.0, linestyle="-.")
    pins = np.array([np.asarray(p, float) for p in scene.pins]).reshape(-1, 3)
    ax.scatter(*pins.T, s=28, facecolor="white", edgecolor="black", depthshade=False, zorder=6)
    grounds = np.array([np.asarray(p, float) for p in (*scene.grounds, *scene.anchors)]).reshape(-1, 3)
    ax.scatter(*grounds.T, s=70, marker="^", facecolor="0.8", edgecolor="0.2", depthshade=False, zorder=6)
    if show_forces:
        for _, p, f in scene.forces:
            p, v = np.asarray(p, float), scale * np.asarray(f, float)
            if _norm(v) > 0:
                ax.quiver(*p, *v, color="#d62728", linewidth=1.8, arrow_length_ratio=0.15)
    ax.set_xlim(*box[0])
    ax.set_ylim(*box[1])
    ax.set_zlim(*box[2])
    ax.set_box_aspect(tuple(box[:, 1] - box[:, 0]), zoom=1.0)
    ax.set_xlabel(_label_3d("x", scene), fontsize=_FONT)
    ax.set_ylabel(_label_3d("y", scene), fontsize=_FONT)
    ax.set_zlabel(_label_3d("z", scene), fontsize=_FONT)
    ax.tick_params(labelsize=_FONT)
    from matplotlib.ticker import MaxNLocator

    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):   # few ticks: at four, a short axis's labels ran together
        axis.set_major_locator(MaxNLocator(3))
    # the loads' values above the panel, under its title: a box in the panel's corner lay over the axes
    loads = _loads_text(scene, show_forces).splitlines()
    lines = [", ".join(loads[k:k + 2]) for k in range(0, len(loads), 2)]
    if title or lines:
        ax.set_title("\n".join([title or "", *lines]).strip("\n"), fontsize=_FONT + 1)


def _draw_view(ax: Axes, scene: Scene, view: str, limits: tuple[float, float, float, float], scale: float,
               show_forces: bool, quiet_loads: Sequence[str] = (), colours: dict[str, str] | None = None) -> None:
    h_i, v_i, n_i = VIEWS[view]
    flat = project(scene, view)
    # a projected load is a component, not the load: its arrow is drawn, its value is printed in the 3-D view
    quiet = (*quiet_loads, *(n for n, _, _ in flat.forces), *(n for n, _, _ in flat.moments),
             *(n for n, _, _, _ in flat.actuators))
    _d.draw_scene(flat, ax, title=f"{view} (seen along {_AXIS[n_i]})", show_forces=show_forces, force_scale=scale,
                  limits=limits, quiet_loads=quiet, colours=colours)
    h = _d._SYMBOL * max(limits[1] - limits[0], limits[3] - limits[2])
    for a, b in _axis_lines(scene, view, 6 * h):
        ax.plot(*np.array([a, b]).T, color="0.3", linewidth=1.0, linestyle="-.", zorder=6.5, gid="joint-axis")
    ax.set_xlabel(f"{_AXIS[h_i]} ({scene.units.label('m')})")
    ax.set_ylabel(f"{_AXIS[v_i]} ({scene.units.label('m')})")


#: Where each view of the default layout sits (row, column) and which corner of its cell it hugs: front and side
#: share the vertical axis z, side and top the horizontal axis x (third-angle projection), the 3-D view below front.
_GRID = {"front": (0, 0, "SE"), "side": (0, 1, "SW"), "3d": (1, 0, "C"), "top": (1, 1, "NW")}


def spatial_layout(fig: Figure, views: Sequence[str] = _DEFAULT_VIEWS,
                   limits: dict[str, tuple[float, float, float, float]] | None = None) -> dict[str, Axes]:
    """Axes for ``views`` on ``fig``: ``{view: axes}``, the 3-D one with a 3-D projection.

    With the four default views (in any order; ``"diagram"`` may stand for ``top``) and the
    views' ``limits`` (``{view: (hmin, hmax, vmin, vmax)}`` m), the panels are sized to their
    drawings at one scale and drawn against each other: front beside side (same height), top
    below side (same width). Otherwise two columns in the order given.
    """
    for v in views:
        if v not in ("3d", "diagram"):
            _check_view(v)
    if not views:
        raise InputError("view", "give at least one view")
    kw = {"3d": {"projection": "3d"}}
    slots = {("top" if v == "diagram" else v) for v in views}
    if limits is not None and slots == set(_GRID) and len(views) == 4 and {"front", "side"} <= set(limits):
        f, s = limits["front"], limits["side"]
        t = limits.get("top", (s[0], s[1], f[0], f[1]))   # top: x across, y up (y as wide as the front view)
        # the 3-D view's cell (below front, beside top) at least 0.9 of the side view's width and 0.6 of the front
        # view's height: the front and top views keep their scale and alignment (anchored to the side view), the
        # 3-D view gets room for its ticks (a narrow front view left it a thumbnail)
        widths = (max(f[1] - f[0], 0.9 * (s[1] - s[0])), s[1] - s[0])
        heights = (f[3] - f[2], max(t[3] - t[2], 0.6 * (f[3] - f[2])))
        gs = fig.add_gridspec(2, 2, width_ratios=widths, height_ratios=heights)
        out: dict[str, Axes] = {}
        for v in views:
            r, c, anchor = _GRID["top" if v == "diagram" else v]
            out[v] = fig.add_subplot(gs[r, c], **kw.get(v, {}))
            out[v].set_anchor(anchor)
        return out
    cols = 1 if len(views) == 1 else 2
    rows = math.ceil(len(views) / cols)
    return {v: fig.add_subplot(rows, cols, k + 1, **kw.get(v, {})) for k, v in enumerate(views)}


def layout_size(limits: dict[str, tuple[float, float, float, float]], width: tuple[float, float] = (8.5, 13.0),
                height: float = 9.5) -> tuple[float, float]:
    """Figure size (in) of the default four-view layout of views with ``limits``: ``height`` tall, as wide as the
    panels need at that height (within ``width``), room left for ticks, titles and the legend."""
    f, s = limits["front"], limits["side"]
    t = limits.get("top", (s[0], s[1], f[0], f[1]))
    aspect = (max(f[1] - f[0], 0.9 * (s[1] - s[0])) + (s[1] - s[0])) / max(
        (f[3] - f[2]) + max(t[3] - t[2], 0.6 * (f[3] - f[2])), 1e-12)   # the cells of spatial_layout
    return float(np.clip(aspect * (height - 2.2) + 1.6, *width)), height


def legend(fig: Figure, colours: dict[str, str], scene: Scene) -> None:
    """One legend below the panels: a line per body in its colour, and the spring, damper, actuator and load
    symbols the scene has."""
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=c, linewidth=5, solid_capstyle="round", label=n) for n, c in colours.items()]
    extra: tuple[tuple[str, str, Any, float, Sequence[object]], ...] = (
        ("springs", "#ff7f0e", "-", 1.3, scene.springs), ("dampers", "#8c564b", "--", 2.0, scene.dampers),
        ("rotary springs, dampers (at their joint)", "#ff7f0e", ":", 1.3, scene.coils),
             ("actuators", "#6a3d9a", "-", 5, scene.actuators), ("loads", "#d62728", "-", 1.8, scene.forces),
             ("joint axes", "0.3", "-.", 1.0, scene.joint_axes))
    for n, c, ls, lw, items in extra:
        if items:
            handles.append(Line2D([], [], color=c, linestyle=ls, linewidth=lw, label=n))
    fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 6), fontsize=_FONT, frameon=False)


def label_views(axes: dict[str, Axes], scene: Scene, *, bodies: bool = True, label_points: bool = False) -> None:
    """Name the bodies (with ``bodies``) and the named points (with ``label_points``) in each orthographic view of the laid-out
    figure of ``axes``: beside what they name, clear of each other and of the drawing where there is room,
    inside the axes, with leader lines (see :mod:`mechcont.outputs._labels`)."""
    from ._labels import Label, place_labels

    renderer = _d._laid_out(next(iter(axes.values())))   # label positions are measured in pixels
    colours = _d.body_colours([scene])
    for view, ax in axes.items():
        if view not in VIEWS:
            continue
        flat = project(scene, view)
        items = [Label(name, _body_anchor(pts), colours[name], bold=True, gid=f"body:{name}")
                 for name, pts in _first_of_each(flat.bars)] if bodies else []
        points = _d._point_groups(flat.points, _d._size(ax.get_xlim() + ax.get_ylim())) if label_points else []
        for p, _ in points:
            ax.plot(p[0], p[1], "o", color="black", markersize=2.5, zorder=7)
        items += [Label(_stacked(names), (float(p[0]), float(p[1])), gid=f"point:{names[0]}") for p, names in points]
        place_labels(ax, items, renderer, avoid=_d._scene_samples(flat), fontsize=_FONT)


def _stacked(names: Sequence[str]) -> str:
    """Names of coincident points, two to a line (a long one-line label finds no room)."""
    return ",\n".join(", ".join(names[k:k + 2]) for k in range(0, len(names), 2))


def _first_of_each(bars: Iterable[tuple[str, np.ndarray]]) -> list[tuple[str, np.ndarray]]:
    seen: dict[str, np.ndarray] = {}
    for name, pts in bars:
        seen.setdefault(name, pts)
    return list(seen.items())


def _body_anchor(pts: npt.ArrayLike) -> tuple[float, float]:
    """The middle of the longest segment of a body's polyline (on the body, where it is easiest to see)."""
    pts = np.atleast_2d(np.asarray(pts, float))
    if len(pts) < 2:
        return float(pts[0, 0]), float(pts[0, 1])
    k = int(np.argmax(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    mid = 0.5 * (pts[k] + pts[k + 1])
    return float(mid[0]), float(mid[1])


class _Frame:
    """Fixed views (limits, force scale, body colours) shared by every scene of a drawing or an animation."""

    def __init__(self, scenes: Sequence[Scene], views: Sequence[str], show_forces: bool,
                 force_scale: float | None = None) -> None:
        if not scenes or not all(is_spatial(s) for s in scenes):
            raise InputError("scene", "a spatial drawing needs scenes with 3-D coordinates")
        self.scale = _force_scale(scenes) if force_scale is None else float(force_scale)
        if not (math.isfinite(self.scale) and self.scale >= 0):
            raise InputError("force_scale", f"must be a non-negative number of m/N, not {force_scale!r}")
        self.views = tuple(views)
        self.limits = {v: _view_limits(scenes, v, self.scale, show_forces) for v in views if v in VIEWS}
        self.box = _box3d(scenes, self.scale, show_forces)
        self.show_forces = show_forces
        self.colours = _d.body_colours(scenes)

    def render(self, axes: dict[str, Axes], scene: Scene, *, title: str | None, quiet_loads: Sequence[str] = (),
               clear: bool = True) -> None:
        """Draw ``scene`` in every view of ``axes`` (bodies unnamed: see :func:`label_views`); ``clear=False``
        keeps what they hold (an animation removes its previous frame's artists itself and keeps the axes,
        ticks and all)."""
        for v, ax in axes.items():
            if clear:
                ax.clear()
            if v == "3d":
                _draw_3d(ax, scene, self.box, self.scale, self.show_forces, "3-D view", self.colours)
            else:
                _draw_view(ax, scene, v, self.limits[v], self.scale, self.show_forces, quiet_loads, self.colours)
        if title:
            next(iter(axes.values())).figure.suptitle(title)


def _compose(scene: Scene, fig: Figure | None, views: Sequence[str], title: str | None, show_forces: bool,
             force_scale: float | None, labels: bool, label_points: bool,
             note: tuple[str, bool | None] | None = None) -> dict[str, Axes]:
    """The whole spatial drawing on ``fig`` (a new sized one when None): views, legend, note, labels."""
    frame = _Frame([scene], views, show_forces, force_scale)
    if fig is None:
        from matplotlib.figure import Figure

        four = set(views) == set(_GRID) and len(views) == 4
        grow = 1.6 if label_points else 1.0   # room for every point's name
        size = layout_size(frame.limits, (8.5 * grow, 13.0 * grow), 9.5 * grow) if four else (11 * grow, 9 * grow)
        fig = Figure(figsize=size, layout="constrained")
    axes = spatial_layout(fig, views, frame.limits)
    frame.render(axes, scene, title=title)
    legend(fig, frame.colours, scene)
    first = next((ax for v, ax in axes.items() if v in VIEWS), None)
    if note is not None and first is not None:
        view = next(v for v in axes if v in VIEWS)
        _d._put_note(first, note[0], note[1], _d._note_corner([project(scene, view)], frame.limits[view]))
    if labels or label_points:
        label_views(axes, scene, bodies=labels, label_points=label_points)
    return axes


def draw_scene3d(scene: Scene, fig: Figure | None = None, *, views: Sequence[str] = _DEFAULT_VIEWS,
                 title: str | None = None, show_forces: bool = True, force_scale: float | None = None,
                 labels: bool = True, label_points: bool = False) -> dict[str, Axes]:
    """Draw a spatial :class:`Scene` as orthographic views and a 3-D view on one figure.

    Parameters
    ----------
    scene:
        3-D primitives, coordinates in metres, forces in newtons.
    fig:
        Matplotlib figure to draw on; a new one (Agg canvas, sized to the views, about 9 x 9.5 in) when omitted.
    views:
        Any of ``front``, ``side``, ``top`` (see :data:`VIEWS`) and ``3d``, in any order (the four
        together are laid out as a third-angle projection, see :func:`spatial_layout`).
    title:
        Figure title.
    show_forces, force_scale:
        As for :func:`mechcont.outputs.drawing.draw_scene` (the scale in m/N, shared by every view).
    labels:
        Name the bodies in the orthographic views (leader lines, no two labels overlapping); a
        legend below the views gives each body's colour in any case.
    label_points:
        Name the points of ``scene.points`` too (coincident points share one label).

    Returns
    -------
    dict
        ``{view: matplotlib axes}``; every axis labelled with its coordinate in metres.
    """
    return _compose(scene, fig, views, title, show_forces, force_scale, labels, label_points)


def draw3d(system: EquationSystem, x: npt.ArrayLike | SpecialPoint, path: str | os.PathLike[str] | None = None, *,
           views: Sequence[str] = _DEFAULT_VIEWS, title: str | None = None, show_forces: bool = True,
           annotate: Sequence[str] = (), stable: bool | None = None, label: str = "", dpi: int = 100,
           labels: bool = True, label_points: bool = False) -> dict[str, Axes]:
    """Draw a spatial ``system`` at the full variable vector ``x`` (three-view + 3-D) and optionally save it.

    Like :func:`mechcont.outputs.drawing.draw` (same ``x``, ``annotate``, ``stable``,
    ``label``); the note with the annotated values is printed in the first orthographic view.
    ``labels`` and ``label_points`` are :func:`draw_scene3d`'s.

    Returns
    -------
    dict
        ``{view: axes}``.

    Raises
    ------
    InputError
        No scene, a planar scene, a wrong-length or non-finite ``x``, an unknown name, view or suffix.
    """
    from matplotlib.figure import Figure

    out = _d._check_out(path, _d.IMAGE_SUFFIXES) if path is not None else None
    scene_fn = _d._scene_of(system)
    if hasattr(x, "x") and hasattr(x, "label"):
        label = label or str(x.label)
        x = x.x
    x = _d._check_x(system, x)
    for name in annotate:
        system.index(name)
    axes = _compose(scene_fn(x), None, views, title or system.name, show_forces, None, labels, label_points,
                    note=(_d._note(system, x, annotate, stable, label), stable))
    if out is not None:
        fig = next(iter(axes.values())).get_figure()
        assert isinstance(fig, Figure)   # the new figure of _compose
        _d._atomic_write(out, lambda tmp: fig.savefig(tmp, format=out.suffix[1:].lower(), dpi=dpi))
    return axes
