"""`mechcont paper`: figures and a summary whose numbers agree with the closed form.

The command runs end to end here (``paper_dir``: the overcentre section, every cache of it cleared first; again only
when the session's review run of the section was made in another process); the sections' other checks read the runs
tests/test_figure_review.py makes once per session (``section_run``)."""

import re

import pytest
from click.testing import CliRunner

from mechcont.cli._app import _register, cli


def _clear_overcentre_caches():
    """Forget the overcentre section's results computed in this process (its next run computes everything again)."""
    from mechcont.paper import overcentre

    for f in (overcentre.system, overcentre._start, overcentre.branch):
        f.cache_clear()
    overcentre._SWEEPS.clear()


@pytest.fixture(scope="module")
def paper_dir(tmp_path_factory, shared):
    """`mechcont paper --only overcentre` run in full: every result of the section computed afresh, after the
    session's review run of the section (``section_run``) was made, in this process or another (the former the run
    test_summary_is_the_same_on_every_run compares with)."""
    from test_figure_review import section_run

    section_run("overcentre", shared)
    _clear_overcentre_caches()
    _register()
    out = tmp_path_factory.mktemp("paper")
    r = CliRunner().invoke(cli, ["paper", "--out", str(out), "--only", "overcentre", "--quiet"])
    assert r.exit_code == 0, r.output
    assert r.output == ""
    return out


def test_overcentre_figures_written(paper_dir):
    names = {p.name for p in paper_dir.glob("*.png")}
    for stem in ("fig3b", "fig4a", "fig4b", "fig4c", "fig5a", "fig5b", "fig5c"):
        assert any(n.startswith(stem) for n in names), stem
    for p in paper_dir.glob("*.png"):
        assert p.read_bytes().startswith(b"\x89PNG") and p.stat().st_size > 10_000


def test_summary_reports_folds_cusp_and_downlock_length(paper_dir):
    text = (paper_dir / "summary.md").read_text()
    errors = [float(e) for e in re.findall(r"\| ([0-9.]+e[-+][0-9]+) \|", text)]
    assert errors and max(errors) < 1e-8
    cusp = re.search(r"Cusp \(CP\) on the fold curve at LU = ([0-9.]+) m", text)
    assert cusp and float(cusp.group(1)) == pytest.approx(1.5, rel=1e-9)
    lu0 = re.search(r"crosses F = 0 at LU = ([0-9.]+) m", text)
    assert lu0 and 1.1 < float(lu0.group(1)) < 1.3


def test_unknown_section_is_an_error(tmp_path):
    _register()
    r = CliRunner().invoke(cli, ["paper", "--out", str(tmp_path / "p"), "--only", "nope"])
    assert r.exit_code == 2 and "unknown section" in r.stderr
    assert not (tmp_path / "p").exists()


def test_summary_is_the_same_on_every_run(paper_dir, shared, tmp_path):
    """summary.md holds results only: a second run in this process, each computing everything itself, gives the
    same bytes (floats are compared bit for bit only within one process): the session's review run of the section
    when this process made it (before the command's run cleared every cache), else the command run again with the
    caches cleared; run times go to timings.txt; no Python True/False in the prose."""
    from test_figure_review import section_run

    from mechcont.paper.sections import summary_header

    text = (paper_dir / "summary.md").read_text()
    assert "computed in" not in text and " took " not in text
    assert not re.search(r"\b(True|False|None|nan)\b", text)
    assert (paper_dir / "timings.txt").read_text().startswith("run times")
    if shared.computed_here("section-overcentre"):
        other = "\n".join([*summary_header(), *section_run("overcentre", shared).lines]).rstrip("\n") + "\n"
        assert (paper_dir / "summary.md").read_bytes() == other.encode()
        return
    _clear_overcentre_caches()
    _register()
    r = CliRunner().invoke(cli, ["paper", "--out", str(tmp_path), "--only", "overcentre", "--quiet"])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "summary.md").read_bytes() == (paper_dir / "summary.md").read_bytes()


def test_fig3b_shows_the_bistability_at_20_newtons(paper_dir):
    """The branch spans the whole force range: at the paper's F = 20 N two stable equilibria and an unstable one."""
    from mechcont.paper.overcentre import F_RANGE, _equilibria_at, branch

    b = branch(0.4)
    assert b["F"].min() == pytest.approx(F_RANGE[0]) and b["F"].max() == pytest.approx(F_RANGE[1])
    eq = _equilibria_at(b, 20.0)
    assert [st for _, st in sorted(eq)] == [True, False, True]
    text = (paper_dir / "summary.md").read_text()
    assert "At F = 20 N the equilibria are theta1 = -73.6 deg (stable), -4.2 deg (unstable), 75.4 deg (stable)" in text


def test_overcentre_figures_have_units_honest_legends_and_labels_inside(shared):
    """Each figure of the section's run (the session's review run) saved once under its own name, and
    :func:`figure_checks.check_figure` finds nothing wrong in any."""
    from test_figure_review import section_run

    run = section_run("overcentre", shared)
    assert len(set(run.saves)) == len(run.saves) >= 7
    assert run.checks == [], "\n".join(run.checks)


