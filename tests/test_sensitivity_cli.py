"""``mechcont sensitivity``: the JSON it writes, checked against closed forms and the API; its one-line errors."""

import json

import pytest
from cli_helpers import make_runner, one_line_error

run = make_runner()

L, K, LU, W = 1.5, 127.0, 0.4, 9.81  # the overcentre's defaults, W = (m1 + m2) g / 2


@pytest.fixture(scope="module")
def branch_csv(tmp_path_factory):
    path = tmp_path_factory.mktemp("sens") / "b.csv"
    r = run("continue", "overcentre", "--set", f"LU={LU}", "--start", "theta1=0.3", "--vary", "F",
            "--bounds", "F=-200:200", "--out", path, "--quiet")
    assert r.exit_code == 0, r.output
    return path


def test_fold_load_json_matches_closed_form(branch_csv, tmp_path):
    out = tmp_path / "s.json"
    r = run("sensitivity", "overcentre", "--point", f"{branch_csv}:LP1", "--params", "LU,k", "--out", out)
    assert r.exit_code == 0, r.output
    assert "fold" in r.output and f"wrote {out}" in r.output
    doc = json.loads(out.read_text())
    q = doc["quantity"]
    assert q["name"] == "F" and q["unit"] == "N" and q["kind"] == "fold" and q["point"] == "LP1"
    u = 1 - (LU / L) ** (2 / 3)
    s = 1.0 if q["value"] > W else -1.0  # F* = W + s k L u^{3/2}
    assert q["value"] == pytest.approx(W + s * K * L * u ** 1.5, rel=1e-10)
    assert doc["k"] == pytest.approx(s * L * u ** 1.5, rel=1e-9)
    assert doc["LU"] == pytest.approx(-s * K * u ** 0.5 * (LU / L) ** (-1 / 3), rel=1e-9)
    assert doc["units"] == {"LU": "N/m", "k": "N/(N/m)"}


def test_bad_param_is_one_line_listing_valid_names(branch_csv, tmp_path):
    out = tmp_path / "s.json"
    r = run("sensitivity", "overcentre", "--point", f"{branch_csv}:LP1", "--params", "LU,kk", "--out", out)
    one_line_error(r, "--params", "kk", "valid:", "LU", "k,")
    assert not out.exists()
    r = run("sensitivity", "overcentre", "--point", f"{branch_csv}:LP1", "--params", "theta1", "--out", out)
    one_line_error(r, "--params", "solved for")
    assert not out.exists()


def test_point_not_a_fold_needs_keep(branch_csv, tmp_path):
    out = tmp_path / "s.json"
    r = run("sensitivity", "overcentre", "--point", f"{branch_csv}:5", "--params", "k", "--out", out)
    one_line_error(r, "--keep", "theta1")
    assert not out.exists()
    r = run("sensitivity", "overcentre", "--point", f"{branch_csv}:LP9", "--params", "k")
    one_line_error(r, "--point", "LP")
    r = run("sensitivity", "overcentre", "--params", "k")
    one_line_error(r, "--point", "--downlock")


def test_kept_state_with_set_matches_the_api(branch_csv, tmp_path):
    from mechcont.continuation import Branch
    from mechcont.models import build_overcentre

    out = tmp_path / "s.json"
    r = run("sensitivity", "overcentre", "--point", f"{branch_csv}:5", "--params", "LU,L2", "--keep", "theta1",
            "--set", "k=130", "--out", out)
    assert r.exit_code == 0, r.output
    doc = json.loads(out.read_text())
    model = build_overcentre()
    api = Branch.read_csv(branch_csv).sensitivity(model, 5, ["LU", "L2"], keep="theta1", values={"k": 130.0})
    assert doc["quantity"]["kind"] == "equilibrium"
    for p in ("LU", "L2"):
        assert doc[p] == pytest.approx(api[p], rel=1e-12)
    # the point was solved again at the new stiffness: F differs from the table's
    assert doc["quantity"]["value"] != pytest.approx(Branch.read_csv(branch_csv).values[5][model.index("F")], rel=1e-6)


def test_nose_gear_downlock_slope(tmp_path):
    """dF/dLU of the nose gear's downlock force: the slope behind issue 24's Monte Carlo check (-4239 N/m)."""
    out = tmp_path / "d.json"
    r = run("sensitivity", "nose_gear", "--downlock", "--params", "LU,k", "--out", out)
    assert r.exit_code == 0, r.output
    doc = json.loads(out.read_text())
    assert doc["quantity"]["kind"] == "downlock" and doc["quantity"]["point"] == "downlock"
    assert doc["LU"] == pytest.approx(-4239, rel=1e-3)
    r = run("sensitivity", "nose_gear", "--downlock", "--params", "LU", "--keep", "theta1")
    one_line_error(r, "--keep")


def test_downlock_sensitivity_columns(tmp_path):
    """`downlock --sensitivity LU,l_sp1`: per-row exact derivative columns with units, equal to the downlock
    point's sensitivity solved at that row's k."""
    from mechcont.analysis.sensitivity import downlock_sensitivity
    from mechcont.continuation import Branch
    from mechcont.models import load_model

    out = tmp_path / "d.csv"
    r = run("downlock", "nose_gear", "--vary", "k", "--bounds", "k=18000:22000", "--sensitivity", "LU,l_sp1",
            "--out", out)
    assert r.exit_code == 0, r.output
    branch = Branch.read_csv(out)
    assert branch.units["dF_dLU"] == "N/m" and branch.units["dF_dl_sp1"] == "N/m"
    model = load_model("nose_gear")
    for i in (0, len(branch) - 1):
        s = downlock_sensitivity(model, ["LU", "l_sp1"], {"k": branch["k"][i]})
        assert branch["dF_dLU"][i] == pytest.approx(s["LU"], rel=1e-8)
        assert branch["dF_dl_sp1"][i] == pytest.approx(s["l_sp1"], rel=1e-8)
    bad = tmp_path / "e.csv"
    r = run("downlock", "nose_gear", "--vary", "k", "--bounds", "k=18000:22000", "--sensitivity", "LU,theta1",
            "--out", bad)
    one_line_error(r, "--sensitivity", "theta1", "valid:")
    assert not bad.exists()
