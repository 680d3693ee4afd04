"""Drawings and animations: scene geometry against the overcentre's constraints, valid files, errors."""

from __future__ import annotations

import csv
import math

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from cli_helpers import make_runner, one_line_error  # noqa: E402
from PIL import Image, ImageSequence  # noqa: E402

from mechcont.equations import Scene  # noqa: E402
from mechcont.errors import InputError  # noqa: E402
from mechcont.models import build_overcentre  # noqa: E402
from mechcont.models.overcentre import symmetric_force, symmetric_stable  # noqa: E402
from mechcont.models.overcentre_scene import overcentre_scene  # noqa: E402
from mechcont.outputs.animation import BranchFrames, animate, branch_frames  # noqa: E402
from mechcont.outputs.drawing import draw, draw_scene  # noqa: E402

SMALL = dict(figsize=(3, 2.5), dpi=50)


def assembled(system, theta1, L1, L2, upper=True, **values):
    """Full vector at an assembled configuration, from the geometry alone (not from the model).

    Bar 1 from the origin at angle theta1 to the apex A; the slider end S on y = 0 at
    distance L2 from A (on the far side if ``upper``); centres of gravity at the bar middles.
    """
    ax_, ay = L1 * math.cos(theta1), L1 * math.sin(theta1)
    sx = ax_ + (1 if upper else -1) * math.sqrt(L2**2 - ay**2)
    theta2 = math.atan2(ay, ax_ - sx)
    return system.vector(dict(x1=ax_ / 2, y1=ay / 2, theta1=theta1, x2=(sx + ax_) / 2, y2=ay / 2, theta2=theta2,
                              L1=L1, L2=L2, **values))


@pytest.fixture(scope="module")
def overcentre():
    system = build_overcentre()
    system.scene = overcentre_scene(system)
    return system


def symmetric_rows(system, thetas, LU=0.4):
    p = dict(L=1.5, m1=1.0, m2=1.0, g=9.81, k=127.0, LU=LU)
    return np.array([assembled(system, t, 1.5, 1.5, F=float(symmetric_force(t, **p)), LU=LU) for t in thetas])


def write_branch_csv(path, system, rows, stable, labels):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([*system.names, "s", "stability", "label"])
        for k, (row, st, lab) in enumerate(zip(rows, stable, labels)):
            w.writerow([*map(repr, row.tolist()), k * 0.1, "stable" if st else "unstable", lab])


# -- the overcentre scene obeys the constraints -------------------------------------------

def test_overcentre_scene_matches_constraints_at_random_configurations(overcentre):
    rng = np.random.default_rng(7)
    for _ in range(40):
        L1, L2 = rng.uniform(0.3, 3.0, 2)
        m, n = rng.uniform(-0.5, 0.5) * L1, rng.uniform(-0.5, 0.5) * L2
        limit = math.asin(min(1.0, L2 / L1))
        theta1 = rng.uniform(-0.95, 0.95) * limit
        F = rng.normal(scale=50)
        x = assembled(overcentre, theta1, L1, L2, upper=bool(rng.integers(2)), m=m, n=n, F=F)
        # the configuration really is assembled (the model's own geometric rows vanish)
        assert np.max(np.abs(overcentre.residual(x)[:5])) < 1e-12
        sc = overcentre.scene(x)
        (name1, bar1), (name2, bar2) = sc.bars
        apex = L1 * np.array([math.cos(theta1), math.sin(theta1)])
        assert np.allclose(sc.grounds[0], [0, 0]) and np.allclose(bar1[0], [0, 0], atol=1e-12)
        assert np.allclose(bar1[-1], apex, atol=1e-12) and np.allclose(bar2[-1], apex, atol=1e-12)
        assert np.allclose(sc.pins[0], apex, atol=1e-12)
        slider, direction = sc.sliders[0]
        assert abs(slider[1]) < 1e-12 and np.allclose(slider, bar2[0], atol=1e-12)
        assert np.allclose(direction, [1, 0])
        assert math.isclose(np.hypot(*(bar2[-1] - bar2[0])), L2, rel_tol=1e-12)
        _, s1, s2 = sc.springs[0]
        # spring ends on the bars, at m and n beyond the middles towards the apex
        for start, end, length, off, pt in ((bar1[0], bar1[-1], L1, m, s1), (bar2[0], bar2[-1], L2, n, s2)):
            assert math.isclose(np.hypot(*(pt - start)), abs(length / 2 + off), abs_tol=1e-12)
            assert math.isclose(np.hypot(*(end - pt)), abs(length / 2 - off), abs_tol=1e-12)
        name, at, vec = sc.forces[0]
        assert name == "F" and np.allclose(at, apex) and np.allclose(vec, [0, F])


