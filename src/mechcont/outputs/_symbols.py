"""The drawing symbols of a planar scene, each one Matplotlib artist group: grounds, pins, sliders, slots,
springs (zig-zags), dampers, torsion springs and rotary dampers (coils at their joint), actuators, and load
arrows with their value labels. :mod:`.drawing` places them; sizes are in the scene's units (m), ``h`` the
symbol size."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np
import numpy.typing as npt

from ..equations import Scene

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.lines import Line2D

    _A = TypeVar("_A", bound=Artist)

_COILS = 6           # zig-zag coils per spring, whatever its length
_LABEL_BOX = dict(boxstyle="square,pad=0.1", facecolor="white", edgecolor="none", alpha=0.75)

__all__ = ["load_text", "slider_span"]


def _moment_radius(h: float) -> float:
    return 2.2 * h


def _add(ax: Axes, artist: _A) -> _A:
    """Put ``artist`` on ``ax`` without widening the data limits: :func:`draw_scene` always sets the view
    itself, and measuring a curved patch's extent costs more than drawing it (an animation adds hundreds)."""
    ax.add_artist(artist)
    return artist


def _line(ax: Axes, xs: npt.ArrayLike, ys: npt.ArrayLike, **kw: Any) -> Line2D:
    """A polyline on ``ax`` (as ``ax.plot(xs, ys, **kw)`` draws it when given its colour), see :func:`_add`."""
    from matplotlib.lines import Line2D

    return _add(ax, Line2D(np.asarray(xs, float), np.asarray(ys, float), **kw))

def _along(a: np.ndarray, b: np.ndarray) -> tuple[float, np.ndarray, np.ndarray] | None:
    """The segment ``a`` -> ``b``: its length, unit direction and left normal; None when it has no length."""
    d = b - a
    length = float(np.hypot(*d))
    if length < 1e-12:
        return None
    t = d / length
    return length, t, np.array([-t[1], t[0]])


def _zigzag(a: np.ndarray, b: np.ndarray, width: float) -> np.ndarray:
    """Polyline of a spring from ``a`` to ``b``: straight leads, ``_COILS`` coils of ``width``."""
    frame = _along(a, b)
    if frame is None:
        return np.array([a, b])
    length, t, nrm = frame
    s = np.linspace(0.2, 0.8, 2 * _COILS + 1)
    offsets = np.zeros_like(s)
    offsets[1:-1:2], offsets[2:-1:2] = width, -width
    coil = a + np.outer(s * length, t) + np.outer(offsets, nrm)
    return np.vstack([a, coil, b])


def _hatched_strip(ax: Axes, start: np.ndarray, end: np.ndarray, normal: np.ndarray, depth: float,
                   zorder: float) -> None:
    from matplotlib.patches import Polygon

    quad = np.array([start, end, end + depth * normal, start + depth * normal])
    angle = math.degrees(math.atan2(end[1] - start[1], end[0] - start[0])) % 180
    hatch = "\\\\\\\\" if 20 < angle < 70 else "////"     # strokes never parallel to the strip
    _add(ax, Polygon(quad, closed=True, fill=False, hatch=hatch, edgecolor="0.35", linewidth=0, zorder=zorder))
    _line(ax, [start[0], end[0]], [start[1], end[1]], color="0.2", linewidth=1.2, zorder=zorder)


def _draw_ground(ax: Axes, p: np.ndarray, h: float, down: npt.ArrayLike = (0.0, -1.0), gid: str | None = None) -> None:
    """Triangle on a hatched strip below ``p``; "below" is the unit vector ``down``."""
    from matplotlib.patches import Polygon

    d = np.asarray(down, float)
    e = np.array([-d[1], d[0]])                      # across the strip

    def at(u: float, v: float) -> np.ndarray:        # u across, v below p (units of h)
        return p + h * (u * e + v * d)

    tri = np.array([p, at(-1.2, 2), at(1.2, 2)])
    _add(ax, Polygon(tri, closed=True, facecolor="0.85", edgecolor="0.2", linewidth=1.0, zorder=2, gid=gid))
    _hatched_strip(ax, at(-2, 2), at(2, 2), d, 0.9 * h, 2)


def _anchor_down(p: np.ndarray, scene: Scene) -> np.ndarray:
    """Unit vector pointing away from the springs, dampers and actuators attached at ``p`` (default -y)."""
    pull = np.zeros(2)
    for _, a, b in (*scene.springs, *scene.dampers, *((n, a, b) for n, a, b, _ in scene.actuators)):
        a, b = np.asarray(a, float), np.asarray(b, float)
        for here, there in ((a, b), (b, a)):
            v = there - here
            if np.allclose(here, p, atol=1e-12) and np.hypot(*v) > 1e-12:
                pull += v / np.hypot(*v)
    n = np.hypot(*pull)
    return -pull / n if n > 1e-9 else np.array([0.0, -1.0])


def _unit(direction: npt.ArrayLike) -> np.ndarray:
    u = np.asarray(direction, float)
    return u / np.hypot(*u) if np.hypot(*u) > 0 else np.array([1.0, 0.0])


