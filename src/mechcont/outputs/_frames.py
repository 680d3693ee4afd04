"""Frames of an animation drawn fast, and the files they are written to (GIF, HTML page, MP4).

The fixed parts of an animation's figure (axes, ticks, grid, titles, the branch in the panel
beside the mechanism) are the same in every frame, and drawing them (tick layout and text
above all) is what makes a full redraw slow. :class:`Compositor` draws them once, keeps that
image, and per frame draws only the artists that change over a copy of it (blitting on the Agg
canvas). The sinks take the frames as RGBA pixel arrays: a GIF is written by Pillow in one call
with one palette for all frames, an HTML page by Matplotlib's ``HTMLWriter`` page with each
frame encoded once as PNG (made offline: its icons inline SVG, no stylesheet from a CDN), an MP4
by piping the pixels to ffmpeg.
"""

from __future__ import annotations

import base64
import functools
import io
import math
import subprocess
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.backend_bases import RendererBase
    from matplotlib.figure import Figure
    from PIL.Image import Image

__all__ = ["Compositor", "gif_duration_ms", "gif_frame", "write_gif", "html_sink", "mp4_sink", "offline_player"]


class Compositor:
    """Draws a figure's fixed parts once and, per frame, the changing artists over them.

    Parameters
    ----------
    fig:
        A laid-out figure (its layout engine already set to none: the layout must not move).
    content_axes:
        3-D axes: their panes, grid, ticks and title are fixed like any axes' decorations, but
        their artists are projected, depth-sorted and drawn together by the axes' own ``draw``,
        so each frame draws such an axes with its fixed parts switched off.
    """

    def __init__(self, fig: Figure, content_axes: Sequence[Axes] = ()) -> None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        self.fig = fig
        self.canvas = FigureCanvasAgg(fig)
        self.content_axes = list(content_axes)
        self._background: object | None = None  # the Agg canvas's saved region

    def draw_background(self, hidden: Sequence[Artist]) -> None:
        """Draw and keep the fixed image: the figure without the ``hidden`` artists."""
        with _hidden(hidden):
            self.canvas.draw()
        self._background = self.canvas.copy_from_bbox(self.fig.bbox)

    def order(self, artists: Sequence[Artist]) -> list[Artist]:
        """``artists`` in the order a full draw paints them: axes by axes, by zorder, ties in the order they
        were added (an axes' legend comes after its artists of equal zorder); a content axes stands for all
        its artists."""
        axes = self.fig.axes
        rank = {id(a): k for k, a in enumerate(artists)}
        chosen = [a for a in artists if a.axes not in self.content_axes]
        chosen += [ax for ax in self.content_axes if any(a.axes is ax for a in artists)]
        return sorted(chosen, key=lambda a: (axes.index(a.axes) if a.axes in axes else len(axes), a.zorder,
                                             rank.get(id(a), -1)))

    def frame(self, artists: Sequence[Artist]) -> np.ndarray:
        """The RGBA pixels (height, width, 4; uint8) of the fixed image with ``artists`` drawn over it: a view
        of the canvas, valid until the next frame is drawn."""
        if self._background is None:
            raise RuntimeError("draw_background first")
        self.canvas.restore_region(self._background)
        renderer = self.canvas.get_renderer()
        for a in self.order(artists):
            if a in self.content_axes:
                _draw_content(a, renderer)
            else:
                a.draw(renderer)
        return np.asarray(self.canvas.buffer_rgba())

    def full_frame(self) -> np.ndarray:
        """The RGBA pixels of a full redraw of the figure as it stands (what :meth:`frame` stands in for)."""
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())


class _hidden:
    """Context: ``artists`` invisible inside, as they were after."""

    def __init__(self, artists: Sequence[Artist]) -> None:
        self.artists = list(artists)
        self.was = [a.get_visible() for a in self.artists]

    def __enter__(self) -> None:
        for a in self.artists:
            a.set_visible(False)

    def __exit__(self, *exc: object) -> None:
        for a, v in zip(self.artists, self.was):
            a.set_visible(v)


def _draw_content(ax: Axes, renderer: RendererBase) -> None:
    """Draw a 3-D axes' artists only (projected and depth-sorted by its ``draw``): background patch, panes,
    grid, ticks and title switched off, as they are already in the fixed image."""
    ax.set_axis_off()
    try:
        with _hidden([ax.patch, ax.title]):  # the left and right titles are empty
            ax.draw(renderer)
    finally:
        ax.set_axis_on()


def gif_duration_ms(fps: float, hold: float) -> int:
    """A GIF frame's duration (ms): ``1/fps`` plus ``hold`` seconds, rounded up to the format's 10 ms steps
    (so that the animation lasts at least its length)."""
    return 10 * math.ceil(round(100.0 / fps + 100.0 * hold, 6))


