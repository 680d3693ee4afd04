"""`mechcont paper`: figures and a summary whose numbers agree with the closed form."""

import re

import pytest
from click.testing import CliRunner

from mechcont.cli._app import _register, cli


@pytest.fixture(scope="module")
def paper_dir(tmp_path_factory):
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
