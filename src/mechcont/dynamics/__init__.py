"""Dynamics: time simulation of mechanisms (Udwadia–Kalaba), quasi-static sweeps, comparisons.

The dynamic model is the engineers' baseline that the paper validates continuation
against: :func:`simulate` integrates any :class:`~mechcont.equations.MechanicalModel`;
:func:`sweep` ramps loads slowly and reports the jumps.
"""

from ._events import Crossing
from ._result import SimulationResult, SimulationStatus
from ._simulate import assemble, simulate
from ._sweep import Jump, Ramp, SweepResult, sweep
from ._udwadia_kalaba import ConstrainedDynamics, fundamental_equation

__all__ = ["simulate", "assemble", "sweep", "Ramp", "Jump", "SweepResult", "SimulationResult", "SimulationStatus", "Crossing", "ConstrainedDynamics",
           "fundamental_equation"]
