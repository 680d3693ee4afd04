"""Damper tensions of a simulated mechanism: ``T = c v + c2 v |v|`` at each row or at any state."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ._result import SimulationResult

if TYPE_CHECKING:
    from ..equations import DamperFacts, Model

__all__ = ["damper_tensions", "DamperTension"]


def damper_tensions(system: Model, result: SimulationResult, h: float = 1e-7) -> dict[str, np.ndarray]:
    """Tension (N) of every damper of ``system`` (:attr:`~mechcont.equations.Model.dampers`) at every row of
    ``result``.

    ``T = c v + c2 v |v|`` with ``v = dl/dt`` (see :mod:`mechcont.mechanism.elements.damper`): the
    length ``l`` between the damper's drawn end points, its rate by a central difference along the
    row's velocity (error ``O(h^2)``, relative ~1e-14 at the default ``h``). The coefficients are the model's
    (compiled from its description when it was built: a model loaded from the cache needs no description).
    """
    tension = DamperTension(system, result.coordinates, h)
    names = tension.names
    out = {n: np.zeros(len(result)) for n in names}
    for i in range(len(result)):
        for n, v in tension(result.values[i], result.qdot[i]).items():
            out[n][i] = v
    return out


class DamperTension:
    """The dampers' tensions (N) at one state: ``DamperTension(model, coordinates)(x, qdot)`` ->
    ``{damper: T}`` for a full row ``x`` and the velocities of ``coordinates`` (as :func:`damper_tensions`;
    ``names`` the dampers, empty when the model has none or no scene to measure their lengths)."""

    def __init__(self, system: Model, coordinates: Sequence[str], h: float = 1e-7) -> None:
        self.dampers: tuple[DamperFacts, ...] = system.dampers if system.scene is not None else ()
        self.names = [d.name for d in self.dampers]
        self.system, self.h = system, h
        # the coefficients depend on the description's parameters only; a stop's contact reaction is a parameter of
        # the equations too but changes at every row in contact, and would make every row a new key (and a new
        # evaluation of the model's value fields)
        reactions = {s.reaction for s in system.stops}
        self.params = [v.name for v in system.variables if v.kind == "parameter" and v.name not in reactions]
        self.q_index = np.array([system.index(c) for c in coordinates], dtype=int)
        own = tuple(float(system.variable(n).value) for n in self.params)
        # the coefficients per parameter vector (a sweep ramps parameters in time): the model's at its own values
        self.coefficients: dict[tuple, tuple[DamperFacts, ...]] = {own: self.dampers}

    def _lengths(self, x: np.ndarray) -> dict[str, float]:
        assert self.system.scene is not None  # no dampers without a scene (__init__)
        ends = {name: (a, b) for name, a, b in self.system.scene(x).dampers}
        return {n: float(np.linalg.norm(np.asarray(b) - np.asarray(a))) for n, (a, b) in ends.items()}

    def __call__(self, x: np.ndarray, qdot: np.ndarray) -> dict[str, float]:
        if not self.dampers:
            return {}
        p = {n: float(x[self.system.index(n)]) for n in self.params}
        key = tuple(p.values())
        if key not in self.coefficients:
            at = self.system.fields_at(p) if self.system.fields_at is not None else {}
            self.coefficients[key] = at.get("dampers", self.dampers)
        xp, xm = np.array(x, float), np.array(x, float)
        xp[self.q_index] += self.h * qdot
        xm[self.q_index] -= self.h * qdot
        lp, lm = self._lengths(xp), self._lengths(xm)
        out = {}
        for d in self.coefficients[key]:
            v = (lp[d.name] - lm[d.name]) / (2 * self.h)
            out[d.name] = d.c * v + d.c2 * v * abs(v)
        return out
