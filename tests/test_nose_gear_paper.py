"""The nose-gear figures of the paper (Figs. 7-11): trends asserted against fits and closed forms."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from mechcont.models.nose_gear import overcentre_angle
from mechcont.models.nose_gear_geometry import aligned_downlock_force, defaults, downlocked_pose, fold_depth_bound
from mechcont.paper.nose_gear import compute, fit_residual, run, summary


@pytest.fixture(scope="module")
def res():
    return compute()


def test_fig7_no_fold_stable_and_time_simulation_follows(res):
    b = res.fig7_branch
    oc = overcentre_angle(b["theta4"], b["theta5"])
    order = np.argsort(b["F"])
    assert np.all(np.diff(oc[order]) > 0)  # monotone: no fold, no hysteresis with no spring
    assert not b.special("LP") and np.all(b.stable)
    # at 180 deg the force equals half the lock links' weight (dead centre, closed form)
    F180 = np.interp(np.pi, oc[order], b["F"][order])
    assert F180 == pytest.approx((2.5 + 2.0) * 9.81 / 2, abs=1e-3)
    # stated tolerance: the 20 N/s sweep stays within 0.5 deg of the stable branch
    assert res.fig7_max_angle_gap < np.radians(0.5)


def test_downlock_force_matches_slow_time_simulation(res):
    """Continuation vs a 2 N/s ramp of F through theta4 = 0: stated tolerance 0.05 N (0.07 %)."""
    assert res.sweep_downlock_force == pytest.approx(res.downlock_force, abs=0.05)
    assert res.downlock_force == pytest.approx(aligned_downlock_force(defaults()), rel=1e-12)


def test_fig8_quadratic_in_airspeed_only_off_the_dead_centre(res):
    a, m = res.fig8_aligned, res.fig8_misrigged
    assert np.ptp(a["F"]) < 1e-9  # aligned: a dead centre, drag does no virtual work
    assert fit_residual(m["U"], m["F"], 2) < 1e-9  # exactly quadratic ...
    assert fit_residual(m["U"], m["F"], 1) > 1e-2  # ... and not a line
    c = np.polyfit(m["U"], m["F"], 2)
    assert abs(c[1]) < 1e-9 * abs(c[0]) * 100  # F = a + c U^2 (drag ~ U^2)
    dF = m["F"][np.argmax(m["U"])] - m["F"][np.argmin(m["U"])]
    assert -5.0 < dF < 0.0  # small decrease, as in the paper


def test_fig9_linear_in_LU_and_k_with_closed_form_slopes(res):
    lu, kk = res.fig9_LU, res.fig9_k
    assert fit_residual(lu["LU"], lu["F"], 1) < 1e-10
    assert fit_residual(kk["k"], kk["F"], 1) < 1e-10
    p = defaults()
    slope_LU = (aligned_downlock_force({**p, "LU": 1.31}) - aligned_downlock_force({**p, "LU": 1.29})) / 0.02
    slope_k = (aligned_downlock_force({**p, "k": 21000.0}) - aligned_downlock_force({**p, "k": 19000.0})) / 2000.0
    assert np.polyfit(lu["LU"], lu["F"], 1)[0] == pytest.approx(slope_LU, rel=1e-8)
    assert np.polyfit(kk["k"], kk["F"], 1)[0] == pytest.approx(slope_k, rel=1e-8)
    assert slope_LU < 0 < slope_k


def _phi(l, p, q):
    """Closed form: F(l_sp1) has an extremum where LU = s^3 / (s^2 + (L4/2 - l_sp1) dx) (dead centre)."""
    K = np.array([q["x4"], q["y4"]]) - 0.5 * p["L4"] * np.array([1.0, 0.0])
    S4 = K + np.array([0.5 * p["L4"] - l, 0.0])
    S3 = -p["l_sp2"] * np.array([np.cos(q["theta3"] + p["psi3"]), np.sin(q["theta3"] + p["psi3"])])
    dx, dy = S3 - S4
    s2 = dx * dx + dy * dy
    return s2**1.5 / (s2 + (0.5 * p["L4"] - l) * dx)


def test_fig10_two_extrema_where_the_closed_form_puts_them(res):
    b = res.fig10
    order = np.argsort(b["l_sp1"])
    F = b["F"][order]
    interior = np.sign(np.diff(F))
    assert np.count_nonzero(np.diff(interior)) == 2  # a local minimum and a local maximum
    p, q = defaults(), downlocked_pose(defaults())
    for lp in res.fig11_force_branch.special("LP"):
        assert _phi(lp["l_sp1"], p, q) == pytest.approx(1.3, abs=1e-9)


def test_fig11_cusp_where_the_closed_form_puts_it(res):
    cps = res.fig11_fold_curve.special("CP")
    assert len(cps) == 1
    p, q = defaults(), downlocked_pose(defaults())
    best = minimize_scalar(lambda l: _phi(l, p, q), bounds=(-0.175, 0.175), method="bounded",
                           options={"xatol": 1e-10})
    assert cps[0]["LU"] == pytest.approx(best.fun, abs=1e-7)
    assert cps[0]["l_sp1"] == pytest.approx(best.x, abs=1e-4)
    # folds only above the cusp
    assert res.fig11_fold_curve["LU"].min() >= cps[0]["LU"] - 1e-9
    below = [br for br, v in zip(res.fig11_surface, res.fig11_levels) if v < cps[0]["LU"] - 1e-3]
    above = [br for br, v in zip(res.fig11_surface, res.fig11_levels) if cps[0]["LU"] + 1e-3 < v < 1.31]
    assert below and above
    for br in below:
        assert np.all(np.diff(br["F"][np.argsort(br["l_sp1"])]) < 0)  # monotone: no extremum
    for br in above:
        assert np.count_nonzero(np.diff(np.sign(np.diff(br["F"][np.argsort(br["l_sp1"])])))) == 2


def test_design_region_boundary_is_zero_force(res):
    r = res.region
    assert r.boundary is not None and len(r.boundary) > 5
    assert np.max(np.abs(r.boundary["F"])) < 1e-12
    row = min(r.rows, key=lambda q: abs(q.level - 1.3))
    assert len(row.folds) == 2 and row.margin_to_fold == pytest.approx(min(abs(0.1 - f) for f in row.folds))


def test_design_table_against_the_closed_form(res):
    """Each row: the force and its slope at the design point, the F = 0 crossings and the margin
    to them, against the dead-centre closed form (independent of the continuation)."""
    r = res.region
    p = defaults()
    crossings_seen = 0
    for row in r.rows:
        def F(l, lu=row.level):
            return aligned_downlock_force({**p, "LU": lu, "l_sp1": l})

        assert row.force_at_design == pytest.approx(F(0.1), abs=1e-9)
        h = 1e-4
        assert row.slope_at_design == pytest.approx((F(0.1 + h) - F(0.1 - h)) / (2 * h), rel=1e-5)
        ends = [e for iv in row.locking_intervals for e in iv if -0.175 < e < 0.175]
        for e in ends:
            assert abs(F(e)) < 1e-8
        crossings_seen += len(ends)
        if ends:
            assert row.margin_to_zero == pytest.approx(min(abs(0.1 - e) for e in ends), abs=1e-15)
        else:
            assert np.isnan(row.margin_to_zero)
    assert crossings_seen >= 3
    table = r.table()
    assert list(table[0])[:2] == ["LU (m)", "F at l_sp1=0.1 m (N)"]
    assert any(v == "none" for rec in table for v in rec.values())


def test_run_writes_figures_and_summary(tmp_path, res, monkeypatch):
    import mechcont.paper.nose_gear as ng

    monkeypatch.setattr(ng, "compute", lambda: res)
    lines = run(tmp_path, quiet=True)
    for k in (7, 8, 9, 10, 11):
        assert (tmp_path / f"nose_gear_fig{k}.png").stat().st_size > 1000
    assert (tmp_path / "nose_gear_design.png").is_file()
    text = "\n".join(lines)
    assert "Fig. 8" in text and "Reappears" in text and "cusp" in text
    assert summary(res)[0].startswith("## Nose")


def test_fold_band_lies_within_the_bound(res):
    """Every computed fold has |s - LU| <= (a |dx| / s) / (1 - |r|), r = a dx / s^2, a = L4/2 - l_sp1:
    the band's distance from the spring length is bounded by the lock link, which is why it is narrow here."""
    p, q = defaults(), downlocked_pose(defaults())
    K = np.array([q["x4"], q["y4"]]) - 0.5 * p["L4"] * np.array([1.0, 0.0])
    S3 = -p["l_sp2"] * np.array([np.cos(q["theta3"] + p["psi3"]), np.sin(q["theta3"] + p["psi3"])])
    fc = res.fig11_fold_curve
    for l, LU in zip(fc["l_sp1"], fc["LU"]):
        a = 0.5 * p["L4"] - l
        dx, dy = S3[0] - (K[0] + a), S3[1] - K[1]
        s_ = np.hypot(dx, dy)
        r = abs(a * dx) / s_**2
        assert abs(s_ - LU) <= abs(a * dx) / s_ / (1 - r) + 1e-12
        assert abs(s_ - LU) <= fold_depth_bound(p)[0] + 1e-12
    bound, s_min = fold_depth_bound(p)
    assert fc.special("CP")[0]["LU"] >= s_min - bound
    assert 0.0 < bound < p["L4"]


