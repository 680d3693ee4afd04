"""`optimize` over two design parameters on the nose gear's design map (issue 24, item 2): the optimum lies on the
boundary the map's F = 100 contour shows (to the map's resolution) and beats the best point of a grid study at the
same constraint; `--plot` draws it."""

import numpy as np
import pytest

from mechcont.analysis.optimize import Constraint, optimize, optimum_map
from mechcont.models import load_model

BOUNDS = {"l_sp1": (-0.175, 0.175), "LU": (1.25, 1.35)}
BOUND = 100.0


@pytest.fixture(scope="module")
def nose_gear():
    return load_model("nose_gear")


@pytest.fixture(scope="module")
def longest(nose_gear):
    cons = [Constraint.parse(f"downlock_force >= {BOUND:g}")]
    result = optimize(nose_gear, "LU", BOUNDS, maximize=True, constraints=cons, starts=2)
    return result, optimum_map(nose_gear, result, BOUNDS, constraints=cons)


def test_optimum_lies_on_the_maps_contour(nose_gear, longest):
    import contourpy

    from mechcont.analysis.downlock import downlock_point

    result, omap = longest
    # the longest LU with 100 N of downlock force is at the end of the attachment's range
    assert result.success and [w for w, _ in result.active] == ["downlock_force >= 100", "l_sp1 >= -0.175"]
    x, y = omap.optimum
    F = downlock_point(nose_gear, {"l_sp1": x, "LU": y})[nose_gear.index("F")]
    assert F == pytest.approx(BOUND, rel=1e-8)  # re-solved: on the boundary exactly
    region = omap.region
    hx, hy = region.x[1] - region.x[0], region.y[1] - region.y[0]
    lines = contourpy.contour_generator(region.x, region.y, region.force).lines(BOUND)
    pts = np.vstack(lines)
    # the map's F = 100 contour passes within one grid cell of the optimum, and the optimum is where that contour
    # reaches its highest LU (to the map's resolution)
    assert np.min(np.maximum(np.abs(pts[:, 0] - x) / hx, np.abs(pts[:, 1] - y) / hy)) <= 1.0
    assert abs(pts[:, 1].max() - y) <= hy
    # the exactly continued boundary passes through the optimum and never above it in LU
    (what, bx, by), (edge, ex, _) = omap.boundaries
    assert what == "downlock_force >= 100" and edge == "l_sp1 >= -0.175" and np.all(ex == -0.175)
    assert np.min(np.hypot((bx - x) / hx, (by - y) / hy)) < 1e-6
    assert by.max() <= y + 1e-9


def test_one_start_finds_the_local_optimum_on_the_fold_locus(nose_gear, longest):
    """From the model's design SLSQP stops where the F = 100 contour turns in LU: grad F is along LU there, so
    dF/dl_sp1 = 0, a fold of the design map (an extremum of F in l_sp1); the multi-start optimum is longer."""
    from mechcont.analysis.sensitivity import downlock_sensitivity

    local = optimize(nose_gear, "LU", BOUNDS, maximize=True, constraints=[Constraint.parse("downlock_force >= 100")])
    assert local.success and local.quantities["downlock_force"] == pytest.approx(BOUND, rel=1e-8)
    s = downlock_sensitivity(nose_gear, ["l_sp1", "LU"], local.design)
    assert abs(s["l_sp1"]) < 1e-5 * abs(s["LU"])
    assert local.value < longest[0].value


def test_optimum_beats_the_best_grid_point(tmp_path, longest):
    from mechcont.analysis.study import GridAxis, StudySpec, run_study

    result, _ = longest
    spec = StudySpec("nose_gear", "grid", (("l_sp1", GridAxis(*BOUNDS["l_sp1"], 15)), ("LU", GridAxis(*BOUNDS["LU"], 15))))
    df = run_study(spec, tmp_path / "grid").frame()
    ok = df[(df["status"] == "converged") & (df["downlock_force"] >= BOUND)]
    assert len(ok) > 10
    best = float(ok["LU"].max())
    assert result.value > best
    assert result.value - best < (BOUNDS["LU"][1] - BOUNDS["LU"][0]) / 14  # within a grid step: the same optimum


def test_cli_plot_writes_the_map_and_refuses_one_parameter(tmp_path):
    from cli_helpers import make_runner, one_line_error

    run = make_runner()
    png = tmp_path / "opt.png"
    r = run("optimize", "nose_gear", "--maximize", "LU", "--design", "l_sp1=-0.175:0.175", "--design", "LU=1.25:1.35",
            "--constraint", "downlock_force >= 100", "--starts", "2", "--plot", png)
    assert r.exit_code == 0, r.output
    assert png.read_bytes().startswith(b"\x89PNG") and f"wrote {png}" in r.output
    one_line_error(run("optimize", "nose_gear", "--maximize", "LU", "--design", "LU=1.25:1.35", "--constraint",
                       "downlock_force >= 100", "--plot", tmp_path / "x.png"), "--plot", "two")
    assert not (tmp_path / "x.png").exists()


def test_optimum_figure_marks_optimum_and_boundary(longest, monkeypatch):
    from figure_checks import check_figure

    from mechcont.outputs.design_plots import optimum_figure

    result, omap = longest
    fig = optimum_figure(omap, title="nose gear: longest LU", value_text=f"LU = {result.value:.4g} m")
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "active: downlock_force >= 100" in labels and any(t.startswith("optimum: LU = 1.29") for t in labels)
    check_figure(fig, "optimum")
