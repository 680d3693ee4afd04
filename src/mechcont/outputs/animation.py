"""Animations of mechanisms along a continuation branch (GIF, or MP4 with ffmpeg).

The rows of a branch (a :class:`~mechcont.continuation.Branch`, its CSV table or plain
rows of full variable vectors) become :class:`BranchFrames`; :func:`animate` draws each
with :mod:`mechcont.outputs.drawing` in one fixed view, annotated with the continuation
parameter (with units, degrees for angles), chosen variables, stability and label, and
optionally beside the bifurcation diagram with the current point marked.
"""

from __future__ import annotations

import csv
import functools
import math
import os
import shutil
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..errors import InputError
from . import drawing as _d

__all__ = ["animate", "BranchFrames", "branch_frames", "check_fps", "frame_rows", "default_fps",
           "ANIMATION_SUFFIXES", "FPS_RANGE", "MIN_DURATION", "MAX_FPS", "HOLD"]

ANIMATION_SUFFIXES = (".gif", ".mp4", ".html")



@dataclass(frozen=True)
class BranchFrames:
    """Points of a branch ready to _d.draw.

    Attributes
    ----------
    values:
        Array (N, n_names), rows are full variable vectors ordered like ``system.names``.
    stable:
        Per row ``True`` (stable), ``False`` (unstable) or ``None`` (not known).
    labels:
        Special-point label per row (``"LP"``, ``"BP"``, ... or ``""``).
    vary:
        The continuation parameter, printed first on every frame: the ``Branch``'s
        ``vary``, or for a table without it the one parameter that changes along the rows
        (``None`` when that is not unique).
    """

    values: np.ndarray
    stable: tuple[bool | None, ...]
    labels: tuple[str, ...]
    vary: str | None = None

    @property
    def numbered_labels(self) -> list[str]:
        """Labels numbered per kind in branch order (``LP1``, ``LP2``), as ``row`` accepts them."""
        return _numbered(self.labels)

    def row(self, spec: str | int) -> int:
        """Row index from an integer (0-based, negative from the end) or a label like ``"LP2"``.

        ``"LP2"`` is the second row labelled ``LP`` (``"LP"`` alone: the first); an
        :class:`InputError` names what is valid.
        """
        n = len(self.values)
        text = str(spec).strip()
        if len(text) > 32:  # no branch has rows or labels numbered beyond 32 digits
            raise InputError("point", f"no row '{text[:20]}...'; give a row number 0..{n - 1} or a label with its "
                                      "number (e.g. LP1)")
        try:
            i = int(text)
        except ValueError:
            text = text.rstrip("?")  # LP1? (an approximate fold) is LP1
            kind = text.rstrip("0123456789")
            count = int(text[len(kind):] or 1)
            hits = [j for j, lab in enumerate(self.labels) if lab.rstrip("?") == kind]
            if not kind or count < 1 or count > len(hits):
                have = sorted({lab.rstrip("?") for lab in self.labels if lab})
                raise InputError("point", f"no row '{text}'; give a row number 0..{n - 1} or a label "
                                          f"({', '.join(have) or 'this branch has none'}) with its number") from None
            return hits[count - 1]
        if not -n <= i < n:
            raise InputError("point", f"row {i} out of range; the branch has {n} rows (0..{n - 1})")
        return i % n


def _numbered(labels: Sequence[str]) -> list[str]:
    """``["LP", "", "LP?"]`` -> ``["LP1", "", "LP2?"]``: the names ``branch["LP2"]`` and ``--point`` use.

    A ``?`` (a special point only approximately located) keeps its place in the numbering.
    """
    seen: dict[str, int] = {}
    out = []
    for lab in labels:
        if lab:
            kind, mark = lab.rstrip("?"), "?" if lab.endswith("?") else ""
            seen[kind] = seen.get(kind, 0) + 1
            lab = f"{kind}{seen[kind]}{mark}"
        out.append(lab)
    return out


#: Words of the ``stability`` column: a fold (``LP`` row) is neutral, neither stable nor unstable.
_STABILITY_WORDS = {"stable": True, "unstable": False, "fold": None, "": None}


def _columns(path: Path, header: list[str], system) -> dict[str, tuple[str, float]]:
    """``{name: (header, factor to SI)}`` from headers ``name [unit]`` (or bare names, as
    tables were written before units). A unit must be the model's; an angle may be in ``deg``."""
    from ..continuation._branch import read_csv_header

    out: dict[str, tuple[str, float]] = {}
    for h in header:
        name, unit = read_csv_header(h or "")
        factor = 1.0
        if unit and name in system.names:
            want = system.variable(name).unit
            if unit == "deg" and want == "rad":
                factor = math.pi / 180.0
            elif unit != want:
                raise InputError("branch", f"'{path}' column '{h}': the unit of {name} in model '{system.name}' is "
                                           f"'{want or 'none'}', not '{unit}'")
        out.setdefault(name, (h, factor))
    return out


