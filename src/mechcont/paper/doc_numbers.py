"""Numbers the docs quote from a ``mechcont paper`` run, filled in from the run's ``summary.md``.

A quoted number is written in a document between two HTML comments naming what it is (invisible once the
Markdown is rendered)::

    the aft upper arm <!--run:kinematic_offset_mm-->236<!--/run--> mm off its airframe point

:data:`QUOTES` says where each named number stands in ``summary.md`` (a regular expression whose first group is
the number as printed). ``python -m mechcont.paper.doc_numbers DIR [FILE ...]`` fills every marked number of the
files (default: ``README.md`` and ``docs/*.md`` of the current folder) from ``DIR/summary.md``;
:func:`mismatches` lists the ones that differ (``tests/test_doc_numbers.py`` asks for none against a fresh run of
the sections the quotes come from).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

__all__ = ["QUOTES", "MARK", "quoted", "fill", "mismatches", "main"]

_N = r"([-+]?[0-9][0-9.,e+-]*)"
#: ``{name: (section, pattern)}``: the ``mechcont paper`` section whose summary prints the number, and where.
QUOTES: dict[str, tuple[str, str]] = {
    "kinematic_offset_mm": ("freefall", r"the aft upper arm ends " + _N + r" mm off its airframe point"),
    "kinematic_aft_deg": ("freefall", r"seen in their fold plane, " + _N + r" deg from aligned"),
    "released_deflection_um": ("freefall", r"the attachment deflects " + _N + r" um under its load"),
    "released_fwd_deg": ("freefall", r"folded fwd " + _N + r" deg, aft"),
    "released_aft_deg": ("freefall", r"folded fwd [-+0-9.]+ deg, aft " + _N + r" deg"),
    "lock_gap_min_ms": ("freefall", r"Both sidestays lock in every run, [^,]+, " + _N + r" to"),
    "lock_gap_max_ms": ("freefall", r"Both sidestays lock in every run, [^,]+, [-+0-9.]+ to " + _N + r" ms apart"),
    "lock_order": ("freefall", r"Both sidestays lock in every run, ([^,]+),"),
    "nominal_lock_s": ("freefall", r"the nominal gear has locked " + _N + r" s after"),
    "first_strike_min_s": ("freefall", r"the first strike comes " + _N + r" to"),
    "first_strike_max_s": ("freefall", r"the first strike comes [-+0-9.]+ to " + _N + r" s after"),
}
#: A marked number in a document: its name (lower case: ``NAME`` in the docs that describe the marks is not one)
#: and the text between the marks.
MARK = re.compile(r"<!--run:([a-z0-9_]+)-->(.*?)<!--/run-->")


def quoted(summary: str) -> dict[str, str]:
    """``{name: the number as summary.md prints it}`` for every name of :data:`QUOTES` found in ``summary``."""
    out = {}
    for name, (_, pattern) in QUOTES.items():
        m = re.search(pattern, summary)
        if m:
            out[name] = m.group(1).rstrip(".,")
    return out


def fill(text: str, summary: str) -> str:
    """``text`` with every marked number replaced by the summary's. Raises ``KeyError`` naming a mark that
    :data:`QUOTES` does not know or the summary does not print."""
    values = quoted(summary)

    def one(m: re.Match) -> str:
        if m.group(1) not in values:
            raise KeyError(f"{m.group(1)}: not in QUOTES or not printed in this summary")
        return f"<!--run:{m.group(1)}-->{values[m.group(1)]}<!--/run-->"

    return MARK.sub(one, text)


def mismatches(text: str, summary: str) -> list[tuple[str, str, str | None]]:
    """``[(name, quoted, printed)]`` for every marked number of ``text`` that is not what ``summary`` prints
    (``printed`` None: the summary does not print it)."""
    values = quoted(summary)
    return [(m.group(1), m.group(2), values.get(m.group(1))) for m in MARK.finditer(text)
            if values.get(m.group(1)) != m.group(2)]


def main(argv: list[str] | None = None) -> int:
    """``python -m mechcont.paper.doc_numbers DIR [FILE ...]``: fill the marked numbers of the files from
    ``DIR/summary.md``; prints each file changed. Returns the exit status (2 on bad input)."""
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
    for path in files:
        text = path.read_text(encoding="utf-8")
        try:
            new = fill(text, summary)
        except KeyError as e:
            print(f"{path}: {e.args[0]}", file=sys.stderr)
            return 2
        if new != text:
            path.write_text(new, encoding="utf-8")
            print(f"filled {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