def test_overcentre_scene_shows_a_broken_configuration(overcentre):
    """A vector that violates a constraint is drawn as it is, not repaired."""
    x = assembled(overcentre, 0.4, 1.5, 1.5)
    x[overcentre.index("x1")] += 0.1
    sc = overcentre.scene(x)
    assert np.hypot(*sc.bars[0][1][0]) > 0.09      # bar 1 has left its ground pin
    assert not np.allclose(sc.bars[0][1][-1], sc.bars[1][1][-1])


def test_overcentre_scene_weights(overcentre):
    sc = overcentre_scene(overcentre, weights=True)(assembled(overcentre, 0.3, 1.5, 1.5))
    w = {name: vec for name, _, vec in sc.forces}
    assert np.allclose(w["w1"], [0, -9.81]) and np.allclose(w["w2"], [0, -9.81])


# -- drawing ------------------------------------------------------------------------------

def every_primitive():
    return Scene(
        bars=[("crank", np.array([[0, 0], [1, 0.5]])), ("body", np.array([[1, 0.5], [2, 0.2], [2.5, 1.0]]))],
        pins=[np.array([1, 0.5])],
        grounds=[np.array([0.0, 0.0])],
        sliders=[(np.array([2.5, 1.0]), np.array([1.0, 1.0]))],
        springs=[("k1", np.array([0.5, 0.25]), np.array([2.0, 0.2])), ("slack", np.array([1, 1.0]), np.array([1, 1.0]))],
        forces=[("P", np.array([2.0, 0.2]), np.array([3.0, -4.0])), ("Q", np.array([1.0, 0.5]), np.zeros(2))],
    )


def test_draw_scene_places_force_arrows_and_springs():
    sc = every_primitive()
    ax = draw_scene(sc, force_scale=0.1)
    arrows = [t for t in ax.texts if hasattr(t, "xyann") and t.arrow_patch is not None]
    assert len(arrows) == 1
    assert np.allclose(arrows[0].xy, [2.3, -0.2]) and np.allclose(arrows[0].xyann, [2.0, 0.2])
    labels = [t.get_text() for t in ax.texts]
    assert "P = 5 N" in labels and "Q = 0 N" in labels
    coil = next(line for line in ax.lines if line.get_label() == "k1").get_xydata()
    assert np.allclose(coil[0], [0.5, 0.25]) and np.allclose(coil[-1], [2.0, 0.2])
    xmin, xmax = ax.get_xlim()
    ymin, ymax = ax.get_ylim()
    assert xmin < 0 and xmax > 2.5 and ymin < -0.2 and ymax > 1.0   # everything, arrow tip included, in view
    assert ax.get_aspect() == 1.0


def test_default_force_scale_draws_the_largest_force_at_a_fixed_fraction():
    sc = every_primitive()
    ax = draw_scene(sc)
    (arrow,) = [t for t in ax.texts if hasattr(t, "xyann") and t.arrow_patch is not None]
    length = np.hypot(*(np.asarray(arrow.xy) - arrow.xyann))
    xmin, xmax, ymin, ymax = sc.extent()
    assert math.isclose(length, 0.3 * max(xmax - xmin, ymax - ymin), rel_tol=1e-12)


