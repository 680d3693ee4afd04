"""Tables as text and files: branch tables, record tables (Markdown or CSV), special-point tables.

No Matplotlib here: the commands that print tables stay light.
"""

from __future__ import annotations

import io
import math
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from .._io import atomic_write
from ..units import display, display_unit
from .plotting import axis_label

if TYPE_CHECKING:
    from ..continuation import Branch, CycleBranch
    from ..dynamics import SimulationResult

__all__ = ["BRANCH_SUFFIXES", "RECORD_SUFFIXES", "write_branch_table", "markdown_table", "write_records", "branch_value",
           "hopf_lines", "hopf_curve_lines", "heading", "special_table", "approximate_warnings", "jump_lines", "fold_sides",
           "event_labels", "write_rows", "summary_rows", "write_text", "cycle_lines"]

#: A branch is written as CSV or JSON (by suffix).
BRANCH_SUFFIXES = (".csv", ".json")
#: A table of records (one dict per row) is written as CSV or Markdown (by suffix).
RECORD_SUFFIXES = (".csv", ".md")


def write_branch_table(branch: Branch, path: str | Path) -> Path:
    """Write ``branch`` to ``path`` as JSON when its suffix is ``.json`` (any case), else as CSV; returns the path."""
    path = Path(path)
    (branch.to_json if path.suffix.lower() == ".json" else branch.to_csv)(path)
    return path


def markdown_table(records: list[dict]) -> str:
    """A Markdown table of ``records`` (one dict per row, the first one's keys as headings); floats as ``.6g``."""
    keys = list(records[0])
    lines = ["| " + " | ".join(keys) + " |", "|" + "|".join("---" for _ in keys) + "|"]
    for r in records:
        lines.append("| " + " | ".join(f"{v:.6g}" if isinstance(v, float) else str(v) for v in r.values()) + " |")
    return "\n".join(lines)


def write_records(records: list[dict], path: str | Path) -> Path:
    """Write ``records`` to ``path`` as CSV (suffix ``.csv``, full precision) or else as Markdown, atomically."""
    import csv  # imported where a table is written: a command that writes none starts without it

    path = Path(path)
    buf = io.StringIO()
    if path.suffix.lower() == ".csv":
        w = csv.DictWriter(buf, fieldnames=list(records[0]), lineterminator="\n")
        w.writeheader()
        w.writerows(records)
    else:
        buf.write(markdown_table(records) + "\n")
    return atomic_write(path, lambda tmp: Path(tmp).write_text(buf.getvalue(), encoding="utf-8"))


