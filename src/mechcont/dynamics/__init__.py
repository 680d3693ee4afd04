"""Dynamics: time simulation of mechanisms (Udwadia–Kalaba), quasi-static sweeps, comparisons.

The dynamic model is the engineers' baseline that the paper validates continuation
against: :func:`simulate` integrates any :class:`~mechcont.equations.MechanicalModel`;
:func:`sweep` ramps loads slowly and reports the jumps.
"""

from ._checks import MAX_SECONDS, check_duration, check_simulable
from ._compare import (
    JumpGap,
    RateGap,
    branch_differences,
    branch_jump_gaps,
    branch_runaway_gap,
    gap_versus_rate,
    jump_gaps,
    runaway_gap,
)
from ._contact import StopConstraints, StopEvent
from ._events import Crossing
from ._exudyn import exudyn_available, exudyn_overcentre
from ._held_differences import held_branch_differences
from ._ode import OdeHistory, ode_start, simulate_ode
from ._result import SimulationResult, SimulationStatus
from ._simulate import METHODS, assemble, check_integrator, simulate
from ._stall import UNRESOLVED
from ._sweep import Jump, Ramp, SweepResult, parse_ramps, sweep, sweep_start
from ._udwadia_kalaba import ConstrainedDynamics, fundamental_equation

__all__ = ["simulate", "assemble", "sweep", "sweep_start", "parse_ramps", "Ramp", "Jump", "SweepResult", "SimulationResult",
           "SimulationStatus", "Crossing", "ConstrainedDynamics", "fundamental_equation", "jump_gaps", "JumpGap",
           "branch_jump_gaps", "branch_differences", "runaway_gap", "branch_runaway_gap",
           "gap_versus_rate", "RateGap", "exudyn_available", "exudyn_overcentre", "StopEvent",
           "StopConstraints", "MAX_SECONDS", "check_duration", "check_simulable", "OdeHistory", "ode_start", "simulate_ode",
           "METHODS", "check_integrator", "UNRESOLVED", "held_branch_differences"]
