"""Issue 37, item 6: the numbers the docs quote from a run (a ``mechcont paper`` section or a documented command)
are the run's.

docs/dual-sidestay.md quoted 217 mm / 0.1 deg for the kinematic assembly at gear up where the run's summary.md
printed 236 mm / 2.9 deg. Quoted numbers are now marked (``<!--run:NAME-->value<!--/run-->``) and filled from the
run's summary and the documented commands' output by ``python -m mechcont.paper.doc_numbers DIR``
(:mod:`mechcont.paper.doc_numbers`). The slow tests run each source afresh and compare every marked number: the
documented commands that a runnable block shows on the run tests/test_doc_examples.py makes of them (each ran
here a second time: 5-30 s of CPU each, about 100 s in all), the one no runnable block shows (the dual-sidestay
freefall) here; the quoted paper sections (freefall, design_optimum) in tests/test_figure_review.py
(``test_the_docs_quote_what_the_section_prints``), on the run its figure review makes, rather than a second one.

A code block showing a command's output (a transcript, where a mark would show as text) is named by
``<!--transcript:SOURCE-->`` before its fence; its every line is checked against what the command prints, number by
number to the precision shown (docs/reliability.md's FORM transcript lacked the "4956 in the failure domain" the
study prints; docs/reference.md's energy line was from an older run: residual 6.16e-06, bound 0.00614 where the
README's freefall prints -1.39e-06, 0.0033).
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
from test_doc_examples import _arguments, examples, outputs, quoted_here, quoted_wrong

from mechcont.paper.doc_numbers import (
    BLOCK_MARK,
    COMMANDS,
    MARK,
    QUOTES,
    TRANSCRIPT,
    command_outputs,
    fill,
    main,
    mismatches,
    quoted,
    transcript_mismatches,
)

ROOT = Path(__file__).resolve().parent.parent
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SUMMARY = ("Assembled kinematically ... the aft upper arm ends 236 mm off its airframe point and the aft lock links, "
           "seen in their fold plane, 2.9 deg from aligned, where ... the attachment deflects 30 um under its load "
           "and the lock links are folded fwd -26.6 deg, aft -12.0 deg from aligned ...\n"
           "Both sidestays lock in every run, in either order, 9.5 to 33.3 ms apart; the nominal gear has locked "
           "1.607 s after the release. The fall itself ...: the first strike comes 1.588 to 1.590 s after the release")
#: Excerpts of the two commands' output, as they print it (the check's deflection lines abridged).
CHECK = ("  aft_A_x  -1.861e-05 m  reaction R_aft_A_x = -930.462 N, stiffness 5e+07 N/m\n"
         "  aft_A_y  3.164e-05 m   reaction R_aft_A_y = 1581.92 N, stiffness 5e+07 N/m\n"
         "  aft_A_z  -1.944e-05 m  reaction R_aft_A_z = -972.163 N, stiffness 5e+07 N/m\n"
         "...\n  theta             -0.0070 deg       -0.0070 deg       condition theta: retraction angle\n")
FALL = ("# energy [J]: start -1602.89, kinetic 2.60352e-07, potential -19821.9, dissipated 18219, external work "
        "-6.14293e-06, residual -0.00907 (worst 0.0092, bound 32.4)\n"
        "peak damper tension actuator: 45365.1 N at t = 0.576333 s\n")
TOUR = ("overcentre: 73 points in F\npoint             F (N)    theta1 (deg)  stability\n"
        "EP1                 120     80.32517727     stable\nLP1        -75.58066788     49.93474965       fold\n"
        "LP2         95.20066788    -49.93474965       fold\n")
OPTIMUM = ("converged: Optimization terminated successfully (3 iterations, 3 solves)\nLU = 1.2692029 m\n"
           "  beta(not locking) = 4.753424309\n")
DS_OPTIMUM = ("converged: Optimization terminated successfully (14 iterations, 19 solves)\n"
              "unlock_force = 72.36004747 N\n  k_lock = 3947.131936 N/m\n  stretch = 0.8363771622\n"
              "  beta(not locking) = 4.753424309\n  P(not locking) = 1e-06\n"
              "active: beta(not locking) >= 4.75342 (multiplier 2.61789)\n")
LOCKSTAY = ("converged: Optimization terminated successfully (4 iterations, 4 solves)\nunlock_force = 363.1575518 N\n"
            "  LU = 0.5989687468 m\n  k = 10000 N/m\n  beta(not locking) = 4.753424309\n"
            "active: beta(not locking) >= 4.75342 (multiplier 28.2445); k >= 10000 (multiplier 0.0523043)\n")
#: The reliability-based design section's summary lines (abridged).
DESIGN = ("* Nose gear, tolerances ...: the longest nominal lock-spring free length is LU = 1.269202900 m (beta = 4.75342, "
          "P = 1e-06; 3 iterations); its nominal downlock force is 202.55 N.\n"
          "* Lock stay, tolerances LU normal, ...: the least unlock load is 363.158 N at k = 10000.0 N/m and "
          "LU = 0.598968747 m (nominal downlock force 185.57 N; 4 iterations). Active: beta(not locking) >= 4.75342 "
          "(multiplier 28.24); k >= 10000 (multiplier 0.0523); ...\n\n"
          "* Dual-sidestay gear (...): the least unlock load of both pairs together is 102.491 N at k_lock = 2001.3 N/m "
          "and stretch = 0.500000, with each stop's preload at rest at least 20 N m (fwd 20.0000, ...). The "
          "description's springs (k_lock = 8000 N/m, stretch = 0.7) need 199.3 N with preloads fwd 61.7, aft 70.5 N m. "
          "...\n")
DS_PRELOAD = ("converged: Optimization terminated successfully (7 iterations, 7 solves)\nunlock_force = 102.4914221 N\n"
              "  k_lock = 2001.323877 N/m\n  stretch = 0.5\n  R_fwd_stop = 20 N m\n  R_aft_stop = 37.46775086 N m\n"
              "active: R_fwd_stop >= 20 (multiplier 2.22666); stretch >= 0.5 (multiplier 4.52694)\n")
FOLDS = ("overcentre: 57 points in LU\npoint            LU (m)           F (N)    theta1 (deg)  stability\n"
         "EP1                 0.1    -135.6962354     66.07878176          -\n"
         "CP1                 1.5            9.81 6.422336365e-15          -\n")
REL = ("FORM: beta = 1.68933, P(downlock_force <= 0) = 0.0455781 (4 iterations, 9 solves)\n"
       "SORM (Breitung): P = 0.0453002\n")
RARE = ("FORM: beta = 4.71391, P(downlock_force <= 0) = 1.21504e-06 (7 iterations, 13 solves)\n"
        "SORM (Breitung): P = 1.18719e-06\n")
PRINTED = {"freefall": SUMMARY, "check_locked": CHECK, "freefall_sidestay_cli": FALL, "tour_continue": TOUR,
           "optimize_nose_gear": OPTIMUM, "optimize_dual_sidestay": DS_OPTIMUM,
           "optimize_lockstay": LOCKSTAY, "design_optimum": DESIGN,
           "optimize_ds_preload": DS_PRELOAD, "tour_folds": FOLDS, "study_rel": REL,
           "study_rare": RARE}


def test_marked_numbers_are_filled_from_the_summary_and_differences_reported():
    values = quoted(PRINTED)
    assert set(values) == set(QUOTES)   # every pattern finds its number in a text written as the run writes it
    assert values["kinematic_offset_mm"] == "236" and values["lock_gap_max_ms"] == "33.3"
    text = "off by <!--run:kinematic_offset_mm-->217<!--/run--> mm, <!--run:kinematic_aft_deg-->0.1<!--/run--> deg"
    assert mismatches(text, PRINTED) == [("kinematic_offset_mm", "217", "236"), ("kinematic_aft_deg", "0.1", "2.9")]
    filled = fill(text, PRINTED)
    assert filled == "off by <!--run:kinematic_offset_mm-->236<!--/run--> mm, <!--run:kinematic_aft_deg-->2.9<!--/run--> deg"
    assert mismatches(filled, PRINTED) == []
    with pytest.raises(KeyError, match="no_such_number"):
        fill("<!--run:no_such_number-->1<!--/run-->", PRINTED)
    assert quoted({"check_locked": CHECK}).keys() == {n for n, q in QUOTES.items() if q.source == "check_locked"}


def test_a_number_in_a_code_block_is_named_before_its_fence_with_the_text_around_it():
    """``<!--block:NAME TEXT-->``: the code block after it holds TEXT with the run's number (README's Python example
    names the cusp of the overcentre's folds in a comment); fill rewrites that number only."""
    doc = ("<!--block:tour_cusp_lu_m LU={},-->\n```python\nx = 1.25\nfolds['CP1']   # CP at row ..., LU=1.25, ...)\n```\n")
    assert quoted(PRINTED)["tour_cusp_lu_m"] == "1.5"
    assert mismatches(doc, PRINTED) == [("tour_cusp_lu_m", "1.25", "1.5")]
    filled = fill(doc, PRINTED)
    assert filled == doc.replace("LU=1.25", "LU=1.5") and mismatches(filled, PRINTED) == []
    assert mismatches(doc.replace("LU=1.25,", "LU 1.25,"), PRINTED)[0][1] == "no 'LU={},' in the block"
    with pytest.raises(KeyError, match="its code block has no 'LU="):
        fill(doc.replace("LU=1.25,", "LU 1.25,"), PRINTED)


