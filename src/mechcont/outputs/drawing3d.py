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
from collections.abc import Sequence

import numpy as np

from ..equations import Scene
from ..errors import InputError
from . import drawing as _d

__all__ = ["VIEWS", "is_spatial", "project", "draw_scene3d", "draw3d", "spatial_layout"]

#: View name -> (horizontal axis index, vertical axis index, axis seen along).
VIEWS: dict[str, tuple[int, int, int]] = {"front": (1, 2, 0), "side": (0, 2, 1), "top": (0, 1, 2)}
_AXIS = "xyz"
_DEFAULT_VIEWS = ("front", "side", "top", "3d")


def is_spatial(scene: Scene) -> bool:
    """True when ``scene`` holds 3-D coordinates."""
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

    def p2(p) -> np.ndarray:
        p = np.asarray(p, float)
        return p[..., [h, v]].copy()

    out = Scene()
    out.bars = [(name, p2(pts)) for name, pts in scene.bars]
    out.pins = [p2(p) for p in scene.pins]
    out.grounds = [p2(p) for p in scene.grounds]
    out.sliders = [(p2(p), p2(d)) for p, d in scene.sliders]
    out.springs = [(name, p2(a), p2(b)) for name, a, b in scene.springs]
    out.dampers = [(name, p2(a), p2(b)) for name, a, b in scene.dampers]
    out.actuators = [(name, p2(a), p2(b), t) for name, a, b, t in scene.actuators]
    out.forces = [(name, p2(p), p2(f)) for name, p, f in scene.forces]
    out.moments = [(name, p2(p), sign * float(np.asarray(m, float)[n])) for name, p, m in scene.moments]
    out.anchors = [p2(p) for p in scene.anchors]
    out.points = [(name, p2(p)) for name, p in scene.points]
    return out


def _norm(v) -> float:
    return float(np.linalg.norm(np.asarray(v, float)))


def _force_scale(scenes: Sequence[Scene]) -> float:
    """m/N so that the largest force of all ``scenes`` is drawn ``_ARROW`` of their size."""
    fmax = max((_norm(f) for s in scenes for _, _, f in s.forces), default=0.0)
    box = np.array([s.extent() for s in scenes]).reshape(len(scenes), 3, 2)
    size = float(np.max(box[:, :, 1].max(axis=0) - box[:, :, 0].min(axis=0)))
    return _d._ARROW * max(size, 1e-12) / fmax if fmax > 0 else 0.0


def _view_limits(scenes: Sequence[Scene], view: str, scale: float, show_forces: bool):
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


def _axis_lines(scene: Scene, view: str | None, length: float):
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


def _label_3d(text: str) -> str:
    return f"{text} (m)"


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