def _read_csv(system, path: Path) -> BranchFrames:
    try:
        with open(path, newline="") as fh:
            reader = csv.DictReader(fh)
            rows = list(reader)
            header = list(reader.fieldnames or [])
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InputError("branch", f"cannot read '{path}': {getattr(exc, 'strerror', None) or exc}") from None
    if not rows:
        raise InputError("branch", f"'{path}' has no rows")
    repeated = sorted({h for h in header if header.count(h) > 1})
    if repeated:  # DictReader would keep the last of them silently
        raise InputError("branch", f"'{path}' has the column(s) {', '.join(map(repr, repeated))} more than once")
    cols = _columns(path, header, system)
    missing = [n for n in system.names if n not in cols]
    if missing:
        raise InputError("branch", f"'{path}' lacks the column(s) {', '.join(missing)} of model '{system.name}'")
    values = np.empty((len(rows), len(system.names)))
    for r, row in enumerate(rows):
        for c, name in enumerate(system.names):
            key, factor = cols[name]
            try:
                values[r, c] = float(row[key]) * factor
            except (TypeError, ValueError):
                raise InputError("branch", f"'{path}' line {r + 2}, column {key}: not a number: {row[key]!r}") from None

    def cell(row, name):
        key = cols.get(name, (name, 1.0))[0]
        return (row.get(key) or "").strip()

    stable = []
    for r, row in enumerate(rows):
        word = cell(row, "stability").lower()
        if word not in _STABILITY_WORDS:
            raise InputError("branch", f"'{path}' line {r + 2}, column stability: {word!r} is not stable, unstable "
                                       "or fold")
        stable.append(_STABILITY_WORDS[word])
    for r, row in enumerate(rows):
        _check_extra_cells(path, r, cell(row, "s"), cell(row, "n_unstable"))
    labels = tuple(cell(row, "label") for row in rows)
    vary = cell(rows[0], "vary") or None  # written by Branch.to_csv
    if vary is not None and vary not in system.names:
        raise InputError("branch", f"'{path}' column vary: '{vary}' is not a variable of '{system.name}'")
    return BranchFrames(values, tuple(stable), labels, vary)


def _check_extra_cells(path: Path, r: int, s: str, n_unstable: str) -> None:
    """A branch table's ``s`` (arclength: a finite number) and ``n_unstable`` (a count of unstable
    directions, -1 for not evaluated) when present; InputError naming the line otherwise."""
    if s:
        try:
            ok = math.isfinite(float(s))
        except ValueError:
            ok = False
        if not ok:
            raise InputError("branch", f"'{path}' line {r + 2}, column s: {s!r} is not a finite number (arclength)")
    if n_unstable:
        try:
            k = int(n_unstable)
        except ValueError:
            k = -2
        if k < -1:
            raise InputError("branch", f"'{path}' line {r + 2}, column n_unstable: {n_unstable!r} is not a count of "
                                       "unstable directions (0, 1, 2, ...; -1 for not evaluated)")


def _changing_parameter(system, values: np.ndarray) -> str | None:
    """The only parameter whose column is not constant along ``values``, else ``None``."""
    changing = []
    for i, v in enumerate(system.variables):
        col = values[:, i]
        if v.kind == "parameter" and np.ptp(col) > 1e-12 * max(1.0, float(np.max(np.abs(col)))):
            changing.append(v.name)
    return changing[0] if len(changing) == 1 else None


