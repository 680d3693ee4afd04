"""Equations: named algebraic systems with exact derivatives, and their mechanics."""

from ._dynamics import Dynamics, LinearDynamics, OdeDynamics, OdeFacts, dynamics_of, ode_model
from ._mechanics import MechanicalModel, StabilityResult, velocity_symbol
from ._model import DownlockFacts, Model, StopLimit, ValueFields, as_model, at_values, check_values_at
from ._rates import branch_rates
from ._scene import Scene
from ._system import EquationSystem, Limit, Variable

__all__ = ["EquationSystem", "Model", "StopLimit", "DownlockFacts", "ValueFields", "as_model", "at_values", "check_values_at",
           "Variable", "Limit", "Dynamics", "LinearDynamics", "OdeDynamics", "OdeFacts", "dynamics_of", "ode_model",
           "MechanicalModel", "StabilityResult", "velocity_symbol", "Scene", "branch_rates"]
