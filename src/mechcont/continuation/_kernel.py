"""Which corrector a branch runs: the compiled one (``_ckernel``) where it applies, else Python.

The compiled corrector (:mod:`._ckernel`, built from Cython by ``pip install`` when a C
compiler is present) takes a whole step of :class:`~._corrector.PseudoArclength` in one call:
predictor, Newton on the bordered system, the new tangent and the branch-point test
function. It applies to problems of at most ``MAX_SIZE`` unknowns solved with the default
dense LU: an equilibrium problem's compiled model is called from C, and so is a fold
curve's, its determinant row included; any other problem has its ``evaluate`` called back,
the loop around it compiled. Other linear solvers, larger models, and machines where it was
not built run the Python corrector.
``MECHCONT_PURE_PYTHON=1`` (read at the start of each branch) turns it off, e.g. to compare
the two.
"""

from __future__ import annotations

import importlib
import os
from typing import Any, Protocol

import numpy as np

from ._linalg import DenseLU
from ._options import ContinuationOptions
from ._problem import CompiledModel, ContinuationProblem

__all__ = ["AVAILABLE", "CODE_NAMES", "CompiledStepper", "StepResult", "bordered_newton", "condensation"]

_ck: Any = None
try:
    _ck = importlib.import_module("mechcont.continuation._ckernel")
except ImportError:  # not built (no C compiler at install): the Python corrector runs
    pass

_cc: Any = None
try:  # the collocation's condensation of parameters, compiled (built beside _ckernel)
    _cc = importlib.import_module("mechcont.continuation._ccondense")
except ImportError:
    pass

#: Whether the compiled corrector was built on this machine.
AVAILABLE = _ck is not None

#: ``{code: name}`` of the compiled step's return codes (``"converged"``, ``"not_finite"``, ...)
CODE_NAMES: dict[int, str] = {} if _ck is None else {code: name for name, code in _ck.CODES.items()}


#: What :meth:`CompiledStepper.step` returns: ``(code, iterations, z, jac, tangent, det_sign, log_det)`` on
#: convergence (code 0), ``(code, iterations, None, None, None, 0.0, 0.0)`` otherwise
StepResult = (tuple[int, int, np.ndarray, np.ndarray, np.ndarray, float, float]
              | tuple[int, int, None, None, None, float, float])


class CompiledStepper(Protocol):
    """The compiled corrector (``_ckernel.BorderedNewton``): one whole step of
    :class:`~._corrector.PseudoArclength` per call."""

    def step(self, z0: np.ndarray, t0: np.ndarray, sigma: float, z_start: np.ndarray | None = None) -> StepResult:
        """Predict ``z0 + sigma t0``, correct, and take the new tangent: see :data:`StepResult`."""
        ...


def bordered_newton(problem: ContinuationProblem, scale: np.ndarray,
                    options: ContinuationOptions) -> CompiledStepper | None:
    """A compiled stepper (``_ckernel.BorderedNewton``) for ``problem``, or None where it does not apply.

    Where ``problem.compiled_model()`` gives a :class:`~._problem.CompiledModel` (see
    :meth:`~._problem.EquilibriumProblem.compiled_model` and
    :meth:`~._folds.FoldProblem.compiled_model`) the model is called from C; where it gives
    None (the protocol's default) ``problem.evaluate`` is called back. ``scale`` are the unknowns' scales
    (``PseudoArclength.D``).
    """
    if _ck is None or os.environ.get("MECHCONT_PURE_PYTHON", "") not in ("", "0"):
        return None
    if type(options.linear_solver) is not DenseLU or len(scale) > _ck.MAX_SIZE:
        return None
    # a problem written to the protocol without subclassing it may lack the hook: no compiled model
    m: CompiledModel | None = getattr(problem, "compiled_model", lambda: None)()
    e = options.engine
    if m is None:  # the loop compiled, the model called back
        return _ck.BorderedNewton(problem.evaluate, 0, None, None, None, scale, e.newton_tol, e.residual_tol,
                                  e.max_newton, e.max_contraction, None)
    return _ck.BorderedNewton(m.fn, m.n_out, m.src, m.base, m.idx, scale, e.newton_tol, e.residual_tol, e.max_newton,
                              e.max_contraction, m.fold)


def condensation() -> Any:
    """The compiled condensation of parameters (module ``_ccondense``), or None where it was not built or
    ``MECHCONT_PURE_PYTHON`` is set (then :mod:`._condensation` runs NumPy and LAPACK)."""
    if _cc is None or os.environ.get("MECHCONT_PURE_PYTHON", "") not in ("", "0"):
        return None
    return _cc
