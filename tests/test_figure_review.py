"""Issue 37: every figure of ``mechcont paper`` and of the README's and docs' commands, reviewed by measurement.

Each figure is drawn as it is saved (``Figure.savefig`` wrapped: the file is written at a low resolution, which
scales every pixel measure alike) and :func:`figure_checks.review_problems` measures it: no two texts overlapping,
no text outside the figure, no legend over a curve, a marker or a text, no marker cut by the frame, every axis
labelled with its unit, no ragged 3-D surface (Matplotlib pads one with uninitialised memory, whose projection
overflowed on some runs: the sections run with RuntimeWarnings as errors), no leader line through a label. A
paper section also shows every figure it writes in its summary lines (``![...](file)``). An animation is reviewed
in its first, middle and last frames, each on the animation's own figure with that frame's artists drawn.

Times measured on the shared 2-core machine (loaded, warm disk cache): overcentre about 16 s (its computation is
cached per process, which other paper tests share); under ``slow``: nose gear 16 s, design_optimum 15 s (a minute
more when the dual-sidestay gear is first built), dynamics 36 s, dual_sidestay (quick) 29 s, shimmy 32-46 s (its
time simulations 20 s), freefall 91 s (its bisections and damping study); the documented commands are reviewed on
the session's run of the documents' examples (tests/doc_runs.py), which tests/test_doc_examples.py checks. A
section runs once per test session, in whichever worker process asks first (:func:`section_run`): the check of the
numbers the docs quote from the freefall section reads that run's summary lines (0.1 s of CPU) instead of computing
the dual-sidestay freefall table again (30 s of CPU), and tests/test_freefall_paper.py and
tests/test_dual_sidestay.py check the summaries of the freefall and dual_sidestay (quick) runs made here (they ran
each section again, 90 s and 29 s), tests/test_paper.py those of the overcentre and design_optimum runs (and compares
the overcentre's with its own run of `mechcont paper`) and tests/test_dynamics_paper.py the dynamics run's, each
figure of those two checked by figure_checks.check_figure in the run (they ran each section again: 8 s of CPU each
and the overcentre's twice). The paper's GIF frames: 15 s of CPU (the retraction continued and animated), written
once per session (:func:`retraction_gif`) for the review here and tests/test_paper_animation.py's frame count (which
animated the retraction again, 12 s).
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import re
import shutil
import tempfile
import warnings
from dataclasses import dataclass
from pathlib import Path

import pytest
from figure_checks import drawn, review_problems

ROOT = Path(__file__).resolve().parent.parent
#: Written at this resolution: enough for every measure, a quarter of the pixels of 100 dpi.
DPI = 50
IMAGE = re.compile(r"!\[[^\]]*\]\(([^)\s]+)\)")


@contextlib.contextmanager
def capturing(order: list | None = None):
    """Context: ``{file name: figure}`` of every figure saved inside it (written at :data:`DPI`); ``order``, if given,
    gets each saved file's name as it is saved (a name saved twice, twice)."""
    import matplotlib.figure

    figures: dict[str, object] = {}
    save = matplotlib.figure.Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        name = Path(str(fname)).name
        m = re.match(r"^\.(.+)\.mechcont-\d+-", name)   # atomic_write's temporary file: .<stem>.mechcont-<pid>-…
        name = (m.group(1) + Path(name).suffix) if m else name
        figures[name] = self
        if order is not None:
            order.append(name)
        kwargs["dpi"] = DPI
        return save(self, fname, *args, **kwargs)

    with _patched(matplotlib.figure.Figure, "savefig", savefig):
        yield figures


