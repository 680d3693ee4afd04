"""A fold curve through a cusp, planar and spatial, against its closed form.

The toggle press of tests/data/press.toml (two bars of length L, pinned at O, the ram sliding
along x, a spring k of free length L0 from O to the ram, a vertical force F at the knee; phi the
first bar's angle) has the potential V = k (2 L cos(phi) - L0)^2 / 2 - F L sin(phi), so its
equilibria are F = -2 k (2 L sin(phi) - L0 tan(phi)), its folds (dF/dphi = 0) lie on
L0 = 2 L cos^3(phi), F = -4 k L sin^3(phi), and the fold curve has one cusp, at phi = 0, L0 = 2 L,
F = 0, where its two halves (phi > 0 and phi < 0) meet. tests/data/spatial/press_3d.toml is the
same press written with spatial elements.
"""

from pathlib import Path

import numpy as np
import pytest

from mechcont.continuation import ContinuationOptions, continuation, continue_folds, find_equilibrium
from mechcont.models import load_model

DATA = Path(__file__).parent / "data"
L, K = 0.5, 2000.0
FILES = {"planar": DATA / "press.toml", "spatial": DATA / "spatial" / "press_3d.toml"}


def _fold_curve(path):
    s = load_model(path)
    x0 = find_equilibrium(s, hold={"phi": 0.3}, free=["F"])
    b = continuation(s, x0, "F", options=ContinuationOptions(bounds={"phi": (-1.2, 1.2)}))
    return continue_folds(s, b["LP1"], vary="F", free="L0", options=ContinuationOptions(bounds={"L0": (0.5, 1.2)}))


@pytest.fixture(scope="module")
def curves():
    return {kind: _fold_curve(path) for kind, path in FILES.items()}


@pytest.mark.parametrize("kind", list(FILES))
def test_fold_curve_is_the_closed_form_with_one_cusp(curves, kind):
    c = curves[kind]
    phi, L0, F = c["phi"], c["L0"], c["F"]
    assert np.max(np.abs(L0 - 2 * L * np.cos(phi) ** 3)) < 1e-11
    assert np.max(np.abs(F + 4 * K * L * np.sin(phi) ** 3)) < 1e-11 * 4 * K * L
    labels = [lab for lab in c.row_labels() if lab]
    assert labels == ["EP", "CP", "EP"], labels  # one cusp, never CP? on an ordinary fold point
    cp = c["CP1"].values
    assert cp["L0"] == pytest.approx(2 * L, abs=1e-12) and abs(cp["phi"]) < 1e-12 and abs(cp["F"]) < 1e-9
    # the curve crosses from one half to the other once: phi changes sign once along it
    assert np.count_nonzero(np.diff(np.sign(phi[np.abs(phi) > 1e-9])) != 0) == 1


def test_spatial_press_equals_the_planar_one_at_the_cusp_and_the_ends(curves):
    """The ends, where the bound L0 = 0.5 m stops the curve, on the closed form to full accuracy:
    cos^3(phi) = L0 / (2 L) and F = -+4 k L sin^3(phi); and the two formulations agree."""
    phi_end = np.arccos((0.5 / (2 * L)) ** (1 / 3))
    ends = {}
    for kind, c in curves.items():
        rows = [i for i, lab in enumerate(c.labels) if lab == "EP"]
        assert c["L0"][rows] == pytest.approx([0.5, 0.5], abs=1e-15)
        np.testing.assert_allclose(np.abs(c["phi"][rows]), phi_end, rtol=0, atol=1e-12)
        np.testing.assert_allclose(c["F"][rows], -4 * K * L * np.sin(c["phi"][rows]) ** 3, rtol=1e-12)
        ends[kind] = np.column_stack([c["phi"][rows], c["F"][rows]])
    np.testing.assert_allclose(ends["spatial"], ends["planar"], rtol=1e-12, atol=1e-12)
    cps = [curves[k]["CP1"].values for k in FILES]
    assert cps[0]["L0"] == pytest.approx(cps[1]["L0"], abs=1e-12)


@pytest.mark.parametrize("kind", list(FILES))
def test_fold_curve_of_a_stiff_press_has_one_located_cusp(kind):
    """The same press with the spring 1000 times stiffer: the equations scale (forces and reactions by
    1000, and so do their continuation scales) and the fold curve should not change in phi and L0."""
    s = load_model(FILES[kind], k=1000 * K)
    x0 = find_equilibrium(s, hold={"phi": 0.3}, free=["F"])
    b = continuation(s, x0, "F", options=ContinuationOptions(bounds={"phi": (-1.2, 1.2)}))
    c = continue_folds(s, b["LP1"], vary="F", free="L0",
                       options=ContinuationOptions(bounds={"L0": (0.5, 1.2)}, max_steps=300))
    assert [lab for lab in c.row_labels() if lab] == ["EP", "CP", "EP"]
    assert c["CP1"].info["status"] == "located"
    assert c["CP1"].values["L0"] == pytest.approx(2 * L, abs=1e-12) and abs(c["CP1"].values["phi"]) < 1e-9
    phi = c["phi"]
    assert np.max(np.abs(c["L0"] - 2 * L * np.cos(phi) ** 3)) < 1e-11
    assert np.count_nonzero(np.diff(np.sign(phi[np.abs(phi) > 1e-9])) != 0) == 1  # no back and forth
    assert len(phi) < 80  # arclength in the physical unknowns: about as many steps as the soft press


@pytest.mark.parametrize("kind", list(FILES))
@pytest.mark.parametrize("phi", [-0.4, -1e-3, 0.0, 2e-5])
def test_fold_condition_gradient_agrees_with_finite_differences(kind, phi):
    """The fold condition det(R G_s C) / N and its exact gradient (the adjugate contracted with
    the generated second derivatives) against central differences, on and near the cusp."""
    from mechcont.continuation import FoldProblem

    s = load_model(FILES[kind])
    x0 = find_equilibrium(s, hold={"phi": 0.3}, free=["F"])
    lp = continuation(s, x0, "F", options=ContinuationOptions(bounds={"phi": (-1.2, 1.2)}))["LP1"]
    prob = FoldProblem(s, lp.x, "F", "L0", lp.info["unknowns"])
    x = find_equilibrium(s, hold={"phi": phi}, free=["F"])
    u = x[prob.idx_vars]
    J = prob.jacobian(u)
    h = 1e-6 * prob.scale
    fd = np.array([(prob.residual(u + hi * e) - prob.residual(u - hi * e)) / (2 * hi)
                   for hi, e in zip(h, np.eye(len(u)))]).T
    scale = np.abs(J[-1] * prob.scale).max()
    assert scale > 0
    np.testing.assert_allclose(J[-1] * prob.scale, fd[-1] * prob.scale, rtol=0, atol=1e-6 * scale)