def slider_span(p: np.ndarray, direction: npt.ArrayLike, h: float,
                travel: tuple[float, float] = (0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """Ends of a slider's guide: ``travel`` (min, max distance along the guide from ``p``) and 4 h more each way."""
    u = _unit(direction)
    return p + (travel[0] - 4.0 * h) * u, p + (travel[1] + 4.0 * h) * u


def _draw_slider(ax: Axes, p: np.ndarray, direction: np.ndarray, h: float,
                 span: tuple[npt.ArrayLike, npt.ArrayLike] | None = None) -> None:
    """A block in a slot: two guide lines along ``span`` (default a short one around ``p``), fixed to
    the ground by a hatched cap at each end. Drawn locally, so bars elsewhere never cross it."""
    from matplotlib.patches import Polygon

    u = _unit(direction)
    nrm = np.array([u[1], -u[0]])          # right of the direction: "below" a rail along +x
    a, b = slider_span(p, u, h) if span is None else (np.asarray(span[0], float), np.asarray(span[1], float))
    hw, hh = 1.6 * h, 0.6 * h
    w = hh + 0.25 * h                       # half width of the slot
    for side in (-1.0, 1.0):
        _line(ax, [a[0] + side * w * nrm[0], b[0] + side * w * nrm[0]], [a[1] + side * w * nrm[1], b[1] + side * w * nrm[1]],
                color="0.55", linewidth=0.8, zorder=1, gid="slider-guide")
    for end, out in ((a, -u), (b, u)):      # ground caps, hatched away from the slot
        _hatched_strip(ax, end - (w + 0.4 * h) * nrm, end + (w + 0.4 * h) * nrm, out, 0.8 * h, 1)
    block = np.array([p - hw * u - hh * nrm, p + hw * u - hh * nrm, p + hw * u + hh * nrm, p - hw * u + hh * nrm])
    _add(ax, Polygon(block, closed=True, facecolor="0.75", edgecolor="0.2", linewidth=1.0, zorder=3))


def _draw_slot(ax: Axes, name: str, a: np.ndarray, b: np.ndarray) -> None:
    """A straight slot cut in a body: a dark channel with a light floor from ``a`` to ``b``, inside the
    body's bar (drawn 6 points wide) and under the pin."""
    for width, colour, z in ((4.0, "0.2", 5.2), (2.0, "white", 5.3)):
        _line(ax, [a[0], b[0]], [a[1], b[1]], color=colour, linewidth=width, solid_capstyle="round", zorder=z,
              gid="slot", label=f"slot {name}")


def _draw_pin(ax: Axes, p: np.ndarray, h: float) -> None:
    from matplotlib.patches import Circle

    _add(ax, Circle((float(p[0]), float(p[1])), 0.45 * h, facecolor="white", edgecolor="black", linewidth=1.2, zorder=6))


def _draw_damper(ax: Axes, name: str, a: np.ndarray, b: np.ndarray, width: float) -> None:
    """Dashpot from ``a`` to ``b``: a cylinder open towards ``b`` and a piston on a rod."""
    frame = _along(a, b)
    if frame is None:
        return
    length, t, nrm = frame

    def at(s: float, w: float) -> np.ndarray:
        return a + s * length * t + w * width * nrm

    kw: dict[str, Any] = dict(color="#8c564b", linewidth=1.3, zorder=4)
    cyl = np.array([at(0.6, 1), at(0.3, 1), at(0.3, -1), at(0.6, -1)])
    _line(ax, *np.array([a, at(0.3, 0)]).T, label=name, **kw)
    _line(ax, *cyl.T, **kw)
    _line(ax, *np.array([at(0.5, 0.75), at(0.5, -0.75)]).T, **kw)
    _line(ax, *np.array([at(0.5, 0), b]).T, **kw)


def _draw_coil(ax: Axes, name: str, p: np.ndarray, kind: str, h: float) -> None:
    """A rotary element at the joint ``p``: a torsion spring (``kind`` ``"spring"``) as a spiral of
    two and a half turns from the pin out to ``1.6 h``; a rotary damper as a 200-degree arc of radius
    ``3 h`` (outside a moment's arrow) (open below, clear of a ground symbol) with a dashpot across its middle."""
    if kind == "spring":
        phi = np.linspace(0.0, 5 * np.pi, 121)
        r = h * (0.55 + 1.05 * phi / phi[-1])
        _line(ax, p[0] + r * np.cos(phi), p[1] + r * np.sin(phi), color="#ff7f0e", linewidth=1.3, zorder=4,
              label=name, gid=f"coil:{name}")
        return
    r = 3.0 * h
    phi = np.radians(np.linspace(-10.0, 190.0, 61))
    kw: dict[str, Any] = dict(color="#8c564b", linewidth=1.3, zorder=4)
    _line(ax, p[0] + r * np.cos(phi), p[1] + r * np.sin(phi), label=name, gid=f"coil:{name}", **kw)
    top = p + np.array([0.0, r])
    _line(ax, [top[0] - 0.5 * h, top[0] - 0.5 * h], [top[1] - 0.45 * h, top[1] + 0.45 * h], **kw)
    cup = top + np.array([[0.7 * h, 0.6 * h], [-0.2 * h, 0.6 * h], [-0.2 * h, -0.6 * h], [0.7 * h, -0.6 * h]])
    _line(ax, cup[:, 0], cup[:, 1], **kw)


def _draw_actuator(ax: Axes, name: str, a: np.ndarray, b: np.ndarray, tension: float, width: float,
                   label: bool, unit: str = "N") -> None:
    """Actuator from ``a`` to ``b``: a closed cylinder from ``a`` and a thinner rod to ``b``,
    labelled with its load in ``unit`` (tension: pulls its ends together; compression: pushes)."""
    from matplotlib.patches import Polygon

    frame = _along(a, b)
    if frame is None:
        return
    length, t, nrm = frame
    colour = "#6a3d9a"
    barrel = [a + w * width * nrm + s * length * t for s, w in ((0, 1), (0.55, 1), (0.55, -1), (0, -1))]
    _add(ax, Polygon(np.array(barrel), closed=True, facecolor="#cab2d6", edgecolor=colour, linewidth=1.3,
                         zorder=4, gid=f"actuator:{name}", label=name))
    _line(ax, *np.array([a + 0.45 * length * t, b]).T, color=colour, linewidth=2.4, solid_capstyle="butt", zorder=3.9)
    for end in (a, b):
        _draw_pin(ax, end, width)
    if label:
        sense = "tension" if tension > 0 else ("compression" if tension < 0 else "unloaded")
        at = a + 0.3 * length * t + 2.2 * width * nrm
        ax.text(at[0], at[1], f"{name} = {load_text(abs(tension), unit)} {sense}", ha="center", va="center", fontsize=9,
                color=colour, zorder=8, bbox=_LABEL_BOX, gid=f"load:{name}")


def load_text(value: float, unit: str) -> str:
    """A load for a label, three significant digits with an SI prefix on newtons: ``9.69 kN``, ``12.5 N m``,
    ``1.2 MN``, ``3.4 kN mm``; a load in other units (``"g mm/s^2"``) without one: ``1.2e+09 g mm/s^2``."""
    for factor, prefix in ((1e6, "M"), (1e3, "k")):
        if abs(value) >= factor and unit.split(" ")[0] == "N":
            return f"{value / factor:.3g} {prefix}{unit}"
    return f"{value:.3g} {unit}"


def _draw_moment(ax: Axes, name: str, p: np.ndarray, value: float, h: float, label: bool = True,
                 unit: str = "N m") -> None:
    """Curved arrow of 270 degrees around ``p`` (open below): counter-clockwise if ``value`` > 0; label |value| in
    ``unit``."""
    text = f"{name} = {load_text(abs(value), unit)}"
    r = _moment_radius(h)
    colour = "#d62728"
    if value != 0:
        phi = np.radians(np.linspace(-45.0, 225.0, 61))    # open at the bottom, where a ground symbol is
        if value < 0:
            phi = phi[::-1]
        arc = p + r * np.column_stack([np.cos(phi), np.sin(phi)])
        _line(ax, arc[:-3, 0], arc[:-3, 1], color=colour, linewidth=1.6, zorder=7, gid=f"moment:{name}",
                solid_capstyle="butt")
        ax.annotate("", xy=arc[-1], xytext=arc[-4], zorder=7,
                    arrowprops=dict(arrowstyle="-|>", color=colour, linewidth=1.6, mutation_scale=12,
                                    shrinkA=0, shrinkB=0))
    if not label:
        return
    at = p + 1.25 * r * np.array([math.cos(math.pi / 4), math.sin(math.pi / 4)])
    ax.text(at[0], at[1], text, ha="left", va="bottom", fontsize=9, color=colour, zorder=8, bbox=_LABEL_BOX,
            gid=f"load:{name}")


def _draw_force(ax: Axes, name: str, p: np.ndarray, v: np.ndarray, scale: float, h: float,
                label: bool = True, unit: str = "N") -> None:
    mag = float(np.hypot(*v))
    text = f"{name} = {load_text(mag, unit)}"
    if not label and (mag == 0 or scale == 0):
        return
    if mag == 0 or scale == 0:
        ax.text(p[0], p[1] + 1.5 * h, text, ha="center", va="bottom", fontsize=9, color="#d62728", zorder=8,
                bbox=_LABEL_BOX, gid=f"load:{name}")
        return
    tip = p + v * scale
    ax.annotate("", xy=(float(tip[0]), float(tip[1])), xytext=(float(p[0]), float(p[1])), zorder=7,
                arrowprops=dict(arrowstyle="-|>", color="#d62728", linewidth=1.8, mutation_scale=14,
                                shrinkA=0, shrinkB=0))
    if not label:
        return
    u = v / mag
    at = tip + 0.8 * h * u
    if abs(u[1]) >= abs(u[0]):
        ha, va = "center", ("bottom" if u[1] > 0 else "top")
    else:
        ha, va = ("left" if u[0] > 0 else "right"), "center"
    ax.text(at[0], at[1], text, ha=ha, va=va, fontsize=9, color="#d62728", zorder=8, bbox=_LABEL_BOX,
            gid=f"load:{name}")
