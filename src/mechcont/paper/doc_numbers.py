"""Numbers the docs quote from a run, filled in from what the run prints.

A quoted number is written in a document between two HTML comments naming what it is (invisible once the
Markdown is rendered)::

    the aft upper arm <!--run:kinematic_offset_mm-->236<!--/run--> mm off its airframe point

:data:`QUOTES` says where each named number stands in the printed text of its source (a regular expression) and
how the document shows it: the source is a ``mechcont paper`` section (its lines of ``summary.md``) or one of the
documented commands of :data:`COMMANDS` (what it prints). ``python -m mechcont.paper.doc_numbers DIR [FILE ...]``
fills every marked number of the files (default: ``README.md`` and ``docs/*.md`` of the current folder, the
repository's root, whose ``examples/`` the commands read) from ``DIR/summary.md`` and the commands' output; :func:`mismatches`
lists the ones that differ (``tests/test_doc_numbers.py`` asks for none: against the paper sections' run of the
session and the documented commands' output from the test suite's run of the documents' examples, a command no
example runs run afresh).

A number inside a code block (a comment of a Python example) is named by an HTML comment before the fence with the
text around it, ``<!--block:NAME LU={},-->``: the block holds that text with the number the run prints.
A code block that shows what a command of :data:`COMMANDS` prints (a transcript, where a mark would show as text)
is named by an HTML comment on the line before its fence, ``<!--transcript:SOURCE-->``; :func:`transcript_mismatches`
finds each of its lines among the command's output lines, in order (the text alike up to spaces, ``...`` standing
for any text), and each number in it the printed one to the precision the document shows (half a unit of its last
digit).
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import NamedTuple

__all__ = ["QUOTES", "COMMANDS", "MARK", "BLOCK_MARK", "TRANSCRIPT", "Quote", "quoted", "fill", "block_fill",
           "mismatches", "transcript_mismatches", "command_outputs", "main"]

_N = r"([-+]?[0-9][0-9.,e+-]*)"


def _printed(m: re.Match) -> str:
    """The number as printed (a trailing full stop or comma is the sentence's)."""
    return m.group(1).rstrip(".,")


def _shown(scale: float, fmt: str, *, of: Callable[..., float] = lambda v, *_: v, absolute: bool = False,
           minus: str = "-") -> Callable[[re.Match], str]:
    """A reader of a match: ``of`` its numbers (default: the first; ``math.hypot``: the length of the vector they
    are) times ``scale``, formatted with ``fmt`` (``absolute``: its magnitude; ``minus``: the sign the document
    writes, e.g. U+2212; an exponent without its leading zeros, ``2.6e-7``)."""
    def show(m: re.Match) -> str:
        v = scale * of(*(float(g.rstrip(".,")) for g in m.groups()))
        text = format(abs(v) if absolute else v, fmt)
        text = re.sub(r"e([-+])0*(\d)", lambda e: "e" + e.group(1).replace("+", "") + e.group(2), text)
        return text.replace("-", minus, 1) if text.startswith("-") else text
    return show


def _times_ten(digits: int) -> Callable[[re.Match], str]:
    """A reader of a match: its first number to ``digits`` significant digits as a table writes it, ``1.215·10⁻⁶``."""
    def show(m: re.Match) -> str:
        mantissa, exponent = format(float(_printed(m)), f".{digits - 1}e").split("e")
        return f"{mantissa}·10" + str(int(exponent)).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))
    return show


class Quote(NamedTuple):
    """Where a quoted number comes from: ``source`` (a ``mechcont paper`` section, or a key of
    :data:`COMMANDS`), ``pattern`` (a regular expression on the source's printed text; its groups are the
    numbers), ``shown`` (the text the document writes, from the match)."""

    source: str
    pattern: str
    shown: Callable[[re.Match], str] = _printed