def sampled_frames(n: int) -> list[int]:
    """The frames of an ``n``-frame animation reviewed: the first, the middle and the last."""
    return sorted({0, n // 2, n - 1})


@contextlib.contextmanager
def reviewing_animations():
    """Context: ``{file name: [problems]}`` of every animation written inside it (``animate``: GIF, HTML or MP4),
    its :func:`sampled_frames` reviewed as drawn: the animation's own Matplotlib figure with the frame's artists in
    it, measured by :func:`figure_checks.review_problems` after the frame is written and before the next is drawn
    (a full draw of the figure, which the next frame's fixed image overwrites)."""
    from mechcont.outputs import animation

    found: dict[str, list[str]] = {}
    current = [""]
    animate, frame_pixels = animation.animate, animation._frame_pixels

    def named(system, branch, path, *args, **kwargs):
        current[0] = Path(str(path)).name
        found[current[0]] = []
        return animate(system, branch, path, *args, **kwargs)

    def reviewed(renderer, n, **kwargs):
        sample = sampled_frames(n)
        for k, rgba in enumerate(frame_pixels(renderer, n, **kwargs)):
            yield rgba
            if k in sample:
                found[current[0]] += review_problems(renderer.fig, f"{current[0]} frame {k + 1} of {n}")

    with _patched(animation, "animate", named), _patched(animation, "_frame_pixels", reviewed):
        yield found


@contextlib.contextmanager
def _patched(owner, name: str, value):
    """Context: ``owner.name`` is ``value`` inside, as it was after."""
    was = getattr(owner, name)
    setattr(owner, name, value)
    try:
        yield
    finally:
        setattr(owner, name, was)


@pytest.fixture
def captured():
    """``{file name: figure}`` of every figure saved while the test runs (:func:`capturing`)."""
    with capturing() as figures:
        yield figures


@pytest.fixture
def animations():
    """``{file name: [problems]}`` of every animation written while the test runs (:func:`reviewing_animations`)."""
    with reviewing_animations() as found:
        yield found


#: The sections whose figures :func:`figure_checks.check_figure` checks in the run (tests/test_paper.py and
#: tests/test_dynamics_paper.py read what it finds).
CHECKED = ("overcentre", "dynamics")


@dataclass(frozen=True)
class SectionRun:
    """A paper section run once: its summary ``lines``, ``timings``, the files it ``wrote`` (figures and GIFs), their
    ``sizes`` (bytes) and first bytes (``heads``, the file type's signature), those it saved through Matplotlib
    (``saved``; ``saves``: each save's file name in order), the animations whose frames were reviewed (``animated``),
    the ``problems`` the review finds and, for a section of :data:`CHECKED`, those :func:`figure_checks.check_figure`
    finds (``checks``: units on every axis, legends naming only what is drawn, texts inside their axes; checked as the
    figures stand after the run; ``None`` for another section)."""

    lines: list
    timings: dict
    written: set
    sizes: dict
    heads: dict
    saved: set
    saves: list
    animated: set
    problems: list
    checks: list


def section_run(section: str, shared) -> SectionRun:
    """The paper section ``section`` run once per test session (``shared``: conftest.py's fixture; its figure review
    here, the check of the numbers the docs quote from its summary, and the checks of its summary in
    tests/test_freefall_paper.py and tests/test_dual_sidestay.py share it, whichever worker process asks first
    running it) into a scratch folder, with RuntimeWarnings as errors (Matplotlib's "overflow encountered in dot",
    issue 37, item 8); every figure reviewed as it stands when the run ends, every animation frame by frame."""
    return shared.get(f"section-{section}", functools.partial(_section_run, section))


def _section_run(section: str) -> SectionRun:
    """The paper section ``section`` run into a scratch folder and reviewed (see :func:`section_run`)."""
    module = importlib.import_module(f"mechcont.paper.{section}")
    options = {"quick": True} if section == "dual_sidestay" else {}   # the same figures, fewer scan points, no GIF
    timings: dict[str, float] = {}
    saves: list[str] = []
    with tempfile.TemporaryDirectory(prefix=f"mechcont-review-{section}-") as folder:
        with warnings.catch_warnings(), capturing(saves) as figures, reviewing_animations() as animations:
            warnings.simplefilter("error", RuntimeWarning)
            lines = module.run(Path(folder), True, timings, **options)
            problems = [p for name, fig in sorted(figures.items()) for p in review_problems(fig, name)]
            checks = [c for name, fig in sorted(figures.items()) for c in _checked(fig, name)] if section in CHECKED else None
        files = [p for p in Path(folder).iterdir() if p.suffix in (".png", ".gif")]
        sizes = {p.name: p.stat().st_size for p in files}
        heads = {p.name: p.read_bytes()[:8] for p in files}
    problems += [p for name in sorted(animations) for p in animations[name]]
    return SectionRun(lines, timings, set(sizes), sizes, heads, set(figures), saves, set(animations), problems, checks)


def _checked(fig, name: str) -> list[str]:
    """What :func:`figure_checks.check_figure` finds wrong in ``fig`` (its first failure), as a list."""
    from figure_checks import check_figure

    try:
        check_figure(fig, name)
    except AssertionError as e:
        return [str(e)]
    return []


#: The freefall section last: tests/test_freefall_paper.py, collected right after this file (conftest.py), asks for
#: it too, so that with two pytest-xdist workers the other worker computes it while this one reviews the rest (when
#: it came fifth, this worker reached it first and the other waited for it, or the other way round).
SECTIONS = [pytest.param("overcentre"),
            *(pytest.param(s, marks=pytest.mark.slow) for s in ("nose_gear", "dynamics", "design_optimum",
                                                                 "dual_sidestay", "shimmy", "freefall"))]


@pytest.mark.parametrize("section", SECTIONS)
def test_every_figure_of_a_paper_section_passes_the_review_and_is_shown(section, shared):
    run = section_run(section, shared)
    if section == "dual_sidestay":   # the drawings' time is in timings.txt (it was left out: 17 s of the section)
        assert {"dual_sidestay: 3-D drawings, gear down and up",
                "dual_sidestay: 3-D drawing of the generated gear"} <= set(run.timings)
    assert run.written and run.saved >= {n for n in run.written if n.endswith(".png")}
    assert run.animated == {n for n in run.written if n.endswith(".gif")}   # each GIF's frames were reviewed
    assert not run.problems, "\n".join(run.problems)
    shown = set(IMAGE.findall("\n".join(run.lines)))
    assert run.written <= shown, f"named or written but not shown in the summary: {sorted(run.written - shown)}"


@pytest.mark.slow
@pytest.mark.parametrize("section", ["freefall", "design_optimum"])
def test_the_docs_quote_what_the_section_prints(section, shared):
    """Every number the docs quote from a paper section (the freefall's: the dual-sidestay freefall's summary lines;
    the reliability-based optima; see tests/test_doc_numbers.py) is what the section's run prints: the run the
    review above makes, not another."""
    from test_doc_numbers import DOCUMENTS

    from mechcont.paper.doc_numbers import COMMANDS, QUOTES, mismatches, quoted

    assert {q.source for q in QUOTES.values()} - set(COMMANDS) == {"freefall", "design_optimum"}   # each checked
    printed = {section: "\n".join(section_run(section, shared).lines)}
    assert set(quoted(printed)) == {n for n, q in QUOTES.items() if q.source == section}
    wrong = [(path.name, *m) for path in DOCUMENTS for m in mismatches(path.read_text(encoding="utf-8"), printed)
             if m[0] in QUOTES and QUOTES[m[0]].source == section]
    assert not wrong, f"quoted numbers that are not the run's (fill them: python -m mechcont.paper.doc_numbers): {wrong}"


@dataclass(frozen=True)
class GifRun:
    """The paper's retraction GIF written once: the frames ``animate`` reported (``n``), those in the file
    (``frames``), the animations whose frames were reviewed (``animated``, file names) and what the review found in
    each (``problems``)."""

    n: int
    frames: int
    animated: list
    problems: dict


def retraction_gif(shared) -> GifRun:
    """The paper's GIF (``sidestay_retraction.gif``, the dual-sidestay section's full run; its quick run draws no GIF)
    written once per test session (``shared``: conftest.py's fixture; this file's review and
    tests/test_paper_animation.py's frame count share it): the retraction continued and animated as the section does
    (``dual_sidestay.retraction_animation``), with RuntimeWarnings as errors, its sampled frames reviewed."""
    return shared.get("retraction-gif", _retraction_gif)


def _retraction_gif() -> GifRun:
    """The paper's GIF written into a scratch folder and reviewed (see :func:`retraction_gif`)."""
    from figure_checks import gif_frames

    from mechcont.models.dual_sidestay import build_dual_sidestay_kinematics
    from mechcont.models.dual_sidestay_geometry import DEFAULT_GEOMETRY
    from mechcont.paper import dual_sidestay

    ret = dual_sidestay.retraction(DEFAULT_GEOMETRY, base=build_dual_sidestay_kinematics(DEFAULT_GEOMETRY))
    with tempfile.TemporaryDirectory(prefix="mechcont-review-gif-") as folder:
        path = Path(folder) / dual_sidestay.ANIMATION[0]
        with warnings.catch_warnings(), reviewing_animations() as animations:
            warnings.simplefilter("error", RuntimeWarning)
            n = dual_sidestay.retraction_animation(ret, DEFAULT_GEOMETRY, path)
        return GifRun(n, gif_frames(path), list(animations), animations)


@pytest.mark.slow
def test_every_sampled_frame_of_the_papers_retraction_gif_passes_the_review(shared):
    """The paper's GIF (:func:`retraction_gif`): the first, middle and last frames reviewed. About 15 s warm."""
    from mechcont.paper import dual_sidestay

    gif = retraction_gif(shared)
    assert gif.n > 3 and gif.animated == [dual_sidestay.ANIMATION[0]]
    assert not gif.problems[dual_sidestay.ANIMATION[0]], "\n".join(gif.problems[dual_sidestay.ANIMATION[0]])


def _figure_documents() -> list[Path]:
    """The README and docs whose examples draw a figure (``--plot``, ``draw``, ``animate``)."""
    from doc_runs import writes_figure
    from test_doc_examples import DOCUMENTS, _arguments, examples

    return [path for path in DOCUMENTS
            if any(kind == "run" and writes_figure(_arguments(text)) for kind, text in examples(path))]


@pytest.mark.slow
@pytest.mark.parametrize("document", _figure_documents(), ids=lambda p: p.name)
def test_every_figure_of_the_documented_commands_passes_the_review(document, shared):
    """Every figure a document's commands draw, on the session's run of its examples (``doc_runs.document_run``,
    whose commands tests/test_doc_examples.py checks run clean): each figure a command saves through Matplotlib is
    reviewed in the command's process once it has run, at the figure's dpi, an animation's sampled frames as drawn
    (:func:`reviewing_animations`). Each command that draws has its figures reviewed (it runs in a forked process,
    where the review is), its animations among them."""
    from doc_runs import document_run, writes_figure
    from test_doc_examples import outputs

    run = document_run(document, shared)
    failed = [(c.text, c.returncode, c.stderr[-2000:]) for c in run.ran() if c.returncode]
    assert not failed and len(run.ran()) == sum(kind == "run" for kind, _ in run.steps), failed
    for command in run.ran():
        if writes_figure(list(command.args)):
            assert not command.fresh and command.figures, f"{document.name}: `{command.text}`: no figure reviewed"
        if command.args[0] == "animate":   # each animation's frames were reviewed
            assert {Path(o).name for o in outputs(list(command.args))} <= set(command.figures), command.text
    problems = [p for command in run.ran() for name, found in sorted(command.figures.items()) for p in found]
    assert not problems, "\n".join(problems)


def test_the_sampled_frames_of_an_animation_are_reviewed_as_drawn(overcentre, tmp_path, animations, monkeypatch):
    """A GIF of the overcentre mechanism along a short branch: its first, middle and last frames are reviewed, each
    with its own artists: a label pushed out of the figure in the middle frame only is found there and in no other
    frame, and the GIF still holds every frame."""
    from figure_checks import gif_frames

    from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
    from mechcont.outputs import animation

    x0 = find_equilibrium(overcentre, hold={"theta1": 0.3}, free=["F"])
    branch = continuation(overcentre, x0, "F", options=ContinuationOptions(bounds={"F": (-40.0, 0.0)}, max_steps=6))
    n = len(animation.frame_rows(animation.branch_frames(overcentre, branch)))
    render = animation._Renderer.render

    def stray_label(self, k):   # the middle frame writes a label beyond the figure's right edge
        out = render(self, k)
        if k == n // 2:
            self._current.append(self.axes[0].text(1.6, 0.5, "stray", transform=self.axes[0].transAxes))
            out.append(self._current[-1])
        return out

    monkeypatch.setattr(animation._Renderer, "render", stray_label)
    assert animation.animate(overcentre, branch, tmp_path / "stray.gif", hold=0.0) == n >= 5
    assert list(animations) == ["stray.gif"] and len(animations["stray.gif"]) == 1, animations
    assert f"frame {n // 2 + 1} of {n}" in animations["stray.gif"][0] and "stray" in animations["stray.gif"][0]
    assert gif_frames(tmp_path / "stray.gif") == n


def test_an_annotated_load_is_printed_once_with_its_sign_and_direction(overcentre, tmp_path):
    """lp1.png of the README's tour: the fold at F = -75.58 N was printed F = -75.58 N in the note and F = 75.6 N on
    its arrow. Now the note gives the signed value and the direction a positive F acts in (up: the arrow,
    unlabelled, points down), and no other text of the drawing names F."""
    import numpy as np

    from mechcont.outputs.drawing import draw

    x = overcentre.defaults().copy()
    x[overcentre.index("F")] = -75.58
    scene = overcentre.scene(x)
    (vector,) = [v for name, _, v in scene.forces if name == "F"]
    assert vector[1] < 0 and abs(vector[0]) < 1e-12   # acts down: a positive F acts up
    ax = draw(overcentre, x, annotate=("F",))
    texts = [t.get_text() for t in ax.texts if "F =" in t.get_text()]
    assert len(texts) == 1 and "F = -75.58 N (+ up)" in texts[0]
    assert np.isfinite(vector).all()


@pytest.mark.slow
def test_the_readme_images_are_what_the_paper_draws_now():
    """docs/readme-images.json records the fingerprint of what each README image shows; the figures the paper draws
    now show the same (else: bash run.sh paper --readme-images docs). About 15 s (the overcentre and nose-gear
    computations)."""
    from mechcont.paper.readme_images import README_IMAGES, stale

    assert stale(ROOT / "docs") == []
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    for name in README_IMAGES:
        assert f"(docs/{name})" in readme


def test_a_fingerprint_follows_the_data_and_the_style_not_the_pixels():
    """The same figure drawn at two resolutions has one fingerprint, and with a point moved by a part in 1e9; a data
    point moved by a part in a hundred, or a colour changed, gives another."""
    from matplotlib.figure import Figure

    from mechcont.paper.readme_images import fingerprint

    def figure(y, colour="k", size=(4, 3), dpi=100):
        fig = Figure(figsize=size, dpi=dpi)
        ax = fig.add_subplot()
        ax.plot([0.0, 1.0, 2.0], y, color=colour, label="curve")
        ax.set_xlabel("x (m)")
        ax.legend()
        return fig

    base = fingerprint(figure([0.0, 1.0, 4.0]))
    assert fingerprint(figure([0.0, 1.0, 4.0], dpi=50)) == base
    assert fingerprint(figure([0.0, 1.0, 4.0 + 1e-9])) == base
    assert fingerprint(figure([0.0, 1.01, 4.0])) != base
    assert fingerprint(figure([0.0, 1.0, 4.0], colour="tab:blue")) != base


@pytest.mark.slow
def test_the_nose_gear_freefall_figure_shows_every_run_to_its_end_and_the_failure_short_of_the_stop(tmp_path,
                                                                                                    monkeypatch):
    """Issue 37, item 4: the figure plotted the main fitting's angle, identical for a run that locks and one whose
    lock links hover short of their stop, and cut the time axis before the failing run's end. Now: the lock links'
    angle from their stop, the time axis to the end of every run, the locked runs ending on the stop (0) and the
    failing run's last half second short of it, inside the enlarged panel. About 10 s (six freefalls)."""
    import numpy as np

    from mechcont.dynamics.freefall import freefall
    from mechcont.models import model_from_text
    from mechcont.outputs import plotting
    from mechcont.paper import freefall as section
    from mechcont.paper._freefall_figures import nose_gear_figure

    system = model_from_text(section.description_text(), "nose_gear_freefall.toml")
    runs = [(U, freefall(system, {"fitting": section.THETA_UP}, lock="downlock", until=section.UNTIL,
                         values={"U": U})) for U in section.AIRSPEEDS]
    assert [r.locked for _, r in runs].count(False) == 1   # U = 125 m/s does not lock
    figs = []
    monkeypatch.setattr(plotting, "save_figure", lambda fig, path, **kw: figs.append(fig))
    stop = next(st for st in system.stops if st.name == "downlock")
    nose_gear_figure(runs, stop.limit, tmp_path / "f.png")
    (fig,) = figs
    whole, near = fig.axes
    assert whole.get_xlim()[1] >= max(r.history.t[-1] for _, r in runs) - 1e-12
    assert "stop" in whole.get_ylabel()
    lo, hi = near.get_ylim()
    for (_, r), line in zip(runs, near.get_lines()[1:]):   # the first line is the stop's (0)
        t, gap = line.get_xdata(), line.get_ydata()
        assert np.allclose(t, r.history.t) and np.allclose(gap, np.degrees(r.history["overcentre"] - stop.limit))
        tail = gap[t >= t[-1] - 0.5]
        if r.locked:
            assert abs(gap[-1]) < 1e-6
        else:
            assert np.all(tail < -1e-3) and np.all(tail > lo)   # short of the stop, inside the enlarged panel
    assert not review_problems(fig, "freefall_nose_gear.png")


def test_the_sidestay_table_gives_strike_speeds_in_degrees_per_second():
    """summary.md gave a lock-link pair's strike speed as the rate of its condition, a sine ("sine per second"). The
    cell now holds the lock links' angular speed: checked against a central difference of asin(s(t)) across the
    strike, s moving at the event's rate through the stop's sine."""
    import math
    from types import SimpleNamespace

    from mechcont.paper.freefall_sidestay import LOCKS, _row

    limit, rate, t0 = math.sin(math.radians(2.0)), 75.3, 1.5893
    event = [SimpleNamespace(stop=n, kind="impact", time=t0, speed=rate) for n in LOCKS]
    run = SimpleNamespace(history=SimpleNamespace(stop_events=event), outcome="locked",
                          stops={n: SimpleNamespace(time=t0) for n in LOCKS}, peak_damper={"actuator": 4.5e4})
    cells = [c.strip() for c in _row(5e7, 0.7, run, {n: limit for n in LOCKS}).strip("|").split("|")]
    h = 1e-6
    psi = [math.asin(limit + rate * dt) for dt in (-h, h)]
    expected = math.degrees((psi[1] - psi[0]) / (2 * h))
    assert cells[3] == f"{1e3 * t0:.1f} ({expected:.0f} deg/s)"


def test_the_stability_chart_of_a_hopf_point_passes_the_review(tmp_path, captured, monkeypatch):
    """docs/reference.md's `folds MODEL --point BRANCH.csv:HB1 --along P2 --plot chart.png` (no runnable block
    draws it), on the README's ab model: the words ``stable`` and ``unstable`` overlapped each other beside the
    curve's middle and the legend lay in the axes; now each word is in its own side's largest empty area, the
    legend below the axes, and the chart passes the review. About 5 s."""
    from click.testing import CliRunner

    from mechcont.cli._app import _register, cli

    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    _register()
    for args in (["continue", "examples/ab.toml", "--set", "B=17", "--vary", "D", "--bounds", "D=0:0.2", "--out",
                  "ab.csv"],
                 ["folds", "examples/ab.toml", "--set", "B=17", "--point", "ab.csv:HB1", "--along", "B", "--bounds",
                  "B=10:20", "--out", "hopf.csv", "--plot", "chart.png"]):
        r = CliRunner().invoke(cli, args)
        assert r.exit_code == 0, r.output[-2000:]
    fig = captured["chart.png"]
    (ax,) = fig.axes
    assert {t.get_text() for t in ax.texts} >= {"stable", "unstable"}
    assert ax.get_legend() is None and fig.legends   # below the axes
    problems = review_problems(fig, "chart.png")
    assert not problems, "\n".join(problems)


def test_side_words_go_to_the_middle_of_the_largest_empty_area_of_their_side():
    """A boundary y = x across the unit square (first side above it): each word lands on its own side, inside
    the axes, clear of a large marker put at the upper triangle's centroid and clear of the boundary, and, with
    the marker there, away from the centroid; with a coarse grid of small dots everywhere, the words still find
    a gap between them."""
    import numpy as np
    from matplotlib.figure import Figure

    from mechcont.outputs._regions import label_sides

    def figure(dots: bool):
        fig = Figure(figsize=(5, 4), dpi=100, layout="constrained")
        ax = fig.add_subplot()
        ax.plot([0, 1], [0, 1], "-", color="tab:blue", label="boundary")
        ax.plot([1 / 3], [2 / 3], "*", ms=30, color="k", label="marker")
        if dots:
            g = np.linspace(0.05, 0.95, 10)
            ax.plot(*np.meshgrid(g, g), ".", ms=3, color="0.5")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        t = np.linspace(0, 1, 50)
        words = label_sides(ax, np.column_stack([t, t]), np.tile([-1.0, 1.0], (50, 1)), np.ones(50, bool),
                            (("above", "g"), ("below", "r")))
        return fig, ax, words

    for dots in (False, True):
        fig, ax, words = figure(dots)
        assert [w.get_text() for w in words] == ["above", "below"]
        (xa, ya), (xb, yb) = (w.get_position() for w in words)
        assert ya > xa and yb < xb
        assert np.hypot(xa - 1 / 3, ya - 2 / 3) > 0.1   # not on the marker
        assert not review_problems(fig, f"sides (dots: {dots})")
        renderer = drawn(fig)
        marker = ax.transData.transform([[1 / 3, 2 / 3]])[0]
        for w in words:
            e = w.get_window_extent(renderer)
            assert ax.bbox.x0 <= e.x0 and e.x1 <= ax.bbox.x1 and ax.bbox.y0 <= e.y0 and e.y1 <= ax.bbox.y1
            corners = np.array([[e.x0, e.y0], [e.x1, e.y1], [e.x0, e.y1], [e.x1, e.y0]])
            data = ax.transData.inverted().transform(corners)
            assert np.all(np.sign(data[:, 1] - data[:, 0]) == np.sign(w.get_position()[1] - w.get_position()[0]))
            assert not (e.x0 - 15 < marker[0] < e.x1 + 15 and e.y0 - 15 < marker[1] < e.y1 + 15)
            if dots:
                grid = np.meshgrid(*[np.linspace(0.05, 0.95, 10)] * 2)
                g = ax.transData.transform(np.column_stack([a.ravel() for a in grid]))
                assert not np.any((g[:, 0] > e.x0) & (g[:, 0] < e.x1) & (g[:, 1] > e.y0) & (g[:, 1] < e.y1))