def write_rows(path: str | Path, header: list[str], rows: Iterable[Sequence[object]]) -> Path:
    """Write a CSV of ``header`` and ``rows`` (numbers written in full, ``repr``; ``nan`` as ``nan``), atomically."""
    import csv

    def write(tmp: str) -> None:
        with open(tmp, "w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh, lineterminator="\n")
            w.writerow(header)
            w.writerows([repr(v) if isinstance(v, float) else v for v in row] for row in rows)

    return atomic_write(path, write)


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) at ``path`` atomically (no partial file left on failure); returns the path."""

    def write(tmp: str) -> None:
        Path(tmp).write_text(text, encoding="utf-8")

    return atomic_write(path, write)


def summary_rows(n: int, about: int = 10) -> list[int]:
    """The rows a summary of an ``n``-row table prints: every ``n // about``-th from the first, and the last."""
    step = max(1, n // about)
    return list(range(0, n, step)) + ([n - 1] if (n - 1) % step else [])


def branch_value(branch: Branch, name: str, value: float) -> float:
    """``value`` of column ``name`` of ``branch`` as shown in tables: angles (``rad``) in degrees, else SI."""
    return display(value, branch.units.get(name, ""))[0]


def heading(branch: Branch, name: str) -> str:
    """A column heading with its display unit: ``F (N)``, ``theta1 (deg)``, ``s``."""
    return axis_label(name, branch.units.get(name, ""))


def special_table(branch: Branch, cols: Sequence[str] | None = None) -> str:
    """A plain-text table of the special points of a branch (columns ``cols``).

    Points are named as everywhere else (:meth:`Branch.point_names`, numbered along the
    branch; ``LP2?`` when only approximate); angles are shown in degrees, every heading
    carries its unit, and a fold's stability is ``fold``, a non-smooth fold's (``NSF``) too (the stability
    on either side of it is in :func:`jump_lines`).
    """
    cols = list(dict.fromkeys(cols or [branch.vary, *branch.unknowns[:3]]))
    width = max(16, *(len(heading(branch, c)) + 2 for c in cols))
    head = f"{'point':<7}" + "".join(f"{heading(branch, c):>{width}}" for c in cols) + f"{'stability':>11}"
    lines = [f"{branch.model}: {len(branch)} points in {branch.vary}", head]
    st = branch.stability_labels()
    for name, p in zip(branch.point_names(), branch.special_points):
        vals = "".join(f" {branch_value(branch, c, p.values[c]):>{width - 1}.10g}" for c in cols)
        tag = name + ("" if p.located else "?")
        lines.append(f"{tag:<7}{vals}{st[p.index] or '-':>11}")
    return "\n".join(lines)


def hopf_lines(branch: Branch) -> list[str]:
    """One line per Hopf point (``HB``) of ``branch`` carrying its payload: where, the frequency (rad/s)
    and period (s), the first Lyapunov coefficient and what it means for the cycles born there."""
    out = []
    v = branch.vary
    unit = display_unit(branch.units.get(v, ""))
    for name, p in zip(branch.point_names(), branch.special_points):
        hopf = p.extra.get("hopf")
        if p.label != "HB" or hopf is None:
            continue
        where = f"{branch_value(branch, v, p.values[v]):.10g}" + (f" {unit}" if unit else "")
        out.append(f"{name} at {v} = {where}: omega = {hopf.frequency:.10g} rad/s (period {hopf.period:.6g} s), "
                   f"l1 = {hopf.lyapunov:.6g}: {hopf.criticality}")
    return out


def hopf_curve_lines(curve: Branch) -> list[str]:
    """One line per special point of a Hopf curve (:func:`~mechcont.continuation.continue_hopf`): its ``omega``
    (rad/s) and ``l1`` there, and what a ``BT`` or ``GH`` point means."""
    meaning = {"BT": "Bogdanov-Takens: omega reaches 0, the Hopf curve meets a fold curve",
               "GH": "generalised Hopf: l1 changes sign, the cycles born change stability"}
    out = []
    omega, l1 = curve.column("omega"), curve.column("l1")
    for name, p in zip(curve.point_names(), curve.special_points):
        if p.label in meaning:
            lyapunov = f"{l1[p.index]:.6g}" if math.isfinite(float(l1[p.index])) else "undefined"
            out.append(f"{name}: omega = {omega[p.index]:.6g} rad/s, l1 = {lyapunov} ({meaning[p.label]})")
    return out


def approximate_warnings(branch: Branch) -> list[str]:
    """One line per special point of ``branch`` that was detected but not located: where, and why."""
    out = []
    for name, p in zip(branch.point_names(), branch.special_points):
        if not p.located:
            why = p.reason or "not located"
            v = branch.vary
            unit = display_unit(branch.units.get(v, ""))
            out.append(f"{name} at {v} = {branch_value(branch, v, p.values[v]):.10g} {unit} is approximate "
                       f"({why}); its row is labelled {p.tag}".replace("  ", " "))
    return out


def jump_lines(branch: Branch, vary: str, y: str) -> list[str]:
    """One line per non-smooth fold (``NSF``) of a branch with stops: the load, the stability of the two pieces
    that meet there (:func:`fold_sides`), and where the mechanism lands."""
    out = []
    names = dict(zip((id(p) for p in branch.special_points), branch.point_names()))
    for p in branch.special("NSF"):
        at_fold = branch_value(branch, vary, p[vary])
        fold = p.nonsmooth
        sides = "" if fold is None else fold_sides(fold.sides)
        head = (f"{names[id(p)]}: non-smooth fold at {heading(branch, vary)} = {at_fold:.10g} (stop {p.stop}"
                + (f"; {sides}" if sides else "") + ")")
        land = None if fold is None else fold.landing
        if land is not None:
            at = dict(zip(branch.names, land.x))
            on = ", ".join(land.contact) or "none"
            how = "stable" if land.stable else "UNSTABLE"
            out.append(f"{head}: the mechanism jumps and lands at {heading(branch, y)} = "
                       f"{branch_value(branch, y, at[y]):.10g} (stops in contact: {on}; {how})")
        elif fold is not None and fold.jump:
            where = "back" if fold.behind else "further"
            out.append(f"{head}: the mechanism jumps; no equilibrium at that {vary} {where} along the branch "
                       "catches it within the bounds")
        else:
            out.append(f"{head}: reached along an unstable branch (nothing jumps there)")
    return out


def fold_sides(sides: Sequence[int]) -> str:
    """The stability of the pieces meeting at a non-smooth fold from their unstable counts
    (:attr:`~mechcont.continuation.NonSmoothFold.sides`), whichever was walked first:
    ``"stable on one side, unstable (1 direction) on the other"``; ``""`` when not computed."""
    def word(n: int) -> str:
        return "stable" if n == 0 else f"unstable ({n} direction{'s' if n > 1 else ''})"

    if len(sides) == 1:
        return f"{word(sides[0])} on the side found (no other piece)"
    if len(sides) == 2:
        return f"{word(sides[0])} on both sides" if sides[0] == sides[1] else (
            f"{word(sides[0])} on one side, {word(sides[1])} on the other")
    return ""


def event_labels(result: SimulationResult, units: Mapping[str, str]) -> list[str]:
    """One label per row of a time history (its CSV's label column): the stop events at that row,
    ``"impact rest 5.24 rad/s; contact rest"``; ``units`` maps a stop's name to its condition's unit."""
    labels = [""] * len(result.t)
    for ev in result.stop_events:
        rate = f"{units.get(ev.stop) or '1'}/s"
        text = f"{ev.kind} {ev.stop}" + (f" {ev.speed:.6g} {rate}" if ev.kind == "impact" else "")
        labels[ev.row] = f"{labels[ev.row]}; {text}" if labels[ev.row] else text
    return labels


def cycle_lines(family: CycleBranch) -> list[str]:
    """The orbits of a family of cycles as ``mechcont cycles`` prints them: a heading, one line per named orbit (its
    point name, ``LPC1?`` when only detected, the parameter in its unit (an angle in degrees), the period in s,
    the largest non-trivial Floquet multiplier's modulus, stability) and the count, with why the family ends."""
    unit = display_unit(family.vary_unit)
    vary = f"{family.vary} [{unit}]" if unit else family.vary
    out = [f"{'point':>6}  {vary:>12}  {'period [s]':>12}  {'floquet_max':>12}  stability"]
    stab, fmax = family.stability(), family.floquet_max
    for name, i in family.point_names():
        name += "?" if i in family.approximate else ""  # detected, not located: as the table writes it (LPC?)
        p = display(float(family.p[i]), family.vary_unit)[0]
        out.append(f"{name:>6}  {p:{max(12, len(vary))}.6g}  {family.period[i]:12.6g}  {fmax[i]:12.6g}  {stab[i]}")
    out.append(f"{len(family)} orbits" + (f"; ends: {family.message}" if family.message else ""))
    return out

