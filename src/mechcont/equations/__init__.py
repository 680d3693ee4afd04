"""Equations: named algebraic systems with exact derivatives, and their mechanics."""

from ._codegen import compile_dense, gradient, symbol_names
from ._deferred import Apart
from ._dynamics import Dynamics, LinearDynamics, OdeDynamics, OdeFacts, dynamics_of, ode_model
from ._linear_dynamics import NEUTRAL_RTOL
from ._mechanics import MechanicalModel, StabilityResult, velocity_symbol
from ._model import DamperFacts, DownlockFacts, Model, StopLimit, ValueFields, at_values, check_values_at, units_of
from ._ode_text import ode_equations
from ._protocols import Mechanics
from ._rates import branch_rates
from ._scene import Scene
from ._stored import stored
from ._system import EquationSystem
from ._variables import Limit, Variable
from ._velocity_names import VELOCITY_SUFFIX, velocity_coordinate, velocity_name

__all__ = ["EquationSystem", "Model", "StopLimit", "DamperFacts", "DownlockFacts", "ValueFields", "at_values",
           "check_values_at", "units_of",
           "Variable", "Limit", "Dynamics", "LinearDynamics", "NEUTRAL_RTOL", "OdeDynamics", "OdeFacts", "dynamics_of",
           "ode_model",
           "ode_equations",
           "MechanicalModel", "Mechanics", "StabilityResult", "velocity_symbol", "VELOCITY_SUFFIX", "velocity_name",
           "velocity_coordinate", "Scene", "branch_rates",
           # for the generators and the models: compiled code, parts pickled apart, the disk cache
           "compile_dense", "gradient", "symbol_names", "Apart", "stored"]
