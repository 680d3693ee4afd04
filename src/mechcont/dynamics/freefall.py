"""Freefall extension: released at rest from the uplock, does the gear fall out and lock?

:func:`freefall` simulates a mechanism with its stops from rest in the retracted pose (an uplock
release) until it locks (the lock stop in contact and at rest, or a lock condition reached), and
reports how it ended: locked; at rest short of locking (it hangs in an intermediate equilibrium, or
back on the uplock); or still moving at the end of the run (e.g. it struck the lock and left it
again); with the time to lock, the impact speed at the lock, the peak damper tensions and the peak
stop reactions.

:func:`critical_airspeed` and :func:`quasi_static_critical` bracket the airspeed where the outcome
changes by runs, beside its quasi-static predictor; :func:`critical_scan` does so over the values of another
parameter (a damper's coefficient) and says whether each bracket differs from the predictor.

This module is the freefall's public face; the work is in :mod:`._freefall` (one run), :mod:`._poses`
(the released pose, the travel, the lock), :mod:`._critical` (on runs), :mod:`._critical_scan` and :mod:`._dampers`.
"""

from ._critical import CriticalAirspeed, QuasiStaticCritical, bisection_runs, critical_airspeed, quasi_static_critical
from ._critical_scan import CriticalScan, critical_scan
from ._dampers import DamperTension, damper_tensions
from ._freefall import AT_REST, FAILED, LOCKED, MOVING, FreefallResult, StopLock, freefall
from ._poses import condition_value, find_lock_stops, held_pose, travel_of

__all__ = ["FreefallResult", "StopLock", "freefall", "CriticalAirspeed", "critical_airspeed", "bisection_runs",
           "QuasiStaticCritical", "quasi_static_critical", "CriticalScan", "critical_scan", "damper_tensions",
           "DamperTension", "travel_of", "condition_value", "held_pose", "find_lock_stops", "LOCKED", "AT_REST",
           "MOVING", "FAILED"]
