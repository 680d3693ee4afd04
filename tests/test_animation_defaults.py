"""Animations made for a human: long enough, wide enough, every special point shown and held, labels off the
mechanism, ground drawn locally, an HTML page for notebooks; frames drawn fast (fixed parts once) that show
what a full redraw shows, a special point's frame naming its values."""

import matplotlib

matplotlib.use("Agg")

import base64  # noqa: E402
import io  # noqa: E402
import math  # noqa: E402
import os  # noqa: E402
import re  # noqa: E402
import stat  # noqa: E402

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium  # noqa: E402
from mechcont.models import build_overcentre  # noqa: E402
from mechcont.outputs import _drawing_parts, _frames, drawing  # noqa: E402
from mechcont.outputs import animation as anim  # noqa: E402
from mechcont.outputs.animation import HOLD, MIN_DURATION, animate, branch_frames, frame_rows  # noqa: E402


@pytest.fixture(scope="module")
def overcentre():
    return build_overcentre(LU=0.4)


@pytest.fixture(scope="module")
def branch(overcentre):
    x0 = find_equilibrium(overcentre, hold={"theta1": 0.3}, free=["F"])
    return continuation(overcentre, x0, "F", options=ContinuationOptions(bounds={"F": (-90, 110), "theta1": (-1.5, 1.5)}))


@pytest.mark.slow
def test_defaults_last_six_seconds_hold_special_points_and_are_800_px_wide(tmp_path, overcentre, branch):
    out = tmp_path / "a.gif"
    n = animate(overcentre, branch, out, every=7, diagram=("F", "theta1"))
    rows = frame_rows(branch_frames(overcentre, branch), 7)
    assert n == len(rows) and {p.index for p in branch.special_points} <= set(rows)
    with Image.open(out) as im:
        assert im.size[0] >= 800 and im.n_frames == n
        durations = []
        for k in range(im.n_frames):
            im.seek(k)
            durations.append(im.info["duration"])
    assert sum(durations) >= 1000 * MIN_DURATION
    held = [d for d, i in zip(durations, rows) if branch.labels[i]]
    plain = [d for d, i in zip(durations, rows) if not branch.labels[i]]
    assert len(held) == len(branch.special_points)
    assert min(held) - max(plain) >= 1000 * HOLD - 20  # GIF durations are in 10 ms steps


def test_no_label_over_the_mechanism_and_a_local_slider_guide(overcentre, branch, monkeypatch):
    """The force printed in the note is not written again beside its arrow; the slider guide spans the
    slider's travel, not the view."""
    texts = []
    real = _drawing_parts.draw_scene

    def spy(scene, ax, **kw):
        out = real(scene, ax, **kw)
        texts.append([t.get_text() for t in ax.texts])
        guides = [ln for ln in ax.lines if ln.get_gid() == "slider-guide"]
        xs = np.concatenate([ln.get_xdata() for ln in guides])
        travel = [float(s.sliders[0][0][0]) for s in scenes]
        h = _drawing_parts._SYMBOL * max(np.diff(ax.get_xlim())[0], np.diff(ax.get_ylim())[0])
        assert xs.min() >= min(travel) - 4.5 * h and xs.max() <= max(travel) + 4.5 * h
        return out

    rows = frame_rows(branch_frames(overcentre, branch), 10)
    scenes = [overcentre.scene(branch.values[i]) for i in rows]
    monkeypatch.setattr(_drawing_parts, "draw_scene", spy)
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        animate(overcentre, branch, f"{d}/a.gif", every=10, figsize=(4, 3), dpi=30)
    assert texts and all(not any(t.startswith("F = ") for t in frame) for frame in texts)


def test_a_single_drawing_has_a_short_slider_guide(overcentre, branch):
    ax = drawing.draw(overcentre, branch["LP1"])
    guides = [ln for ln in ax.lines if ln.get_gid() == "slider-guide"]
    assert len(guides) == 2
    width = np.diff(ax.get_xlim())[0]
    assert all(np.ptp(ln.get_xdata()) < 0.35 * width for ln in guides)


def test_html_page_for_notebooks(tmp_path, overcentre, branch):
    out = tmp_path / "a.html"
    n = animate(overcentre, branch, out, every=20, figsize=(4, 3), dpi=30)
    text = out.read_text()
    assert "<script" in text and text.count("data:image/png") >= n


def test_cli_animation_is_quiet_off_a_terminal(tmp_path, branch):
    from cli_helpers import make_runner

    path = branch.to_csv(tmp_path / "b.csv")
    r = make_runner()("animate", "overcentre", "--branch", path, "--out", tmp_path / "a.gif", "--every", "25")
    assert r.exit_code == 0, r.output
    assert r.stderr == ""
    with Image.open(tmp_path / "a.gif") as im:
        assert im.size[0] >= 800  # the default panel beside the mechanism: the branch, current point marked


# -- fast frames: the fixed parts drawn once, each frame's artists over them -----------------------------
# A blitted frame must show what a full redraw shows; the GIF's shared palette stays close to the drawn
# colours; every output (GIF, HTML, MP4 through ffmpeg's pipe) gets every frame, special points held.

def _renderer(system, branch, every, diagram, **kw):
    frames = anim.branch_frames(system, branch)
    rows = anim.frame_rows(frames, every)
    annotate = _drawing_parts._with_vary(frames.vary, drawing.default_annotate(system))
    r = anim._renderer(system.scene, system, frames, rows, annotate, title=None, show_forces=True, diagram=diagram,
                       **{"figsize": None, "dpi": 100, **kw})
    return frames, rows, r


