"""The parts of a mechanism's drawing (:mod:`mechcont.outputs.drawing`): the planar scene drawn on an axes
(:func:`draw_scene`), its limits, labels and note, and the checked output file, shared by the planar and the
spatial drawings (:mod:`.drawing3d`); :func:`mechcont.outputs.drawing.draw` picks one of them."""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from .._io import atomic_write
from ..equations import Scene
from ..errors import InputError
from ..units import display
from ._symbols import (  # noqa: F401 (the symbols' names, used here and by drawing3d)
    _COILS,
    _LABEL_BOX,
    _add,
    _anchor_down,
    _draw_actuator,
    _draw_coil,
    _draw_damper,
    _draw_force,
    _draw_ground,
    _draw_moment,
    _draw_pin,
    _draw_slider,
    _draw_slot,
    _hatched_strip,
    _line,
    _moment_radius,
    _unit,
    _zigzag,
    load_text,
    slider_span,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.backends.backend_agg import RendererAgg

    from ..equations import EquationSystem

__all__ = ["draw_scene", "label_scene", "default_annotate", "body_colours", "IMAGE_SUFFIXES"]

IMAGE_SUFFIXES = (".png", ".svg", ".pdf")

_SYMBOL = 0.03       # symbol size h as a fraction of the larger side of the view
_PAD = 0.12          # view margin as a fraction of the scene size
_ARROW = 0.3         # default longest force arrow as a fraction of the scene size
_DEFAULT_ANNOTATE = ("F", "theta1")
_BAR_COLOURS = ("#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#17becf", "#7f7f7f", "#bcbd22", "#e377c2",
                "#393b79", "#637939", "#843c39", "#7b4173")


def body_colours(scenes: Iterable[Scene]) -> dict[str, str]:
    """``{body name: colour}``: one colour per distinct bar name of ``scenes``, in the order they first appear,
    so a body has the same colour in every view, frame and legend."""
    out: dict[str, str] = {}
    for scene in scenes:
        for name, _ in scene.bars:
            if name not in out:
                out[name] = _BAR_COLOURS[len(out) % len(_BAR_COLOURS)]
    return out


# -- geometry of a view --------------------------------------------------------------------

def _size(bounds: tuple[float, float, float, float]) -> float:
    xmin, xmax, ymin, ymax = bounds
    s = max(xmax - xmin, ymax - ymin)
    return s if s > 1e-12 else 1.0


def _union(boxes: Iterable[tuple[float, ...]]) -> tuple[float, float, float, float]:
    b = np.array(list(boxes), dtype=float)
    return float(b[:, 0].min()), float(b[:, 1].max()), float(b[:, 2].min()), float(b[:, 3].max())


def _max_force(scene: Scene) -> float:
    return max((math.hypot(*np.asarray(v, float)) for _, _, v in scene.forces), default=0.0)  # hypot: no overflow


def _default_force_scale(scenes: Sequence[Scene]) -> float:
    """Metres per newton so that the largest force of all ``scenes`` is ``_ARROW`` of their size."""
    fmax = max((_max_force(s) for s in scenes), default=0.0)
    size = _size(_union(s.extent() for s in scenes))
    return _ARROW * size / fmax if fmax > 0 else 0.0


def _bounds(scene: Scene, force_scale: float, show_forces: bool) -> tuple[float, float, float, float]:
    """Box around every primitive and, if shown, every force arrow with room for its label."""
    xmin, xmax, ymin, ymax = _checked_extent(scene.extent())
    if show_forces:
        h = _SYMBOL * _size((xmin, xmax, ymin, ymax))
        for _, p, v in scene.forces:
            p, v = np.asarray(p, float), np.asarray(v, float) * force_scale
            n = np.hypot(*v)
            with np.errstate(over="ignore", invalid="ignore"):  # an absurd force: refused by _limits
                tip = p + v + (3 * h * v / n if n > 0 else np.array([0.0, 2 * h]))
            xmin, xmax = min(xmin, tip[0]), max(xmax, tip[0])
            ymin, ymax = min(ymin, tip[1]), max(ymax, tip[1])
        r = _moment_radius(h) + 2 * h
        for _, p, _ in scene.moments:
            xmin, xmax = min(xmin, p[0] - r), max(xmax, p[0] + r)
            ymin, ymax = min(ymin, p[1] - r), max(ymax, p[1] + r)
    return xmin, xmax, ymin, ymax


#: Largest extent (m) of a drawing: beyond it a coordinate is no mechanism's (e.g. 1e308 read from a file).
_MAX_EXTENT = 1e9


def _limits(bounds: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    xmin, xmax, ymin, ymax = _checked_extent(bounds)
    pad = _PAD * _size(bounds)
    return xmin - pad, xmax + pad, ymin - pad, ymax + pad


def _checked_extent(bounds: tuple[float, ...]) -> tuple[float, ...]:
    """``bounds``, or InputError when they reach beyond :data:`_MAX_EXTENT` (or are not finite)."""
    if not all(math.isfinite(b) and abs(b) <= _MAX_EXTENT for b in bounds):
        raise InputError("configuration", f"the drawing would reach {max(map(abs, bounds)):.3g} m from the origin, "
                                          f"beyond any mechanism (at most {_MAX_EXTENT:g} m): a coordinate or force "
                                          "drawn is not a physical value")
    return bounds


# -- primitives ----------------------------------------------------------------------------

def _point_groups(points: Iterable[tuple[str, npt.ArrayLike]], size: float) -> list[tuple[np.ndarray, list[str]]]:
    """Named ``points`` grouped where they lie within a thousandth of ``size`` (m) of each other:
    ``[(position, [names])]``, in the order they first appear."""
    groups: list[tuple[np.ndarray, list[str]]] = []
    for name, p in points:
        p = np.asarray(p, float)
        for q, names in groups:
            if np.hypot(*(p - q)) <= 1e-3 * size:
                names.append(name)
                break
        else:
            groups.append((p, [name]))
    return groups


def label_scene(ax: Axes, scene: Scene) -> None:
    """Name every body and every named point of ``scene`` on the laid-out axes ``ax``, and place the loads' value
    labels again, all by :func:`mechcont.outputs._labels.place_labels`: each beside what it names, clear of the
    other texts, inside the axes, covering as little of the drawing as it can, with a leader line when away from it
    (the texts written at fixed offsets ran into each other: a moment's value over a body's name, the labels of
    loads at one point over each other). Points closer than a thousandth of the view share one label."""
    from ._labels import Label, place_labels

    renderer = _laid_out(ax)
    to_data = ax.transData.inverted().transform
    items = []
    for t in list(ax.texts):
        if str(t.get_gid() or "").startswith("load:"):
            e = t.get_window_extent(renderer)
            c = to_data(np.array([[(e.x0 + e.x1) / 2, (e.y0 + e.y1) / 2]]))[0]
            items.append(Label(t.get_text(), (float(c[0]), float(c[1])), t.get_color(), gid=t.get_gid()))
            t.remove()
    colours = body_colours([scene])
    seen: set[str] = set()
    for name, pts in scene.bars:
        if name not in seen:
            seen.add(name)
            c = np.unique(np.atleast_2d(np.asarray(pts, float)), axis=0).mean(axis=0)
            items.append(Label(name, (float(c[0]), float(c[1])), colours[name], bold=True, gid=f"body:{name}"))
    for p, names in _point_groups(scene.points, _size((*ax.get_xlim(), *ax.get_ylim()))):
        ax.plot(p[0], p[1], "o", color="black", markersize=2.5, zorder=7)
        items.append(Label(", ".join(names), (float(p[0]), float(p[1])), gid=f"point:{names[0]}"))
    place_labels(ax, items, renderer, avoid=_scene_samples(scene), fontsize=9)


def _laid_out(ax: Axes) -> RendererAgg:
    """Lay out the figure of ``ax`` (on an Agg canvas) and return its renderer, to measure texts in pixels."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = ax.get_figure()
    assert isinstance(fig, Figure), "labels are placed on axes of a figure, not of a subfigure"
    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    fig.draw_without_rendering()   # the layout: labels are placed in pixels
    return canvas.get_renderer()


def draw_scene(scene: Scene, ax: Axes | None = None, *, title: str | None = None, show_forces: bool = True,
               force_scale: float | None = None, limits: tuple[float, float, float, float] | None = None,
               labels: bool = False, slider_spans: Sequence[tuple[npt.ArrayLike, npt.ArrayLike]] | None = None,
               quiet_loads: Iterable[str] = (), colours: dict[str, str] | None = None) -> Axes:
    """Draw one :class:`Scene` on matplotlib axes.

    Parameters
    ----------
    scene:
        The primitives, coordinates in metres, forces in newtons (or in the scene's :attr:`~Scene.units`,
        which label the axes and the loads).
    ax:
        Axes to draw on; a new figure (Agg canvas) is made when omitted.
    title:
        Optional axes title.
    show_forces:
        Draw the applied forces as arrows labelled with their magnitude (N) and the applied
        moments as curved arrows (counter-clockwise for a positive value) labelled with
        their magnitude (N m).
    force_scale:
        Arrow length per force, m/N; by default the largest force is drawn 0.3 times the
        size of the mechanism.
    limits:
        Fixed view ``(xmin, xmax, ymin, ymax)`` (m); by default the scene with a margin.
        Symbol sizes are a fixed fraction of the view.
    labels:
        Name every body at its centre and label every named point of ``scene.points``
        (coincident points share one label).
    slider_spans:
        Per slider, the ends ``(a, b)`` of its guide (an animation passes the whole travel,
        see :func:`slider_span`); by default a short guide around the block.
    quiet_loads:
        Names of forces, moments and actuators drawn without their value label (printed elsewhere,
        e.g. in an animation's note), so no text covers the mechanism.
    colours:
        ``{body name: colour}`` (see :func:`body_colours`, the default), e.g. shared by several views.

    Returns
    -------
    matplotlib.axes.Axes
        The axes, with equal aspect and metres on both axes.
    """
    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=(6, 4.5)).add_subplot()
    scale = _default_force_scale([scene]) if force_scale is None else float(force_scale)
    if not (math.isfinite(scale) and scale >= 0):
        raise InputError("force_scale", f"must be a non-negative number of m/N, not {force_scale!r}")
    if limits is None:
        limits = _limits(_bounds(scene, scale, show_forces))
    h = _SYMBOL * max(limits[1] - limits[0], limits[3] - limits[2])
    force = scene.units.label("N")

    for k, (p, direction) in enumerate(scene.sliders):
        _draw_slider(ax, np.asarray(p, float), direction, h, None if slider_spans is None else slider_spans[k])
    for p in scene.grounds:
        _draw_ground(ax, np.asarray(p, float), h, gid="ground")
    for p in scene.anchors:
        p = np.asarray(p, float)
        _draw_ground(ax, p, 0.7 * h, down=_anchor_down(p, scene), gid="anchor")
    for name, a, b in scene.springs:
        line = _zigzag(np.asarray(a, float), np.asarray(b, float), 0.7 * h)
        _line(ax, line[:, 0], line[:, 1], color="#ff7f0e", linewidth=1.3, zorder=4, label=name)
    for name, a, b in scene.dampers:
        _draw_damper(ax, name, np.asarray(a, float), np.asarray(b, float), 0.6 * h)
    for name, p, kind in scene.coils:
        _draw_coil(ax, name, np.asarray(p, float), kind, h)
    for name, a, b, tension in scene.actuators:
        _draw_actuator(ax, name, np.asarray(a, float), np.asarray(b, float), float(tension), 0.8 * h,
                       show_forces and name not in set(quiet_loads), force)
    colours = {**body_colours([scene]), **(colours or {})}
    for name, pts in scene.bars:
        pts = np.atleast_2d(np.asarray(pts, float))
        _line(ax, pts[:, 0], pts[:, 1], color=colours[name], linewidth=6,
                solid_capstyle="round", solid_joinstyle="round", zorder=5, label=name)
    for name, a, b in scene.slots:
        _draw_slot(ax, name, np.asarray(a, float), np.asarray(b, float))
    for p in [*scene.pins, *scene.grounds, *(q for q, _ in scene.sliders)]:
        _draw_pin(ax, np.asarray(p, float), h)
    for p in scene.anchors:
        _draw_pin(ax, np.asarray(p, float), 0.7 * h)
    if show_forces:
        quiet = set(quiet_loads)
        for name, p, v in scene.forces:
            _draw_force(ax, name, np.asarray(p, float), np.asarray(v, float), scale, h, label=name not in quiet,
                        unit=force)
        for name, p, value in scene.moments:
            _draw_moment(ax, name, np.asarray(p, float), float(value), h, label=name not in quiet,
                         unit=scene.units.label("N m"))
    ax.set_xlim(limits[0], limits[1])
    ax.set_ylim(limits[2], limits[3])
    ax.set_aspect("equal", adjustable="box")
    length = scene.units.label("m")
    ax.set_xlabel(f"x ({length})")
    ax.set_ylabel(f"y ({length})")
    ax.grid(True, linewidth=0.3, alpha=0.5)
    if title:
        ax.set_title(title)
    if labels:
        label_scene(ax, scene)
    return ax


# -- files ---------------------------------------------------------------------------------

def _check_out(path: str | os.PathLike, valid: Sequence[str]) -> Path:
    path = Path(path)
    if path.suffix.lower() not in valid:
        raise InputError("out", f"unknown file type '{path.suffix or path.name}'; valid: {', '.join(valid)}")
    if not path.parent.is_dir():
        raise InputError("out", f"directory '{path.parent}' does not exist")
    return path


def _atomic_write(path: Path, write: Callable[[str], None]) -> None:
    """Call ``write(tmp)`` on a temporary file next to ``path``, then move it into place."""
    atomic_write(path, write)


def _check_x(system: EquationSystem, x: npt.ArrayLike) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    if x.shape != (len(system.names),):
        raise InputError("x", f"expected {len(system.names)} values ordered like the names of '{system.name}', "
                              f"got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        bad = [n for n, v in zip(system.names, x) if not math.isfinite(v)]
        raise InputError(bad[0], "value is not finite")
    return x


def _scene_of(system: EquationSystem) -> Callable[[np.ndarray], Scene]:
    if system.scene is None:
        raise InputError("model", f"'{system.name}' has no drawing (its EquationSystem has no scene)")
    return system.scene


def default_annotate(system: EquationSystem) -> tuple[str, ...]:
    """Variables printed on a drawing when none are asked for: ``F`` and ``theta1`` where the
    model has them, else its first angle state (e.g. ``theta_crank``), else nothing."""
    names = tuple(n for n in _DEFAULT_ANNOTATE if n in system.names)
    if names:
        return names
    angles = [v.name for v in system.variables if v.kind == "state" and v.unit == "rad"]
    return tuple(angles[:1])


def _with_vary(vary: str | None, annotate: Sequence[str]) -> tuple[str, ...]:
    """``annotate`` with the continuation parameter ``vary`` first (once)."""
    return tuple(dict.fromkeys([*([vary] if vary else []), *annotate]))


def _direction(u: npt.ArrayLike) -> str:
    """Words for the unit vector ``u`` (2 or 3 components): ``up``, ``down``, ``left``, ``right`` in a plane when
    within a degree of an axis, else its angle from +x; ``along (ux, uy, uz)`` in space."""
    u = np.asarray(u, float)
    if len(u) != 2:
        return "along (" + ", ".join(f"{c:.2f}" for c in u) + ")"
    angle = math.degrees(math.atan2(u[1], u[0]))
    for target, word in ((90.0, "up"), (-90.0, "down"), (0.0, "right"), (180.0, "left"), (-180.0, "left")):
        if abs(angle - target) < 1.0:
            return word
    return f"at {angle:.0f}° from +x"


def _note(system: EquationSystem, x: np.ndarray, annotate: Sequence[str], stable: bool | None, label: str,
          unknown: str = "", forces: Mapping[str, npt.ArrayLike] | None = None) -> str:
    """Text lines: each annotated variable (angles in degrees), stability (``unknown`` when not known) and label.
    A variable that is a drawn load of ``forces`` (``{name: force vector (N)}``) is printed signed with the
    direction its positive value acts in (``F = -75.58 N (+ up)``): its arrow, unlabelled, shows where it acts."""
    lines = []
    for name in annotate:
        var, val = system.variable(name), float(x[system.index(name)])
        if var.unit == "rad":
            lines.append(f"{name} = {round(display(val, 'rad')[0], 2) + 0.0:.2f}°")   # no "-0.00°"
        else:
            line = f"{name} = {val:.4g} {var.unit}".rstrip()
            v = None if forces is None else forces.get(name)
            if v is not None and val != 0 and np.linalg.norm(v) > 0:
                d = np.asarray(v, float) / val   # the direction of a positive value
                line += f" (+ {_direction(d / np.linalg.norm(d))})"
            lines.append(line)
    status = unknown if stable is None else ("stable" if stable else "unstable")
    if label.rstrip("0123456789?") in ("LP", "NSF"):
        status = "fold"  # neutral: neither stable nor unstable (see Branch.stability_labels)
    tail = " ".join(s for s in (status, label) if s)
    if tail:
        lines.append(tail)
    return "\n".join(lines)


_CORNERS = ((0.02, 0.98, "left", "top"), (0.98, 0.98, "right", "top"),
            (0.02, 0.02, "left", "bottom"), (0.98, 0.02, "right", "bottom"))


def _scene_samples(scene: Scene) -> np.ndarray:
    """Points (k x 2, m) along every drawn line and at every symbol of ``scene``."""
    t = np.linspace(0.0, 1.0, 11)[:, None]
    lines = [np.atleast_2d(np.asarray(b, float)) for _, b in scene.bars]
    lines += [np.array([a, b], float) for _, a, b in (*scene.springs, *scene.dampers)]
    lines += [np.array([a, b], float) for _, a, b, _ in scene.actuators]
    pts = [a + t * (b - a) for line in lines for a, b in zip(line[:-1], line[1:])]
    pts += [np.atleast_2d(np.asarray(p, float)) for p in (*scene.pins, *scene.grounds, *scene.anchors)]
    pts += [np.atleast_2d(np.asarray(p, float)) for _, p, _ in (*scene.moments, *scene.forces)]
    return np.vstack(pts) if pts else np.zeros((0, 2))


def _note_corner(scenes: Sequence[Scene], limits: Sequence[float]) -> tuple[float, float, str, str]:
    """The corner of the view (axes fraction, alignment) that the fewest drawn points fall into.

    A corner box is 40 % of the width by 30 % of the height; ties go to top-left, then
    top-right, bottom-left, bottom-right.
    """
    xmin, xmax, ymin, ymax = limits
    pts = np.vstack([_scene_samples(s) for s in scenes])
    u, v = (pts[:, 0] - xmin) / (xmax - xmin), (pts[:, 1] - ymin) / (ymax - ymin)
    counts = [int(np.sum((np.abs(u - cx) < 0.4) & (np.abs(v - cy) < 0.3))) for cx, cy, _, _ in _CORNERS]
    return _CORNERS[int(np.argmin(counts))]


def _put_note(ax: Axes, text: str, stable: bool | None,
              corner: tuple[float, float, str, str] = _CORNERS[0]) -> None:
    if not text:
        return
    colour = "white" if stable is None else ("#e5f5e0" if stable else "#fde0dd")
    x, y, ha, va = corner
    ax.text(x, y, text, transform=ax.transAxes, ha=ha, va=va, fontsize=9, zorder=10,
            bbox=dict(boxstyle="round,pad=0.3", facecolor=colour, edgecolor="0.6", alpha=0.9))
