"""mechcont: numerical continuation for quasi-static mechanisms (aircraft landing gear first).

The public API in one place; each name is imported on first use (PEP 562), so
``import mechcont`` costs no SymPy, SciPy or Matplotlib import::

    import mechcont as mc
    s = mc.load_model("overcentre", LU=0.4)
    x0 = mc.find_equilibrium(s, hold={"theta1": 0.3}, free=["F"])
    b = mc.continuation(s, x0, "F", options=mc.ContinuationOptions(bounds={"theta1": (-1.2, 1.2)}))
    folds = mc.continue_folds(s, b["LP1"], vary="F", free="LU")

The analyses and studies are here too (``mc.downlock``, ``mc.design_region``, ``mc.run_study``,
``mc.optimize``, ``mc.freefall``...), each with its own module in ``analysis`` or ``dynamics``; what
every command shows is written in ``outputs`` (``outputs.tables``) and ``units.display``.

The layers are subpackages, each importing only those below it (tests/test_layers.py): ``equations``
(the model type, compiled code); ``mechanism`` (descriptions to models) and ``continuation``; ``models``
(built-in models); ``dynamics`` (time simulation); ``analysis`` (its studies simulate too); ``outputs``; then this API, the
paper and the CLI. ``mechcont.continuation``
is both the subpackage and, called, the function :func:`mechcont.continuation.continuation`.
"""

from __future__ import annotations

import importlib
import os
import sys
from typing import TYPE_CHECKING, Any

from ._version import __version__ as __version__  # re-exported: mechcont.__version__
from .errors import ConvergenceError, InputError, MechcontError

# OpenBLAS (NumPy's and SciPy's BLAS) runs every matrix operation on one thread per core. mechcont's
# matrices are small (tens to a few hundred rows), where the threads cost more than they give, and
# when another process holds a core they spin: a 63 x 64 SVD took 96 ms instead of 0.5 ms on the
# 2-core machine with the other core busy. One thread unless the user chose (only possible before
# NumPy is first imported; set OPENBLAS_NUM_THREADS yourself to override).
if "numpy" not in sys.modules:
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

#: public name -> the module that defines it
_LAZY = {
    # models: built-in names and description files
    "load_model": "mechcont.models",
    "model_names": "mechcont.models",
    "Mechanism": "mechcont.mechanism",
    "load_description": "mechcont.mechanism",
    # equations
    "Model": "mechcont.equations",
    "EquationSystem": "mechcont.equations",
    "MechanicalModel": "mechcont.equations",
    "StabilityResult": "mechcont.equations",
    "Variable": "mechcont.equations",
    # continuation
    "find_equilibrium": "mechcont.continuation",
    "continue_folds": "mechcont.continuation",
    "continue_hopf": "mechcont.continuation",
    "locate_hopf": "mechcont.continuation",
    "HopfPoint": "mechcont.continuation",
    "switch_branch": "mechcont.continuation",
    "ContinuationOptions": "mechcont.continuation",
    "Branch": "mechcont.continuation",
    "SpecialPoint": "mechcont.continuation",
    "ValueEvent": "mechcont.continuation",
    "cycles_from_hopf": "mechcont.continuation",
    "cycles_from_samples": "mechcont.continuation",
    "CycleBranch": "mechcont.continuation",
    # time simulation
    "simulate": "mechcont.dynamics",
    "sweep": "mechcont.dynamics",
    "SimulationResult": "mechcont.dynamics",
    # how a result ended (branches, special points, simulations, studies)
    "Status": "mechcont._status",
    "freefall": "mechcont.dynamics.freefall",
    "critical_airspeed": "mechcont.dynamics.freefall",
    # analyses: downlock and unlock, stops, families, design maps
    "downlock": "mechcont.analysis.downlock",
    "DownlockResult": "mechcont.analysis.downlock",
    "downlock_condition": "mechcont.analysis.downlock",
    "unlock_folds": "mechcont.analysis.unlock",
    "continuation_with_stops": "mechcont.analysis.stops",
    "equilibrium_on_stops": "mechcont.analysis.stops",
    "equilibrium_family": "mechcont.analysis.surface",
    "design_region": "mechcont.analysis.design",
    "fold_locus": "mechcont.analysis.design",
    "redundancy_along": "mechcont.analysis.redundancy",
    # sensitivities, optimisation, reliability, studies
    "equilibrium_sensitivity": "mechcont.analysis.sensitivity",
    "fold_sensitivity": "mechcont.analysis.sensitivity",
    "downlock_sensitivity": "mechcont.analysis.sensitivity",
    "optimize": "mechcont.analysis.optimize",
    "downlock_reliability": "mechcont.analysis.reliability",
    "StudySpec": "mechcont.analysis.study",
    "run_study": "mechcont.analysis.study",
    "read_results": "mechcont.analysis.study",
    "failure_probability": "mechcont.analysis.study",
}
_SUBPACKAGES = {"analysis", "continuation", "dynamics", "equations", "mechanism", "models", "outputs", "errors", "units"}