def branch_frames(system, source) -> BranchFrames:
    """The rows of a branch to _d.draw, from any of the forms a branch comes in.

    Parameters
    ----------
    system:
        The model the branch belongs to.
    source:
        A :class:`BranchFrames`, a continuation ``Branch`` (``.values``, ``.labels``, ``.n_unstable`` with -1 for
        not evaluated), a path to a branch CSV (one column per variable name, optional
        ``stability`` with ``stable``/``unstable``/empty and ``label``; other columns such
        as ``s`` are ignored), or an array of rows ordered like ``system.names``.

    Returns
    -------
    BranchFrames
        With ``vary`` from the ``Branch``, or else the one parameter that changes along the rows.

    Raises
    ------
    InputError
        Unreadable file, missing columns, wrong row length, non-finite values.
    """
    if isinstance(source, BranchFrames):
        frames = source
    elif isinstance(source, (str, os.PathLike)):
        frames = _read_csv(system, Path(source))
    elif hasattr(source, "values") and not isinstance(source, np.ndarray):
        names = getattr(source, "names", None)
        if names is not None and tuple(names) != tuple(system.names):
            raise InputError("branch", f"its variables are not those of model '{system.name}'")
        values = np.asarray(source.values, dtype=float)
        nu = getattr(source, "n_unstable", None)
        stable = (None,) * len(values) if nu is None else tuple(None if k < 0 else bool(k == 0) for k in nu)
        labels = getattr(source, "labels", None)
        vary = getattr(source, "vary", None)
        frames = BranchFrames(values, stable, tuple(labels) if labels is not None else ("",) * len(values),
                              vary if vary in system.names else None)
    else:
        values = np.asarray(source, dtype=float)
        n = len(values) if values.ndim else 0
        frames = BranchFrames(values, (None,) * n, ("",) * n)
    v = frames.values
    if v.ndim != 2 or v.shape[1] != len(system.names):
        raise InputError("branch", f"rows must hold the {len(system.names)} variables of '{system.name}', "
                                   f"got shape {v.shape}")
    if len(v) == 0:
        raise InputError("branch", "the branch has no points")
    if not np.all(np.isfinite(v)):
        raise InputError("branch", f"row {int(np.where(~np.isfinite(v).all(axis=1))[0][0])} has a non-finite value")
    if len(frames.stable) != len(v) or len(frames.labels) != len(v):
        raise InputError("branch", "stability and labels must have one entry per row")
    if frames.vary is not None and frames.vary not in system.names:
        raise InputError("vary", f"'{frames.vary}' is not a variable of '{system.name}'")
    if frames.vary is None:
        frames = replace(frames, vary=_changing_parameter(system, v))
    return frames


#: Frame rates that make sense (frames per second): a GIF stores each frame's duration in
#: hundredths of a second (at most 655.35 s), and players show at most 100 frames a second.
FPS_RANGE = (0.01, 100.0)


def check_fps(fps) -> float:
    """``fps`` as a float within :data:`FPS_RANGE`, else :class:`InputError`."""
    lo, hi = FPS_RANGE
    if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not math.isfinite(fps) or fps <= 0:
        raise InputError("fps", f"must be a positive number, not {fps!r}")
    if not lo <= fps <= hi:
        raise InputError("fps", f"{fps:g} frames per second is outside {lo:g}..{hi:g} (a frame lasts at most "
                                f"{1 / lo:g} s and at least {1 / hi:g} s)")
    return float(fps)


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


def _writer(out: Path, fps: float):
    from matplotlib import animation

    suffix = out.suffix.lower()
    if suffix == ".gif":
        return _GifWriter(fps=fps)
    if suffix in (".html", ".htm"):
        return animation.HTMLWriter(fps=fps, embed_frames=True, embed_limit=200)
    if shutil.which("ffmpeg") is None or not animation.writers.is_available("ffmpeg"):
        raise InputError("out", "writing .mp4 needs ffmpeg, which is not installed; write a .gif (or .html) instead")
    return animation.FFMpegWriter(fps=fps)


@functools.cache
def _gif_writer_class():
    from matplotlib import animation

    class GifWriter(animation.PillowWriter):
        """Pillow GIF writer with a duration per frame (special points are held longer)."""

        def setup(self, fig, outfile, dpi=None):
            super().setup(fig, outfile, dpi=dpi)
            self._durations: list[int] = []

        def grab_frame(self, hold: float = 0.0, **savefig_kwargs):
            super().grab_frame(**savefig_kwargs)
            # a GIF stores durations in 10 ms steps: round up, so that the animation lasts at least its length
            self._durations.append(10 * math.ceil(round(100.0 / self.fps + 100.0 * hold, 6)))

        def finish(self):
            if not self._frames:  # interrupted before the first frame: nothing to write (the error propagates)
                return
            self._frames[0].save(self.outfile, save_all=True, append_images=self._frames[1:],
                                 duration=self._durations, loop=0)

    return GifWriter


def _GifWriter(fps: float):
    return _gif_writer_class()(fps=fps)


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


def _diagram(ax, system, frames: BranchFrames, names: tuple[str, str]):
    """Branch projected on ``names`` (x, y): stable solid, unstable dashed, labels marked."""
    (xn, yn) = names
    xs, ys = (frames.values[:, system.index(n)] for n in names)
    conv = [math.degrees(1) if system.variable(n).unit == "rad" else 1.0 for n in names]
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
        ax.legend(fontsize=8, loc="best")
    for i, lab in enumerate(_numbered(frames.labels)):
        if lab:
            ax.plot(xs[i], ys[i], "k.", markersize=5)
            ax.annotate(lab, (xs[i], ys[i]), textcoords="offset points", xytext=(3, 3), fontsize=8)
    units = ["deg" if system.variable(n).unit == "rad" else system.variable(n).unit for n in names]
    ax.set_xlabel(f"{xn} ({units[0]})" if units[0] else xn)
    ax.set_ylabel(f"{yn} ({units[1]})" if units[1] else yn)
    ax.grid(True, linewidth=0.3, alpha=0.5)
    (marker,) = ax.plot([], [], "o", color="#d62728", markersize=8, zorder=5)
    return marker, xs, ys


