"""What the pluggable parts of a model provide, as structural types: its mechanics, its scene, its
value check and its choice of redundant rows (any object with these members fits)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Protocol

import numpy as np

from ._scene import Scene

if TYPE_CHECKING:
    import sympy as sp

    from ._mechanics import StabilityResult
    from ._model import Model

__all__ = ["Mechanics", "SceneFunction", "ValueCheck", "Reselect", "DofFacts", "Description"]


class Mechanics(Protocol):
    """The physical mechanism behind a model's equations (:class:`~mechcont.equations.MechanicalModel`):
    coordinates ``q`` (m, rad), constraints ``Phi``, applied forces ``Q``, masses; ``x`` is a full
    variable vector of the model, ``qdot`` the coordinates' rates (m/s, rad/s)."""

    @property
    def names(self) -> tuple[str, ...]:
        """All variable names of the model (``x`` is ordered like this)."""

    @property
    def coordinates(self) -> tuple[str, ...]:
        """Names of the generalised coordinates."""

    @property
    def q_index(self) -> np.ndarray:
        """Positions of the coordinates in ``x``."""

    @property
    def n_constraints(self) -> int:
        """Number of constraints ``Phi``."""

    @property
    def constraint_names(self) -> tuple[str, ...] | None:
        """Name of each constraint, or None when they are the model's rows after the equilibrium rows."""

    @property
    def constraints(self) -> list[sp.Expr]:
        """The constraints ``Phi_k`` as SymPy expressions in the variables (and the velocity symbols)."""

    @property
    def mass_matrix(self) -> sp.Matrix:
        """The mass matrix ``M(q)`` as a SymPy matrix (n_q x n_q; kg, kg m^2)."""

    @property
    def element_states(self) -> tuple[str, ...]:
        """Names of the force elements' first-order states (a tyre's lateral deflection); empty for most."""

    @property
    def s_index(self) -> np.ndarray:
        """Positions of the element states in ``x`` (in :attr:`element_states`' order)."""

    def phi(self, x: np.ndarray, qdot: np.ndarray | None = None) -> np.ndarray:
        """Constraint residuals."""

    def phi_q(self, x: np.ndarray) -> np.ndarray:
        """Constraint Jacobian ``dPhi/dq``, shape (n_constraints, n_q)."""

    def gamma(self, x: np.ndarray, qdot: np.ndarray) -> np.ndarray:
        """Right-hand side of ``Phi_q qddot = gamma``."""

    def applied_forces(self, x: np.ndarray, qdot: np.ndarray | None = None) -> np.ndarray:
        """Generalised applied forces ``Q`` (N, N m)."""

    def applied_forces_batch(self, X: np.ndarray, Qdot: np.ndarray) -> np.ndarray:
        """:meth:`applied_forces` at every row of ``X`` (full vectors) with the velocities ``Qdot``: (m, n_q)."""

    def potential_energy(self, x: np.ndarray) -> float:
        """Potential energy ``V`` (J) of the conservative forces (0 when the model declares none)."""

    def damping_matrix(self, x: np.ndarray, qdot: np.ndarray | None = None) -> np.ndarray:
        """``-dQ/dqdot`` (N s/m)."""

    def mass(self, x: np.ndarray) -> np.ndarray:
        """Mass matrix ``M(q)`` (kg, kg m^2)."""

    def inertial_forces(self, x: np.ndarray, qdot: np.ndarray) -> np.ndarray:
        """Velocity-product (centrifugal, Coriolis, gyroscopic) generalised forces (N, N m); zero at rest."""

    def acceleration_terms(self, x: np.ndarray, qdot: np.ndarray, drift: bool = True,
                           varying_mass: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray,
                                                               np.ndarray | None]:
        """``(phi_q, gamma, phi or None, applied (+ inertial) forces, mass or None)`` from one argument vector."""

    def element_state_rates(self, x: np.ndarray, qdot: np.ndarray | None = None) -> np.ndarray:
        """The element states' rates (each state's unit per second), in :attr:`element_states`' order."""

    def multipliers(self, x: np.ndarray) -> np.ndarray:
        """Constraint reactions ``lambda`` with ``Phi_q^T lambda = Q`` (least squares)."""

    def force_jacobian(self, x: np.ndarray) -> np.ndarray:
        """``dQ/dq`` at rest, shape (n_q, n_q)."""

    def tangent_stiffness(self, x: np.ndarray, multipliers: np.ndarray | None = None) -> np.ndarray:
        """Tangent stiffness at rest, shape (n_q, n_q)."""

    def allowed_motions(self, x: np.ndarray, rtol: float = 1e-10) -> np.ndarray:
        """Orthonormal basis of the motions the joints allow."""

    def stability(self, x: np.ndarray, rtol: float = 1e-9, held: np.ndarray | None = None) -> StabilityResult:
        """Physical stability of the equilibrium at ``x``."""

    def count_unstable(self, X: np.ndarray, rtol: float = 1e-9) -> np.ndarray:
        """Number of unstable directions at every row of ``X``."""


class SceneFunction(Protocol):
    """``scene(x) -> Scene``: what to draw of the model at the full variable vector ``x`` (m, N)."""

    def __call__(self, x: np.ndarray, /) -> Scene: ...


class ValueCheck(Protocol):
    """``check(values)``: raises :class:`~mechcont.errors.InputError` for physically impossible
    parameter values ``{name: value}`` (SI)."""

    def __call__(self, values: Mapping[str, float], /) -> None: ...


class Reselect(Protocol):
    """The choice of a model's dropped redundant rows, for a choice that depends on the configuration."""

    def quality(self, x: np.ndarray) -> float:
        """Positive while the dropped rows suit the full vector ``x``."""

    def switch(self, model: Model, x: np.ndarray, force: bool = False) -> tuple[Model, np.ndarray] | None:
        """The variant of ``model`` chosen at ``x`` with ``x``'s reactions solved again, or None when it is this one."""


class DofFacts(Protocol):
    """Degrees of freedom of a model's assembled configuration (:class:`~mechcont.mechanism.DofReport`)."""

    @property
    def dof(self) -> int:
        """``n_q - rank(Phi_q)``."""

    @property
    def rank(self) -> int:
        """Numerical rank of the constraint Jacobian."""

    @property
    def redundant(self) -> tuple[tuple[str, ...], ...]:
        """Groups of joints whose constraints are linearly dependent, one per redundant row."""


class Description(Protocol):
    """The description a model was generated from (:class:`~mechcont.mechanism.Mechanism`)."""

    @property
    def name(self) -> str:
        """The mechanism's name."""

    def build(self, **overrides: float) -> Model:
        """The model at the parameter values ``overrides`` (in the description's units; the others at their defaults)."""
