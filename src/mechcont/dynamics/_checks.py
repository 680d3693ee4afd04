"""What every time simulation asks of its model and its duration, checked once."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..errors import InputError

if TYPE_CHECKING:
    from ..equations import Mechanics, Model

__all__ = ["MAX_SECONDS", "check_simulable", "check_duration"]

#: Longest time (s) a simulation may be asked for (as a sweep's).
MAX_SECONDS = 1e6


def check_simulable(system: Model, model: str) -> Mechanics:
    """``system.mechanics``, or :class:`InputError` (field ``model``) when ``system`` (loaded from ``model``) has
    no mechanics to simulate."""
    if system.mechanics is None:
        raise InputError("model", f"'{model}' has no mechanics (masses, forces): it cannot be simulated")
    return system.mechanics


def check_duration(seconds: float, field: str = "until") -> float:
    """``seconds`` (a simulated time) if ``0 < seconds <=`` :data:`MAX_SECONDS`, else :class:`InputError` naming ``field``."""
    if not (math.isfinite(seconds) and 0 < seconds <= MAX_SECONDS):
        raise InputError(field, f"must be a number of seconds, 0 < SECONDS <= {MAX_SECONDS:g}, got {seconds:g}")
    return float(seconds)