def test_a_number_derived_from_the_printed_ones_is_shown_as_the_document_writes_it():
    """The check prints the attachment's deflection and reaction by component; the docs quote their lengths
    (|(-18.61, 31.64, -19.44)| um = 41.5 um, |(-930.5, 1581.9, -972.2)| N = 2077 N), the energy released as the
    start's energy less the end's potential (-1602.89 + 19821.9 J = 18.2 kJ), a small number with a short
    exponent and the document's minus sign."""
    values = quoted(PRINTED)
    assert values["locked_deflection_um"] == "42" and values["locked_reaction_kn"] == "2.08"
    assert values["locked_theta_deg"] == "\u22120.007"
    assert values["fall_released_kj"] == "18" and values["fall_kinetic_j"] == "2.6e-7"
    assert values["fall_residual_j"] == "0.009" and values["fall_bound_j"] == "32"
    assert values["fall_actuator_kn"] == "45.4" and values["fall_actuator_s"] == "0.58"
    assert values["tour_lp1_n"] == "\u221275.58" and values["tour_lp2_n"] == "+95.20"
    assert values["optimum_nose_lu_m"] == "1.2692" and values["optimum_nose_iterations"] == "3"
    assert [values[f"ds_optimum_{n}"] for n in ("unlock_n", "k_lock", "stretch", "beta", "iterations", "multiplier")] \
        == ["72.36", "3947.1", "0.83638", "4.75342", "14", "2.62"]
    assert [values[f"lockstay_optimum_{n}"] for n in ("unlock_n", "k", "lu_m", "multiplier")] \
        == ["363", "10000", "0.59897", "28.2"]
    assert [values[f"paper_{n}"] for n in ("nose_lu_m", "nose_force_n", "stay_unlock_n", "stay_k", "stay_lu_m",
                                           "stay_multiplier", "ds_unlock_n", "ds_k_lock", "ds_stretch")] \
        == ["1.269203", "202.55", "363.158", "10000", "0.598969", "28.24", "102.49", "2001.3", "0.5"]
    assert [values[f"paper_ds_nominal_{n}"] for n in ("unlock_n", "fwd_nm", "aft_nm")] == ["199.3", "61.7", "70.5"]
    assert [values[f"ds_preload_{n}"] for n in ("unlock_n", "k_lock", "stretch", "iterations", "aft_nm",
                                                "fwd_multiplier", "stretch_multiplier")] \
        == ["102.49", "2001.3", "0.5", "7", "37.47", "2.23", "4.53"]
    assert [values[n] for n in ("rel_beta", "rel_p_form", "rel_p_sorm", "rare_beta", "rare_p_form", "rare_p_sorm")] \
        == ["1.689", "0.04558", "0.0453", "4.714", "1.215·10⁻⁶", "1.187·10⁻⁶"]
    moved = {**PRINTED, "check_locked": CHECK.replace("3.164e-05", "6.164e-05")}   # |(-18.61, 61.64, -19.44)| = 67
    assert quoted(moved)["locked_deflection_um"] == "67"