@pytest.mark.parametrize("suffix, magic", [(".png", b"\x89PNG\r\n\x1a\n"), (".pdf", b"%PDF-"), (".svg", b"<?xml")])
def test_draw_writes_valid_files(tmp_path, overcentre, suffix, magic):
    x = assembled(overcentre, 0.5, 1.5, 1.5, F=20.0, m=0.2, n=0.1)
    out = tmp_path / f"fig{suffix}"
    draw(overcentre, x, out, annotate=("F", "theta1"), stable=True, label="LP", **SMALL)
    data = out.read_bytes()
    assert data.startswith(magic) and len(data) > 3000
    if suffix == ".svg":
        assert b"<svg" in data and "28.65°".encode() in data      # theta1 = 0.5 rad shown in degrees
    if suffix == ".png":
        with Image.open(out) as im:
            assert im.size == (150, 125)
    assert [p.name for p in tmp_path.iterdir()] == [out.name]     # no temporary left behind


def test_draw_errors_leave_nothing(tmp_path, overcentre):
    x = assembled(overcentre, 0.5, 1.5, 1.5)
    with pytest.raises(InputError, match=r"out: unknown file type '\.jpg'; valid: \.png, \.svg, \.pdf"):
        draw(overcentre, x, tmp_path / "fig.jpg")
    bare = build_overcentre()
    bare.scene = None
    with pytest.raises(InputError, match="model: 'overcentre' has no drawing"):
        draw(bare, x, tmp_path / "fig.png")
    with pytest.raises(InputError, match="x: expected 17 values"):
        draw(overcentre, x[:-1], tmp_path / "fig.png")
    with pytest.raises(InputError, match="unknown variable"):
        draw(overcentre, x, tmp_path / "fig.png", annotate=("nope",))
    with pytest.raises(InputError, match="does not exist"):
        draw(overcentre, x, tmp_path / "missing" / "fig.png")
    assert list(tmp_path.iterdir()) == []


# -- branches and animation ----------------------------------------------------------------

def test_animate_gif_frame_count_and_fixed_view(tmp_path, overcentre):
    thetas = np.linspace(-0.5, 0.7, 7)
    rows = symmetric_rows(overcentre, thetas)
    stable = [bool(symmetric_stable(t, 1.5, 0.4)) for t in thetas]
    frames = BranchFrames(rows, tuple(stable), ("EP", "", "", "LP", "", "", "EP"))
    out = tmp_path / "a.gif"
    ticks = []
    n = animate(overcentre, frames, out, fps=5, every=2, diagram=("F", "theta1"), figsize=(4, 2), dpi=40,
                on_frame=lambda: ticks.append(1))
    assert n == 5 and len(ticks) == 5  # rows 0, 2, 4, 6 and the fold at row 3, which --every must not drop
    with Image.open(out) as im:
        assert im.n_frames == 5
        durations = []
        for k in range(im.n_frames):
            im.seek(k)
            durations.append(im.info["duration"])
    assert durations == [800, 200, 800, 200, 800]  # 1/5 s a frame; the special points held 0.6 s longer
    assert [p.name for p in tmp_path.iterdir()] == ["a.gif"]


def test_branch_frames_from_csv_and_rows(tmp_path, overcentre):
    thetas = np.linspace(-0.3, 0.3, 5)
    rows = symmetric_rows(overcentre, thetas)
    path = tmp_path / "b.csv"
    write_branch_csv(path, overcentre, rows, [True, False, False, True, True], ["EP", "LP", "", "LP", "EP"])
    fr = branch_frames(overcentre, path)
    assert np.array_equal(fr.values, rows)
    assert fr.stable == (True, False, False, True, True)
    assert fr.row("LP2") == 3 and fr.row("LP") == 1 and fr.row(-1) == 4 and fr.row("2") == 2
    with pytest.raises(InputError, match=r"point: row 5 out of range; the branch has 5 rows \(0..4\)"):
        fr.row(5)
    with pytest.raises(InputError, match="no row 'BP1'"):
        fr.row("BP1")


def test_branch_frames_from_a_branch_object(overcentre):
    class FakeBranch:  # the attributes mechcont.continuation.Branch has
        names = overcentre.names
        values = symmetric_rows(overcentre, [0.1, 0.2, 0.3])
        n_unstable = np.array([0, 1, -1])
        labels = ["", "LP", ""]

    fr = branch_frames(overcentre, FakeBranch())
    assert fr.stable == (True, False, None) and fr.labels == ("", "LP", "")