def _slider_spans(scenes, h: float):
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


def _planar_renderer(system, frames, rows, scenes, annotate, labels, *, title, show_forces, diagram, figsize):
    """Figure and ``render(k)`` drawing frame ``k`` of a planar mechanism (one fixed view, optional diagram)."""
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
    fig = Figure(figsize=figsize, layout="constrained")
    if diagram:
        ax, dax = fig.subplots(1, 2, width_ratios=(mech_w, 6.0))
        marker, dx, dy = _diagram(dax, system, frames, tuple(diagram))
    else:
        ax = fig.add_subplot()

    def render(k: int) -> None:
        i = rows[k]
        ax.clear()
        _d.draw_scene(scenes[k], ax, title=title or system.name, show_forces=show_forces, force_scale=scale,
                      limits=limits, slider_spans=spans, quiet_loads=annotate)
        _d._put_note(ax, _d._note(system, frames.values[i], annotate, frames.stable[i], labels[i]), frames.stable[i],
                     corner)
        if diagram:
            marker.set_data([dx[i]], [dy[i]])

    return fig, render


def _spatial_renderer(system, frames, rows, scenes, annotate, labels, *, title, show_forces, diagram, figsize):
    """Figure and ``render(k)`` for a spatial mechanism: front, side, top and 3-D views (fixed for every
    frame) and, with ``diagram``, the branch with the current point in place of the top view."""
    from matplotlib.figure import Figure

    from . import drawing3d as _d3

    views = ("front", "side", "diagram", "3d") if diagram else ("front", "side", "top", "3d")
    frame = _d3._Frame(scenes, [v for v in views if v != "diagram"], show_forces)
    fig = Figure(figsize=figsize or (11.0, 9.0), layout="constrained")
    axes = {v: fig.add_subplot(2, 2, k + 1, **({"projection": "3d"} if v == "3d" else {}))
            for k, v in enumerate(views)}
    if diagram:
        marker, dx, dy = _diagram(axes.pop("diagram"), system, frames, tuple(diagram))

    def render(k: int) -> None:
        i = rows[k]
        frame.render(axes, scenes[k], labels=True, title=title or system.name, quiet_loads=annotate)
        _d._put_note(axes["front"], _d._note(system, frames.values[i], annotate, frames.stable[i], labels[i]),
                     frames.stable[i])
        if diagram:
            marker.set_data([dx[i]], [dy[i]])

    return fig, render


def animate(system, branch, path: str | os.PathLike, fps: float | None = None, every: int = 1,
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
        An :class:`~mechcont.equations.EquationSystem` with a ``scene``.
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
    if not (isinstance(hold, (int, float)) and math.isfinite(hold) and 0 <= hold <= 60):
        raise InputError("hold", f"must be a number of seconds between 0 and 60, not {hold!r}")
    if tuple(annotate) == _d._DEFAULT_ANNOTATE:
        annotate = _d.default_annotate(system)
    for name in (*annotate, *(diagram or ()), *([vary] if vary is not None else [])):
        system.index(name)
    if diagram is not None and len(diagram) != 2:
        raise InputError("diagram", "give exactly two variable names (x, y)")
    frames = branch_frames(system, branch)
    rows = frame_rows(frames, every)
    fps = default_fps(len(rows)) if fps is None else float(fps)
    writer = _writer(out, fps)
    annotate = _d._with_vary(vary or frames.vary, annotate)
    scenes = [scene_fn(frames.values[i]) for i in rows]
    labels = _numbered(frames.labels)
    if scenes[0].dimension == 3:
        fig, render = _spatial_renderer(system, frames, rows, scenes, annotate, labels, title=title,
                                        show_forces=show_forces, diagram=diagram, figsize=figsize)
    else:
        fig, render = _planar_renderer(system, frames, rows, scenes, annotate, labels, title=title,
                                       show_forces=show_forces, diagram=diagram, figsize=figsize)

    # Lay the figure out once (the view is fixed, so every frame has the same layout).
    render(0)
    fig.draw_without_rendering()
    fig.set_layout_engine("none")
    repeats = int(round(hold * fps))
    gif = isinstance(writer, _gif_writer_class())

    def write(tmp: str) -> None:
        with writer.saving(fig, tmp, dpi):
            for k in range(len(scenes)):
                render(k)
                held = bool(labels[rows[k]])
                if gif:  # a GIF holds a frame by its duration
                    writer.grab_frame(hold=hold if held else 0.0)
                else:  # MP4 and HTML have one frame rate: the frame is repeated
                    for _ in range(1 + (repeats if held else 0)):
                        writer.grab_frame()
                if on_frame is not None:
                    on_frame()

    _d._atomic_write(out, write)
    return len(scenes)
