"""The explorer page in a real browser: headless Chromium (the distribution's package) driven by Playwright.

Clicking a special point (its button, its marker in the diagram), dragging the slider and
hovering draw the mechanism in that pose: the coordinates read back from the drawn SVG
elements (``data-xy``, metres) are the model's scene at that row, and the pixels drawn are
those coordinates under one scale per view. A screenshot shows the bodies' colours.
Needs ``apt-get install chromium`` (``/usr/bin/chromium``) and ``pip install playwright``
(no browser download); skipped otherwise.
"""

from __future__ import annotations

import io
import shutil

import numpy as np
import pytest
from cli_helpers import make_runner

from mechcont.continuation import Branch
from mechcont.models import load_model
from mechcont.outputs.explore import write_explore

CHROMIUM = next((p for p in map(shutil.which, ("chromium", "chromium-browser")) if p), None)
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no Chromium on PATH (Debian: apt-get install chromium)")
sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed (pip install playwright)")

#: Chromium on a machine without network: no background connections, no sandbox as root (see the machine notes).
ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
        "--disable-component-update", "--disable-sync"]

run = make_runner()


@pytest.fixture(scope="module")
def browser():
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield b
        b.close()


def _open(browser, path, size=(1500, 1000)):
    page = browser.new_page(viewport={"width": size[0], "height": size[1]})
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(path.as_uri())
    page.wait_for_selector("[data-ready='1']", timeout=15000)
    return page, errors


def _points(text: str) -> np.ndarray:
    return np.array([[float(v) for v in p.split()] for p in text.split(";")])


def _drawn(page, view: str) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(body, points in m, points in px) of every bar drawn in ``view``."""
    out = []
    for e in page.query_selector_all(f"svg.mech[data-view='{view}'] [data-kind='bar']"):
        px = np.array([[float(v) for v in p.split(",")] for p in e.get_attribute("points").split()])
        out.append((e.get_attribute("data-body"), _points(e.get_attribute("data-xy")), px))
    return out


def _check_pose(page, system, x, views=("plane",), axes=((0, 1),)) -> None:
    """The bars drawn in each view are the scene's at ``x`` (1e-12 m) and drawn at one scale, y (or z) up."""
    scene = system.scene(x)
    for view, (h, v) in zip(views, axes):
        drawn = _drawn(page, view)
        assert [b for b, _, _ in drawn] == [n for n, _ in scene.bars]
        for (_, got, _), (_, want) in zip(drawn, scene.bars):
            np.testing.assert_allclose(got, np.asarray(want, float), rtol=0, atol=1e-12)
        m = np.vstack([g[:, [h, v]] for _, g, _ in drawn])
        px = np.vstack([p for _, _, p in drawn])
        # px = (x0 + s x, y0 - s y): one scale, y up, solved by least squares over every point drawn
        A = np.zeros((2 * len(m), 3))
        A[0::2, 0], A[0::2, 2], A[1::2, 1], A[1::2, 2] = 1, m[:, 0], 1, -m[:, 1]
        sol, *_ = np.linalg.lstsq(A, px.ravel(), rcond=None)
        assert sol[2] > 0
        np.testing.assert_allclose(A @ sol, px.ravel(), rtol=0, atol=1e-6)


def _shows_colour(png: bytes, colour: str) -> bool:
    from matplotlib.image import imread

    img = imread(io.BytesIO(png), format="png")[..., :3]
    want = np.array([int(colour[i:i + 2], 16) / 255 for i in (1, 3, 5)])
    assert img.std() > 0.01  # not blank
    return int(np.sum(np.all(np.abs(img - want) < 0.02, axis=-1))) > 50


