"""Pictures and animations of mechanisms from their :class:`~mechcont.equations.Scene`.

A model provides ``system.scene(x) -> Scene`` (coordinates in metres, forces in newtons);
this module draws it: bars as thick polylines, pins as small circles, ground pins with a
hatched ground symbol (a smaller one, facing away, where only springs or dampers are
anchored), sliders as a block in a short slot fixed to the ground at its ends (drawn
locally, never as a band across the view), slots in a body (pin-in-slot joints) as a channel
along the body, springs as zig-zag coils, torsion springs as a spiral and rotary dampers as an arc
with a dashpot around their joint, dampers as dashpots, actuators as a cylinder and rod
labelled with their load (N, tension or compression), forces as arrows labelled in newtons and
moments as curved arrows around their point (counter-clockwise for a positive value) labelled
in newton metres. :func:`draw` saves one configuration (PNG, SVG, PDF), animations along a
branch are in :mod:`mechcont.outputs.animation`.

Sizes of the symbols (pins, ground, coil width) are a fixed fraction of the view so that
every frame of an animation looks alike; force arrows are ``force_scale`` metres per newton.
Files are written to a temporary name and moved into place, so a failure leaves nothing.
Matplotlib is imported lazily and only the non-interactive Agg canvas is used.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy.typing as npt

from ._drawing_parts import (
    IMAGE_SUFFIXES,
    _atomic_write,
    _check_out,
    _check_x,
    _note,
    _note_corner,
    _put_note,
    _scene_of,
    body_colours,
    default_annotate,
    draw_scene,
    label_scene,
    load_text,
)
from .drawing3d import draw3d, is_spatial

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..continuation import SpecialPoint
    from ..equations import EquationSystem

__all__ = ["draw_scene", "draw", "label_scene", "default_annotate", "IMAGE_SUFFIXES", "body_colours", "load_text"]


def draw(system: EquationSystem, x: npt.ArrayLike | SpecialPoint, path: str | os.PathLike[str] | None = None, *,
         ax: Axes | None = None, title: str | None = None, show_forces: bool = True, force_scale: float | None = None,
         annotate: Sequence[str] = (), stable: bool | None = None, label: str = "",
         figsize: tuple[float, float] = (6, 4.5), dpi: int = 120, labels: bool = False,
         label_points: bool = False) -> Axes | dict[str, Axes]:
    """Draw ``system`` at the full variable vector ``x`` and optionally save it.

    Parameters
    ----------
    system:
        An :class:`~mechcont.equations.EquationSystem` with a ``scene``.
    x:
        Full variable vector ordered like ``system.names`` (SI units, radians), or a
        special point of a branch (``branch["LP1"]``: its ``.x``; its label is shown).
    path:
        Output file; its suffix picks the format: ``.png``, ``.svg`` or ``.pdf``.
    ax, title, show_forces, force_scale:
        As for :func:`draw_scene`.
    annotate:
        Variable names whose values are printed in a corner (angles in degrees).
    stable, label:
        Stability of the point and its special-point label (``"LP"`` ...), printed too.
    figsize, dpi:
        Figure size (inches) and resolution of a raster file.
    labels:
        Name every body and every named point (see :func:`draw_scene`).
    label_points:
        Name the named points too (a planar drawing: as ``labels``; a spatial one names its
        bodies in any case and its points only with this).

    Returns
    -------
    matplotlib.axes.Axes
        For a spatial mechanism (3-D scene, no ``ax`` given) the drawing is
        :func:`mechcont.outputs.drawing3d.draw3d`'s and this is its ``{view: axes}``.

    Raises
    ------
    InputError
        No scene for the model, a wrong-length or non-finite ``x``, an unknown annotated
        name, or an unknown file suffix.
    """
    out = _check_out(path, IMAGE_SUFFIXES) if path is not None else None
    scene_fn = _scene_of(system)
    if hasattr(x, "x") and hasattr(x, "label"):
        label = label or str(x.label)
        x = x.x
    x = _check_x(system, x)
    for name in annotate:
        system.index(name)
    if ax is None and is_spatial(scene_fn(x)):  # a spatial mechanism: three-view and 3-D view

        return draw3d(system, x, path, title=title, show_forces=show_forces, annotate=annotate, stable=stable,
                      label=label, dpi=dpi, label_points=label_points)
    from matplotlib.figure import Figure

    if ax is None:
        ax = Figure(figsize=figsize, layout="constrained").add_subplot()
    scene = scene_fn(x)
    # a load that is also annotated is printed once, signed, in the note; its arrow shows where it acts
    forces = {name: v for name, _, v in scene.forces if name in annotate}
    draw_scene(scene, ax, title=title or system.name, show_forces=show_forces, force_scale=force_scale,
               quiet_loads=list(forces))
    corner = _note_corner([scene], (*ax.get_xlim(), *ax.get_ylim()))
    _put_note(ax, _note(system, x, annotate, stable, label, forces=forces), stable, corner)
    if labels or label_points:
        label_scene(ax, scene)   # after the note, which the labels then keep clear of
    if out is not None:
        fig = ax.get_figure()
        assert isinstance(fig, Figure), "draw saves the figure of axes on a figure, not on a subfigure"
        _atomic_write(out, lambda tmp: fig.savefig(tmp, format=out.suffix[1:].lower(), dpi=dpi))
    return ax