#: What ``mechcont continue`` of ab prints (an excerpt), and a transcript of it as a document shows it.
AB = ("ab: 30 points in D\npoint             D (1)          u1 (1)  stability\n"
      "HB1        0.1650420453    0.4059553721     stable\nwrote ab.csv\n"
      "HB1 at D = 0.1650420453: omega = 1.024756375 rad/s (period 6.13139 s), l1 = 1.55238: subcritical (unstable cycles)\n")
AB_DOC = ("prints\n\n<!--transcript:continue_ab-->\n```\nab: 30 points in D\n...\n"
          "HB1 at D = 0.16504: omega = 1.0248 rad/s (period 6.13139 s), l1 = ...: subcritical (unstable cycles)\n```\n")


def test_a_transcript_holds_the_printed_lines_to_the_precision_it_shows():
    """Each line of a marked code block is a printed line, in order, each number within half a unit of its last
    shown digit of the printed one (0.16504 for 0.1650420453; 0.1650 is not, 0.16505 is not); the digits of a
    name (HB1, u1) are text; ``...`` stands for left-out text or lines."""
    printed = {"continue_ab": AB}
    assert transcript_mismatches(AB_DOC, printed) == []
    assert transcript_mismatches(AB_DOC.replace("0.16504", "0.16505"), printed) \
        == [("continue_ab", AB_DOC.splitlines()[6].replace("0.16504", "0.16505"), AB.splitlines()[-1])]
    assert transcript_mismatches(AB_DOC.replace("30 points", "31 points"), printed) \
        == [("continue_ab", "ab: 31 points in D", AB.splitlines()[0])]
    assert transcript_mismatches(AB_DOC.replace("30 points", "30.0 points"), printed) == []   # 30.0 holds 30
    assert transcript_mismatches(AB_DOC.replace("subcritical", "supercritical"), printed)[0][2] == "not printed"
    assert transcript_mismatches(AB_DOC.replace("HB1 at", "HB2 at"), printed)[0][2] == "not printed"
    swapped = AB_DOC.replace("ab: 30 points in D\n...\n", "").replace("s), l1 = ...: subcritical (unstable cycles)\n",
                                                                      "s), l1 = ...\nab: 30 points in D\n")
    assert transcript_mismatches(swapped, printed)[0][1:] == ("ab: 30 points in D", "not printed")   # out of order
    assert transcript_mismatches(AB_DOC, {})[0][2] == "not run"
    assert transcript_mismatches(AB_DOC.replace("<!--transcript:continue_ab-->\n", ""), {}) == []   # unmarked


