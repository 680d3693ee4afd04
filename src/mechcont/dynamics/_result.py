"""The result of a time simulation: named columns like a continuation branch."""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._io import atomic_write
from .._status import Status
from ..equations import velocity_coordinate, velocity_name
from ..errors import InputError
from ._energy import EnergyBalance

if TYPE_CHECKING:
    from ._contact import StopEvent
    from ._peaks import DenseHistory, Peak

__all__ = ["SimulationStatus", "SimulationResult"]


#: How a simulation ended: ``FINISHED``, ``EVENT`` or ``FAILED`` of the one :class:`~mechcont._status.Status`
#: vocabulary (the name kept for the code written before it).
SimulationStatus = Status

#: A failed simulation's message: what failed and what to try.
_INTEGRATOR_FAILED = "The integrator failed (step size became too small); try a looser rtol or a smaller max_step."


@dataclass
class SimulationResult:
    """A time history of a mechanism, with the same column names as a continuation branch.

    Attributes
    ----------
    t:
        Times (s), shape (N,).
    values:
        Full variable vectors (N x len(names)): coordinates from the simulation, parameters
        at their (possibly time-varying) values.
    qdot:
        Coordinate velocities (N x n_q), columns named ``<coordinate>_dot``.
    names, coordinates:
        Column names of ``values`` and the coordinate names (order of ``qdot``).
    status:
        :attr:`Status.FINISHED <mechcont._status.Status.FINISHED>`, ``EVENT`` or ``FAILED``;
        ``message`` says it as a sentence.
    constraint_drift:
        ``max |Phi|`` over the saved points (units of the constraints, m for the overcentre).
    velocity_drift:
        ``max |Phi_q qdot|`` over the saved points (m/s).
    t_events, x_events:
        Per event: the times (s) and full variable vectors where it occurred.
    nfev:
        Number of right-hand side evaluations.
    detail:
        Where and why the integrator stopped, when it failed (time and the solver's message).
    units:
        ``{name: unit}`` of the variables (written into the CSV headers), each in the model's units.
    energy_unit:
        The unit of the energy audit's columns: ``"J"``, or the description's energy unit
        (``"g mm^2/s^2"`` for a file in mm and g, :class:`~mechcont.units.UnitSystem`).
    stop_events:
        With stops simulated: every :class:`~._contact.StopEvent` (impact, contact, release) in
        time order, each with the index of its history row.
    energy:
        The energy audit (J), ``{column: values per row}``: ``E_kin``, ``E_pot``, ``E_diss``, ``W_ext``
        and ``E_residual`` (see :mod:`._energy`); columns of the history like the others. Empty for a
        history made otherwise (a sweep's).
    energy_tolerance:
        The energy error (J) the integrator's tolerances explain over the run (for :attr:`balance`'s
        bound; :meth:`~._energy.EnergyLedger.step_error`).
    indeterminate_rows:
        Rows whose joint reactions are statically indeterminate (redundant constraints: the
        accelerations are determinate, the split of the reactions among the redundant rows is not;
        the reported ones are the minimum-norm multipliers, :mod:`._redundant`).
    integrator_failure:
        Why the integrator stopped early (SciPy's words, e.g. its step fell below the spacing of the
        floating-point numbers: the tolerance cannot be met there, or the forces blew up); ``""`` when it
        did not (a run stopped by too many stop events is :attr:`status` FAILED with this empty).
    motion_warning:
        One line when the motion stalled where nothing stops it or the redundant constraints could
        not be resolved (:func:`~._stall.motion_warning`), else ``""``.
    dense:
        The integrator's dense output, per accepted step (:class:`~._peaks.DenseHistory`: ``state(t)``,
        ``row(t)``), on which :meth:`peak` locates peaks; None for a result read back or pickled.
    """

    t: np.ndarray
    values: np.ndarray
    qdot: np.ndarray
    names: tuple[str, ...]
    coordinates: tuple[str, ...]
    status: Status
    constraint_drift: float
    velocity_drift: float
    t_events: list[np.ndarray] = field(default_factory=list)
    x_events: list[np.ndarray] = field(default_factory=list)
    nfev: int = 0
    detail: str = ""
    units: dict[str, str] = field(default_factory=dict)
    stop_events: list[StopEvent] = field(default_factory=list)
    energy: dict[str, np.ndarray] = field(default_factory=dict)
    energy_tolerance: float = math.nan
    indeterminate_rows: int = 0
    integrator_failure: str = ""
    motion_warning: str = ""
    dense: DenseHistory | None = field(default=None, repr=False, compare=False)
    energy_unit: str = "J"

    def __getstate__(self) -> dict[str, Any]:
        """Pickled without the dense output (the interpolants and the model's compiled dynamics)."""
        return {**self.__dict__, "dense": None}

    def peak(self, quantity: str | Callable[[np.ndarray, np.ndarray], float], *, absolute: bool = False) -> Peak:
        """The largest value of a column (``"R_downlock"``, ``"theta_dot"``, a condition; its unit) or of a
        callable ``quantity(x, qdot)`` (``x`` a full row), of its magnitude with ``absolute``, located on
        the integrator's dense output, not sampled at the rows: a :class:`~._peaks.Peak` (``value``, and
        ``time`` in s)."""
        from ._peaks import locate_peak

        if callable(quantity):
            fn = quantity
        elif quantity in self.names:
            i = self.names.index(quantity)

            def fn(x: np.ndarray, qd: np.ndarray) -> float:
                return float(x[i])
        elif (c := velocity_coordinate(quantity, self.coordinates)) is not None:
            j = self.coordinates.index(c)

            def fn(x: np.ndarray, qd: np.ndarray) -> float:
                return float(qd[j])
        else:
            raise InputError(quantity, f"not a column with a peak; valid: {', '.join(self.columns)}")
        return locate_peak(self, (lambda x, qd: abs(fn(x, qd))) if absolute else fn)

    def unit(self, column: str) -> str:
        """Unit of a column (``t``: s; ``<coordinate>_dot``: its unit per second; the energy audit's:
        :attr:`energy_unit`; ``""`` if none)."""
        if column == "t":
            return "s"
        if column in self.energy:
            return self.energy_unit
        if (c := velocity_coordinate(column, self.coordinates)) is not None:
            u = self.units.get(c, "")
            return f"{u}/s" if u else "1/s"
        return self.units.get(column, "")

    @property
    def success(self) -> bool:
        """True unless the integrator failed."""
        return self.status is not Status.FAILED

    @property
    def message(self) -> str:
        """Readable termination reason (with where and why, if the integrator failed)."""
        text = _INTEGRATOR_FAILED if self.status is Status.FAILED else self.status.message
        return f"{text} {self.detail}" if self.detail else text

    @property
    def columns(self) -> tuple[str, ...]:
        """All column names: ``names``, the velocity columns ``<coordinate>_dot``, then the energy audit's."""
        return self.names + tuple(velocity_name(c) for c in self.coordinates) + tuple(self.energy)

    @property
    def balance(self) -> EnergyBalance:
        """The energy balance at the end of the history (:class:`~._energy.EnergyBalance`: the audit's
        terms in J, the worst residual, the bound the tolerance explains and whether it closes).
        Raises :class:`InputError` for a history without the audit."""
        if not self.energy:
            raise InputError("energy", "this history has no energy audit (simulate makes one unless audit=False)")
        return EnergyBalance.of(self.energy, self.energy_tolerance)

    def __getitem__(self, name: str) -> np.ndarray:
        """Column ``name`` (a variable, ``<coordinate>_dot`` or ``t``) as an array."""
        if name == "t":
            return self.t
        if name in self.names:
            return self.values[:, self.names.index(name)]
        if (c := velocity_coordinate(name, self.coordinates)) is not None:
            return self.qdot[:, self.coordinates.index(c)]
        if name in self.energy:
            return self.energy[name]
        raise InputError(name, f"not a column; valid: t, {', '.join(self.columns)}")

    def __len__(self) -> int:
        return len(self.t)

    def at(self, i: int) -> dict[str, float]:
        """Row ``i`` as ``{column: value}``."""
        row = {"t": float(self.t[i])}
        row.update({n: float(v) for n, v in zip(self.names, self.values[i])})
        row.update({velocity_name(c): float(v) for c, v in zip(self.coordinates, self.qdot[i])})
        row.update({c: float(v[i]) for c, v in self.energy.items()})
        return row

    def to_csv(self, path: str | Path, labels: Sequence[str] | None = None) -> Path:
        """Write every row as CSV: ``t``, one column per variable (named as in a continuation
        branch, so ``mechcont draw/animate`` read it), the velocities ``<coordinate>_dot``, the energy
        audit's columns (``E_kin [J]`` ..., :mod:`._energy`), and,
        if ``labels`` (one string per row) is given, a ``label`` column. Headers carry the
        units as branch tables do (``t [s]``, ``F [N]``, ``theta1_dot [rad/s]``). Written
        atomically; returns the path."""
        from ..continuation import unit_header

        if labels is not None and len(labels) != len(self.t):
            raise InputError("labels", f"needs one label per row ({len(self.t)})")

        def write(tmp: str) -> None:
            with open(tmp, "w", newline="") as fh:
                w = csv.writer(fh, lineterminator="\n")
                w.writerow([unit_header(c, self.unit(c)) for c in ("t", *self.columns)]
                           + (["label"] if labels is not None else []))
                for i in range(len(self.t)):
                    w.writerow([repr(float(self.t[i])), *(repr(float(v)) for v in self.values[i]),
                                *(repr(float(v)) for v in self.qdot[i]), *(repr(float(v[i])) for v in self.energy.values()),
                                *((labels[i],) if labels is not None else ())])

        return atomic_write(path, write)
