"""Compliant stops in the time simulation: a penalty reaction instead of a unilateral constraint.

A stop with ``contact = "compliant"`` lets the condition pass its limit by the penetration
``p = -g`` (``g`` the gap, :mod:`._contact`) and pushes back with the reaction

    R = max(0, k p + c p')      for p > 0,   else 0,

(``k`` the stiffness, ``c`` the damping, per unit of the condition; a Kelvin–Voigt contact that
never pulls), applied as the stop's own reaction parameter ``R_NAME``: the mechanics turns it into
the generalised force ``R grad g`` along the condition's gradient, exactly as for a rigid stop.
Undamped, it stores the energy ``k p^2 / 2``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from ..equations import StopLimit

__all__ = ["CompliantLaw"]


class CompliantLaw:
    """Penalty reactions of the compliant stops among ``stops`` (:class:`~mechcont.equations.StopLimit`).

    ``index`` are the positions (in ``stops``) of the compliant ones; ``stiffness`` and ``damping``
    their coefficients.
    """

    def __init__(self, stops: Sequence[StopLimit]) -> None:
        self.index = [k for k, s in enumerate(stops) if s.contact == "compliant"]
        self.stiffness = np.array([float(stops[k].stiffness) for k in self.index])
        self.damping = np.array([float(stops[k].damping) for k in self.index])
        for k, kk, cc in zip(self.index, self.stiffness, self.damping):
            if not (np.isfinite(kk) and kk > 0):
                raise InputError(f"stops.{stops[k].name}.stiffness", f"must be a positive finite number, got {kk:g}")
            if not (np.isfinite(cc) and cc >= 0):
                raise InputError(f"stops.{stops[k].name}.damping", f"must be a finite number >= 0, got {cc:g}")

    def __bool__(self) -> bool:
        return bool(self.index)

    def reactions(self, gaps: np.ndarray, rates: np.ndarray) -> np.ndarray:
        """``max(0, k p + c p')`` where the penetration ``p = -gap > 0``, else 0 (reaction units)."""
        p, pd = -np.asarray(gaps, float), -np.asarray(rates, float)
        return np.where(p > 0, np.maximum(0.0, self.stiffness * p + self.damping * pd), 0.0)

    def energy(self, gaps: np.ndarray) -> np.ndarray:
        """Energy stored in each compliant stop's spring, ``k p^2 / 2`` for ``p > 0`` (J)."""
        p = np.maximum(0.0, -np.asarray(gaps, float))
        return 0.5 * self.stiffness * p**2
