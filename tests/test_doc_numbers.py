"""Issue 37, item 6: the numbers the docs quote from a ``mechcont paper`` run are the run's.

docs/dual-sidestay.md quoted 217 mm / 0.1 deg for the kinematic assembly at gear up where the run's summary.md
printed 236 mm / 2.9 deg. Quoted numbers are now marked (``<!--run:NAME-->value<!--/run-->``) and filled from the
run's summary by ``python -m mechcont.paper.doc_numbers DIR`` (:mod:`mechcont.paper.doc_numbers`); the slow test
runs the section part they come from (the dual-sidestay freefall: about 25 s with a warm disk cache, a minute or
more when the gear is first built) and compares every marked number.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from mechcont.paper.doc_numbers import MARK, QUOTES, fill, main, mismatches, quoted

ROOT = Path(__file__).resolve().parent.parent
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SUMMARY = ("Assembled kinematically ... the aft upper arm ends 236 mm off its airframe point and the aft lock links, "
           "seen in their fold plane, 2.9 deg from aligned, where ... the attachment deflects 30 um under its load "
           "and the lock links are folded fwd -26.6 deg, aft -12.0 deg from aligned ...\n"
           "Both sidestays lock in every run, in either order, 9.5 to 33.3 ms apart; the nominal gear has locked "
           "1.607 s after the release. The fall itself ...: the first strike comes 1.588 to 1.590 s after the release")


def test_marked_numbers_are_filled_from_the_summary_and_differences_reported():
    values = quoted(SUMMARY)
    assert set(values) == set(QUOTES)   # every pattern finds its number in a summary written as the run writes it
    assert values["kinematic_offset_mm"] == "236" and values["lock_gap_max_ms"] == "33.3"
    text = "off by <!--run:kinematic_offset_mm-->217<!--/run--> mm, <!--run:kinematic_aft_deg-->0.1<!--/run--> deg"
    assert mismatches(text, SUMMARY) == [("kinematic_offset_mm", "217", "236"), ("kinematic_aft_deg", "0.1", "2.9")]
    filled = fill(text, SUMMARY)
    assert filled == "off by <!--run:kinematic_offset_mm-->236<!--/run--> mm, <!--run:kinematic_aft_deg-->2.9<!--/run--> deg"
    assert mismatches(filled, SUMMARY) == []
    with pytest.raises(KeyError, match="no_such_number"):
        fill("<!--run:no_such_number-->1<!--/run-->", SUMMARY)


def test_the_fill_command_refuses_a_folder_without_a_summary(tmp_path, capsys):
    assert main([str(tmp_path / "missing")]) == 2
    assert "no summary.md" in capsys.readouterr().err
    doc = tmp_path / "doc.md"
    doc.write_text("<!--run:nominal_lock_s-->9<!--/run--> s\n", encoding="utf-8")
    (tmp_path / "summary.md").write_text(SUMMARY, encoding="utf-8")
    assert main([str(tmp_path), str(doc)]) == 0
    assert doc.read_text(encoding="utf-8") == "<!--run:nominal_lock_s-->1.607<!--/run--> s\n"


def test_every_quoted_number_is_marked_and_every_mark_is_known():
    """The docs mark every number of :data:`QUOTES` somewhere, and name no number QUOTES does not know."""
    marks = [m.group(1) for path in DOCUMENTS for m in MARK.finditer(path.read_text(encoding="utf-8"))]
    assert set(marks) == set(QUOTES), (set(QUOTES) - set(marks), set(marks) - set(QUOTES))


@pytest.mark.slow
def test_the_docs_quote_what_the_run_prints():
    """The dual-sidestay freefall's summary lines, computed afresh, print every marked number as the docs quote it."""
    from mechcont.paper import freefall_sidestay

    summary = "\n".join(freefall_sidestay.lines({}))
    assert set(quoted(summary)) == set(QUOTES)
    wrong = [(path.name, *m) for path in DOCUMENTS for m in mismatches(path.read_text(encoding="utf-8"), summary)]
    assert not wrong, f"quoted numbers that are not the run's (fill them: python -m mechcont.paper.doc_numbers): {wrong}"
