"""The parameters of a description (the force elements are in :mod:`.elements`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

__all__ = ["Parameter", "StopReaction"]


@dataclass(frozen=True)
class Parameter:
    """A named parameter: default value (SI), unit, meaning and typical magnitude.

    ``scale`` (optional, positive) weights the parameter in the continuation arclength;
    by default it is inferred from the unit and the mechanism's size.
    """

    name: str
    value: float
    unit: str = ""
    description: str = ""
    scale: float | None = None
    #: Whether the mechanism made it (from another element) rather than the user.
    GENERATED: ClassVar[bool] = False


@dataclass(frozen=True)
class StopReaction(Parameter):
    """The contact reaction parameter ``R_<stop>`` that a stop adds (default 0: out of contact);
    made by the mechanism from its ``stops``, never read from a file."""

    GENERATED: ClassVar[bool] = True
