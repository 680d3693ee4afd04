"""Animations made for a human: long enough, wide enough, every special point shown and held, labels off the
mechanism, ground drawn locally, an HTML page for notebooks."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium  # noqa: E402
from mechcont.models import build_overcentre  # noqa: E402
from mechcont.outputs import drawing  # noqa: E402
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
    real = drawing.draw_scene

    def spy(scene, ax, **kw):
        out = real(scene, ax, **kw)
        texts.append([t.get_text() for t in ax.texts])
        guides = [ln for ln in ax.lines if ln.get_gid() == "slider-guide"]
        xs = np.concatenate([ln.get_xdata() for ln in guides])
        travel = [float(s.sliders[0][0][0]) for s in scenes]
        h = drawing._SYMBOL * max(np.diff(ax.get_xlim())[0], np.diff(ax.get_ylim())[0])
        assert xs.min() >= min(travel) - 4.5 * h and xs.max() <= max(travel) + 4.5 * h
        return out

    rows = frame_rows(branch_frames(overcentre, branch), 10)
    scenes = [overcentre.scene(branch.values[i]) for i in rows]
    monkeypatch.setattr(drawing, "draw_scene", spy)
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
