"""Time simulation of an ODE model (a ``[system]`` file): ``du/dt = f(u, p)`` integrated by SciPy.

A mechanism's simulation (:mod:`._simulate`) integrates its equations of motion; an ODE model is its
own dynamics (:func:`~mechcont.equations.dynamics_of`), integrated as written, with its exact Jacobian
given to the implicit methods (Radau, BDF, LSODA).
"""

from __future__ import annotations

import csv
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._io import atomic_write
from ..equations import Model, dynamics_of
from ..errors import InputError
from ._checks import check_duration
from ._simulate import METHODS, check_integrator

__all__ = ["OdeHistory", "simulate_ode", "ode_start"]


@dataclass(frozen=True)
class OdeHistory:
    """The states of an ODE model against time.

    Attributes
    ----------
    model:
        The model's name.
    t:
        Times (s), one per accepted integrator step (the start included).
    states:
        The states at each time, shape (len(t), n).
    names, units:
        Each state's name and unit.
    parameters:
        Each parameter's name, value (SI) and unit: constant columns of the table (a table holds every
        variable of its model, as a mechanism's history does, so ``explore`` and ``draw`` can read it).
    nfev:
        Evaluations of the rates.
    integrator_failure:
        Empty when the integrator reached the end; else why it stopped (``"step budget"`` when it
        would have needed more than ``max_steps`` steps).
    detail:
        A sentence on the failure (for a step budget: what to change).
    """

    model: str
    t: np.ndarray
    states: np.ndarray
    names: tuple[str, ...]
    units: tuple[str, ...]
    parameters: tuple[tuple[str, float, str], ...]
    nfev: int
    integrator_failure: str = ""
    detail: str = ""
    stop_events: tuple = ()

    @property
    def success(self) -> bool:
        """Whether the integrator reached the end time."""
        return not self.integrator_failure

    def __len__(self) -> int:
        return len(self.t)

    def __getitem__(self, name: str) -> np.ndarray:
        """The column ``name`` (``t`` or a state)."""
        if name == "t":
            return self.t
        if name not in self.names:
            raise InputError(name, f"not a state of {self.model}; valid: {', '.join(self.names)}")
        return self.states[:, self.names.index(name)]

    def unit(self, name: str) -> str:
        """The unit of column ``name`` (``s`` for ``t``)."""
        return "s" if name == "t" else self.units[self.names.index(name)]

    def to_csv(self, path: str | Path) -> Path:
        """Write ``t``, each state and each parameter as CSV, the headers with units as branch tables have
        them (``t [s]``, ``x [m]``); written atomically; returns the path."""
        from ..continuation import unit_header

        header = [unit_header("t", "s"), *(unit_header(n, u) for n, u in zip(self.names, self.units)),
                  *(unit_header(n, u) for n, _, u in self.parameters)]
        constants = [repr(float(v)) for _, v, _ in self.parameters]

        def write(tmp: str) -> None:
            with open(tmp, "w", newline="") as fh:
                w = csv.writer(fh, lineterminator="\n")
                w.writerow(header)
                for ti, row in zip(self.t, self.states):
                    w.writerow([repr(float(ti)), *(repr(float(v)) for v in row), *constants])

        return atomic_write(path, write)


def ode_start(model: Model, start: Mapping[str, float], field: str = "--start") -> np.ndarray:
    """The full vector an ODE simulation starts from: the file's initial states, those named in ``start``
    replaced (SI). :class:`InputError` naming ``field`` for a name that is not a state."""
    facts = model.ode
    if facts is None:
        raise InputError(field, f"{model.name} is not an ODE system")
    for name in start:
        if name not in facts.states:
            raise InputError(field, f"{name} is not a state of {model.name}; valid: {', '.join(facts.states)}")
    return model.vector(dict(start))


def simulate_ode(model: Model, x0: np.ndarray, t_span: tuple[float, float], *, method: str = "RK45",
                 rtol: float = 1e-8, atol: float = 1e-10, max_steps: int = 1_000_000,
                 progress: Callable[[float], object] | None = None) -> OdeHistory:
    """Integrate ``du/dt = f(u, p)`` of the ODE ``model`` from the full vector ``x0`` (its states the
    initial state, its parameters ``p``) over ``t_span`` (s), with SciPy's ``method`` (:data:`METHODS`;
    the implicit ones get the exact ``df/du``) at tolerances ``rtol``/``atol`` (each state's unit).

    Returns an :class:`OdeHistory` (a row per accepted step). Stops early, saying why in
    ``integrator_failure``, where the integrator fails or would need more than ``max_steps`` steps.
    Raises :class:`InputError` for an algebraic model (no dynamics), a bad integrator choice or span.
    """
    dyn = dynamics_of(model)  # InputError for an [equations] system
    check_integrator(method, rtol, atol)
    t0, t1 = (float(t) for t in t_span)
    check_duration(t1 - t0, "until")
    if not (isinstance(max_steps, int) and max_steps > 0):
        raise InputError("max_steps", f"must be a positive number of steps, got {max_steps!r}")
    x = np.asarray(x0, dtype=float)
    z0 = dyn.state_at(x)
    if not np.all(np.isfinite(dyn.rates(z0, x))):
        raise InputError("x0", f"the rates of {model.name} are not finite at the initial state")
    nfev = 0

    def fun(_t: float, z: np.ndarray) -> np.ndarray:
        nonlocal nfev
        nfev += 1
        return dyn.rates(z, x)

    extra = {"jac": lambda _t, z: dyn.rates_jacobian(z, x)} if method in ("Radau", "BDF", "LSODA") else {}
    solver = METHODS[method](fun, t0, z0, t1, rtol=rtol, atol=atol, **extra)
    ts, zs = [t0], [z0.copy()]
    failure, detail = "", ""
    while solver.status == "running":
        if len(ts) > max_steps:
            failure = "step budget"
            detail = (f"the integrator needed more than {max_steps} steps (max_steps) to reach t = {t1:g} s; "
                      f"{model.name} may be stiff there: use method Radau")
            break
        message = solver.step()
        if solver.status == "failed":
            failure = str(message or "the step size became too small")
            break
        ts.append(float(solver.t))
        zs.append(np.array(solver.y, dtype=float))
        if progress is not None:
            progress(float(solver.t) - t0)
    names = tuple(dyn.state_names)
    params = tuple((n, float(x[model.index(n)]), model.variable(n).unit) for n in model.parameter_names)
    return OdeHistory(model.name, np.array(ts), np.array(zs), names, tuple(model.variable(n).unit for n in names),
                      params, nfev, failure, detail)
