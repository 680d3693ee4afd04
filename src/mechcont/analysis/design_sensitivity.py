"""Per level of a design map (:func:`mechcont.analysis.design_region`): the exact derivatives of the downlock force at
the design value, of the lock margin and of the margin to the fold (``mechcont design --sensitivity``)."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from ..continuation import choose_unknowns
from ..equations import Model
from ..errors import ConvergenceError, InputError
from ..units import derivative_unit
from .design import DesignRegion
from .sensitivity import Sensitivity, check_parameters, downlock_sensitivity, margin_sensitivity

__all__ = ["DesignSensitivity", "design_sensitivity", "check_design_parameters", "TARGETS"]

#: What is differentiated per level, in the order of the columns.
TARGETS = ("force", "lock margin", "margin to fold")


@dataclass(frozen=True)
class DesignSensitivity:
    """The derivatives of :func:`design_sensitivity`.

    ``columns``: one heading per target of :data:`TARGETS` and parameter (in that order), its unit in brackets, e.g.
    ``"dF/dk at LU=1.3 (N/(N/m))"`` or ``"d(lock margin)/dk (m/(N/m))"``; ``rows``: per level of the map, in its
    order, the derivative under each heading (SI units), ``None`` where the level has no F = 0 crossing or fold to
    differentiate, or the solve failed; ``notes``: one line per solve that failed, saying why."""

    columns: tuple[str, ...]
    rows: tuple[dict[str, float | None], ...]
    notes: tuple[str, ...]


def check_design_parameters(system: Model, params: Iterable[str], hold: Mapping[str, float],
                            force: str) -> list[str]:
    """``params`` checked before any solve: each a parameter held in the downlock solve (``hold`` states held,
    ``force`` solved for); :class:`InputError` (field ``params``) otherwise."""
    params = list(params)
    if not params:
        return []
    try:
        return check_parameters(system, params, [*choose_unknowns(system, hold=hold, free=[force])])
    except InputError as exc:
        raise InputError("params", str(exc)[len(exc.field) + 2:]) from None


def design_sensitivity(system: Model, region: DesignRegion, params: Iterable[str],
                       values: Mapping[str, float] | None = None, *, hold: Mapping[str, float],
                       force: str) -> DesignSensitivity:
    """Per level of ``region``: the exact derivatives (implicit-function theorem, SI units) with respect to each of
    ``params`` of the downlock ``force`` at the design value of the map's x (``hold`` held), of the lock margin (the
    F = 0 crossing of x nearest the design value, inside the map's x range) and of the margin to the fold (the fold
    of x nearest it), the other parameters at ``values``.

    A level with no crossing or fold has ``None`` there; a solve that fails gives ``None`` and a note."""
    params = list(params)
    xn, yn = region.x_name, region.y_name
    x0, (lo, hi) = region.design[0], (float(region.x[0]), float(region.x[-1]))
    ux, uf = region.units[0], region.units[2]
    columns: list[str] = []
    rows: list[dict[str, float | None]] = []
    notes: list[str] = []
    for row in region.rows:
        at = {**(values or {}), xn: x0, yn: row.level}
        crossings = [e for iv in row.locking_intervals for e in iv if lo < e < hi]
        near = {"lock margin": min(crossings, key=lambda c: abs(c - x0), default=None),
                "margin to fold": min(row.folds, key=lambda c: abs(c - x0), default=None)}
        out: dict[str, float | None] = {}
        for what in TARGETS:
            unit = uf if what == "force" else ux
            s: Sensitivity | None
            try:
                if what == "force":
                    s = downlock_sensitivity(system, params, at, hold=hold, force=force)
                elif near[what] is None:
                    s = None
                else:
                    s = margin_sensitivity(system, xn, params, at, kind="lock" if what == "lock margin" else "fold",
                                           at=near[what], hold=hold, force=force)
            except (ConvergenceError, InputError) as exc:
                notes.append(f"{yn} = {row.level:g}: the sensitivity of the {what} is unknown: {exc}")
                s = None
            for p in params:
                u = derivative_unit(unit, system.variable(p).unit)
                head = f"d{force}/d{p} at {xn}={x0:g}" if what == "force" else f"d({what})/d{p}"
                out[f"{head} ({u})"] = s[p] if s is not None else None
        rows.append(out)
        columns = list(out)
    return DesignSensitivity(tuple(columns), tuple(rows), tuple(notes))
