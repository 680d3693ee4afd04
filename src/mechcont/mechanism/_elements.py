"""The parameters of a description and its two-point force elements (springs, dampers)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ._expr import Value

__all__ = ["Parameter", "StopReaction", "Spring", "Damper"]


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


@dataclass(frozen=True)
class Spring:
    """A linear spring between points ``a`` and ``b``: tension ``preload + k (l - free_length)``
    (N), potential ``preload*l + k/2 (l - free_length)^2`` (J). ``k`` > 0 (N/m),
    ``free_length`` > 0 (m)."""

    name: str
    a: str
    b: str
    k: Value
    free_length: Value
    preload: Value = 0


@dataclass(frozen=True)
class Damper:
    """A hydraulic damper between points ``a`` and ``b``: tension ``c v + c2 v |v|`` (N) with
    ``v = dl/dt`` (m/s), ``c`` >= 0 (N s/m, linear), ``c2`` >= 0 (N s^2/m^2, quadratic: a restrictor
    orifice). Only the dynamic model feels it (zero at rest); see :mod:`._dampers`."""

    name: str
    a: str
    b: str
    c: Value
    c2: Value = 0