def _draw_3d(ax, scene: Scene, box: np.ndarray, scale: float, show_forces: bool, labels: bool, title: str | None):
    """Scene in Matplotlib 3-D axes ``ax`` within ``box`` (3, 2) m, equal scale on the three axes."""
    size = float(np.max(box[:, 1] - box[:, 0]))
    h = _d._SYMBOL * size
    for i, (name, pts) in enumerate(scene.bars):
        pts = np.atleast_2d(np.asarray(pts, float))
        ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], color=_d._BAR_COLOURS[i % len(_d._BAR_COLOURS)], linewidth=4,
                solid_capstyle="round", label=name)
    for name, a, b in scene.springs:
        line = _zigzag3d(np.asarray(a, float), np.asarray(b, float), 0.7 * h)
        ax.plot(*line.T, color="#ff7f0e", linewidth=1.3, label=name)
    for name, a, b in scene.dampers:
        ax.plot(*np.array([a, b], float).T, color="#8c564b", linewidth=2.0, linestyle="--", label=name)
    for name, a, b, tension in scene.actuators:
        a, b = np.asarray(a, float), np.asarray(b, float)
        mid = a + 0.55 * (b - a)
        ax.plot(*np.array([a, mid]).T, color="#6a3d9a", linewidth=7, alpha=0.55, solid_capstyle="butt", label=name)
        ax.plot(*np.array([a, b]).T, color="#6a3d9a", linewidth=2.4)
        if show_forces:
            sense = "tension" if tension > 0 else ("compression" if tension < 0 else "unloaded")
            ax.text(*(a + 0.3 * (b - a)), f"{name} = {_d.load_text(abs(tension), 'N')} {sense}", fontsize=7,
                    color="#6a3d9a")
    for a, b in _axis_lines(scene, None, 6 * h):
        ax.plot(*np.array([a, b]).T, color="0.3", linewidth=1.0, linestyle="-.")
    pins = np.array([np.asarray(p, float) for p in scene.pins]).reshape(-1, 3)
    ax.scatter(*pins.T, s=28, facecolor="white", edgecolor="black", depthshade=False, zorder=6)
    grounds = np.array([np.asarray(p, float) for p in (*scene.grounds, *scene.anchors)]).reshape(-1, 3)
    ax.scatter(*grounds.T, s=70, marker="^", facecolor="0.8", edgecolor="0.2", depthshade=False, zorder=6)
    if show_forces:
        for name, p, f in scene.forces:
            p, v = np.asarray(p, float), scale * np.asarray(f, float)
            if _norm(v) > 0:
                ax.quiver(*p, *v, color="#d62728", linewidth=1.8, arrow_length_ratio=0.15)
            ax.text(*(p + v), f"{name} = {_d.load_text(_norm(f), 'N')}", fontsize=7, color="#d62728")
    if labels:
        seen: set[str] = set()
        for i, (name, pts) in enumerate(scene.bars):
            if name not in seen:
                seen.add(name)
                c = np.unique(np.atleast_2d(np.asarray(pts, float)), axis=0).mean(axis=0)
                ax.text(*c, name, fontsize=8, fontweight="bold", color=_d._BAR_COLOURS[i % len(_d._BAR_COLOURS)])
    ax.set_xlim(*box[0])
    ax.set_ylim(*box[1])
    ax.set_zlim(*box[2])
    ax.set_box_aspect(tuple(box[:, 1] - box[:, 0]))
    ax.set_xlabel(_label_3d("x"))
    ax.set_ylabel(_label_3d("y"))
    ax.set_zlabel(_label_3d("z"))
    ax.tick_params(labelsize=7)
    if title:
        ax.set_title(title)


def _draw_view(ax, scene: Scene, view: str, limits, scale: float, show_forces: bool, labels: bool,
               quiet_loads: Sequence[str] = ()):
    h_i, v_i, n_i = VIEWS[view]
    flat = project(scene, view)
    # a projected load is a component, not the load: its arrow is drawn, its value is printed in the 3-D view
    quiet = (*quiet_loads, *(n for n, _, _ in flat.forces), *(n for n, _, _ in flat.moments),
             *(n for n, _, _, _ in flat.actuators))
    _d.draw_scene(flat, ax, title=f"{view} (seen along {_AXIS[n_i]})", show_forces=show_forces, force_scale=scale,
                  limits=limits, labels=labels, quiet_loads=quiet)
    h = _d._SYMBOL * max(limits[1] - limits[0], limits[3] - limits[2])
    for a, b in _axis_lines(scene, view, 6 * h):
        ax.plot(*np.array([a, b]).T, color="0.3", linewidth=1.0, linestyle="-.", zorder=6.5, gid="joint-axis")
    ax.set_xlabel(f"{_AXIS[h_i]} (m)")
    ax.set_ylabel(f"{_AXIS[v_i]} (m)")


def spatial_layout(fig, views: Sequence[str] = _DEFAULT_VIEWS):
    """Axes for ``views`` on ``fig`` (two columns): ``{view: axes}``, the 3-D one with a 3-D projection."""
    for v in views:
        if v != "3d":
            _check_view(v)
    if not views:
        raise InputError("view", "give at least one view")
    cols = 1 if len(views) == 1 else 2
    rows = math.ceil(len(views) / cols)
    return {v: fig.add_subplot(rows, cols, k + 1, **({"projection": "3d"} if v == "3d" else {}))
            for k, v in enumerate(views)}


