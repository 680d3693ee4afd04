"""The explorer shows families of periodic orbits (issue 35, item 6; issue 36, item 4) and the torsion springs,
rotary dampers and tyres of a mechanism (issue 36, item 1).

Truths: the ``ab`` demo's orbits embedded in the page are solutions of its two rates, integrated here by
scipy from the page's first instant over the page's period; the shimmy gear's poses over one period put the
tyre's contact point a caster length ``e`` behind the swivel along the wheel's heading, and its side force
``F_max tanh(C y / (sigma F_max))`` along the wheel's lateral axis at the point trailed by ``t_p``, each from
the orbit's own state; the amplitude of the page's orbit is the table's max and min (over finer samples).
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error
from scipy.integrate import solve_ivp
from test_pages_offline import offline_problems

from mechcont.continuation import Branch
from mechcont.models import load_model
from mechcont.outputs.explore import page_data, pose_json

run = make_runner()


def _data(page: str) -> dict:
    return json.loads(re.search(r'<script type="application/json" class="mcx-data">(.*?)</script>', page, re.S)
                      .group(1))


@pytest.fixture(scope="module")
def ab(tmp_path_factory):
    d = tmp_path_factory.mktemp("ab")
    r = run("continue", "examples/ab.toml", "--set", "B=17", "--vary", "D", "--bounds", "D=0:0.2",
            "--out", d / "ab.csv", "--quiet")
    assert r.exit_code == 0, r.output
    r = run("cycles", "examples/ab.toml", "--set", "B=17", "--point", f"{d / 'ab.csv'}:HB1", "--vary", "D",
            "--bounds", "D=0:0.2", "--bounds", "period=0:20", "--out", d / "cycles.csv", "--orbits",
            d / "orbits.csv", "--quiet")
    assert r.exit_code == 0, r.output
    return d


@pytest.fixture(scope="module")
def shimmy(tmp_path_factory):
    d = tmp_path_factory.mktemp("shimmy")
    r = run("continue", "examples/shimmy.toml", "--dynamic", "--vary", "V", "--bounds", "V=1:100", "--out",
            d / "branch.csv", "--quiet")
    assert r.exit_code == 0, r.output
    r = run("cycles", "examples/shimmy.toml", "--point", f"{d / 'branch.csv'}:HB1", "--vary", "V", "--bounds",
            "V=1:100", "--max-steps", "5", "--ntst", "10", "--out", d / "cycles.csv", "--orbits", d / "orbits.csv",
            "--quiet")
    assert r.exit_code == 0, r.output
    return load_model("examples/shimmy.toml"), d


def test_an_ode_family_is_drawn_as_its_amplitude_and_its_rows_are_phase_portraits_of_true_orbits(ab, tmp_path):
    out = tmp_path / "ab.html"
    r = run("explore", "examples/ab.toml", "--set", "B=17", "--branch", ab / "ab.csv", "--branch", ab / "cycles.csv",
            "--orbits", ab / "orbits.csv", "--out", out)
    assert r.exit_code == 0, r.output
    page = out.read_text()
    assert offline_problems(page) == []
    data = _data(page)
    eq, cyc = data["branches"]
    assert "cycle" not in eq and cyc["cycle"]["states"] == ["u1", "u2"] and "poses" not in cyc
    assert [s["name"] for s in cyc["special"]] == ["HB1", "EP1"]  # numbered as a branch's points are
    table = Branch.read_csv(ab / "cycles.csv")
    B, beta, integrated = 17.0, 3.0, 0
    for k, row in enumerate(cyc["rows"]):
        orbit = np.array(cyc["orbits"][k])
        T, D = table.column("period")[row], table.column("D")[row]
        assert cyc["columns"]["period"][k] == pytest.approx(T, rel=1e-12)
        # the extremes of the orbit's samples are the table's, taken over the 20 x 4 collocation points: between
        # them a sample may pass them by at most the curvature over half a spacing, (2 pi / 80)^2 / 8 < 1e-3 of the
        # amplitude for a near-harmonic orbit
        for j, s in enumerate(("u1", "u2")):
            lo, hi = table.column(f"min_{s}")[row], table.column(f"max_{s}")[row]
            tol = 1e-3 * (hi - lo) + 1e-9
            assert lo - tol <= orbit[:, j].min() and orbit[:, j].max() <= hi + tol
            assert orbit[:, j].max() - orbit[:, j].min() >= 0.8 * (hi - lo) - 1e-9
        if 0 < row and T < 12:  # an orbit near the Hopf point: integrate the rates from its first instant
            def f(t, u, D=D):
                e = (1 - u[0]) * math.exp(u[1])
                return [-u[0] + D * e, -u[1] + D * B * e - beta * u[1]]

            t = np.linspace(0.0, T, len(orbit) + 1)[:-1]  # the page's instants are equally spaced over one period
            sol = solve_ivp(f, (0.0, T), orbit[0], t_eval=t, rtol=1e-11, atol=1e-13)
            amp = np.ptp(orbit, axis=0)
            np.testing.assert_allclose((sol.y.T - orbit) / amp, 0.0, atol=2e-3)
            integrated += 1
    assert integrated >= 3
    assert "orbit's phase portrait" not in json.dumps(eq)


def test_a_cycles_table_without_its_orbits_is_the_diagram_and_says_how_to_get_them(ab):
    from mechcont.outputs.explore import explore_page

    data = _data(explore_page(load_model("examples/ab.toml", B=17.0), [ab / "cycles.csv"]))
    doc = data["branches"][0]
    assert doc["cycle"]["frames"] == 0 and "orbits" not in doc and "--orbits" in doc["note"]
    assert data["axes"] == ["D", "u1"]   # the parameter against the first state's amplitude


def test_the_shimmy_family_plays_one_period_of_the_gear_with_its_tyre_and_rotary_elements(shimmy, tmp_path):
    model, d = shimmy
    out = tmp_path / "shimmy.html"
    r = run("explore", "examples/shimmy.toml", "--branch", d / "cycles.csv", "--orbits", d / "orbits.csv",
            "--out", out)
    assert r.exit_code == 0, r.output
    page = out.read_text()
    assert offline_problems(page) == []
    data = _data(page)
    doc = data["branches"][0]
    assert data["axes"][0] == "V" and doc["cycle"]["frames"] == 24
    table = Branch.read_csv(d / "cycles.csv")
    v = model.defaults()
    e, sigma, C, Fmax, tp = (v[model.index(n)] for n in ("e", "sigma", "C_tyre", "F_max", "t_p"))
    orbits = Branch.read_csv(d / "orbits.csv")
    rows = orbits.column("row")
    for k, row in enumerate(doc["rows"]):
        poses = doc["poses"][k]
        assert len(poses) == 24
        here = np.flatnonzero(rows == row)
        th_all = orbits.column("theta_wheel")[here]
        # the table's extremes are the mesh nodes'; between them the collocation polynomial may reach further, by
        # the collocation's accuracy (the same 1e-3 of the amplitude as the ODE orbits above)
        table_span = table.column("max_theta_wheel")[row] - table.column("min_theta_wheel")[row]
        assert abs(np.ptp(th_all) - table_span) <= 1e-3 * table_span + 1e-12
        thetas = []
        for pose in poses:
            (name, contact), = pose["contacts"]
            assert name == "nose"
            coils = {(n, kind): c for n, c, kind in pose["coils"]}
            assert set(coils) == {("torsion", "spring"), ("shimmy_damper", "damper")}
            # the wheel's bar runs from the swivel through the contact point: its heading is the swivel's angle
            (wheel,) = [pts for b, pts in pose["bars"] if data["bodies"][b]["name"] == "wheel"]
            sw = np.array(coils[("torsion", "spring")])
            np.testing.assert_allclose(coils[("shimmy_damper", "damper")], sw, atol=1e-12)
            far = np.array(max(wheel, key=lambda p: np.hypot(*(np.array(p) - sw))))
            th = math.atan2(*(sw - far)[::-1])  # the tread runs aft of the swivel: the heading points from it
            thetas.append(th)
            h, lat = np.array([math.cos(th), math.sin(th)]), np.array([-math.sin(th), math.cos(th)])
            np.testing.assert_allclose(contact, sw - e * h, atol=1e-9)
            (fname, at, force), = pose["forces"]
            np.testing.assert_allclose(at, sw - (e + tp) * h, atol=1e-9)
            y = float(np.dot(force, lat))
            assert abs(float(np.dot(force, h))) <= 1e-9 * max(1.0, abs(y))   # along the lateral axis
            # the side force is the tyre's of a deflection the orbit passes through
            deflection = orbits.column("y_nose")[here]
            ys = sigma * Fmax / C * np.arctanh(np.clip(y / Fmax, -1 + 1e-15, 1 - 1e-15))
            assert deflection.min() - 1e-12 <= ys <= deflection.max() + 1e-12
        # the poses swing the wheel through the orbit's angles: over one period, the table's amplitude
        span = np.ptp(np.unwrap(thetas))
        assert span <= np.ptp(th_all) + 1e-9 and (np.ptp(th_all) == 0 or span >= 0.8 * np.ptp(th_all))


def test_a_family_from_python_embeds_the_same_periods_and_the_budget_thins_rows_not_frames(shimmy):
    from mechcont.continuation import ContinuationOptions, cycles_from_hopf
    from mechcont.equations import dynamics_of

    model, d = shimmy
    branch = Branch.read_csv(d / "branch.csv")
    x = model.vector({n: float(branch.point("HB1")[n]) for n in model.names})
    fam = cycles_from_hopf(model, x, "V", options=ContinuationOptions(max_steps=6), ntst=10)
    full = page_data(model, [fam])
    doc = full["branches"][0]
    assert [s["name"] for s in doc["special"]][:1] == ["HB1"] and len(doc["rows"]) == len(fam)
    k = len(fam) - 1
    t, X = fam.full_vectors(dynamics_of(model), k, 24)
    i = model.index("theta_wheel")
    assert doc["poses"][k][6]["coils"] and len(doc["poses"][k]) == 24
    # the pose at a quarter period has the wheel turned as the orbit is then
    (wheel,) = [pts for b, pts in doc["poses"][k][6]["bars"] if full["bodies"][b]["name"] == "wheel"]
    sw = np.array(doc["poses"][k][6]["coils"][0][1])
    far = np.array(max(wheel, key=lambda p: np.hypot(*(np.array(p) - sw))))
    assert math.atan2(*(sw - far)[::-1]) == pytest.approx(X[6, i], abs=1e-9)
    one = len(json.dumps(doc["poses"][k], separators=(",", ":")))
    small = page_data(model, [fam], budget=3.5 * one)
    s = small["branches"][0]
    assert len(s["rows"]) < len(doc["rows"]) and all(len(p) == 24 for p in s["poses"])
    assert {p["name"] for p in s["special"]} == {p["name"] for p in doc["special"]}
    assert len(json.dumps(s, separators=(",", ":"))) <= 3.5 * one + 2000


def test_a_family_with_an_equation_system_alone_is_refused_naming_it(shimmy):
    """A family's orbits need the model's dynamics: an equation system alone (no rates, no mechanics) is refused
    with an InputError naming it (it was an AttributeError)."""
    from mechcont.continuation import ContinuationOptions, cycles_from_hopf
    from mechcont.equations import EquationSystem
    from mechcont.errors import InputError

    model, d = shimmy
    branch = Branch.read_csv(d / "branch.csv")
    x = model.vector({n: float(branch.point("HB1")[n]) for n in model.names})
    fam = cycles_from_hopf(model, x, "V", options=ContinuationOptions(max_steps=2), ntst=10)
    plain = EquationSystem(model.name, model.variables, model.equations, scene=model.scene)
    with pytest.raises(InputError, match="no dynamics"):
        page_data(plain, [fam])


def test_the_pose_json_carries_coils_and_tyre_contacts(shimmy):
    model, _ = shimmy
    x = model.defaults()
    pose = pose_json(model.scene(x), {"strut": 0, "wheel": 1})
    assert sorted(k for _, _, k in pose["coils"]) == ["damper", "spring"]
    (name, p), = pose["contacts"]
    e = x[model.index("e")]
    np.testing.assert_allclose(p, [x[model.index("x_wheel")] - e * math.cos(x[model.index("theta_wheel")]),
                                   x[model.index("y_wheel")] - e * math.sin(x[model.index("theta_wheel")])],
                               atol=1e-12)


def test_bad_orbit_tables_and_paths_are_one_line_errors(ab, tmp_path):
    r = run("explore", "examples/ab.toml", "--set", "B=17", "--branch", ab / "cycles.csv", "--orbits",
            ab / "ab.csv", "--out", tmp_path / "x.html")
    one_line_error(r, "orbits", "not an orbit table")
    r = run("explore", "examples/ab.toml", "--set", "B=17", "--branch", ab / "ab.csv", "--orbits",
            ab / "orbits.csv", "--out", tmp_path / "x.html")
    one_line_error(r, "orbits", "cycles tables")
    r = run("cycles", "examples/ab.toml", "--set", "B=17", "--point", f"{ab / 'ab.csv'}:HB1", "--vary", "D",
            "--orbits", tmp_path / "o.txt")
    one_line_error(r, "--orbits")
    assert not (tmp_path / "x.html").exists()


def _browser_page():
    """The page at ``path`` in headless Chromium (tests/test_explore_browser.py's set-up); skipped without one."""
    import shutil

    chromium = next((p for p in map(shutil.which, ("chromium", "chromium-browser")) if p), None)
    if chromium is None:
        pytest.skip("no Chromium on PATH")
    sync_api = pytest.importorskip("playwright.sync_api")
    from test_explore_browser import ARGS

    return sync_api, chromium, ARGS


def test_in_a_browser_the_family_is_two_curves_with_labelled_markers_and_a_row_plays_its_period(ab, shimmy, tmp_path):
    model, d = shimmy
    pages = {"ab": tmp_path / "ab.html", "shimmy": tmp_path / "shimmy.html"}
    assert run("explore", "examples/ab.toml", "--set", "B=17", "--branch", ab / "ab.csv", "--branch",
               ab / "cycles.csv", "--orbits", ab / "orbits.csv", "--out", pages["ab"]).exit_code == 0
    assert run("explore", "examples/shimmy.toml", "--branch", d / "cycles.csv", "--orbits", d / "orbits.csv",
               "--out", pages["shimmy"]).exit_code == 0
    sync_api, chromium, args = _browser_page()
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=args)
        page = browser.new_page(viewport={"width": 1500, "height": 1000})
        errors: list[str] = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(pages["ab"].as_uri())
        page.wait_for_selector("[data-ready='1']", timeout=15000)
        # the family's markers sit on its max and its min curve, labelled once as the branch's points are
        for name in ("HB1", "EP1"):
            curves = {e.get_attribute("data-curve") for e in
                      page.query_selector_all(f".diagram .mcx-sp[data-branch='1'][data-point='{name}']")}
            assert curves == {"max", "min"}, name
        labels = [e.text_content() for e in page.query_selector_all(".diagram .mcx-label[data-branch='1']")]
        assert sorted(labels) == ["EP1", "HB1"]
        assert {e.get_attribute("data-curve") for e in
                page.query_selector_all(".diagram polyline[data-branch='1']")} == {"max", "min"}
        page.click(".sp button[data-branch='1'][data-point='EP1']")
        orbit = page.wait_for_selector("[data-kind='orbit']")
        pts = np.array([[float(v) for v in s.split()] for s in orbit.get_attribute("data-xy").split(";")])
        table = Branch.read_csv(ab / "cycles.csv")
        row = table.point("EP1").index
        assert pts[:, 0].max() == pytest.approx(table.column("max_u1")[row], rel=1e-2)
        seen = set()
        for _ in range(4):  # the dot runs round the orbit
            page.wait_for_timeout(120)
            seen.add(page.get_attribute(".mcx-now", "data-frame"))
        assert len(seen) > 1
        # the shimmy gear: a row plays its 24 poses in turn, each with the tyre's contact and the rotary elements
        page.goto(pages["shimmy"].as_uri())
        page.wait_for_selector("[data-ready='1']", timeout=15000)
        page.click(".sp button[data-point='EP1']")
        frames = set()
        for _ in range(5):
            page.wait_for_timeout(150)
            frames.add(page.get_attribute("svg.mech", "data-frame"))
            assert page.query_selector_all("svg.mech [data-kind='contact']")
            kinds = {e.get_attribute("data-coil") for e in page.query_selector_all("svg.mech [data-kind='coil']")}
            assert kinds == {"spring", "damper"}
        assert len(frames) > 2
        assert errors == []
        browser.close()