def test_every_figure_has_units_honest_legends_and_labels_inside(res, tmp_path, monkeypatch):
    from figure_checks import check_figure

    import mechcont.paper._nose_gear_figures as ng_figures
    import mechcont.paper.nose_gear as ng

    figs = []
    monkeypatch.setattr(ng_figures, "_save", lambda fig, path: figs.append((fig, path.name)))
    ng._plot_all(res, tmp_path)
    assert len(figs) == 6
    for fig, name in figs:
        check_figure(fig, name)
    # Fig. 10 is drawn through the continuation's points, eight samples per step: no coarse polyline
    fig10 = next(f for f, n in figs if n == "nose_gear_fig10.png")
    (curve,) = [ln for ln in fig10.axes[0].get_lines() if len(ln.get_xdata()) > 10]
    assert len(curve.get_xdata()) == 8 * (len(res.fig10) - 1) + 1
    # the design point is marked with its force and signed lock margin; colour-bar ticks are round numbers
    design = next(f for f, n in figs if n == "nose_gear_design.png")
    ax = design.axes[0]
    star = [ln for ln in ax.get_lines() if ln.get_label().startswith("design point")]
    assert star and tuple(star[0].get_xydata()[0]) == pytest.approx(res.region.design)
    # the force and margin are in the legend, which leaves the F = 0 curve uncovered; the margin says along what
    entries = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any("lock margin +0.149 m along l_sp1" in t for t in entries), entries
    from figure_checks import drawn

    renderer = drawn(design)
    box = ax.get_legend().get_window_extent(renderer)
    (zero,) = [ln for ln in ax.get_lines() if ln.get_label().startswith("F = 0")]
    px = ax.transData.transform(zero.get_xydata())
    assert not np.any((px[:, 0] > box.x0) & (px[:, 0] < box.x1) & (px[:, 1] > box.y0) & (px[:, 1] < box.y1))
    # colour-bar ticks are the levels, round (1-2-5) numbers; the design force is at least two bands from F = 0
    ticks = design.axes[1].get_yticks()
    mantissa = np.abs(ticks[ticks != 0]) / 10.0 ** np.floor(np.log10(np.abs(ticks[ticks != 0])))
    assert np.allclose(mantissa, np.round(mantissa)) and set(np.round(mantissa)) <= {1, 2, 5}
    row = min(res.region.rows, key=lambda r: abs(r.level - res.region.design[1]))
    assert np.sum((ticks > 0) & (ticks < row.force_at_design)) >= 2