def _differences(renderer, n):
    """Per frame: (fraction of pixels that differ at all, largest difference in any channel) between the
    blitted frame and a full redraw of the same figure."""
    out = []
    for blit, full in anim._frame_pixels(renderer, n, check=True):
        d = np.abs(blit.astype(int) - full.astype(int)).max(axis=2)
        out.append((float(np.mean(d > 0)), int(d.max())))
    return out


def test_blitted_frames_are_full_redraws(overcentre, branch):
    """Drawing order is zorder within each axes either way; only antialiased edges where a frame's artist
    meets a fixed one (the faint grid) may differ by a few levels."""
    frames, rows, r = _renderer(overcentre, branch, 6, ("F", "theta1"))
    diffs = _differences(r, len(rows))
    assert len(diffs) == len(rows) > 5
    assert max(f for f, _ in diffs) < 1e-3 and max(m for _, m in diffs) <= 32, diffs


def test_blitted_frames_of_a_spatial_mechanism_are_full_redraws():
    from test_drawing3d import Swing

    system = Swing()
    rows = np.column_stack([np.linspace(0.0, 1.2, 4), np.linspace(0.0, 3.0, 4)])
    frames, order, r = _renderer(system, rows, 1, ("F", "theta"), figsize=(8.0, 6.5), dpi=60)
    assert r.content_axes and r.content_axes[0].name == "3d"
    diffs = _differences(r, len(order))
    assert max(f for f, _ in diffs) < 1e-3 and max(m for _, m in diffs) <= 32, diffs


def test_a_special_point_frame_names_its_values_and_marks_the_branch(overcentre, branch):
    frames, rows, r = _renderer(overcentre, branch, 10, ("F", "theta1"))
    labels = frames.numbered_labels
    special = [k for k, i in enumerate(rows) if labels[i]]
    assert {rows[k] for k in special} == {p.index for p in branch.special_points}
    for k in special:
        i = rows[k]
        over = r.render(k)
        notes = [a.get_text() for a in over if isinstance(a, matplotlib.text.Text) and "=" in a.get_text()]
        F, theta = branch.values[i, overcentre.index("F")], branch.values[i, overcentre.index("theta1")]
        status = "fold" if labels[i].startswith("LP") else "stable"
        assert notes == [f"F = {F:.4g} N\ntheta1 = {round(math.degrees(theta), 2) + 0.0:.2f}°\n{status} {labels[i]}"]
        x, y = r.marker[0].get_data()
        assert np.allclose([x[0], y[0]], [F, math.degrees(theta)], rtol=1e-12, atol=1e-12)
        assert r.marker[0] in over


def test_gif_frames_stay_close_to_the_drawn_pixels(tmp_path, overcentre, branch):
    """One palette of 256 colours for all frames: the few colours of the drawing are kept exactly (the
    white background stays white), and the antialiased blends between them (thousands of shades) are
    mapped to near ones."""
    frames, rows, r = _renderer(overcentre, branch, 9, ("F", "theta1"))
    drawn = [px[..., :3].copy() for px in anim._frame_pixels(r, len(rows))]
    out = tmp_path / "a.gif"
    _frames.write_gif(out, [_frames.gif_frame(np.dstack([f, np.full(f.shape[:2], 255, np.uint8)])) for f in drawn],
                      [100] * len(drawn))
    with Image.open(out) as im:
        assert im.n_frames == len(drawn)
        for k, want in enumerate(drawn):
            im.seek(k)
            got = np.asarray(im.convert("RGB")).astype(int)
            d = np.abs(got - want).max(axis=2)
            assert d.mean() < 1 and np.quantile(d, 0.999) <= 24, (k, d.mean(), np.quantile(d, 0.999))
            white = (want == 255).all(axis=2)
            assert white.mean() > 0.5 and (got[white] == 255).all()


def _html_frames(path):
    text = path.read_text()
    return [np.asarray(Image.open(io.BytesIO(base64.b64decode(d.replace("\\n", ""))))) for d in
            re.findall(r'data:image/png;base64,([^"]+)"', text)]


def test_html_and_mp4_hold_special_points_by_repeating_frames(tmp_path, overcentre, branch, monkeypatch):
    """MP4 goes through ffmpeg's pipe as raw RGBA frames: a stand-in ffmpeg keeps them."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    fake = bin_dir / "ffmpeg"
    fake.write_text('#!/bin/sh\nfor last; do :; done\ncat > "$last"\n')
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("PATH", f"{bin_dir}{os.pathsep}{os.environ['PATH']}")
    kw = dict(every=12, fps=5, hold=0.4, figsize=(4, 3), dpi=30)  # 120 x 90 px: even, as h264 wants
    n = anim.animate(overcentre, branch, tmp_path / "a.html", **kw)
    assert anim.animate(overcentre, branch, tmp_path / "a.mp4", **kw) == n
    rows = anim.frame_rows(anim.branch_frames(overcentre, branch), 12)
    held = [bool(branch.labels[i]) for i in rows]
    total = sum(1 + (2 if h else 0) for h in held)  # 0.4 s at 5 frames a second: 2 more frames
    html = _html_frames(tmp_path / "a.html")
    raw = np.frombuffer((tmp_path / "a.mp4").read_bytes(), np.uint8)
    assert len(html) == total and raw.size == total * 90 * 120 * 4
    mp4 = raw.reshape(total, 90, 120, 4)
    for k in range(total):
        assert np.array_equal(mp4[k, ..., :3], html[k][..., :3])
    starts = np.cumsum([0] + [1 + (2 if h else 0) for h in held])[:-1]
    for k, h in zip(starts, held):
        assert all(np.array_equal(mp4[k], mp4[k + j]) for j in range(1, 3 if h else 1))
    assert not np.array_equal(mp4[starts[0]], mp4[starts[1]])