#: The documented commands whose printed numbers the docs quote: ``{source: mechcont arguments}``, each run in a
#: scratch folder holding a copy of the repository's ``examples/`` (as a document shows it:
#: ``tests/test_doc_numbers.py`` checks they are there).
COMMANDS: dict[str, tuple[str, ...]] = {
    "optimize_nose_gear": ("optimize", "nose_gear", "--maximize", "LU", "--design", "LU=1.2:1.4", "--dist",
                           "LU=normal:1.3:0.01", "--dist", "l_sp1=truncnormal:0.1:0.005:0.09:0.11", "--constraint",
                           "P(not locking) <= 1e-6"),
    "optimize_dual_sidestay": ("optimize", "examples/dual_sidestay.toml", "--minimize", "unlock_force", "--force",
                               "F_lock", "--design", "k_lock=1000:16000", "--design", "stretch=0.5:0.85", "--dist",
                               "k_lock=normal:8000:200", "--dist", "stretch=normal:0.7:0.005", "--constraint",
                               "P(not locking) <= 1e-6", "--set", "k_lock=2000", "--set", "stretch=0.5"),
    "tour_continue": ("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--bounds",
                      "F=-100:120", "--out", "branch.csv", "--plot", "branch.png"),
    "check_locked": ("check", "examples/dual_sidestay_locked.toml"),
    "freefall_sidestay_cli": ("freefall", "examples/dual_sidestay.toml", "--start", "theta=1.4835298641951802",
                              "--held-by", "F_act", "--lock", "fwd_stop", "--lock", "aft_stop", "--until", "3",
                              "--rtol", "1e-6"),
    "optimize_ds_preload": ("optimize", "examples/dual_sidestay.toml", "--minimize", "unlock_force", "--force", "F_lock",
                            "--design", "k_lock=1000:16000", "--design", "stretch=0.5:0.85", "--constraint",
                            "stop_preload >= 20"),
    "tour_folds": ("folds", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--along", "LU",
                   "--bounds", "F=-200:200", "--bounds", "LU=0.1:2", "--out", "folds.csv"),
    "optimize_lockstay": ("optimize", "lockstay.toml", "--minimize", "unlock_force", "--design", "LU=0.5:0.7", "--design",
                          "k=10000:30000", "--dist", "LU=normal:0.6:0.005", "--dist", "k=normal:20000:1500",
                          "--constraint", "P(not locking) <= 1e-6"),
    "continue_ab": ("continue", "examples/ab.toml", "--vary", "D", "--bounds", "D=0:0.2", "--out", "ab.csv", "--plot",
                    "ab.png"),
    "study_tolerances": ("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--dist",
                         "l_sp1=truncnormal:0.1:0.005:0.09:0.11", "--n", "10000", "--seed", "1", "--dir", "tolerances",
                         "--plot", "tolerances.png"),
    "freefall_leg": ("freefall", "examples/freefall_leg.toml", "--start", "angle=3.0", "--lock", "downlock", "--until",
                     "10", "--set", "U=40"),
    "study_rel": ("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--dist", "l_sp1=truncnormal:0.1:0.005:0.09:0.11",
                  "--method", "form", "--n", "2000", "--seed", "1", "--scheduler", "serial", "--dir", "rel"),
    "study_rare": ("study", "nose_gear", "--dist", "LU=normal:1.2696:0.01", "--dist",
                   "l_sp1=truncnormal:0.1:0.005:0.09:0.11", "--method", "form", "--n", "10000", "--scheduler", "serial",
                   "--dir", "rare"),
}
_DEFLECTION = r"aft_A_x\s+([-+0-9.e]+) m.*\n\s*aft_A_y\s+([-+0-9.e]+) m.*\n\s*aft_A_z\s+([-+0-9.e]+) m"
_REACTION = r"R_aft_A_x = ([-+0-9.e]+) N.*\n.*R_aft_A_y = ([-+0-9.e]+) N.*\n.*R_aft_A_z = ([-+0-9.e]+) N"
#: ``{name: Quote}``: every number the docs quote from a run.
QUOTES: dict[str, Quote] = {
    "kinematic_offset_mm": Quote("freefall", r"the aft upper arm ends " + _N + r" mm off its airframe point"),
    "kinematic_aft_deg": Quote("freefall", r"seen in their fold plane, " + _N + r" deg from aligned"),
    "released_deflection_um": Quote("freefall", r"the attachment deflects " + _N + r" um under its load"),
    "released_fwd_deg": Quote("freefall", r"folded fwd " + _N + r" deg, aft"),
    "released_aft_deg": Quote("freefall", r"folded fwd [-+0-9.]+ deg, aft " + _N + r" deg"),
    "lock_gap_min_ms": Quote("freefall", r"Both sidestays lock in every run, [^,]+, " + _N + r" to"),
    "lock_gap_max_ms": Quote("freefall", r"Both sidestays lock in every run, [^,]+, [-+0-9.]+ to " + _N
                             + r" ms apart"),
    "lock_order": Quote("freefall", r"Both sidestays lock in every run, ([^,]+),"),
    "nominal_lock_s": Quote("freefall", r"the nominal gear has locked " + _N + r" s after"),
    "first_strike_min_s": Quote("freefall", r"the first strike comes " + _N + r" to"),
    "first_strike_max_s": Quote("freefall", r"the first strike comes [-+0-9.]+ to " + _N + r" s after"),
    # the reliability-based design section: the nose gear's, the lock stay's and the dual-sidestay gear's optima
    "paper_nose_lu_m": Quote("design_optimum", r"lock-spring free length is LU = " + _N + " m", _shown(1.0, ".6f")),
    "paper_nose_force_n": Quote("design_optimum", r"its nominal downlock force is " + _N + " N", _shown(1.0, ".2f")),
    "paper_stay_unlock_n": Quote("design_optimum", r"Lock stay, .*? the least unlock load is " + _N + " N",
                                 _shown(1.0, ".3f")),
    "paper_stay_k": Quote("design_optimum", r"Lock stay, .*? N at k = " + _N + " N/m", _shown(1.0, ".0f")),
    "paper_stay_lu_m": Quote("design_optimum", r"Lock stay, .*? N/m and LU = " + _N + " m", _shown(1.0, ".6f")),
    "paper_stay_multiplier": Quote("design_optimum", r"Lock stay, .*?beta\(not locking\) >= [0-9.]+ \(multiplier "
                                   + _N + r"\)", _shown(1.0, ".2f")),
    "paper_ds_unlock_n": Quote("design_optimum", r"unlock load of both pairs together is " + _N + " N",
                               _shown(1.0, ".2f")),
    "paper_ds_k_lock": Quote("design_optimum", r"both pairs together is [0-9.]+ N at k_lock = " + _N + " N/m",
                             _shown(1.0, ".1f")),
    "paper_ds_stretch": Quote("design_optimum", r"both pairs together is .*? N/m and stretch = " + _N + ", with",
                              _shown(1.0, "g")),
    "paper_ds_nominal_unlock_n": Quote("design_optimum", r"The description's springs .*? need " + _N + " N with",
                                       _shown(1.0, ".1f")),
    "paper_ds_nominal_fwd_nm": Quote("design_optimum", r"The description's springs .*? with preloads fwd " + _N,
                                     _shown(1.0, ".1f")),
    "paper_ds_nominal_aft_nm": Quote("design_optimum", r"The description's springs .*? with preloads fwd [0-9.]+, aft "
                                     + _N + " N m", _shown(1.0, ".1f")),
    # the dual-sidestay gear's least unlock load with each stop preloaded (docs/reliability.md)
    "ds_preload_unlock_n": Quote("optimize_ds_preload", r"unlock_force = " + _N + " N", _shown(1.0, ".2f")),
    "ds_preload_k_lock": Quote("optimize_ds_preload", r"\n  k_lock = " + _N + " N/m", _shown(1.0, ".1f")),
    "ds_preload_stretch": Quote("optimize_ds_preload", r"\n  stretch = " + _N, _shown(1.0, "g")),
    "ds_preload_iterations": Quote("optimize_ds_preload", r"\(([0-9]+) iterations"),
    "ds_preload_aft_nm": Quote("optimize_ds_preload", r"\n  R_aft_stop = " + _N + " N m", _shown(1.0, ".2f")),
    "ds_preload_fwd_multiplier": Quote("optimize_ds_preload", r"R_fwd_stop >= [0-9.]+ \(multiplier " + _N + r"\)",
                                       _shown(1.0, ".2f")),
    "ds_preload_stretch_multiplier": Quote("optimize_ds_preload", r"stretch >= [0-9.]+ \(multiplier " + _N + r"\)",
                                           _shown(1.0, ".2f")),
    # FORM and SORM of the nose gear's tolerances, and with the free length 30 mm shorter (docs/reliability.md)
    "rel_beta": Quote("study_rel", r"FORM: beta = " + _N, _shown(1.0, ".3f")),
    "rel_p_form": Quote("study_rel", r"P\(downlock_force <= 0\) = " + _N, _shown(1.0, ".4g")),
    "rel_p_sorm": Quote("study_rel", r"SORM \(Breitung\): P = " + _N, _shown(1.0, ".3g")),
    "rare_beta": Quote("study_rare", r"FORM: beta = " + _N, _shown(1.0, ".3f")),
    "rare_p_form": Quote("study_rare", r"P\(downlock_force <= 0\) = " + _N, _times_ten(4)),
    "rare_p_sorm": Quote("study_rare", r"SORM \(Breitung\): P = " + _N, _times_ten(4)),
    # the README tour's branch of the overcentre mechanism: its two folds
    "tour_lp1_n": Quote("tour_continue", r"\nLP1\s+" + _N, _shown(1.0, ".2f", minus="\u2212")),
    "tour_lp2_n": Quote("tour_continue", r"\nLP2\s+" + _N, _shown(1.0, "+.2f")),
    "tour_cusp_lu_m": Quote("tour_folds", r"\nCP1\s+" + _N, _shown(1.0, ".4g")),
    # the nose gear's longest free length at P(not locking) <= 1e-6 (docs/reliability.md)
    "optimum_nose_lu_m": Quote("optimize_nose_gear", r"\nLU = " + _N + " m", _shown(1.0, ".4f")),
    "optimum_nose_iterations": Quote("optimize_nose_gear", r"\(([0-9]+) iterations"),
    # the dual-sidestay gear's least unlock load at P(not locking) <= 1e-6 (docs/reliability.md)
    "ds_optimum_unlock_n": Quote("optimize_dual_sidestay", r"unlock_force = " + _N + " N", _shown(1.0, ".2f")),
    "ds_optimum_k_lock": Quote("optimize_dual_sidestay", r"\n  k_lock = " + _N + " N/m", _shown(1.0, ".1f")),
    "ds_optimum_stretch": Quote("optimize_dual_sidestay", r"\n  stretch = " + _N, _shown(1.0, ".5f")),
    "ds_optimum_beta": Quote("optimize_dual_sidestay", r"beta\(not locking\) = " + _N, _shown(1.0, ".5f")),
    "ds_optimum_iterations": Quote("optimize_dual_sidestay", r"\(([0-9]+) iterations"),
    "ds_optimum_multiplier": Quote("optimize_dual_sidestay", r"\(multiplier " + _N + r"\)", _shown(1.0, ".2f")),
    # the lock stay's least unlock load at P(not locking) <= 1e-6 (docs/reliability.md)
    "lockstay_optimum_unlock_n": Quote("optimize_lockstay", r"unlock_force = " + _N + " N", _shown(1.0, ".0f")),
    "lockstay_optimum_k": Quote("optimize_lockstay", r"\n  k = " + _N + " N/m", _shown(1.0, ".0f")),
    "lockstay_optimum_lu_m": Quote("optimize_lockstay", r"\n  LU = " + _N + " m", _shown(1.0, ".5f")),
    "lockstay_optimum_multiplier": Quote("optimize_lockstay", r"beta\(not locking\) >= [0-9.]+ \(multiplier " + _N,
                                         _shown(1.0, ".1f")),
    # mechcont check examples/dual_sidestay_locked.toml: the compliant attachment's deflection and reaction
    # (their lengths: the check prints the components) and the retraction angle
    "locked_theta_deg": Quote("check_locked", r"\n  theta\s+" + _N + r" deg", _shown(1.0, ".3f", minus="\u2212")),
    "locked_deflection_um": Quote("check_locked", _DEFLECTION, _shown(1e6, ".0f", of=math.hypot)),
    "locked_reaction_kn": Quote("check_locked", _REACTION, _shown(1e-3, ".2f", of=math.hypot)),
    # mechcont freefall examples/dual_sidestay.toml ...: the energy balance and the actuator damper's peak
    "fall_released_kj": Quote("freefall_sidestay_cli", r"# energy \[J\]: start " + _N + " .*potential " + _N,
                              _shown(1e-3, ".0f", of=lambda start, end: start - end)),   # released at rest
    "fall_kinetic_j": Quote("freefall_sidestay_cli", r"# energy \[J\]: .*kinetic " + _N, _shown(1.0, ".1e")),
    "fall_residual_j": Quote("freefall_sidestay_cli", r"# energy \[J\]: .*residual " + _N,
                             _shown(1.0, ".1g", absolute=True)),
    "fall_bound_j": Quote("freefall_sidestay_cli", r"# energy \[J\]: .*bound " + _N + r"\)", _shown(1.0, ".0f")),
    "fall_actuator_kn": Quote("freefall_sidestay_cli", r"peak damper tension actuator: " + _N + " N",
                              _shown(1e-3, ".1f")),
    "fall_actuator_s": Quote("freefall_sidestay_cli", r"peak damper tension actuator: [-+0-9.e]+ N at t = " + _N
                             + " s", _shown(1.0, ".2f")),
}
#: A marked number in a document: its name (lower case: ``NAME`` in the docs that describe the marks is not one)
#: and the text between the marks.
MARK = re.compile(r"<!--run:([a-z0-9_]+)-->(.*?)<!--/run-->")