def gif_frame(rgba: np.ndarray) -> Image:
    """An opaque RGBA frame as a Pillow RGB image (a copy), as :func:`write_gif` takes it."""
    from PIL import Image

    height, width = rgba.shape[:2]
    return Image.frombytes("RGB", (width, height), np.ascontiguousarray(rgba), "raw", "RGBX", 0, 1)


#: Palette entries given to the most frequent exact colours of a GIF (the background, the bars, the text).
_EXACT_COLOURS = 64
#: Blend entries within this many levels (in any channel) of an exact colour are dropped (see write_gif).
_NEAR = 10


def write_gif(path: str | Path, frames: Sequence[Image], durations: Sequence[int]) -> None:
    """Write ``frames`` (Pillow RGB images of one size) as a looping GIF, frame ``k`` shown ``durations[k]`` ms.

    All frames share one palette: quantizing each frame on its own is most of a GIF's writing time,
    and one palette keeps a colour from flickering between frames. Its first entries are the most
    frequent colours exactly (a median cut alone would average white with the greys near it into a
    grey background), the rest a median cut of every frame's pixels (a regular sample), for the
    antialiased blends; frames are mapped to it without dithering.
    """
    from PIL import Image

    if not frames:
        raise ValueError("no frames to write")
    width, height = frames[0].size
    # about 300 000 sampled pixels in all, every frame's own pixels (not averages) on a regular grid
    step = max(1, math.isqrt(len(frames) * width * height // 300_000))
    tiles = [f.resize((max(1, width // step), max(1, height // step)), Image.Resampling.NEAREST) for f in frames]
    sample = Image.new("RGB", (tiles[0].width, tiles[0].height * len(tiles)))
    for k, tile in enumerate(tiles):
        sample.paste(tile, (0, k * tile.height))
    pixels = np.asarray(sample, dtype=np.uint32).reshape(-1, 3)
    keys, counts = np.unique((pixels[:, 0] << 16) | (pixels[:, 1] << 8) | pixels[:, 2], return_counts=True)
    exact_rgb: list[np.ndarray] = []
    for key in keys[np.argsort(counts, kind="stable")[::-1]]:  # most frequent first; a shade beside one is not kept
        rgb = np.array([(key >> 16) & 255, (key >> 8) & 255, key & 255], np.int32)
        if all(np.abs(rgb - c).max() > _NEAR for c in exact_rgb):
            exact_rgb.append(rgb)
            if len(exact_rgb) == _EXACT_COLOURS:
                break
    exact = np.array(exact_rgb, np.int32)
    blends = sample.quantize(256 - len(exact), method=Image.Quantize.MEDIANCUT).getpalette() or []
    blend_rgb = np.asarray(blends[: 3 * (256 - len(exact))], np.int32).reshape(-1, 3)
    # Pillow maps a pixel through a cache of 4-level cells, to the entry nearest the cell, not the pixel: a
    # blend entry beside an exact colour (a near-white) would take the exact colour's pixels (white). Away
    # from every exact colour by more than a cell's diagonal (5.2 levels) plus a cell, none can.
    gap = np.abs(blend_rgb[:, None, :] - exact[None, :, :]).max(axis=2).min(axis=1)
    colours = np.concatenate([exact, blend_rgb[gap > _NEAR]]).astype(np.uint8).ravel()
    palette = Image.new("P", (1, 1))
    palette.putpalette(np.resize(colours, 768).tolist())  # padded with repeats of the first entries
    images = [f.quantize(palette=palette, dither=Image.Dither.NONE) for f in frames]
    images[0].save(path, format="GIF", save_all=True, append_images=images[1:], duration=list(durations), loop=0)


def _png_base64(rgba: np.ndarray) -> str:
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(rgba[..., :3]).save(buf, format="png", compress_level=3)  # level 6: +40 % time for -1.5 % size
    return base64.encodebytes(buf.getvalue()).decode("ascii")


class FrameSink(Protocol):
    """A Matplotlib movie writer fed with ready pixels: inside ``saving(fig, outfile, dpi)``, ``add(rgba, repeats)``
    appends a frame (RGBA pixels of the figure's size) ``repeats`` times."""

    def saving(self, fig: Figure, outfile: str | Path, dpi: float | None, *args: Any,
               **kwargs: Any) -> AbstractContextManager[object]: ...

    def add(self, rgba: np.ndarray, repeats: int = 1) -> None: ...


@functools.cache
def _html_class() -> Callable[..., FrameSink]:
    from matplotlib import animation

    class HtmlSink(animation.HTMLWriter):
        """Matplotlib's HTML page (frames embedded, play controls) fed with ready pixels: ``add`` keeps
        ``HTMLWriter.grab_frame``'s bookkeeping (base64 PNG per frame, the size limit), minus the redraw."""

        _saved_frames: list[str]
        _total_bytes: int
        _bytes_limit: float
        _hit_limit: bool

        def add(self, rgba: np.ndarray, repeats: int = 1) -> None:
            """Append a frame (RGBA pixels), ``repeats`` times (a held frame), each encoded once as PNG."""
            if self._hit_limit:
                return
            data = _png_base64(rgba)
            for _ in range(repeats):
                self._total_bytes += len(data)
                if self._total_bytes >= self._bytes_limit:
                    self._hit_limit = True  # as HTMLWriter does: this and later frames are dropped
                    return
                self._saved_frames.append(data)

        def finish(self) -> None:
            """Write the page as ``HTMLWriter.finish`` does, offline: its player script and styles inline, its
            buttons' icons inline SVG (:func:`offline_player`) instead of Font Awesome from a CDN."""
            import uuid

            from matplotlib import _animation_data as page

            modes = dict.fromkeys(("once_checked", "loop_checked", "reflect_checked"), "")
            modes[self.default_mode + "_checked"] = "checked"
            player = page.DISPLAY_TEMPLATE.format(id=uuid.uuid4().hex, Nframes=len(self._saved_frames),
                                                  fill_frames=_frames_js(self._saved_frames, self.frame_format),
                                                  interval=1000 // self.fps, **modes)
            with open(self.outfile, "w", encoding="utf-8") as f:
                f.write(offline_player(page.JS_INCLUDE + page.STYLE_INCLUDE + player))

    return HtmlSink


def _frames_js(frames: Sequence[str], fmt: str) -> str:
    """The player's script lines filling its ``frames`` array with the base64 ``frames`` as ``data:`` URIs."""
    return "\n" + "".join(f'  frames[{i}] = "data:image/{fmt};base64,' + data.replace("\n", "\\\n") + '"\n'
                          for i, data in enumerate(frames))


#: The player's button icons (Font Awesome's names in Matplotlib's page) as 16 x 16 SVG paths.
_ICONS = {
    "fa-minus": "M3 7h10v2H3z", "fa-plus": "M7 3h2v4h4v2H9v4H7V9H3V7h4z",
    "fa-fast-backward": "M15 2L9 8l6 6zM9 2L3 8l6 6zM1 2h2v12H1z", "fa-step-backward": "M13 2L5 8l8 6zM3 2h2v12H3z",
    "fa-play fa-flip-horizontal": "M12 2L2 8l10 6z", "fa-pause": "M3 2h4v12H3zM9 2h4v12H9z", "fa-play": "M4 2l10 6-10 6z",
    "fa-step-forward": "M3 2l8 6-8 6zM11 2h2v12h-2z", "fa-fast-forward": "M1 2l6 6-6 6zM7 2l6 6-6 6zM13 2h2v12h-2z",
}


def offline_player(text: str) -> str:
    """Matplotlib's animation page ``text`` made to work offline: a full HTML document without the stylesheet
    ``<link>`` (Font Awesome from a CDN), each ``<i class="fa ...">`` icon an inline SVG (its title stays on
    the button); a ``ValueError`` names an icon it does not know (a newer Matplotlib's)."""
    import re

    def icon(m: re.Match[str]) -> str:
        name = m.group(1).removeprefix("fa ").strip()
        if name not in _ICONS:
            raise ValueError(f"no offline icon for Matplotlib's {name!r}")
        return (f'<svg width="14" height="14" viewBox="0 0 16 16" aria-hidden="true" style="vertical-align:middle">'
                f'<path fill="currentColor" d="{_ICONS[name]}"/></svg>')

    body = re.sub(r"<link\b[^>]*>", "", text)
    body = re.sub(r'<i class="(fa [^"]+)"></i>', icon, body)
    return ('<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>mechcont animation</title></head>'
            f"<body>\n{body}\n</body></html>\n")


def html_sink(fps: float) -> FrameSink:
    """An ``HTMLWriter`` (frames embedded as PNG, at most 200 MB) with ``add(rgba, repeats)``; its page works
    offline (:func:`offline_player`)."""
    return _html_class()(fps=fps, embed_frames=True, embed_limit=200)


@functools.cache
def _mp4_class() -> Callable[..., FrameSink]:
    from matplotlib import animation

    class Mp4Sink(animation.FFMpegWriter):
        """Matplotlib's ffmpeg pipe fed with ready pixels instead of a redraw per frame (what
        ``MovieWriter.grab_frame`` writes to the pipe: the figure's RGBA pixels)."""

        _proc: subprocess.Popen

        def add(self, rgba: np.ndarray, repeats: int = 1) -> None:
            """Send a frame (RGBA pixels of the figure's size), ``repeats`` times."""
            data = np.ascontiguousarray(rgba).tobytes()
            pipe = self._proc.stdin
            if pipe is None:
                raise RuntimeError("ffmpeg is not running: add frames inside saving()")
            for _ in range(repeats):
                pipe.write(data)

    return Mp4Sink


def mp4_sink(fps: float) -> FrameSink:
    """An ``FFMpegWriter`` (rgba frames through a pipe) with ``add(rgba, repeats)``."""
    return _mp4_class()(fps=fps)
