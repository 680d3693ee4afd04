"""mechcont: numerical continuation for quasi-static mechanisms."""

from .equations import EquationSystem, MechanicalModel, StabilityResult, Variable
from .errors import ConvergenceError, InputError, MechcontError

__all__ = ["EquationSystem", "MechanicalModel", "StabilityResult", "Variable",
           "ConvergenceError", "InputError", "MechcontError"]
__version__ = "0.1.0"
