"""The README's images: three figures of ``mechcont paper``, drawn by the same code, and a record of what they show.

``mechcont paper --readme-images docs`` (``bash run.sh paper --readme-images docs``) draws them and writes them
into ``docs/`` with :data:`MANIFEST`, which holds each image's :func:`fingerprint`: a hash of what the figure
draws (every artist's kind, data rounded to three significant digits, colours, line styles, markers, texts), not
of its pixels, which differ between machines (fonts, Matplotlib's rasteriser). :func:`stale` redraws them and
names the images whose fingerprint changed: ``tests/test_figure_review.py`` asks that there be none, so a change
to the paper's figures or their data fails until the images are regenerated.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["README_IMAGES", "MANIFEST", "figures", "fingerprint", "write", "stale"]

#: The README's image files (in ``docs/``) and the paper figure each one is.
README_IMAGES = {"fig4c_sweep_on_branch.png": "fig4c_overcentre_LU0.4.png",
                 "fig4a_surface.png": "fig4a_overcentre_surface.png",
                 "nose_gear_design.png": "nose_gear_design.png"}
#: The record of the images' fingerprints, beside them.
MANIFEST = "readme-images.json"


def figures() -> dict[str, tuple[Figure, bool]]:
    """``{README image file: (figure, tight)}``: the figures drawn as ``mechcont paper`` draws them (``tight``: saved
    cropped to what is drawn, as the paper saves Fig. 4a)."""
    from . import nose_gear, overcentre
    from ._nose_gear_figures import design_map_figure

    r = overcentre.compute()
    return {"fig4c_sweep_on_branch.png": (overcentre.sweep_figure(r, 0.4), False),
            "fig4a_surface.png": (overcentre.fig4a_figure(r), True),
            "nose_gear_design.png": (design_map_figure(nose_gear.compute(dynamic=False)), False)}


def _rounded(values) -> bytes:
    """``values`` (any numeric array) rounded to three significant digits, as bytes (NaN and infinities kept)."""
    a = np.asarray(values, float).ravel()
    out = a.copy()
    finite = np.isfinite(a) & (a != 0)
    scale = 10.0 ** (np.floor(np.log10(np.abs(a[finite]))) - 2)
    out[finite] = np.round(a[finite] / scale) * scale
    return np.round(out, 12).tobytes()


def _content(artist) -> list[bytes]:
    """What ``artist`` draws, in data coordinates (never pixels: those depend on the fonts and the layout)."""
    from matplotlib.collections import Collection
    from matplotlib.colors import to_rgba_array
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    from matplotlib.text import Text

    label = artist.get_label()   # an Axis's is its label Text, whose repr holds its pixel position
    out = [type(artist).__name__.encode(), (label if isinstance(label, str) else "").encode()]
    if isinstance(artist, Text):
        out.append(artist.get_text().encode())
    elif isinstance(artist, Line2D):
        data = getattr(artist, "_verts3d", None)
        out += [_rounded(np.asarray(data, float) if data is not None else artist.get_xydata()),
                _rounded(to_rgba_array(artist.get_color())), str(artist.get_linestyle()).encode(),
                str(artist.get_marker()).encode(), _rounded([artist.get_linewidth(), artist.get_markersize()])]
    elif isinstance(artist, Collection):
        vec = getattr(artist, "_vec", None)   # a 3-D collection's own vertices (its paths are projected)
        if vec is None:
            offsets3d = getattr(artist, "_offsets3d", None)
            vec = offsets3d if offsets3d is not None else artist.get_offsets()
        paths = [] if getattr(artist, "_vec", None) is not None else [p.vertices for p in artist.get_paths()]
        out += [_rounded(np.asarray(vec, float)), *(_rounded(v) for v in paths),
                _rounded(artist.get_facecolor()), _rounded(artist.get_edgecolor())]
    elif isinstance(artist, Patch):
        out += [_rounded(artist.get_facecolor()), str(artist.get_hatch()).encode()]
    return out


def fingerprint(fig) -> str:
    """A hash (hex) of what ``fig`` draws: every visible artist's kind, label, text, data (three significant
    digits), colours, line style and marker, in drawing order, after a draw (3-D projections, tick labels)."""
    fig.draw_without_rendering()
    h = hashlib.sha256()
    for artist in fig.findobj(lambda a: a.get_visible()):
        for part in _content(artist):
            h.update(len(part).to_bytes(8, "little"))
            h.update(part)
    return h.hexdigest()


def write(folder) -> list[Path]:
    """Draw the README's images into ``folder`` (PNG, 150 dpi) and record their fingerprints in :data:`MANIFEST`
    there. Returns the files written."""
    from ..outputs.plotting import save_figure
    from ..outputs.tables import write_text

    folder = Path(folder)
    record, written = {}, []
    for name, (fig, tight) in figures().items():
        written.append(save_figure(fig, folder / name, tight=tight))
        record[name] = {"paper figure": README_IMAGES[name], "fingerprint": fingerprint(fig)}
    written.append(write_text(folder / MANIFEST, json.dumps(record, indent=2, sort_keys=True) + "\n"))
    return written


def stale(folder) -> list[str]:
    """The README images in ``folder`` whose recorded fingerprint is not that of the figure drawn now (or that are
    missing): empty when the images are current."""
    folder = Path(folder)
    try:
        record = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return list(README_IMAGES)
    return [name for name, (fig, _) in figures().items()
            if not (folder / name).is_file() or record.get(name, {}).get("fingerprint") != fingerprint(fig)]
