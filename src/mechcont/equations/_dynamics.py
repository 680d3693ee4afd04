"""The first-order dynamics behind a model: ``dz/dt = f(z; x)`` and its linearisation at an equilibrium.

This is the seam between what a model *is* and the dynamic analyses (dynamic stability, Hopf points,
periodic orbits): they ask :func:`dynamics_of` for a :class:`Dynamics` and use only its members.

* An ODE model (``Model.ode`` set, from a ``[system]`` file or :func:`ode_model`) is its own dynamics:
  ``z`` are its states, ``f`` its residual, ``df/dz`` the residual's Jacobian columns of the states.
* A mechanism (``Model.mechanics`` set) has the dynamics of its equations of motion: the state holds
  coordinates, velocities and any first-order element states (see :mod:`._mechanism_dynamics`).

``x`` is always a full variable vector of the model: it gives the parameters' values (and, for
:meth:`Dynamics.state_at`, the equilibrium).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

import numpy as np

from ..errors import InputError
from ._linear_dynamics import LinearDynamics

if TYPE_CHECKING:
    import sympy as sp

    from ._model import Model

__all__ = ["LinearDynamics", "Dynamics", "OdeFacts", "OdeDynamics", "dynamics_of", "ode_model"]


class Dynamics(Protocol):
    """The first-order dynamics ``dz/dt = f(z; x)`` of a model (``x`` gives the parameters)."""

    @property
    def state_names(self) -> tuple[str, ...]:
        """Name of each component of ``z``."""

    def state_at(self, x: np.ndarray) -> np.ndarray:
        """The state ``z`` of the equilibrium at the full vector ``x`` (velocities zero)."""

    def full_vector(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """The model's full vector at state ``z`` (parameters from ``x``), for tables and drawings."""

    def full_vectors(self, Z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """:meth:`full_vector` at every row of ``Z`` ((m, len(state_names))): array (m, n_variables)."""

    def rates(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``f(z; x)``, the state's time derivative."""

    def rates_jacobian(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``df/dz``, shape (n, n)."""

    def parameter_rates(self, z: np.ndarray, x: np.ndarray, names: Sequence[str]) -> np.ndarray:
        """``df/dp`` for the named parameters, shape (n, len(names))."""

    def linearise(self, x: np.ndarray) -> LinearDynamics:
        """The linearised dynamics about the equilibrium at ``x``."""


@dataclass(frozen=True)
class OdeFacts:
    """What makes a model an ODE ``du/dt = f(u, p)`` (``algebraic`` False) or an algebraic
    problem ``0 = g(u, p)`` (``algebraic`` True, AUTO's IPS = 0: no dynamics)."""

    states: tuple[str, ...]
    algebraic: bool = False


class OdeDynamics:
    """The dynamics of an ODE model: ``z`` its states, ``f`` its residual (exact derivatives)."""

    def __init__(self, model: Model):
        facts = model.ode
        if facts is None or facts.algebraic:
            raise InputError(model.name, "has no rates (an [equations] system is algebraic, not an ODE)")
        self.model = model
        self.state_names = tuple(facts.states)
        self._cols = np.array([model.index(n) for n in self.state_names], dtype=np.intp)
        self._names = model.names

    def state_at(self, x: np.ndarray) -> np.ndarray:
        """The states' entries of ``x``."""
        return np.asarray(x, dtype=float)[self._cols].copy()

    def full_vector(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``x`` with its states replaced by ``z``."""
        out = np.array(x, dtype=float)
        out[self._cols] = z
        return out

    def full_vectors(self, Z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``x`` repeated once per row of ``Z`` ((m, len(state_names))), its states replaced by the row's."""
        Z = np.asarray(Z, dtype=float)
        if Z.ndim != 2 or Z.shape[1] != len(self._cols):
            raise InputError("Z", f"needs rows of {len(self._cols)} values ({', '.join(self.state_names)})")
        out = np.repeat(np.asarray(x, dtype=float)[None, :], len(Z), axis=0)
        out[:, self._cols] = Z
        return out

    def rates(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``f(z; p)`` (state units per second)."""
        return self.model.residual(self.full_vector(z, x))

    def rates_jacobian(self, z: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``df/dz``, exact."""
        return self.model.jacobian(self.full_vector(z, x))[:, self._cols]

    def parameter_rates(self, z: np.ndarray, x: np.ndarray, names: Sequence[str]) -> np.ndarray:
        """``df/dp`` for the named parameters, exact."""
        cols = [self.model.index(n) for n in names]
        return self.model.jacobian(self.full_vector(z, x))[:, cols]

    def linearise(self, x: np.ndarray) -> LinearDynamics:
        """``A = df/du`` at ``x``, ``E`` the identity."""
        return LinearDynamics(self.rates_jacobian(self.state_at(x), x), None, self.state_names)


def dynamics_of(model: Model, damping: float = 0.0) -> Dynamics:
    """The :class:`Dynamics` of ``model``: its own for an ODE model, its equations of motion for a
    mechanism, with ``damping`` (1/s) mass-proportional damping added to a mechanism's own (as the time
    simulation's option; an ODE model takes none). Raises :class:`InputError` (field: the model's name)
    when it has none."""
    if model.ode is not None:
        if damping:
            raise InputError("damping", f"{model.name} is an ODE system: mass-proportional damping needs masses")
        return OdeDynamics(model)
    if model.mechanics is not None:
        from ._mechanism_dynamics import MechanismDynamics  # on first use: SciPy's linear algebra

        return MechanismDynamics(model, damping=damping)
    raise InputError(model.name, "has neither rates (an ODE file) nor mechanics (a mechanism): no dynamics")


def ode_model(name: str, states: Mapping[str, float], parameters: Mapping[str, float], rates: Mapping[str, sp.Expr],
              units: Mapping[str, str] | None = None, algebraic: bool = False, description: str = "") -> Model:
    """An ODE model ``du/dt = f(u, p)`` (or, ``algebraic``, ``0 = g(u, p)``) from SymPy expressions.

    ``states``: name -> initial value; ``parameters``: name -> value; ``rates``: state name ->
    expression in the symbols ``sympy.Symbol(name, real=True)`` of states and parameters (one per
    state, in the states' order); ``units``: optional unit label per name. Returns a :class:`Model`
    whose residual is ``f`` and whose ``ode`` field says which variables are the states.
    """
    from ._model import Model
    from ._variables import Variable

    units = dict(units or {})
    if list(rates) != list(states):
        missing = [s for s in states if s not in rates] or [r for r in rates if r not in states]
        raise InputError(f"rates.{missing[0]}" if missing else "rates", "give one rate per state, in the states' order")
    # a state's typical size is its initial value's (at least 1), as a parameter's: the same system written in
    # millimetres then takes the same steps as in metres
    variables = [Variable(n, "state", float(v), units.get(n, ""), scale=max(abs(float(v)), 1.0))
                 for n, v in states.items()]
    variables += [Variable(n, "parameter", float(v), units.get(n, ""), scale=max(abs(float(v)), 1.0))
                  for n, v in parameters.items()]
    eq_names = tuple(n if algebraic else f"d{n}/dt" for n in states)
    system = Model(name=name, variables=variables, equations=list(rates.values()), equation_names=eq_names,
                   description=description)
    return system.evolve(ode=OdeFacts(tuple(states), algebraic))