def test_every_transcript_names_a_documented_command_and_every_command_is_quoted():
    """A transcript's comment names a command of COMMANDS (which the next test finds documented), and each command
    of COMMANDS gives the docs a marked number or a transcript (a command run for nothing is a slow test too many)."""
    transcripts = [m.group(1) for path in DOCUMENTS for m in TRANSCRIPT.finditer(path.read_text(encoding="utf-8"))]
    assert set(transcripts) <= set(COMMANDS), set(transcripts) - set(COMMANDS)
    assert set(COMMANDS) == set(transcripts) | {q.source for q in QUOTES.values() if q.source in COMMANDS}
    texts = "".join(path.read_text(encoding="utf-8") for path in DOCUMENTS)
    assert len(re.findall(r"<!--transcript:[a-z0-9_]+-->", texts)) == len(transcripts)   # each right before a fence
    assert len(re.findall(r"<!--block:[a-z0-9_]+ ", texts)) == len(list(BLOCK_MARK.finditer(texts)))


def test_the_quoted_commands_are_the_documented_ones():
    """Each command of COMMANDS is shown in a document as it is run: a line of a code block (joined over its
    backslashes, a comment after `` #`` dropped) with the same arguments."""
    shown = set()
    for path in DOCUMENTS:
        for block in re.findall(r"^```\w*\n(.*?)^```", path.read_text(encoding="utf-8"), re.S | re.M):
            for line in re.sub(r"\\\n\s*", " ", block).splitlines():
                if line.startswith("mechcont "):
                    shown.add(tuple(shlex.split(line.split(" #")[0])[1:]))
    for source, args in COMMANDS.items():
        assert args in shown, source


