"""The critical airspeed of a freefall over a scan of another parameter (a damper's coefficient), each bracket of
runs beside the one quasi-static predictor: what ``mechcont freefall --critical --scan`` reports and tabulates."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..equations import Model
from ..errors import InputError
from ._critical import CriticalAirspeed, QuasiStaticCritical, critical_airspeed, quasi_static_critical
from ._poses import Lock, travel_of

__all__ = ["CriticalScan", "critical_scan"]


@dataclass(frozen=True)
class CriticalScan:
    """Critical values of ``vary`` (an airspeed, m/s) bracketed by runs at each value of ``scan``, and the
    quasi-static predictor beside them.

    Attributes
    ----------
    vary, unit:
        The parameter bisected and its unit.
    until:
        The length of each run (s).
    scan:
        The parameter scanned, or None (one bracket; ``values`` is then ``(nan,)``).
    values:
        The values of ``scan`` (its unit), one per bracket.
    brackets:
        The :class:`~mechcont.dynamics.freefall.CriticalAirspeed` at each value.
    travel:
        The travel variable the quasi-static predictor is continued in.
    quasi_static:
        At each value of ``scan`` (the statics may depend on it: a length, a mass, a stop's limit), the
        :class:`~mechcont.dynamics.freefall.QuasiStaticCritical`, or None when it could not be found;
        ``quasi_static_failure`` then says why.
    """

    vary: str
    unit: str
    until: float
    scan: str | None
    values: tuple[float, ...]
    brackets: tuple[CriticalAirspeed, ...]
    travel: str
    quasi_static: tuple[QuasiStaticCritical | None, ...]
    quasi_static_failure: tuple[str, ...] = ()

    @property
    def quasi_static_values(self) -> tuple[float, ...]:
        """The quasi-static critical value at each value of ``scan`` (units of ``vary``); nan where it could not
        be found."""
        return tuple(q.value if q is not None else math.nan for q in self.quasi_static)

    def _where(self, value: float) -> str:
        return f"{self.scan} = {value:g}: " if self.scan is not None else ""

    def _one_predictor(self) -> bool:
        """Whether the predictor is the same at every value of ``scan`` (a damping: the statics do not see it)."""
        first = self.quasi_static[0]

        def same(q: QuasiStaticCritical | None) -> bool:
            if q is None or first is None:
                return q is first
            return (q.fold == first.fold and math.isclose(q.value, first.value, rel_tol=1e-9)
                    and math.isclose(q.pose, first.pose, rel_tol=1e-9, abs_tol=1e-9))

        return all(same(q) for q in self.quasi_static) and len(set(self.quasi_static_failure)) <= 1

    def describe(self) -> list[str]:
        """Readable lines: each bracket with its warnings (a run left undecided, a failing end still moving),
        then the quasi-static value and, for each bracket, the dynamic minus the quasi-static value and whether
        it exceeds the bracket's width (or contradicts the statics: a run that did not lock where the gear
        has no equilibrium to hang in had not finished)."""
        vary, unit, lines = self.vary, self.unit, []
        for v, crit in zip(self.values, self.brackets):
            where = self._where(v)
            lines += [where + line for line in crit.describe(unit)]
            if crit.unsettled:
                lines.append(f"warning: {where}the bracket could not be narrowed further: a run stayed undecided "
                             f"({crit.stopped})")
            elif crit.undecided:
                lines.append(f"warning: {where}the failing end {vary} = {crit.failed:.6g} was still moving at "
                             f"{self.until:g} s: a longer --until may lock it")
        one = self._one_predictor()
        for v, qs, failure in zip(self.values, self.quasi_static, self.quasi_static_failure):
            where = "" if one else self._where(v)
            if qs is None:
                lines.append(f"{where}quasi-static: {failure}")
            else:
                kind = (f"fold of the stall branch at {self.travel} = {qs.pose:.6g}" if qs.fold
                        else f"at the end {self.travel} = {qs.pose:.6g}")
                lines.append(f"{where}quasi-static critical {vary} = {qs.value:.6g} {unit} ({kind})")
            if one:
                break
        for v, crit, qs in zip(self.values, self.brackets, self.quasi_static):
            if qs is None:
                continue
            where = self._where(v)
            diff, significant = crit.compare(qs.value)
            verdict = "significant" if significant else "not significant (within the bracket's width)"
            if crit.contradicts(qs.value):
                verdict = "contradicts the statics"
                lines.append(f"warning: {where}a run that did not lock, {vary} = {crit.failed:.9g} {unit}, lies on "
                             f"the side of the quasi-static {qs.value:.9g} {unit} where the gear has no equilibrium "
                             "to hang in: it had not finished (give a longer --until); the bracket does not hold the "
                             "critical value")
            lines.append(f"{where}dynamic - quasi-static = {diff:+.4g} {unit} ({diff / qs.value:+.3%}; from the run "
                         f"that locked, bracket width {crit.width:.3g} {unit}): {verdict}".replace(" ;", ";"))
        return lines

    def header(self) -> list[str]:
        """The table's column names, units in brackets: the scanned parameter (if any), then the locked and the
        failed end of each bracket and the quasi-static value."""
        u = self.unit
        return [*([self.scan] if self.scan else []), f"locked_{self.vary} [{u}]", f"failed_{self.vary} [{u}]",
                f"quasi_static_{self.vary} [{u}]"]

    def rows(self) -> list[list[float]]:
        """One row per bracket, ordered like :meth:`header`."""
        return [[*([v] if self.scan else []), crit.locked, crit.failed, qs]
                for v, crit, qs in zip(self.values, self.brackets, self.quasi_static_values)]


def critical_scan(system: Model, start: Mapping[str, float], vary: str, low: float, high: float, *, lock: Lock,
                  until: float, tol: float | None = None, scan: tuple[str, Sequence[float]] | None = None,
                  progress: Callable[[], None] | None = None, **options: Any) -> CriticalScan:
    """The critical value of the parameter ``vary`` (an airspeed, m/s) in ``[low, high]`` bracketed by freefall
    runs (:func:`~mechcont.dynamics.freefall.critical_airspeed`, ``tol`` in units of ``vary``, default
    ``(high - low) / 1000``), at each value of ``scan = (parameter, values)`` (e.g. a damper's coefficient) or
    once, and the quasi-static predictor at each (:func:`~mechcont.dynamics.freefall.quasi_static_critical` on the
    travel from ``start`` to ``lock`` of the model at that value, on the side where its bracket's values lock);
    ``until`` (s) and ``options`` go to each run, ``progress()`` is called after each
    (:func:`~._critical.critical_airspeed`). An :class:`InputError` of a predictor is kept in
    :attr:`CriticalScan.quasi_static_failure`; the brackets' errors are raised.
    Returns the :class:`CriticalScan`."""
    tol = (high - low) / 1000.0 if tol is None else tol
    name, values = scan if scan is not None else (None, [math.nan])
    brackets, predictors, failures = [], [], []
    travel = ""
    for v in values:
        extra = {name: v} if name is not None else {}
        crit = critical_airspeed(system, start, vary, low, high, tol=tol, lock=lock, until=until, values=extra,
                                 progress=progress, **options)
        brackets.append(crit)
        at = system.with_values(extra) if extra else system  # the statics at the scanned value (a length, a limit)
        travel, begin, end = travel_of(at, start, lock)
        qs, failure = None, ""
        try:
            qs = quasi_static_critical(at, travel, begin, end, vary, side="min" if crit.locks_below else "max")
        except InputError as exc:
            failure = str(exc).split(": ", 1)[-1]
        predictors.append(qs)
        failures.append(failure)
    return CriticalScan(vary, system.variable(vary).unit, until, name, tuple(float(v) for v in values),
                        tuple(brackets), travel, tuple(predictors), tuple(failures))