def test_animate_errors(tmp_path, overcentre):
    rows = symmetric_rows(overcentre, [0.1, 0.2])
    with pytest.raises(InputError, match=r"out: unknown file type '\.avi'; valid: \.gif, \.mp4"):
        animate(overcentre, rows, tmp_path / "a.avi")
    with pytest.raises(InputError, match="every: must be an integer >= 1"):
        animate(overcentre, rows, tmp_path / "a.gif", every=0)
    with pytest.raises(InputError, match="fps: must be a positive number"):
        animate(overcentre, rows, tmp_path / "a.gif", fps=0)
    with pytest.raises(InputError, match="branch: rows must hold the 17 variables"):
        animate(overcentre, rows[:, :5], tmp_path / "a.gif")
    bare = build_overcentre()
    bare.scene = None
    with pytest.raises(InputError, match="has no drawing"):
        animate(bare, rows, tmp_path / "a.gif")
    bad = tmp_path / "bad.csv"
    bad.write_text("x1,y1\n0,0\n")
    with pytest.raises(InputError, match="lacks the column"):
        animate(overcentre, bad, tmp_path / "a.gif")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.csv"]


def test_failure_while_writing_leaves_nothing(tmp_path, overcentre):
    count = []

    def fail_on_second_frame():
        count.append(1)
        if len(count) == 2:
            raise RuntimeError("interrupted")

    with pytest.raises(RuntimeError, match="interrupted"):
        animate(overcentre, symmetric_rows(overcentre, [0.1, 0.2, 0.3]), tmp_path / "a.gif", figsize=(2, 2), dpi=30,
                on_frame=fail_on_second_frame)
    assert list(tmp_path.iterdir()) == []


def test_mp4_without_ffmpeg_suggests_gif(tmp_path, overcentre, monkeypatch):
    import shutil

    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(InputError, match=r"ffmpeg.*\.gif"):
        animate(overcentre, symmetric_rows(overcentre, [0.1]), tmp_path / "a.mp4")
    assert list(tmp_path.iterdir()) == []


# -- command line --------------------------------------------------------------------------

@pytest.fixture(scope="module")
def run():
    return make_runner()


@pytest.fixture
def branch_csv(tmp_path, overcentre):
    thetas = np.linspace(-0.5, 0.7, 6)
    path = tmp_path / "branch.csv"
    write_branch_csv(path, overcentre, symmetric_rows(overcentre, thetas),
                     [bool(symmetric_stable(t, 1.5, 0.4)) for t in thetas], ["EP", "", "LP", "", "", "EP"])
    return path




def test_cli_draw_point_and_animate(tmp_path, run, branch_csv):
    r = run("draw", "overcentre", "--point", f"{branch_csv}:LP1", "--out", tmp_path / "p.png")
    assert r.exit_code == 0, r.output
    assert (tmp_path / "p.png").read_bytes().startswith(b"\x89PNG")
    r = run("animate", "overcentre", "--branch", branch_csv, "--out", tmp_path / "a.gif", "--every", "2",
            "--fps", "4", "--diagram", "F,theta1")
    assert r.exit_code == 0, r.output
    with Image.open(tmp_path / "a.gif") as im:
        assert im.n_frames == 4  # rows 0, 2, 4 and the end point at row 5