def test_the_fill_command_refuses_a_folder_without_a_summary(tmp_path, capsys):
    assert main([str(tmp_path / "missing")]) == 2
    assert "no summary.md" in capsys.readouterr().err
    doc = tmp_path / "doc.md"
    doc.write_text("<!--run:nominal_lock_s-->9<!--/run--> s\n", encoding="utf-8")   # no command quoted: none run
    (tmp_path / "summary.md").write_text(SUMMARY, encoding="utf-8")
    assert main([str(tmp_path), str(doc)]) == 0
    assert doc.read_text(encoding="utf-8") == "<!--run:nominal_lock_s-->1.607<!--/run--> s\n"
    capsys.readouterr()
    doc.write_text("<!--transcript:no_such_command-->\n```\nP = 1\n```\n", encoding="utf-8")   # nothing to run
    assert main([str(tmp_path), str(doc)]) == 1
    assert "transcript of no_such_command: 'P = 1': the run prints 'not run'" in capsys.readouterr().err


def test_every_quoted_number_is_marked_and_every_mark_is_known():
    """The docs mark every number of :data:`QUOTES` somewhere, and name no number QUOTES does not know."""
    marks = [m.group(1) for path in DOCUMENTS for mark in (MARK, BLOCK_MARK)
             for m in mark.finditer(path.read_text(encoding="utf-8"))]
    assert set(marks) == set(QUOTES), (set(QUOTES) - set(marks), set(marks) - set(QUOTES))


def test_no_mark_is_inside_code_where_it_would_show_as_text():
    """A mark inside a code span or a code block is not an HTML comment to the reader: it shows as text (a
    transcript is checked line by line instead)."""
    shown = []
    for path in DOCUMENTS:
        text = path.read_text(encoding="utf-8")
        blocks = re.findall(r"^```\w*\n.*?^```", text, re.S | re.M)
        spans = re.findall(r"`[^`\n]+`", re.sub(r"^```\w*\n.*?^```", "", text, flags=re.S | re.M))
        shown += [(path.name, code[:80]) for code in blocks + spans if MARK.search(code)]
    assert not shown, shown


#: The commands of COMMANDS that a document runs (a line of a ```sh block, run by
#: tests/test_doc_examples.py, which checks the numbers quoted from them on that run), and the others.
RUN_BY_EXAMPLES = {source for path in DOCUMENTS for source in quoted_here(path).values()}
NOT_RUN_BY_EXAMPLES = sorted(set(COMMANDS) - RUN_BY_EXAMPLES)


def test_a_command_run_by_the_examples_prints_there_what_it_prints_afresh():
    """The numbers of a command that a document runs are checked on the examples' run of it (in the document's
    scratch folder, after the commands before it): no earlier command writes a file it names, so that run is the
    command run afresh, as :func:`~mechcont.paper.doc_numbers.command_outputs` runs it (a copy of ``examples/``)."""
    assert RUN_BY_EXAMPLES and NOT_RUN_BY_EXAMPLES == ["freefall_sidestay_cli"]
    for path in DOCUMENTS:
        steps = examples(path)
        for k in quoted_here(path):
            earlier = {out for kind, text in steps[:k] if kind == "run" for out in outputs(_arguments(text))}
            earlier |= {text.split("\n", 1)[0] for kind, text in steps[:k] if kind == "file"}
            assert not earlier & set(COMMANDS[quoted_here(path)[k]]), (path.name, steps[k][1])


@pytest.mark.slow
@pytest.mark.parametrize("source", NOT_RUN_BY_EXAMPLES)
def test_the_docs_quote_what_the_documented_command_prints(source):
    """The documented command that no runnable block runs (see the test above), run afresh from the repository's
    root, prints every number the docs quote from it and every line of its transcripts."""
    printed = command_outputs(ROOT, [source])
    assert set(quoted(printed)) == {n for n, q in QUOTES.items() if q.source == source}
    wrong = quoted_wrong(printed)
    assert not wrong, ("quoted numbers and transcript lines that are not the run's (fill the marks: "
                       f"python -m mechcont.paper.doc_numbers): {wrong}")