def quoted(printed: Mapping[str, str]) -> dict[str, str]:
    """``{name: the number as the document shows it}`` for every name of :data:`QUOTES` whose source's printed
    text (``printed``: ``{source: text}``, a paper section's ``summary.md`` lines or a command's output) holds it."""
    out = {}
    for name, quote in QUOTES.items():
        m = re.search(quote.pattern, printed.get(quote.source, ""))
        if m:
            out[name] = quote.shown(m)
    return out


def fill(text: str, printed: Mapping[str, str]) -> str:
    """``text`` with every marked number replaced by the run's (``printed`` as for :func:`quoted`). Raises
    ``KeyError`` naming a mark that :data:`QUOTES` does not know or whose source does not print it."""
    values = quoted(printed)

    def one(m: re.Match) -> str:
        if m.group(1) not in values:
            raise KeyError(f"{m.group(1)}: not in QUOTES or not printed by its source")
        return f"<!--run:{m.group(1)}-->{values[m.group(1)]}<!--/run-->"

    return block_fill(MARK.sub(one, text), values)


def mismatches(text: str, printed: Mapping[str, str]) -> list[tuple[str, str, str | None]]:
    """``[(name, quoted, printed)]`` for every marked number of ``text`` that is not what its source prints
    (``printed`` None: the source does not print it, or was not run)."""
    values = quoted(printed)
    shown = [(m.group(1), m.group(2)) for m in MARK.finditer(text)]
    for m in BLOCK_MARK.finditer(text):   # a number in a code block: the text its mark names, in the block
        found = _in_block(m.group(2)).search(m.group(3))
        shown.append((m.group(1), found.group(1) if found else f"no {m.group(2)!r} in the block"))
    return [(name, value, values.get(name)) for name, value in shown if values.get(name) != value]