class _Frame:
    """Fixed views (limits, force scale) shared by every scene of a drawing or an animation."""

    def __init__(self, scenes: Sequence[Scene], views: Sequence[str], show_forces: bool, force_scale=None):
        if not scenes or not all(is_spatial(s) for s in scenes):
            raise InputError("scene", "a spatial drawing needs scenes with 3-D coordinates")
        self.scale = _force_scale(scenes) if force_scale is None else float(force_scale)
        if not (math.isfinite(self.scale) and self.scale >= 0):
            raise InputError("force_scale", f"must be a non-negative number of m/N, not {force_scale!r}")
        self.views = tuple(views)
        self.limits = {v: _view_limits(scenes, v, self.scale, show_forces) for v in views if v != "3d"}
        self.box = _box3d(scenes, self.scale, show_forces)
        self.show_forces = show_forces

    def render(self, axes: dict, scene: Scene, *, labels: bool, title: str | None, quiet_loads=(), clear: bool = True):
        """Draw ``scene`` in every view of ``axes``; ``clear=False`` keeps what they hold (an animation
        removes its previous frame's artists itself and keeps the axes, ticks and all)."""
        for v, ax in axes.items():
            if clear:
                ax.clear()
            if v == "3d":
                _draw_3d(ax, scene, self.box, self.scale, self.show_forces, labels, "3-D view")
            else:
                _draw_view(ax, scene, v, self.limits[v], self.scale, self.show_forces, labels, quiet_loads)
        if title:
            next(iter(axes.values())).figure.suptitle(title)


def draw_scene3d(scene: Scene, fig=None, *, views: Sequence[str] = _DEFAULT_VIEWS, title: str | None = None,
                 show_forces: bool = True, force_scale: float | None = None, labels: bool = True) -> dict:
    """Draw a spatial :class:`Scene` as orthographic views and a 3-D view on one figure.

    Parameters
    ----------
    scene:
        3-D primitives, coordinates in metres, forces in newtons.
    fig:
        Matplotlib figure to draw on; a new one (Agg canvas, 11 x 9 in) when omitted.
    views:
        Any of ``front``, ``side``, ``top`` (see :data:`VIEWS`) and ``3d``, in the order drawn.
    title:
        Figure title.
    show_forces, force_scale:
        As for :func:`mechcont.outputs.drawing.draw_scene` (the scale in m/N, shared by every view).
    labels:
        Name the bodies (and, in the orthographic views, the named points).

    Returns
    -------
    dict
        ``{view: matplotlib axes}``; every axis labelled with its coordinate in metres.
    """
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(11, 9), layout="constrained")
    frame = _Frame([scene], views, show_forces, force_scale)
    axes = spatial_layout(fig, views)
    frame.render(axes, scene, labels=labels, title=title)
    return axes


def draw3d(system, x, path: str | os.PathLike | None = None, *, views: Sequence[str] = _DEFAULT_VIEWS,
           title: str | None = None, show_forces: bool = True, annotate: Sequence[str] = (),
           stable: bool | None = None, label: str = "", dpi: int = 100, labels: bool = True) -> dict:
    """Draw a spatial ``system`` at the full variable vector ``x`` (three-view + 3-D) and optionally save it.

    Like :func:`mechcont.outputs.drawing.draw` (same ``x``, ``annotate``, ``stable``,
    ``label``); the note with the annotated values is printed in the first orthographic view.

    Returns
    -------
    dict
        ``{view: axes}``.

    Raises
    ------
    InputError
        No scene, a planar scene, a wrong-length or non-finite ``x``, an unknown name, view or suffix.
    """
    out = _d._check_out(path, _d.IMAGE_SUFFIXES) if path is not None else None
    scene_fn = _d._scene_of(system)
    if hasattr(x, "x") and hasattr(x, "label"):
        label = label or str(x.label)
        x = x.x
    x = _d._check_x(system, x)
    for name in annotate:
        system.index(name)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 9), layout="constrained")
    axes = draw_scene3d(scene_fn(x), fig, views=views, title=title or system.name, show_forces=show_forces,
                        labels=labels)
    first = next((ax for v, ax in axes.items() if v != "3d"), None)
    if first is not None:
        _d._put_note(first, _d._note(system, x, annotate, stable, label), stable)
    if out is not None:
        _d._atomic_write(out, lambda tmp: fig.savefig(tmp, format=out.suffix[1:].lower(), dpi=dpi))
    return axes
