"""The names of a mechanism's velocities: ``<coordinate>_dot``, one rule for every table, state and option."""

from __future__ import annotations

from collections.abc import Collection

__all__ = ["VELOCITY_SUFFIX", "velocity_name", "velocity_coordinate"]

#: what a coordinate's name takes to name its velocity (``theta1`` -> ``theta1_dot``); reserved in descriptions
VELOCITY_SUFFIX = "_dot"


def velocity_name(coordinate: str) -> str:
    """The name of ``coordinate``'s velocity (its unit per second): ``theta1`` -> ``theta1_dot``."""
    return coordinate + VELOCITY_SUFFIX


def velocity_coordinate(name: str, coordinates: Collection[str]) -> str | None:
    """The coordinate whose velocity ``name`` is (``theta1_dot`` -> ``theta1``) when it is one of
    ``coordinates``, else None."""
    if name.endswith(VELOCITY_SUFFIX):
        base = name[:-len(VELOCITY_SUFFIX)]
        if base in coordinates:
            return base
    return None
