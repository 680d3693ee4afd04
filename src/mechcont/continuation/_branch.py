"""The result of a continuation run: named columns, stability, labelled special points."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any, TypedDict, Unpack

import numpy as np

from .._io import atomic_write, read_csv_header
from .._status import Status
from ..errors import InputError
from ._special_point import SpecialPoint
from ._table import cell_count, cell_number, read_branch_table, read_table, unit_header

if TYPE_CHECKING:
    import numpy.typing as npt  # (17 ms to import: for the type checker only)
    import pandas as pd

    from ..equations import EquationSystem
    from ._sensitivity import Sensitivity

__all__ = ["Branch", "SpecialPoint", "unit_header", "read_csv_header", "read_branch_table", "read_table",
           "check_branch_table", "cell_count", "cell_number"]


class _Fields(TypedDict, total=False):
    """The constructor's arguments :meth:`Branch.replace` may change."""

    names: Iterable[str]
    values: npt.ArrayLike
    s: npt.ArrayLike
    n_unstable: npt.ArrayLike
    labels: Iterable[str]
    special_points: Iterable[SpecialPoint]
    vary: str
    unknowns: Iterable[str]
    status: Status | str
    message: str
    model: str
    units: Mapping[str, str] | None


class Branch:
    """A continued branch of solutions.

    Attributes
    ----------
    names:
        Column names (all variables of the model).
    values:
        Array (n_points, n_names) of full variable vectors.
    s:
        Scaled arclength of each point (0 at the start point).
    n_unstable:
        Unstable directions per point (-1: not evaluated).
    labels:
        Special-point label per row, or ``""``.
    special_points:
        The labelled :class:`SpecialPoint` objects, in branch order, numbered per label
        (``branch["LP1"]``, ``branch["LP2"]``). The numbering runs along the arclength from
        the first row (AUTO's convention of numbering labels along the branch), and every
        output uses it: the CSV row order, JSON ``special_points[].name``, plots, CLI
        tables, ``--fold N`` and ``--point file.csv:LP2``. The first row is the end reached
        by *decreasing* the continuation parameter from the start point, so two runs from
        the same start with the same bounds number their points alike.
    vary, unknowns:
        The continuation parameter and the names solved for.
    units:
        ``{name: unit}``, the unit each column's values are in (SI, or the units its description
        declares; angles ``rad``); written into the CSV headers (``F [N]``, ``x1 [mm]``), the
        JSON ``units`` map and :meth:`to_frame`'s ``attrs``.
    status, message:
        A :class:`~mechcont._status.Status` (a ``str``): ``"completed"`` (hit a bound or max
        steps) or how it failed (``"step size underflow"``), and the explanation per direction
        joined by ``"; "``. A text status given to the constructor is read as its Status.
    """

    def __init__(self, names: Iterable[str], values: npt.ArrayLike, s: npt.ArrayLike, n_unstable: npt.ArrayLike,
                 labels: Iterable[str], special_points: Iterable[SpecialPoint], vary: str, unknowns: Iterable[str],
                 status: Status | str = "completed", message: str = "", model: str = "",
                 units: Mapping[str, str] | None = None) -> None:
        self.names = tuple(names)
        self.values = np.asarray(values, dtype=float).reshape(-1, len(self.names))
        self.s = np.asarray(s, dtype=float)
        self.n_unstable = np.asarray(n_unstable, dtype=int)
        self.labels = list(labels)
        self.special_points = list(special_points)
        self.vary = vary
        self.unknowns = tuple(unknowns)
        self.status = Status.of(status)
        self.message = message
        self.model = model
        self.units = dict(units or {})
        self.special_points.sort(key=lambda p: p.index)  # arclength order: the numbering's order
        self._col = {n: i for i, n in enumerate(self.names)}  # set last: the branch is complete (see __setattr__)

    def __setattr__(self, name: str, value: object) -> None:
        if "_col" in self.__dict__:
            raise AttributeError(f"a Branch is not changed once made (setting {name!r}); make a changed copy with "
                                 "replace(...) or with_columns(...)")
        object.__setattr__(self, name, value)

    def replace(self, **changes: Unpack[_Fields]) -> Branch:
        """A new branch with the constructor's arguments in ``changes`` replaced (``message``, ``units``, ...);
        the arrays and the special points are shared with this one (nothing is copied)."""
        args: _Fields = {"names": self.names, "values": self.values, "s": self.s, "n_unstable": self.n_unstable,
                         "labels": self.labels, "special_points": self.special_points, "vary": self.vary,
                         "unknowns": self.unknowns, "status": self.status, "message": self.message,
                         "model": self.model, "units": self.units}
        unknown = set(changes) - set(args)
        if unknown:
            raise TypeError(f"Branch.replace() got unknown field(s) {', '.join(sorted(unknown))}")
        args.update(changes)
        return Branch(**args)

    def with_columns(self, columns: Mapping[str, np.ndarray], units: Mapping[str, str] | None = None) -> Branch:
        """A new branch with ``columns`` (``{name: values per row}``) appended after this one's, in ``units``
        (``{name: unit}``); this branch itself is unchanged."""
        if not columns:
            return self.replace()
        new = np.column_stack([self.values, *(np.asarray(c, dtype=float) for c in columns.values())])
        return self.replace(names=(*self.names, *columns), values=new, units={**self.units, **(units or {})})

    # -- access ----------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.values)

    @property
    def stable(self) -> np.ndarray:
        """Boolean array: True where the point is stable (no unstable direction)."""
        stable: np.ndarray = self.n_unstable == 0  # (NumPy's stubs type a comparison of arrays as Any)
        return stable

    @property
    def success(self) -> bool:
        """True when every direction ended normally (bound, max steps)."""
        return self.status is Status.COMPLETED

    def column(self, name: str) -> np.ndarray:
        """Values of variable ``name`` along the branch."""
        try:
            return self.values[:, self._col[name]]
        except KeyError:
            raise InputError(name, f"not a column of this branch; columns: {', '.join(self.names)}") from None

    def special(self, label: str) -> list[SpecialPoint]:
        """All special points with this label, in branch order."""
        return [p for p in self.special_points if p.label == label]

    def point_names(self) -> list[str]:
        """The name of each of :attr:`special_points` (``"LP1"``, ``"CP1"``, ``"EP2"``...), in order.

        Numbered per label along the branch, as ``branch["LP2"]`` finds them; an approximate
        point keeps its place in the numbering (its tag ``LP2?`` adds the ``?``).
        """
        counts: dict[str, int] = {}
        out = []
        for p in self.special_points:
            counts[p.label] = counts.get(p.label, 0) + 1
            out.append(f"{p.label}{counts[p.label]}")
        return out

    def unit(self, name: str) -> str:
        """SI unit of column ``name`` (``""`` when dimensionless or unknown)."""
        self.column(name)
        return self.units.get(name, "")

    def __getitem__(self, key: str) -> Any:
        """``branch["theta1"]`` -> column; ``branch["LP1"]`` -> first fold (SpecialPoint).

        Typed ``Any``: which of the two it is depends on the key's text; :meth:`column` and :meth:`point` are the
        typed spellings."""
        if key in self._col:
            return self.column(key)
        label = key.rstrip("0123456789")
        num = key[len(label):]
        if label and num:
            pts = self.special(label)
            k = int(num)
            if 1 <= k <= len(pts):
                return pts[k - 1]
            raise InputError(key, f"branch has {len(pts)} point(s) labelled {label}")
        raise InputError(key, f"neither a column nor a special point (columns: {', '.join(self.names)})")

    def point(self, spec: str | int) -> SpecialPoint:
        """A row as a :class:`SpecialPoint`: a special point's name (``"LP1"``) or a row number (0-based,
        negative from the end; a special row gives its own point, with what the run recorded)."""
        if isinstance(spec, str):
            text = spec.strip()
            try:
                spec = int(text)
            except ValueError:
                name = text.rstrip("?")
                try:
                    target = self[name]
                except InputError:
                    raise InputError("point", f"no point '{name}'; this branch has {', '.join(self.point_names()) or 'none'}"
                                              f" or rows 0..{len(self) - 1}") from None
                if not isinstance(target, SpecialPoint):
                    raise InputError("point", f"'{text}' is a column; give a special point's name (LP1) or a row "
                                              "number") from None
                return target
        n = len(self)
        if not -n <= spec < n:
            raise InputError("point", f"row {spec} out of range; the branch has {n} rows (0..{n - 1})")
        i = spec % n
        found = [p for p in self.special_points if p.index == i]
        return found[0] if found else SpecialPoint(self.labels[i], i, self.values[i].copy(), self.names)

    def sensitivity(self, system: EquationSystem, point: str | int, params: Iterable[str], *, of: str | None = None,
                    keep: str | None = None, values: Mapping[str, float] | None = None) -> Sensitivity:
        """Exact derivatives of a point's quantity with respect to ``params`` (SI units per SI unit).

        ``point``: as :meth:`point` takes it. The quantity is ``of`` (an unknown of the
        branch, the continuation parameter held; a downlock branch's default is its force), else
        the continuation parameter: at a fold the fold load, elsewhere its value at the state
        ``keep`` held at its value there. ``values`` (``{name: value}``, SI) changes held
        values first; the point is followed there from its own values (:func:`~._move.move_point`).
        ``system`` is the model of the branch. Returns a :class:`~mechcont.analysis.sensitivity.Sensitivity`.
        """
        from ._sensitivity import point_sensitivity

        return point_sensitivity(system, self.point(point), params, vary=self.vary, unknowns=self.unknowns or None,
                                 of=of, keep=keep, values=values)

    def __repr__(self) -> str:
        counts: dict[str, int] = {}
        for p in self.special_points:
            counts[p.label] = counts.get(p.label, 0) + 1
        sp = ", ".join(f"{k}x{v}" for k, v in counts.items()) or "none"
        return f"<Branch {self.model} in {self.vary}: {len(self)} points, special: {sp}, status: {self.status}>"

    # -- export ----------------------------------------------------------------------
    def stability_labels(self) -> list[str]:
        """``"stable"``/``"unstable"`` per point, ``"fold"`` at a fold (``LP`` or ``NSF``) and ``""`` where not
        evaluated.

        A fold is neutral: one direction has zero stiffness there, so the count of unstable
        directions computed at it (``n_unstable``) is that of whichever side rounding puts
        it on. Its row says ``fold`` instead of either word. A non-smooth fold (``NSF``, made by a stop) is
        where two pieces with different contact sets meet, each with its own stability: its row says ``fold``
        too, and its ``n_unstable`` is that of the more stable piece (0 exactly when a stable mechanism reaches
        it and jumps), whichever the run walked first; both are in its
        :attr:`~mechcont.continuation.NonSmoothFold.sides`.
        """
        return ["fold" if lab in ("LP", "NSF") else "" if n < 0 else ("stable" if n == 0 else "unstable")
                for n, lab in zip(self.n_unstable, self.labels)]

    @property
    def approximate(self) -> list[SpecialPoint]:
        """Special points detected but not located (written ``LP?`` etc. in tables)."""
        return [p for p in self.special_points if not p.located]

    def row_labels(self) -> list[str]:
        """Label per row as written in tables: ``"LP"``, ``"LP?"`` (approximate) or ``""``."""
        out = list(self.labels)
        for p in self.special_points:
            if not p.located and 0 <= p.index < len(out):
                out[p.index] = p.tag
        return out

    def to_records(self) -> list[dict[str, Any]]:
        """One dict per point: every variable, ``s``, ``stability``, ``n_unstable``, ``label``, ``vary``.

        ``label`` carries a ``?`` for a special point that is only approximate.
        """
        st = self.stability_labels()
        labels = self.row_labels()
        return [
            {**{n: float(v) for n, v in zip(self.names, row)}, "s": float(s), "stability": st[i],
             "n_unstable": int(self.n_unstable[i]), "label": labels[i], "vary": self.vary}
            for i, (row, s) in enumerate(zip(self.values, self.s))
        ]

    def to_frame(self) -> pd.DataFrame:
        """The table as a pandas DataFrame (``pip install mechcont[tables]``).

        Columns as in :meth:`to_records` (plain names, SI values, angles in rad);
        ``frame.attrs`` holds ``units`` (``{column: unit}``), ``vary``, ``model`` and
        ``special_points`` (``{"LP1": row, ...}``).
        """
        try:
            import pandas as pd  # optional dependency
        except ImportError:
            raise InputError("to_frame", "needs pandas: pip install 'mechcont[tables]'") from None
        frame = pd.DataFrame.from_records(self.to_records())
        frame.attrs.update(units={n: self.units.get(n, "") for n in self.names}, vary=self.vary, model=self.model,
                           special_points={n: p.index for n, p in zip(self.point_names(), self.special_points)})
        return frame

    def csv_header(self) -> list[str]:
        """The CSV column headers: ``name [unit]`` for every variable with a unit (``F [N]``,
        ``theta1 [rad]``), the bare name otherwise, then ``s``, ``stability``, ``n_unstable``,
        ``label``, ``vary``."""
        return [unit_header(n, self.units.get(n, "")) for n in self.names] + list(_EXTRA_COLUMNS)

    def to_csv(self, path: str | os.PathLike[str]) -> Path:
        """Write the table as CSV: one column per variable with its unit in the header
        (``F [N]``, ``theta1 [rad]``: values in SI units or the description's, angles in radians), then ``s``
        (scaled arclength, dimensionless), ``stability`` (``stable``/``unstable``/``fold``, at an ``LP`` or ``NSF``),
        ``n_unstable``, ``label`` (``LP``, ``LP?``...; numbered by row order: the second
        ``LP`` row is ``LP2``) and ``vary`` (the continuation parameter's name, repeated so
        every row is self-describing). :func:`read_csv_header` maps the headers back."""
        recs = self.to_records()
        keys = [*self.names, *_EXTRA_COLUMNS]

        import csv  # csv and json are imported where used: a run that writes no table does without

        def write(f: IO[str]) -> None:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(self.csv_header())
            for r in recs:
                w.writerow([_cell(k, r[k]) for k in keys])

        return _atomic_write(path, write)

    @classmethod
    def read_csv(cls, path: str | os.PathLike[str], *, model: str = "") -> Branch:
        """A branch from a table written by :meth:`to_csv` (or an older one without units).

        Variables are the columns other than ``s``, ``stability``, ``n_unstable``, ``label``
        and ``vary`` and the :data:`DERIVED_COLUMNS` (left out); units come from the headers. Special points are rebuilt from the
        ``label`` column (``LP?`` is an approximate ``LP``), numbered as when written.
        Without ``n_unstable`` the ``stability`` words give 0/1 (-1 where unknown); without
        ``s``, the chord length of the rows stands in for the arclength. Raises
        :class:`InputError` for an unreadable or malformed table.
        """
        rows, units = read_branch_table(path)
        if not rows:
            raise InputError("branch", f"'{path}' has no rows")
        names = [n for n in rows[0] if n not in _EXTRA_COLUMNS and n not in DERIVED_COLUMNS]
        values = np.array([[cell_number(path, i, n, r[n]) for n in names] for i, r in enumerate(rows)])
        if "s" in rows[0]:
            s = np.array([cell_number(path, i, "s", r["s"]) for i, r in enumerate(rows)])
        else:
            s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(values, axis=0), axis=1))])
        words = {"stable": 0, "unstable": 1}
        nu = [cell_count(path, i, r["n_unstable"]) if r.get("n_unstable", "").strip()
              else words.get(r.get("stability", ""), -1) for i, r in enumerate(rows)]
        tags = [(r.get("label") or "").strip() for r in rows]
        labels = [t.rstrip("?") for t in tags]
        special = [SpecialPoint(lab, i, values[i].copy(), tuple(names), status=Status.LOCATED) if not tags[i].endswith("?")
                   else SpecialPoint(lab, i, values[i].copy(), tuple(names), status=Status.APPROXIMATE,
                                     reason="marked approximate in the table")
                   for i, lab in enumerate(labels) if lab]
        vary = (rows[0].get("vary") or "").strip()
        units = {n: u for n, u in units.items() if n not in DERIVED_COLUMNS}
        return cls(names, values, s, nu, labels, special, vary, (), model=model, units=units)

    def to_json(self, path: str | os.PathLike[str]) -> Path:
        """Write the branch as JSON: metadata, columns, special points."""
        doc = {
            "model": self.model, "vary": self.vary, "unknowns": list(self.unknowns), "status": self.status,
            "message": self.message, "columns": {n: self.column(n).tolist() for n in self.names},
            "s": self.s.tolist(), "n_unstable": self.n_unstable.tolist(), "stability": self.stability_labels(),
            "labels": self.row_labels(), "units": {n: self.units.get(n, "") for n in self.names},
            "special_points": [{"name": name, "label": p.label, "index": p.index, "values": p.values,
                                "status": p.status,
                                **{k: v for k, v in p.info.items() if isinstance(v, (int, float, str))},
                                **_hopf_fields(p)}
                               for name, p in zip(self.point_names(), self.special_points)],
        }
        import json

        return _atomic_write(path, lambda f: json.dump(doc, f, indent=1))