def test_fig4a_shows_two_time_simulations_apart_and_no_empty_band(paper_dir, monkeypatch):
    """Issue 25: each time simulation its own style and legend entry; the page cropped to what is drawn."""
    import matplotlib.colors as mcolors
    import numpy as np
    from PIL import Image

    from mechcont.paper import overcentre

    figs = []
    monkeypatch.setattr(overcentre, "save_figure", lambda fig, path, **kw: figs.append(fig))
    overcentre._fig4a(overcentre.compute(), paper_dir / "unused.png")
    ax = figs[0].axes[0]
    legend = ax.get_legend()
    sims = [(t.get_text(), h) for t, h in zip(legend.get_texts(), legend.legend_handles)
            if t.get_text().startswith("time simulation")]
    assert [t for t, _ in sims] == ["time simulation, LU = 0.4 m", "time simulation, LU = 2 m"]
    styles = [(mcolors.to_hex(h.get_color()), h.get_linestyle()) for _, h in sims]
    assert styles[0] != styles[1]
    for colour, style in styles:  # each style is that of a curve drawn
        assert any(mcolors.to_hex(ln.get_color()) == colour and ln.get_linestyle() == style for ln in ax.get_lines())
    with Image.open(next(paper_dir.glob("fig4a*.png"))) as im:
        ink = np.asarray(im.convert("L")) < 240
    rows = np.flatnonzero(ink.any(axis=1))
    assert len(ink) - 1 - rows[-1] < 0.04 * len(ink)   # no empty band at the bottom (was ~100 px of 900)


def test_design_optimum_section_numbers_resolve(shared):
    """The reliability-based design section (the session's run of it, tests/test_figure_review.py's
    ``section_run``): each optimum re-analysed on its own at the printed design (FORM afresh with the tolerances
    centred there gives P = 1e-6; the unlock fold and the downlock force re-solved)."""
    from scipy.stats import norm
    from test_figure_review import section_run

    from mechcont.analysis.downlock import downlock_condition, downlock_point
    from mechcont.analysis.reliability import Variables, downlock_limit_state, form
    from mechcont.analysis.study import Distribution
    from mechcont.analysis.unlock import unlock_folds
    from mechcont.models import load_model

    run = section_run("design_optimum", shared)
    text = "\n".join(run.lines)
    assert run.heads["design_optimum_lockstay.png"].startswith(b"\x89PNG")
    target = norm.isf(1e-6)

    nose = load_model("nose_gear")
    lu = float(re.search(r"free length is LU = ([0-9.]+) m", text).group(1))
    tol = Variables(["LU", "l_sp1"], [Distribution("normal", (lu, 0.01)),
                                      Distribution("truncnormal", (0.1, 0.005, 0.09, 0.11))])
    assert form(downlock_limit_state(nose, ["LU", "l_sp1"], {}), tol).beta == pytest.approx(target, abs=1e-4)
    force = float(re.search(r"its nominal downlock force is ([0-9.]+) N", text).group(1))
    assert force == pytest.approx(downlock_point(nose, {"LU": lu})[nose.index("F")], abs=0.006)

    stay = load_model("lockstay")
    got = re.search(r"least unlock load is ([0-9.]+) N at k = ([0-9.]+) N/m and LU = ([0-9.]+) m", text)
    unlock, k, lu = map(float, got.groups())
    assert k == pytest.approx(10000.0, rel=1e-9)  # at its lower bound: a softer spring would unlock easier still
    tol = Variables(["LU", "k"], [Distribution("normal", (lu, 0.005)), Distribution("normal", (k, 1500.0))])
    assert form(downlock_limit_state(stay, ["LU", "k"], {}), tol).beta == pytest.approx(target, abs=1e-4)
    hold, f = downlock_condition(stay)
    x = downlock_point(stay, {"k": k, "LU": lu})
    assert unlock == pytest.approx(unlock_folds(stay, x, f, released=tuple(hold)).above[f], abs=6e-4)

    # the dual-sidestay gear: the printed design re-solved on its own (locked state, release run to the fold)
    from mechcont.analysis.stop_lock import locked_on_stops, stop_unlock
    from mechcont.paper.dual_sidestay import generated_gear

    got = re.search(r"least unlock load of both pairs together is ([0-9.]+) N at k_lock = ([0-9.]+) N/m and "
                    r"stretch = ([0-9.]+), with each stop's preload at rest at least ([0-9.]+) N m", text)
    unlock, k, st, margin = map(float, got.groups())
    gear = generated_gear()
    x, contact = locked_on_stops(gear, {"k_lock": k, "stretch": st})
    assert set(contact) == {"fwd_stop", "aft_stop"}
    # printed to 0.1 N/m and 1e-6: the reaction moves 0.01 N m per N/m there
    assert min(x[gear.index("R_fwd_stop")], x[gear.index("R_aft_stop")]) == pytest.approx(margin, abs=2e-3)
    assert unlock == pytest.approx(stop_unlock(gear, x, "F_lock", stability=False, both=False).unlock_force, abs=6e-3)
