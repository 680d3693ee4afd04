"""The result of a continuation run: named columns, stability, labelled special points."""

from __future__ import annotations

import csv
import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._io import atomic_write
from ..errors import InputError

__all__ = ["Branch", "SpecialPoint"]


@dataclass
class SpecialPoint:
    """A labelled point of a branch (AUTO's vocabulary).

    Attributes
    ----------
    label:
        ``"LP"`` limit point (fold), ``"BP"`` branch point, ``"CP"`` cusp, ``"EP"`` end
        point, or a user event name.
    index:
        Row of the point in the branch.
    x:
        Full variable vector at the point.
    names:
        Variable names, ordered like ``x``.
    tangent:
        Unit tangent of the branch at the point in the problem's scaled unknowns (when known).
    info:
        Extra data: e.g. ``"null_vector"`` at a fold, ``"status"``, the precision of a
        located fold (``"residual"``: largest equation residual relative to its terms;
        ``"singular_value"``: smallest singular value of the equilibrated state Jacobian
        over the norm of the whole equilibrated Jacobian), an end reason.
    """

    label: str
    index: int
    x: np.ndarray
    names: tuple[str, ...]
    tangent: np.ndarray | None = None
    info: dict = field(default_factory=dict)

    @property
    def values(self) -> dict[str, float]:
        """``{name: value}`` at the point."""
        return {n: float(v) for n, v in zip(self.names, self.x)}

    def __getitem__(self, name: str) -> float:
        return self.values[name]

    @property
    def status(self) -> str:
        """``"located"`` (solved to the tolerances: a fold polished on the augmented system,
        an event's zero found by root finding) or ``"approximate"`` (detected by a sign
        change but not located; ``info["reason"]`` says why)."""
        return self.info.get("status", "located")

    @property
    def located(self) -> bool:
        """True when :attr:`status` is ``"located"``."""
        return self.status == "located"

    @property
    def tag(self) -> str:
        """The label as written in tables: ``"LP"``, or ``"LP?"`` when only approximate."""
        return self.label if self.located else self.label + "?"


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
        (``branch["LP1"]``, ``branch["LP2"]``).
    vary, unknowns:
        The continuation parameter and the names solved for.
    units:
        ``{name: SI unit}`` for display.
    status, message:
        ``"completed"`` (hit a bound or max steps) or a failure reason with an
        explanation, per direction joined by ``"; "``.
    """

    def __init__(self, names, values, s, n_unstable, labels, special_points, vary, unknowns,
                 status="completed", message="", model="", units=None):
        self.names = tuple(names)
        self.values = np.asarray(values, dtype=float).reshape(-1, len(self.names))
        self.s = np.asarray(s, dtype=float)
        self.n_unstable = np.asarray(n_unstable, dtype=int)
        self.labels = list(labels)
        self.special_points = list(special_points)
        self.vary = vary
        self.unknowns = tuple(unknowns)
        self.status = status
        self.message = message
        self.model = model
        self.units = dict(units or {})
        self._col = {n: i for i, n in enumerate(self.names)}

    # -- access ----------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.values)

    @property
    def stable(self) -> np.ndarray:
        """Boolean array: True where the point is stable (no unstable direction)."""
        return self.n_unstable == 0

    @property
    def success(self) -> bool:
        """True when every direction ended normally (bound, max steps)."""
        return self.status == "completed"

    def column(self, name: str) -> np.ndarray:
        """Values of variable ``name`` along the branch."""
        try:
            return self.values[:, self._col[name]]
        except KeyError:
            raise InputError(name, f"not a column of this branch; columns: {', '.join(self.names)}") from None

    def special(self, label: str) -> list[SpecialPoint]:
        """All special points with this label, in branch order."""
        return [p for p in self.special_points if p.label == label]

    def __getitem__(self, key: str):
        """``branch["theta1"]`` -> column; ``branch["LP1"]`` -> first fold (SpecialPoint)."""
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

    def __repr__(self) -> str:
        counts = {}
        for p in self.special_points:
            counts[p.label] = counts.get(p.label, 0) + 1
        sp = ", ".join(f"{k}x{v}" for k, v in counts.items()) or "none"
        return f"<Branch {self.model} in {self.vary}: {len(self)} points, special: {sp}, status: {self.status}>"

    # -- export ----------------------------------------------------------------------
    def stability_labels(self) -> list[str]:
        """``"stable"``/``"unstable"`` per point (``""`` where not evaluated)."""
        return ["" if n < 0 else ("stable" if n == 0 else "unstable") for n in self.n_unstable]

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

    def to_records(self) -> list[dict]:
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

    def to_frame(self):
        """The table as a pandas DataFrame (requires pandas)."""
        import pandas as pd  # optional dependency

        return pd.DataFrame.from_records(self.to_records())

    def to_csv(self, path: str | os.PathLike) -> Path:
        """Write the table as CSV: one column per variable, then ``s`` (scaled arclength),
        ``stability``, ``n_unstable``, ``label`` and ``vary`` (the continuation parameter's
        name, repeated so every row is self-describing)."""
        recs = self.to_records()
        header = [*self.names, "s", "stability", "n_unstable", "label", "vary"]

        def write(f):
            w = csv.DictWriter(f, fieldnames=header, lineterminator="\n")
            w.writeheader()
            for r in recs:
                w.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in r.items()})

        return _atomic_write(path, write)

    def to_json(self, path: str | os.PathLike) -> Path:
        """Write the branch as JSON: metadata, columns, special points."""
        doc = {
            "model": self.model, "vary": self.vary, "unknowns": list(self.unknowns), "status": self.status,
            "message": self.message, "columns": {n: self.column(n).tolist() for n in self.names},
            "s": self.s.tolist(), "n_unstable": self.n_unstable.tolist(), "stability": self.stability_labels(),
            "labels": self.row_labels(),
            "special_points": [{"label": p.label, "index": p.index, "values": p.values, "status": p.status,
                                **{k: v for k, v in p.info.items() if isinstance(v, (int, float, str))}}
                               for p in self.special_points],
        }
        return _atomic_write(path, lambda f: json.dump(doc, f, indent=1))


def _atomic_write(path, writer) -> Path:
    """Write text through ``writer(file)`` without leaving a partial file on failure."""
    def write(tmp):
        with open(tmp, "w", newline="") as f:
            writer(f)

    return atomic_write(path, write)
