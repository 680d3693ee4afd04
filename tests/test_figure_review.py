"""Issue 37: every figure of ``mechcont paper`` and of the README's and docs' commands, reviewed by measurement.

Each figure is drawn as it is saved (``Figure.savefig`` wrapped: the file is written at a low resolution, which
scales every pixel measure alike) and :func:`figure_checks.review_problems` measures it: no two texts overlapping,
no text outside the figure, no legend over a curve, a marker or a text, no marker cut by the frame, every axis
labelled with its unit, no ragged 3-D surface (Matplotlib pads one with uninitialised memory, whose projection
overflowed on some runs: the sections run with RuntimeWarnings as errors), no leader line through a label. A
paper section also shows every figure it writes in its summary lines (``![...](file)``).

Times on the 2-core machine, warm disk cache: overcentre about 10 s (its computation is cached per process,
which other paper tests share); the rest under ``slow``: nose gear about 15 s, dynamics about 10 s, design_optimum
about 10 s (a minute when the dual-sidestay gear is first built), freefall about 50 s, dual_sidestay (quick) about
20 s, the documented commands about 30 s.
"""

from __future__ import annotations

import importlib
import re
import shutil
from pathlib import Path

import pytest
from figure_checks import review_problems

ROOT = Path(__file__).resolve().parent.parent
#: Written at this resolution: enough for every measure, a quarter of the pixels of 100 dpi.
DPI = 50
IMAGE = re.compile(r"!\[[^\]]*\]\(([^)\s]+)\)")


@pytest.fixture
def captured(monkeypatch):
    """``{file name: figure}`` of every figure saved while the test runs (written at :data:`DPI`)."""
    import matplotlib.figure

    figures: dict[str, object] = {}
    save = matplotlib.figure.Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        name = Path(str(fname)).name
        m = re.match(r"^\.(.+)\.mechcont-\d+-", name)   # atomic_write's temporary file: .<stem>.mechcont-<pid>-…
        figures[(m.group(1) + Path(name).suffix) if m else name] = self
        kwargs["dpi"] = DPI
        return save(self, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", savefig)
    return figures


SECTIONS = [pytest.param("overcentre"),
            *(pytest.param(s, marks=pytest.mark.slow) for s in ("nose_gear", "dynamics", "design_optimum", "freefall",
                                                                 "dual_sidestay"))]


@pytest.mark.filterwarnings("error::RuntimeWarning")   # Matplotlib's "overflow encountered in dot" (issue 37, item 8)
@pytest.mark.parametrize("section", SECTIONS)
def test_every_figure_of_a_paper_section_passes_the_review_and_is_shown(section, tmp_path, captured):
    module = importlib.import_module(f"mechcont.paper.{section}")
    options = {"quick": True} if section == "dual_sidestay" else {}   # the same figures, fewer scan points, no GIF
    lines = module.run(tmp_path, True, {}, **options)
    written = {p.name for p in tmp_path.iterdir() if p.suffix in (".png", ".gif")}
    assert written and set(captured) >= {n for n in written if n.endswith(".png")}
    problems = [p for name, fig in sorted(captured.items()) for p in review_problems(fig, name)]
    assert not problems, "\n".join(problems)
    shown = set(IMAGE.findall("\n".join(lines)))
    assert written <= shown, f"named or written but not shown in the summary: {sorted(written - shown)}"


def _figure_commands():
    """``[(document, [commands up to and including each that writes a figure])]`` of the README and docs."""
    from test_doc_examples import DOCUMENTS, _arguments, examples

    out = []
    for path in DOCUMENTS:
        steps = examples(path)
        runs = [(k, t) for k, t in steps if k == "file" or _writes_figure(_arguments(t))] if steps else []
        if any(k == "run" for k, _ in runs):
            out.append((path, [(k, t) for k, t in steps if k == "file" or _needed(t, runs)]))
    return out


def _writes_figure(args) -> bool:
    return "--plot" in args or (args[0] == "draw")


def _needed(command: str, runs) -> bool:
    """A command that writes a figure, or writes a file (``--out X``) one of them reads."""
    from test_doc_examples import _arguments

    args = _arguments(command)
    if _writes_figure(args):
        return True
    outs = [args[k + 1] for k, a in enumerate(args[:-1]) if a == "--out"]
    return any(o in t for o in outs for k, t in runs if k == "run")


@pytest.mark.slow
@pytest.mark.parametrize("document,steps", _figure_commands(), ids=lambda v: v.name if isinstance(v, Path) else "")
def test_every_figure_of_the_documented_commands_passes_the_review(document, steps, tmp_path, captured,
                                                                   monkeypatch):
    from click.testing import CliRunner
    from test_doc_examples import _arguments

    from mechcont.cli._app import _register, cli

    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    _register()
    for kind, text in steps:
        if kind == "file":
            name, body = text.split("\n", 1)
            (tmp_path / name).write_text(body, encoding="utf-8")
            continue
        r = CliRunner().invoke(cli, _arguments(text))
        assert r.exit_code == 0, f"{document.name}: `{text}`: {r.output[-2000:]}"
    assert captured, f"{document.name}: no figure drawn"
    problems = [p for name, fig in sorted(captured.items()) for p in review_problems(fig, name)]
    assert not problems, "\n".join(problems)


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