def test_cli_bad_input_exit_2_and_nothing_written(tmp_path, run, branch_csv):
    before = sorted(p.name for p in tmp_path.iterdir())
    one_line_error(run("draw", "overcentre", "--point", f"{branch_csv}:99", "--out", tmp_path / "p.png"),
                   "row 99 out of range", "6 rows")
    one_line_error(run("draw", "overcentre", "--point", f"{branch_csv}:0", "--out", tmp_path / "p.bmp"),
                   "unknown file type '.bmp'", ".png, .svg, .pdf")
    one_line_error(run("draw", "nomodel", "--out", tmp_path / "p.png"), "unknown model 'nomodel'")
    one_line_error(run("draw", "overcentre", "--set", "LU", "--out", tmp_path / "p.png"), "set:", "NAME=VALUE")
    one_line_error(run("animate", "overcentre", "--branch", branch_csv, "--out", tmp_path / "a.webm"),
                   ".gif, .mp4")
    one_line_error(run("animate", "overcentre", "--branch", tmp_path / "none.csv", "--out", tmp_path / "a.gif"),
                   "cannot read")
    one_line_error(run("animate", "overcentre", "--branch", branch_csv, "--out", tmp_path / "a.gif",
                       "--annotate", "F,bogus"), "bogus")
    one_line_error(run("animate", "overcentre", "--branch", branch_csv, "--out", tmp_path / "a.gif",
                       "--every", "0"), "every")
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_cli_draw_solves_an_equilibrium(tmp_path, run):
    pytest.importorskip("mechcont.continuation")
    out = tmp_path / "eq.svg"
    r = run("draw", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--free", "F", "--out", out)
    assert r.exit_code == 0, r.output
    # the symmetric closed form fixes the force that holds theta1 = 0.3 rad
    F = symmetric_force(0.3, 1.5, 1.0, 1.0, 9.81, 127.0, 0.4)
    assert f"F = {F:.4g} N".encode() in out.read_bytes()
    assert "17.19°".encode() in out.read_bytes()


# -- with the continuation engine ----------------------------------------------------------

@pytest.fixture(scope="module")
def real_branch(overcentre):
    cont = pytest.importorskip("mechcont.continuation")
    x0 = cont.find_equilibrium(overcentre, values={"LU": 0.4}, hold={"theta1": 0.3}, free=["F"])
    return cont.continuation(overcentre, x0, vary="F",
                             options=cont.ContinuationOptions(max_steps=200, bounds={"F": (-100, 100)}))


def test_animate_a_continued_branch(tmp_path, overcentre, real_branch):
    every = 25
    n = animate(overcentre, real_branch, tmp_path / "b.gif", every=every, figsize=(3, 2.5), dpi=40)
    special = {p.index for p in real_branch.special_points}
    assert n == len(set(range(0, len(real_branch), every)) | special) > math.ceil(len(real_branch) / every)
    with Image.open(tmp_path / "b.gif") as im:
        assert im.n_frames == n
    out = tmp_path / "lp.svg"
    draw(overcentre, real_branch["LP1"], out, annotate=("F",), **SMALL)
    assert b"LP" in out.read_bytes() and f"F = {real_branch['LP1'].x[overcentre.index('F')]:.4g} N".encode() in out.read_bytes()
    fr = branch_frames(overcentre, real_branch)
    assert fr.labels.count("LP") == 2 and fr.numbered_labels.count("LP2") == 1


def test_cli_draws_the_folds_of_a_continued_branch(tmp_path, run, overcentre, real_branch):
    """`--point branch.csv:LP1` draws the fold; its F is the closed-form fold force."""
    from mechcont.models.overcentre import symmetric_folds

    csv_path = real_branch.to_csv(tmp_path / "branch.csv")
    folds = {f"F = {F:.4g} N" for _, F in symmetric_folds(1.5, 1.0, 1.0, 9.81, 127.0, 0.4)}
    shown = set()
    for label in ("LP1", "LP2"):
        out = tmp_path / f"{label}.svg"
        r = run("draw", "overcentre", "--point", f"{csv_path}:{label}", "--out", out)
        assert r.exit_code == 0, r.output
        text = out.read_text()
        assert label in text
        shown |= {f for f in folds if f in text}
    assert shown == folds
    r = run("animate", "overcentre", "--branch", csv_path, "--out", tmp_path / "a.gif", "--every", "30")
    assert r.exit_code == 0, r.output
    with Image.open(tmp_path / "a.gif") as im:  # every 30th row and every special point
        special = {p.index for p in real_branch.special_points}
        assert im.n_frames == len(set(range(0, len(real_branch), 30)) | special)


def test_cli_draws_a_mechanism_description_file(tmp_path, run):
    """A generated mechanism (description file) draws too; its equilibrium force matches the closed form."""
    mechanism = pytest.importorskip("mechcont.mechanism")
    path = mechanism.find_description("overcentre")
    if path is None:
        pytest.skip("no shipped overcentre description")
    out = tmp_path / "gen.svg"
    r = run("draw", path, "--set", "LU=0.4", "--start", "theta1=0.3", "--free", "F", "--out", out)
    assert r.exit_code == 0, r.output
    F = symmetric_force(0.3, 1.5, 1.0, 1.0, 9.81, 127.0, 0.4)
    assert f"F = {F:.4g} N".encode() in out.read_bytes()


# -- moments, spring anchors, annotated frames ------------------------------------------------

def _moment_arc(ax, name):
    (line,) = [ln for ln in ax.lines if ln.get_gid() == f"moment:{name}"]
    return line.get_xydata()


@pytest.mark.parametrize("value", [7.0, -3.0])
def test_moment_is_a_curved_arrow_whose_sense_follows_the_sign(value):
    p = np.array([0.4, 0.2])
    sc = Scene(bars=[("bar", np.array([[0.0, 0.0], [1.0, 0.5]]))], moments=[("M", p, value)])
    ax = draw_scene(sc)
    arc = _moment_arc(ax, "M")
    rel = arc - p
    r = np.hypot(rel[:, 0], rel[:, 1])
    assert np.ptp(r) < 1e-9 * r[0] and r[0] > 0                  # a circular arc around the point
    turn = np.sum(rel[:-1, 0] * rel[1:, 1] - rel[:-1, 1] * rel[1:, 0])
    assert np.sign(turn) == np.sign(value)                         # counter-clockwise iff positive
    (head,) = [t for t in ax.texts if hasattr(t, "xyann") and t.arrow_patch is not None]
    tip, tail = np.asarray(head.xy) - p, np.asarray(head.xyann) - p
    assert np.sign(tail[0] * tip[1] - tail[1] * tip[0]) == np.sign(value)   # arrowhead turns the same way
    assert np.hypot(*tip) == pytest.approx(r[0])
    assert f"M = {abs(value):.3g} N m" in [t.get_text() for t in ax.texts]
    xmin, xmax = ax.get_xlim()
    ymin, ymax = ax.get_ylim()
    assert xmin < p[0] - r[0] and xmax > p[0] + r[0] and ymin < p[1] - r[0] and ymax > p[1] + r[0]


def test_zero_moment_is_only_labelled_and_no_forces_hides_moments():
    sc = Scene(bars=[("bar", np.array([[0.0, 0.0], [1.0, 0.5]]))], moments=[("M", np.zeros(2), 0.0)])
    ax = draw_scene(sc)
    assert not [ln for ln in ax.lines if ln.get_gid() == "moment:M"] and "M = 0 N m" in [t.get_text() for t in ax.texts]
    sc.moments = [("M", np.zeros(2), 4.0)]
    ax = draw_scene(sc, show_forces=False)
    assert not [ln for ln in ax.lines if ln.get_gid() == "moment:M"] and not ax.texts


def _symbols(ax, gid):
    return [p for p in ax.patches if p.get_gid() == gid]


def test_anchor_symbol_is_small_and_faces_away_from_its_spring():
    anchor = np.array([0.0, 1.0])
    sc = Scene(bars=[("bar", np.array([[0.0, 0.0], [1.0, 0.0]]))], grounds=[np.zeros(2)], anchors=[anchor],
               springs=[("k", anchor, np.array([0.5, 0.0]))])
    ax = draw_scene(sc)
    (ground,), (anc,) = _symbols(ax, "ground"), _symbols(ax, "anchor")
    tri = anc.get_xy()[:3]
    assert np.allclose(tri[0], anchor)
    away = tri[1:].mean(axis=0) - anchor
    assert np.dot(away, np.array([0.5, 0.0]) - anchor) < 0        # the hatching is behind the anchor
    size = lambda patch: np.ptp(patch.get_xy(), axis=0).max()      # noqa: E731
    assert size(anc) < size(ground)


def test_fourbar_drawing_has_the_moment_and_the_spring_anchor(tmp_path):
    from mechcont.mechanism import assemble, load

    system = load("fourbar")
    x = assemble(system, hold={"theta_crank": 1.0}, free=["T"])
    ax = draw(system, x, tmp_path / "fb.png", **SMALL)
    assert len(_symbols(ax, "ground")) == 2 and len(_symbols(ax, "anchor")) == 1
    arc = _moment_arc(ax, "T")
    assert np.allclose(np.mean(arc, axis=0)[0], 0.0, atol=0.05 * np.ptp(arc[:, 0]))  # around the pin A = (0, 0)
    assert f"T = {abs(x[system.index('T')]):.3g} N m" in [t.get_text() for t in ax.texts]


@pytest.fixture(scope="module")
def fourbar_branch():
    from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
    from mechcont.mechanism import load

    system = load("fourbar")
    x0 = find_equilibrium(system, hold={"theta_crank": 1.0}, free=["T"])
    branch = continuation(system, x0, "T", options=ContinuationOptions(bounds={"theta_crank": (0.0, 6.2)}))
    assert branch.labels.count("LP") >= 2
    return system, branch


def test_frame_of_a_fourbar_branch_prints_the_continuation_parameter(tmp_path, fourbar_branch):
    system, branch = fourbar_branch
    lp = branch["LP1"]
    out = tmp_path / "lp.svg"
    draw(system, lp, out, annotate=("T", "theta_crank"), stable=True, **SMALL)
    svg = out.read_text()
    T, theta = lp.x[system.index("T")], lp.x[system.index("theta_crank")]
    assert f"T = {T:.4g} N m" in svg and f"theta_crank = {math.degrees(theta):.2f}°" in svg
    assert "fold LP" in svg and "stable LP" not in svg  # a fold is neutral, whatever stable= says


@pytest.mark.slow
def test_animation_frames_print_vary_units_stability_and_label(tmp_path, fourbar_branch, monkeypatch):
    """Every frame's note: the branch's vary (N m), the annotated angle (degrees), stability, label."""
    import mechcont.outputs._drawing_parts as parts

    system, branch = fourbar_branch
    notes = []
    real = parts._put_note
    monkeypatch.setattr(parts, "_put_note", lambda ax, text, *a: (notes.append(text), real(ax, text, *a)))
    csv_path = branch.to_csv(tmp_path / "fb.csv")
    frames = branch_frames(system, csv_path)
    assert frames.vary == "T" and branch_frames(system, branch).vary == "T"   # CSV: the one changing parameter
    n = animate(system, csv_path, tmp_path / "fb.gif", every=1, figsize=(3, 2.5), dpi=30)
    notes = notes[1:]                  # the first render lays the figure out before writing
    assert n == len(branch) == len(notes)
    st = branch.stability_labels()
    labels = frames.numbered_labels
    for i, text in enumerate(notes):
        lines = text.splitlines()
        T, theta = branch.values[i, system.index("T")], branch.values[i, system.index("theta_crank")]
        assert lines[0] == f"T = {T:.4g} N m"
        assert lines[1] == f"theta_crank = {round(math.degrees(theta), 2) + 0.0:.2f}°"
        assert lines[2] == " ".join(w for w in (st[i], labels[i]) if w)


def test_vary_on_the_cli(tmp_path, run, fourbar_branch):
    system, branch = fourbar_branch
    csv_path = branch.to_csv(tmp_path / "fb.csv")
    r = run("animate", "fourbar", "--branch", csv_path, "--out", tmp_path / "a.gif", "--every", "40",
            "--vary", "theta_crank")
    assert r.exit_code == 0, r.output
    r = run("draw", "fourbar", "--point", f"{csv_path}:LP2", "--out", tmp_path / "p.svg")
    assert r.exit_code == 0, r.output
    lp2 = branch["LP2"].x
    assert f"T = {lp2[system.index('T')]:.4g} N m" in (tmp_path / "p.svg").read_text()
    one_line_error(run("animate", "fourbar", "--branch", csv_path, "--out", tmp_path / "b.gif", "--vary", "nope"),
                   "nope")
    one_line_error(run("draw", "fourbar", "--start", "theta_crank=1", "--free", "T", "--vary", "T",
                       "--out", tmp_path / "c.png"), "vary")
    assert not (tmp_path / "b.gif").exists() and not (tmp_path / "c.png").exists()


def test_labels_name_every_body_at_its_centre_and_every_named_point():
    """labels=True: each body's name at its centre, or beside it with a leader line from the centre (placed clear of
    the other labels); every ground and body point labelled, coincident ones together."""
    from mechcont.mechanism import load

    s = load("fourbar")
    x = s.defaults()
    ax = draw(s, x, labels=True, **SMALL)
    texts = {t.get_gid(): t for t in ax.texts if t.get_gid()}
    co = s.coordinates_of(x)
    for body in ("crank", "coupler", "rocker"):
        t = texts[f"body:{body}"]
        assert t.get_text() == body
        centre = (co[f"x_{body}"], co[f"y_{body}"])   # the bar's centre
        leaders = [ln for ln in ax.get_lines() if ln.get_gid() == f"leader:body:{body}"]
        at = leaders[0].get_xydata()[0] if leaders else t.get_position()
        assert tuple(at) == pytest.approx(centre, abs=1e-9)
    labels = [t.get_text() for g, t in texts.items() if g.startswith("point:")]
    assert sorted(labels) == sorted(["crank.a, ground.A", "crank.b, coupler.a", "coupler.b, rocker.b",
                                     "rocker.a, ground.D", "ground.S"])
    assert not [t for t in draw(s, x, **SMALL).texts if (t.get_gid() or "").startswith(("body:", "point:"))]


@pytest.mark.parametrize("value, unit, text", [(9690.55, "N", "9.69 kN"), (5.0, "N", "5 N"), (0.0, "N m", "0 N m"),
                                               (12.5, "N m", "12.5 N m"), (1.23e6, "N", "1.23 MN"),
                                               (999.0, "N", "999 N"), (1000.0, "N", "1 kN")])
def test_load_labels_use_si_prefixes(value, unit, text):
    from mechcont.outputs.drawing import load_text

    assert load_text(value, unit) == text


def test_animate_pause_and_its_deprecated_spelling(tmp_path, run, branch_csv):
    """``--hold`` means a held state elsewhere, so the animation's extra seconds are ``--pause``; the old
    ``--hold SECONDS`` still works, with a one-line note, and is not offered in the help."""
    one_line_error(run("animate", "overcentre", "--branch", branch_csv, "--out", tmp_path / "a.gif", "--pause", "99"),
                   "--pause:", "between 0 and 60")
    one_line_error(run("animate", "overcentre", "--branch", branch_csv, "--out", tmp_path / "a.gif", "--hold", "-1"),
                   "--hold:", "between 0 and 60")
    assert not (tmp_path / "a.gif").exists()
    r = run("animate", "overcentre", "--branch", branch_csv, "--out", tmp_path / "a.gif", "--every", "2", "--fps", "4",
            "--hold", "0.5")
    assert r.exit_code == 0, r.output
    assert r.stderr.strip() == "note: animate --hold SECONDS is now --pause SECONDS (--hold will be removed)"
    with Image.open(tmp_path / "a.gif") as old:
        durations = [old.info["duration"] for _ in ImageSequence.Iterator(old)]
    r = run("animate", "overcentre", "--branch", branch_csv, "--out", tmp_path / "b.gif", "--every", "2", "--fps", "4",
            "--pause", "0.5")
    assert r.exit_code == 0 and not r.stderr, r.output
    with Image.open(tmp_path / "b.gif") as new:
        assert [new.info["duration"] for _ in ImageSequence.Iterator(new)] == durations
    assert 750 in durations  # the fold held 0.25 s + 0.5 s
    helptext = run("animate", "--help").output
    assert "--pause" in helptext and "--hold" not in helptext