_EXTRA_COLUMNS = ("s", "stability", "n_unstable", "label", "vary")
#: Columns an analysis appends after the variables (the dynamic stability's, ``continue --dynamic``):
#: :meth:`Branch.read_csv` leaves them out of the variables, so such a table is a branch of its model again.
DERIVED_COLUMNS = ("n_unstable_dynamic", "leading_real", "leading_frequency")
#: Columns holding a count, written as integers (the values of a branch are floats).
COUNT_COLUMNS = frozenset({"n_unstable_dynamic"})


def _cell(name: str, value: Any) -> Any:
    """A table cell: a float by ``repr`` (it reads back exactly), a count column's value as an integer."""
    if name in COUNT_COLUMNS and np.isfinite(value):
        return int(value)
    return repr(value) if isinstance(value, float) else value


def _hopf_fields(p: SpecialPoint) -> dict[str, Any]:
    """A Hopf point's frequency (rad/s), period (s), ``l1`` and criticality for the JSON; ``{}`` elsewhere."""
    h = p.extra.get("hopf")
    if h is None:
        return {}
    return {"frequency": h.frequency, "period": h.period, "l1": h.lyapunov, "criticality": h.criticality}


def check_branch_table(branch: Branch, system: EquationSystem, path: str | os.PathLike[str]) -> None:
    """Check a table read by :meth:`Branch.read_csv` against the model ``system``: its columns are exactly
    the model's variables (none missing, none unknown), each header's unit is the model's, every value
    is finite and the rows are in arclength order. Raises :class:`InputError` (field ``branch``) in one
    line naming the file, the row or column and what would be valid."""
    names = list(system.names)
    unknown = [n for n in branch.names if n not in names]
    if unknown:
        raise InputError("branch", f"'{path}': column(s) {', '.join(unknown)} are not variables of model "
                                   f"'{system.name}'; valid: {', '.join(names)}, {', '.join(_EXTRA_COLUMNS)}")
    missing = [n for n in names if n not in branch.names]
    if missing:
        raise InputError("branch", f"'{path}' lacks the column(s) {', '.join(missing)} of model '{system.name}'")
    if list(branch.names) != names:
        raise InputError("branch", f"'{path}': the columns are not in the model's order ({', '.join(names)})")
    for n, u in branch.units.items():
        want = system.variable(n).unit
        if u != want:
            raise InputError("branch", f"'{path}' column '{unit_header(n, u)}': the unit of {n} in model "
                                       f"'{system.name}' is '{want or 'none'}', not '{u}' (a table's values are in "
                                       "its model's units)")
    bad = np.argwhere(~np.isfinite(branch.values))
    if len(bad):
        r, c = (int(i) for i in bad[0])
        raise InputError("branch", f"'{path}' row {r} (line {r + 2}), column {branch.names[c]}: "
                                   f"{branch.values[r, c]!r} is not a finite number")
    if not np.isfinite(branch.s).all() or (len(branch.s) > 1 and np.any(np.diff(branch.s) < 0)):
        r = int(np.argmax(~np.isfinite(branch.s))) if not np.isfinite(branch.s).all() else \
            int(np.nonzero(np.diff(branch.s) < 0)[0][0]) + 1
        raise InputError("branch", f"'{path}' row {r} (line {r + 2}), column s: the rows are not in arclength "
                                   "order (s must be finite and non-decreasing)")


def _atomic_write(path: str | os.PathLike[str], writer: Callable[[IO[str]], object]) -> Path:
    """Write text through ``writer(file)`` without leaving a partial file on failure."""
    def write(tmp: str) -> None:
        with open(tmp, "w", newline="") as f:
            writer(f)

    return atomic_write(path, write)