def test_overcentre_click_slide_hover(browser, tmp_path):
    csv, page_file = tmp_path / "branch.csv", tmp_path / "page.html"
    result = run("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
                 "--bounds", "F=-100:120", "--out", csv)
    assert result.exit_code == 0, result.output
    system, branch = load_model("overcentre"), Branch.read_csv(csv)
    write_explore(page_file, system, [csv])
    page, errors = _open(browser, page_file)
    buttons = page.query_selector_all(".sp button")
    assert [b.get_attribute("data-point") for b in buttons] == branch.point_names()

    page.click(".sp button[data-point='LP1']")
    lp1 = branch["LP1"]
    assert page.get_attribute(".status", "data-row") == str(lp1.index)
    assert "LP1" in page.inner_text(".status") and "fold" in page.inner_text(".status")
    _check_pose(page, system, lp1.x)
    assert page.inner_text("table.values tr[data-name='F'] td.n") == f"{lp1['F']:.6g}"
    assert "F" in page.inner_text("table.loads")
    png = page.locator("svg.mech").screenshot()
    assert _shows_colour(png, page.get_attribute("svg.mech [data-kind='bar']", "stroke"))
    page.screenshot(path=str(tmp_path / "page.png"), full_page=True)

    page.click("svg.diagram .mcx-sp[data-point='LP2']")  # its marker in the diagram
    _check_pose(page, system, branch["LP2"].x)
    assert page.get_attribute(".mcx-cursor", "data-row") == str(branch["LP2"].index)

    page.focus(".slider")
    page.keyboard.press("End")  # the slider to the last row
    _check_pose(page, system, branch.values[-1])
    page.keyboard.press("ArrowLeft")
    _check_pose(page, system, branch.values[-2])

    box = page.locator("svg.diagram .mcx-sp[data-point='EP1']").bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)  # hover: a preview
    _check_pose(page, system, branch["EP1"].x)
    page.mouse.move(5, 5)  # leaving the diagram: back to the chosen row
    _check_pose(page, system, branch.values[-2])

    page.select_option(".ysel", "F")
    page.select_option(".xsel", "theta2")
    text = page.text_content("svg.diagram") or ""
    assert "theta2 (deg)" in text and "F (N)" in text
    assert errors == []


def test_spatial_three_view(browser, tmp_path):
    csv, page_file = tmp_path / "retraction.csv", tmp_path / "gear.html"
    result = run("continue", "dual_sidestay_kinematics", "--vary", "theta", "--bounds", "theta=0:1.5", "--out", csv)
    assert result.exit_code == 0, result.output
    system, branch = load_model("dual_sidestay_kinematics"), Branch.read_csv(csv)
    write_explore(page_file, system, [csv])
    page, errors = _open(browser, page_file, size=(1400, 900))
    page.click(".sp button[data-point='EP2']")
    _check_pose(page, system, branch["EP2"].x, views=("front", "side", "top"), axes=((1, 2), (0, 2), (0, 1)))
    assert "actuator" in page.inner_text("table.loads")
    # at 1400 x 900 the three views stand beside the diagram and wholly in the window (issue 37: cut off below it)
    diagram = page.locator("svg.diagram").bounding_box()
    for view in ("front", "side", "top"):
        box = page.locator(f"svg.mech[data-view='{view}']").bounding_box()
        assert box["x"] >= diagram["x"] + diagram["width"], view
        assert box["x"] + box["width"] <= 1400 and box["y"] + box["height"] <= 900, (view, box)
    assert errors == []


def _labels(page) -> list[dict]:
    """The diagram's special-point labels: text, the box the browser draws (px) and the box of the page's label
    model (``data-box``)."""
    return page.evaluate("""() => Array.from(document.querySelectorAll('svg.diagram text.mcx-label')).map(t => {
        const b = t.getBBox();
        return {text: t.textContent, drawn: [b.x, b.y, b.x + b.width, b.y + b.height],
                model: t.getAttribute('data-box').split(' ').map(Number)};})""")