#: A number quoted inside a code block (where a mark would show as text): an HTML comment before the fence names it
#: and the text around it, ``<!--block:NAME TEXT-->`` with ``{}`` in TEXT for the number (``LU={}``).
BLOCK_MARK = re.compile(r"<!--block:([a-z0-9_]+) (.*?)-->[ \t]*\n(```\w*\n.*?^```)", re.S | re.M)


def _in_block(template: str) -> re.Pattern:
    """TEXT of a block mark as a pattern: the number in its place (captured), the rest as written."""
    before, _, after = template.partition("{}")
    return re.compile(re.escape(before) + r"([-+\u2212]?[0-9][0-9.e+-]*)" + re.escape(after))


def block_fill(text: str, values: Mapping[str, str]) -> str:
    """``text`` with the number of every block mark replaced by ``values[NAME]`` (as :func:`quoted` gives it)."""
    def one(m: re.Match) -> str:
        if m.group(1) not in values:
            raise KeyError(f"{m.group(1)}: not in QUOTES or not printed by its source")
        pattern = _in_block(m.group(2))
        if not pattern.search(m.group(3)):
            raise KeyError(f"{m.group(1)}: its code block has no {m.group(2)!r}")
        block = pattern.sub(lambda b: m.group(2).replace("{}", values[m.group(1)]), m.group(3), count=1)
        return m.group(0)[:m.start(3) - m.start(0)] + block

    return BLOCK_MARK.sub(one, text)


