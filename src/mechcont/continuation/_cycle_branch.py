"""The result of a continuation of periodic orbits: one row per orbit, with its Floquet multipliers and labels."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .._io import atomic_write
from .._status import Status
from ..errors import InputError
from ._branch import unit_header
from ._collocation import Mesh

if TYPE_CHECKING:
    from ..equations import Dynamics

__all__ = ["CycleBranch", "CYCLE_LABELS"]

#: Labels of a family of periodic orbits (AUTO's vocabulary).
CYCLE_LABELS = {
    "HB": "Hopf point: the family's zero-amplitude start",
    "LPC": "limit point (fold) of cycles: the family turns back in the parameter; two cycles merge",
    "PD": "period doubling: a Floquet multiplier crosses -1; a cycle of twice the period branches off",
    "NS": "Neimark-Sacker (torus): a complex pair of multipliers crosses the unit circle",
    "UZ": "a row located at a value asked for (--at)",
    "EP": "end point of the family",
}


@dataclass
class CycleBranch:
    """A family of periodic orbits continued in one parameter.

    Attributes
    ----------
    model, vary, vary_unit:
        The model's name, the continuation parameter and its SI unit.
    state_names, state_units:
        The dynamic states (``z``) and their units.
    p, period:
        Per row: the parameter's value (SI) and the period ``T`` (s).
    minimum, maximum:
        Per row and state: the orbit's smallest and largest value (over its nodes and collocation points, each refined
        between them: :meth:`~._collocation.Mesh.extremes`).
    multipliers:
        Per row: the non-trivial Floquet multipliers (complex, largest modulus first).
    n_unstable:
        Per row: the number of non-trivial multipliers outside the unit circle.
    labels:
        Per row: ``HB``, ``LPC``, ``PD``, ``NS``, ``UZ``, ``EP`` or ``""``; ``approximate`` holds the rows
        whose label was detected but not located (written ``LPC?``).
    s:
        Arclength (the orbit's L2 norm and the parameter, as the steps measure it) from the first row.
    orbits:
        Per row: ``(mesh, node values (n_nodes, n))`` in the rescaled time ``t / T``; :meth:`orbit` samples it.
    status, message:
        How the continuation ended (``completed``, or ``step size underflow`` with why).
    x_base, names:
        The model's full vector giving the other parameters, and its variables' names.
    coordinate_names, coordinate_units, coordinate_minimum, coordinate_maximum:
        A closed-loop mechanism's coordinates that are not states (the dependent ones: a four-bar's coupler
        and crank when the wheel is the state), their units, and per row their smallest and largest value
        over the same instants as the states'; empty for an ODE or an open chain.
    """

    model: str
    vary: str
    vary_unit: str
    state_names: tuple[str, ...]
    state_units: tuple[str, ...]
    p: np.ndarray
    period: np.ndarray
    minimum: np.ndarray
    maximum: np.ndarray
    multipliers: list[np.ndarray]
    n_unstable: np.ndarray
    labels: list[str]
    s: np.ndarray
    orbits: list[tuple[Mesh, np.ndarray]]
    status: Status = Status.COMPLETED
    message: str = ""
    x_base: np.ndarray = field(default_factory=lambda: np.zeros(0))
    approximate: frozenset[int] = frozenset()
    names: tuple[str, ...] = ()
    coordinate_names: tuple[str, ...] = ()
    coordinate_units: tuple[str, ...] = ()
    coordinate_minimum: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    coordinate_maximum: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))

    def __len__(self) -> int:
        return len(self.p)

    @property
    def floquet_max(self) -> np.ndarray:
        """Per row: the largest modulus of a non-trivial multiplier (nan for a scalar ODE, which has none)."""
        return np.array([float(np.max(np.abs(m))) if len(m) else np.nan for m in self.multipliers])

    @property
    def stable(self) -> np.ndarray:
        """Per row: True where every non-trivial multiplier lies inside the unit circle."""
        stable: np.ndarray = self.n_unstable == 0
        return stable

    def stability(self) -> list[str]:
        """``stable`` / ``unstable`` per row; ``neutral`` at a Hopf point (zero amplitude) and ``fold`` at a fold
        of cycles (a second multiplier at 1: neither, as a fold of equilibria is written in a branch table)."""
        return ["neutral" if lab == "HB" else "fold" if lab == "LPC" else "stable" if n == 0 else "unstable"
                for n, lab in zip(self.n_unstable, self.labels)]

    def point_names(self) -> list[tuple[str, int]]:
        """``[("LPC1", row), ("PD1", row), ...]``: the labelled rows, numbered per label along the family."""
        counts: dict[str, int] = {}
        out = []
        for i, lab in enumerate(self.labels):
            if lab:
                counts[lab] = counts.get(lab, 0) + 1
                out.append((f"{lab}{counts[lab]}", i))
        return out

    def row(self, name: str) -> int:
        """The row of the labelled point ``name`` (``"LPC1"``); :class:`InputError` naming those there are."""
        found = dict(self.point_names())
        if name not in found:
            raise InputError("point", f"no point '{name}'; this family has {', '.join(found) or 'none'}")
        return found[name]

    def columns(self) -> dict[str, np.ndarray]:
        """The table's numeric columns by name: the parameter, ``period``, ``min_X``/``max_X`` per state and per
        dependent coordinate, ``floquet_max``."""
        cols = {self.vary: self.p, "period": self.period}
        for k, name in enumerate(self.state_names):
            cols[f"min_{name}"] = self.minimum[:, k]
            cols[f"max_{name}"] = self.maximum[:, k]
        for k, name in enumerate(self.coordinate_names):
            cols[f"min_{name}"] = self.coordinate_minimum[:, k]
            cols[f"max_{name}"] = self.coordinate_maximum[:, k]
        cols["floquet_max"] = self.floquet_max
        return cols

    def units(self) -> dict[str, str]:
        """``{column: SI unit}`` of :meth:`columns`."""
        out = {self.vary: self.vary_unit, "period": "s", "floquet_max": ""}
        for name, unit in zip(self.state_names + self.coordinate_names, self.state_units + self.coordinate_units):
            out[f"min_{name}"] = out[f"max_{name}"] = unit
        return out

    def row_labels(self) -> list[str]:
        """Label per row as written (``LPC?`` when only detected)."""
        return [lab + "?" if i in self.approximate and lab else lab for i, lab in enumerate(self.labels)]

    def csv_header(self) -> list[str]:
        """``D``, ``period [s]``, ``min_u1``, ``max_u1``, ..., ``floquet_max``, ``n_unstable``, ``stability``, ``label``, ``s``
        (a unit in brackets where the column has one)."""
        units = self.units()
        return [unit_header(n, units[n]) for n in self.columns()] + ["n_unstable", "stability", "label", "s"]

    def to_csv(self, path: str | os.PathLike[str]) -> Path:
        """Write the table (SI units; one row per orbit, in arclength order); nothing is left half-written."""
        import csv

        cols = list(self.columns().values())
        stab, labels = self.stability(), self.row_labels()

        def write(tmp: str) -> None:
            with open(tmp, "w", newline="") as f:
                w = csv.writer(f, lineterminator="\n")
                w.writerow(self.csv_header())
                for i in range(len(self)):
                    w.writerow([repr(float(c[i])) for c in cols]
                               + [int(self.n_unstable[i]), stab[i], labels[i], repr(float(self.s[i]))])

        return atomic_write(path, write)

    def orbit(self, i: int, samples: int = 200) -> tuple[np.ndarray, np.ndarray]:
        """Row ``i``'s orbit over one period: times (s), shape (samples + 1,), and states (samples + 1, n)."""
        mesh, u = self.orbits[i]
        tau = np.linspace(0.0, 1.0, samples + 1)
        Z = mesh.evaluate(u, tau[:-1])
        return tau * self.period[i], np.vstack([Z, u[-1:]])

    def full_vectors(self, dynamics: Dynamics, i: int, samples: int = 60) -> tuple[np.ndarray, np.ndarray]:
        """Row ``i``'s orbit as the model's full vectors (``dynamics.full_vectors``, all instants in one call), for
        drawings and animations: times (s) and an array (samples + 1, n_variables)."""
        t, Z = self.orbit(i, samples)
        x = self.x_base.copy()
        x[self.names.index(self.vary)] = self.p[i]
        return t, dynamics.full_vectors(Z, x)

    def __repr__(self) -> str:
        pts = ", ".join(n for n, _ in self.point_names()) or "none"
        return f"<CycleBranch {self.model} in {self.vary}: {len(self)} orbits, points: {pts}, status: {self.status}>"