__all__ = [
    "load_model", "model_names", "Mechanism", "load_description",
    "Model", "EquationSystem", "MechanicalModel", "StabilityResult", "Variable",
    "find_equilibrium", "continuation", "continue_folds", "switch_branch", "ContinuationOptions", "Branch",
    "SpecialPoint", "ValueEvent", "continue_hopf", "locate_hopf", "HopfPoint",
    "cycles_from_hopf", "cycles_from_samples", "CycleBranch",
    "simulate", "sweep", "SimulationResult", "Status", "freefall", "critical_airspeed",
    "downlock", "DownlockResult", "downlock_condition", "unlock_folds", "continuation_with_stops", "equilibrium_on_stops",
    "equilibrium_family", "design_region", "fold_locus", "redundancy_along",
    "equilibrium_sensitivity", "fold_sensitivity", "downlock_sensitivity", "optimize", "downlock_reliability",
    "StudySpec", "run_study", "read_results", "failure_probability",
    "errors", "units", "ConvergenceError", "InputError", "MechcontError",
]

if TYPE_CHECKING:  # what the lazy names are, for type checkers and IDEs
    from . import errors, units
    from ._status import Status
    from .analysis.design import design_region, fold_locus
    from .analysis.downlock import DownlockResult, downlock, downlock_condition
    from .analysis.optimize import optimize
    from .analysis.redundancy import redundancy_along
    from .analysis.reliability import downlock_reliability
    from .analysis.sensitivity import downlock_sensitivity, equilibrium_sensitivity, fold_sensitivity
    from .analysis.stops import continuation_with_stops, equilibrium_on_stops
    from .analysis.study import StudySpec, failure_probability, read_results, run_study
    from .analysis.surface import equilibrium_family
    from .analysis.unlock import unlock_folds
    from .continuation import (
        Branch,
        ContinuationOptions,
        CycleBranch,
        HopfPoint,
        SpecialPoint,
        ValueEvent,
        continuation,
        continue_folds,
        continue_hopf,
        cycles_from_hopf,
        cycles_from_samples,
        find_equilibrium,
        locate_hopf,
        switch_branch,
    )
    from .dynamics import SimulationResult, simulate, sweep
    from .dynamics.freefall import critical_airspeed, freefall
    from .equations import EquationSystem, MechanicalModel, Model, StabilityResult, Variable
    from .mechanism import Mechanism, load_description
    from .models import load_model, model_names


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is not None:
        value = getattr(importlib.import_module(module), name)
    elif name in _SUBPACKAGES:
        value = importlib.import_module(f"{__name__}.{name}")
    else:
        raise AttributeError(f"module 'mechcont' has no attribute {name!r}")
    globals()[name] = value  # the next access is a plain attribute
    return value


def _branch_html(branch: Any) -> str:
    from .outputs.explore import branch_html

    return branch_html(branch)


def _register_notebook_view() -> bool:
    """In IPython/Jupyter, show every :class:`~mechcont.continuation.Branch` (subclasses too) as the
    explorer page. Registered by the class's name, so nothing is imported until a branch is shown;
    the continuation layer itself knows nothing of outputs. Returns whether it registered."""
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None and hasattr(ipython, "get_ipython") else None
    if shell is None:
        return False
    shell.display_formatter.formatters["text/html"].for_type_by_name("mechcont.continuation._branch", "Branch",
                                                                      _branch_html)
    return True


_register_notebook_view()


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY, *_SUBPACKAGES})