#: A transcript in a document: the source its comment names and the code block's text.
TRANSCRIPT = re.compile(r"<!--transcript:([a-z0-9_]+)-->[ \t]*\n```\w*\n(.*?)^```", re.S | re.M)
#: A number in a transcript line (not the digit of a name such as ``HB1`` or ``l_sp1``).
_NUMBER = re.compile(r"(?<![\w.])[-+]?[0-9]+(?:\.[0-9]+)?(?:[eE][-+]?[0-9]+)?(?!\w)")


def _unit(shown: str) -> float:
    """The unit of the last digit of a number as written (``1.21504e-06``: 1e-11; ``0.9963``: 1e-4; ``13``: 1)."""
    mantissa, _, exponent = shown.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    return 10.0 ** (int(exponent or 0) - decimals)


def _line_pattern(line: str) -> re.Pattern:
    """A transcript line as a pattern on a printed line: its numbers captured, ``...`` any text, spaces any."""
    parts, at = [], 0
    for m in re.finditer(r"\.\.\.|" + _NUMBER.pattern + r"|\s+", line):
        parts.append(re.escape(line[at:m.start()]))
        token = m.group(0)
        parts.append(".*?" if token == "..." else r"\s+" if token.isspace() else "(" + _NUMBER.pattern + ")")
        at = m.end()
    parts.append(re.escape(line[at:]))
    return re.compile("".join(parts))