def test_crowded_event_labels_are_apart_inside_and_unmangled(browser, tmp_path):
    """A bar bouncing on its stop (restitution 0.5: 15 impacts, 10 of them within 0.12 s) as a time history: each
    event's diagram label is its words (no counter glued to its text, no numbers), drawn inside the plot frame,
    and no two labels overlap (measured on the boxes the browser draws); the buttons carry the full event text."""
    from pathlib import Path

    csv, page_file = tmp_path / "drop.csv", tmp_path / "drop.html"
    model = Path(__file__).parent / "data" / "bar_drop.toml"
    result = run("simulate", model, "--start", "theta_bar=0", "--until", "2.6", "--stops", "--out", csv)
    assert result.exit_code == 0, result.output
    branch = Branch.read_csv(csv)
    assert len(branch.special_points) >= 12
    write_explore(page_file, model, [csv])
    page, errors = _open(browser, page_file, size=(1400, 900))
    labels = _labels(page)
    assert len(labels) == len(branch.special_points)
    assert {lab["text"] for lab in labels} == {"impact rest", "impact + contact rest"}
    assert [b.inner_text() for b in page.query_selector_all(".sp button")] == [p.label for p in branch.special_points]
    frame = [float(page.get_attribute("svg.diagram rect[stroke='#888']", k)) for k in ("x", "y", "width", "height")]
    x0, y0, x1, y1 = frame[0], frame[1], frame[0] + frame[2], frame[1] + frame[3]
    boxes = np.array([lab["drawn"] for lab in labels])
    model_boxes = np.array([lab["model"] for lab in labels])
    # the label model's boxes hold what is drawn (0.5 px for rounding), and lie inside the frame
    assert np.all(model_boxes[:, :2] <= boxes[:, :2] + 0.5) and np.all(model_boxes[:, 2:] >= boxes[:, 2:] - 0.5)
    assert np.all(boxes[:, 0] >= x0) and np.all(boxes[:, 2] <= x1) and np.all(boxes[:, 1] >= y0)
    assert np.all(boxes[:, 3] <= y1)
    for i in range(len(boxes)):
        for j in range(i):
            a, b = boxes[i], boxes[j]
            apart = a[2] <= b[0] or b[2] <= a[0] or a[3] <= b[1] or b[3] <= a[1]
            assert apart, (labels[i]["text"], a, labels[j]["text"], b)
    assert errors == []


def test_dragging_on_the_diagram_selects_no_text(browser, tmp_path):
    csv, page_file = tmp_path / "branch.csv", tmp_path / "page.html"
    result = run("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
                 "--bounds", "F=-100:120", "--out", csv)
    assert result.exit_code == 0, result.output
    write_explore(page_file, "overcentre", [csv])
    page, errors = _open(browser, page_file)
    box = page.locator("svg.diagram").bounding_box()
    page.mouse.move(box["x"] + 5, box["y"] + 5)
    page.mouse.down()
    page.mouse.move(box["x"] + box["width"] - 5, box["y"] + box["height"] - 5, steps=10)
    page.mouse.up()
    assert page.evaluate("() => String(window.getSelection())") == ""
    assert page.evaluate("() => getComputedStyle(document.querySelector('svg.diagram')).userSelect") == "none"
    assert errors == []


def test_pin_in_slot_draws_its_slot(browser, tmp_path):
    """A pin-in-slot joint's slot is drawn (an element of kind "slot") where the model's scene has it."""
    from pathlib import Path

    from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium

    system = load_model(Path(__file__).parent / "data" / "quick_return.toml")
    x0 = find_equilibrium(system, hold={"theta_crank": 0.5}, free=["Mc"])
    scales = {n: 10.0 for n in ("Mc", "R_O_x", "R_O_y", "R_C_x", "R_C_y", "R_slot")}
    branch = continuation(system, x0, "Mc", options=ContinuationOptions(bounds={"theta_crank": (0.0, 1.0)},
                                                                      scales=scales))
    page_file = tmp_path / "slot.html"
    write_explore(page_file, system, [branch])
    page, errors = _open(browser, page_file)
    page.click(".sp button[data-point='EP2']")
    slots = page.query_selector_all("svg.mech [data-kind='slot']")
    want = system.scene(branch["EP2"].x).slots
    assert len(slots) == len(want) == 1
    np.testing.assert_allclose(_points(slots[0].get_attribute("data-xy")), np.array([want[0][1], want[0][2]], float),
                               rtol=0, atol=1e-12)
    _check_pose(page, system, branch["EP2"].x)
    assert errors == []
