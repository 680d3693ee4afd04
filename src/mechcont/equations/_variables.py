"""The named quantities of a model (:class:`Variable`) and the physical ranges on them (:class:`Limit`).

Apart from :mod:`._system`: these are the vocabulary a model is written in (the generators, the built-in
models and the ODE files make them before any system exists), while the system is the compiled equations
over them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import InputError
from . import _deferred

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["Variable", "Limit"]


@dataclass(frozen=True)
class Variable:
    """One named quantity of a model.

    Parameters
    ----------
    name:
        Identifier used everywhere (CLI, tables, API), e.g. ``"theta1"``.
    kind:
        ``"state"`` (solved for by default) or ``"parameter"`` (held by default).
    value:
        Default value for a parameter, initial guess for a state (SI units, radians).
    unit:
        The unit its values are in, for display and headers: SI (``"N"``, ``"m"``, ``"rad"``), or a
        description's declared units (``"g mm/s^2"``, ``"mm"``; :class:`~mechcont.units.UnitSystem`).
    scale:
        Typical magnitude, used to weight the arclength so that newtons and radians
        are comparable. Must be positive.
    description:
        A short human-readable meaning.
    """

    name: str
    kind: str = "state"
    value: float = 0.0
    unit: str = ""
    scale: float = 1.0
    description: str = ""

    def __post_init__(self) -> None:
        if not self.name.isidentifier():
            raise InputError(self.name, "variable names must be identifiers (letters, digits, underscore)")
        if self.kind not in ("state", "parameter"):
            raise InputError(self.name, f"kind must be 'state' or 'parameter', not {self.kind!r}")
        if not (self.scale > 0 and math.isfinite(self.scale)):
            raise InputError(self.name, f"scale must be a positive number, not {self.scale!r}")

    @property
    def symbol(self) -> sp.Symbol:
        """The SymPy symbol of this variable (real)."""
        import sympy as sp

        return sp.Symbol(self.name, real=True)


@dataclass(frozen=True)
class Limit(_deferred.Apart):
    """A physical range of a model: ``expr > 0`` (``strict``) or ``expr >= 0``.

    ``expr`` is a SymPy expression in the variables' symbols (usually parameters only: a
    length, a mass, a stiffness, written as the description gives them). Solves refuse
    values outside every limit, and continuation ends at the edge (``EP``) of a limit that
    the continued or freed parameters move.

    Parameters
    ----------
    name:
        Where the quantity comes from, e.g. ``"bodies.1.length"`` or ``"L1"``.
    expr:
        The quantity, in SI units.
    strict:
        True when the quantity must be positive, False when zero is allowed.
    description:
        What it is, with its unit, e.g. ``"length (m)"``.
    """

    name: str
    expr: sp.Expr
    strict: bool = True
    description: str = ""

    # pickled apart: a loaded limit checks values through the system's compiled code (see _deferred)
    _APART = ("expr",)

    def message(self, value: float) -> str:
        """The one-line reason a value violates (or reaches the edge of) this limit."""
        what = self.description or "value"
        return f"{what} must be {'positive' if self.strict else 'non-negative'}, got {value:g}"