def transcript_mismatches(text: str, printed: Mapping[str, str]) -> list[tuple[str, str, str]]:
    """``[(source, line, what the run prints instead)]`` for every line of a transcript of ``text`` (code blocks
    marked ``<!--transcript:SOURCE-->``, ``printed`` as for :func:`quoted`) that its command does not print: no
    output line with its text after the one the previous line matched (``what``: ``not printed``, or ``not run``),
    or a number further from the printed one than half a unit of its last shown digit (``what``: the printed
    line). A line that is only ``...`` stands for lines left out."""
    out = []
    for block in TRANSCRIPT.finditer(text):
        source = block.group(1)
        if source not in printed:
            out.append((source, block.group(2).strip().splitlines()[0], "not run"))
            continue
        lines, at = [ln.strip() for ln in printed[source].splitlines()], 0
        for line in (ln.strip() for ln in block.group(2).splitlines()):
            if line in ("", "..."):
                continue
            pattern, shown = _line_pattern(line), _NUMBER.findall(line)
            hit = next((i for i in range(at, len(lines)) if pattern.fullmatch(lines[i])), None)
            if hit is None:
                out.append((source, line, "not printed"))
                continue
            at = hit + 1
            runs = pattern.fullmatch(lines[hit]).groups()   # type: ignore[union-attr]
            if any(abs(float(s) - float(r)) > 0.5 * _unit(s) * (1 + 1e-9) for s, r in zip(shown, runs)):
                out.append((source, line, lines[hit]))
    return out


def command_outputs(root: Path, sources: Iterable[str] | None = None) -> dict[str, str]:
    """``{source: what the command prints}`` for the :data:`COMMANDS` named in ``sources`` (default: all), each
    run as ``python -m mechcont ARGS`` in a scratch folder holding a copy of ``root/examples`` (``root``: the
    repository's root; the files a command writes go there, and are removed). Raises ``RuntimeError`` naming a
    command that fails."""
    import shutil
    import tempfile

    out = {}
    with tempfile.TemporaryDirectory(prefix="mechcont-doc-numbers-") as scratch:
        shutil.copytree(Path(root) / "examples", Path(scratch) / "examples")
        for source in COMMANDS if sources is None else sources:
            r = subprocess.run([sys.executable, "-m", "mechcont", *COMMANDS[source]], cwd=scratch,
                               capture_output=True, text=True)
            if r.returncode:
                raise RuntimeError(f"mechcont {' '.join(COMMANDS[source])}: exit {r.returncode}: "
                                   f"{r.stderr.strip()[-500:]}")
            out[source] = r.stdout
    return out


def main(argv: list[str] | None = None) -> int:
    """``python -m mechcont.paper.doc_numbers DIR [FILE ...]``, run from the repository's root: fill the marked
    numbers of the files from ``DIR/summary.md`` (every paper section's) and from the output of the
    :data:`COMMANDS` (run on a copy of ``examples/`` of this folder); prints each file changed, and each transcript
    line the run does not print (:func:`transcript_mismatches`; those are left to the writer). Returns the exit
    status (1: a transcript differs; 2 on bad input)."""
    args = sys.argv[1:] if argv is None else argv
    if not args:
        print("usage: python -m mechcont.paper.doc_numbers PAPER_DIR [FILE ...]", file=sys.stderr)
        return 2
    try:
        summary = (Path(args[0]) / "summary.md").read_text(encoding="utf-8")
    except OSError as e:
        print(f"{args[0]}: no summary.md there ({e.strerror})", file=sys.stderr)
        return 2
    files = [Path(a) for a in args[1:]] or [Path("README.md"), *sorted(Path("docs").glob("*.md"))]
    texts = {path: path.read_text(encoding="utf-8") for path in files}
    wanted = {QUOTES[m.group(1)].source for t in texts.values() for mark in (MARK, BLOCK_MARK)
              for m in mark.finditer(t) if m.group(1) in QUOTES}
    wanted |= {m.group(1) for t in texts.values() for m in TRANSCRIPT.finditer(t)}
    printed = {q.source: summary for q in QUOTES.values() if q.source not in COMMANDS}
    try:
        printed.update(command_outputs(Path.cwd(), sorted(wanted & set(COMMANDS))))
    except RuntimeError as e:
        print(e, file=sys.stderr)
        return 2
    for path, text in texts.items():
        try:
            new = fill(text, printed)
        except KeyError as e:
            print(f"{path}: {e.args[0]}", file=sys.stderr)
            return 2
        if new != text:
            path.write_text(new, encoding="utf-8")
            print(f"filled {path}")
    stale = [(path, *m) for path, text in texts.items() for m in transcript_mismatches(text, printed)]
    for path, source, line, run in stale:   # a transcript's text is the writer's: shown, not rewritten
        print(f"{path}: transcript of {source}: {line!r}: the run prints {run!r}", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    raise SystemExit(main())
