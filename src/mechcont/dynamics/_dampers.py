"""Damper tensions of a simulated mechanism: ``T = c v + c2 v |v|`` at each row or at any state."""

from __future__ import annotations

from typing import Any

import numpy as np

from ._result import SimulationResult

__all__ = ["damper_tensions", "DamperTension"]


def damper_tensions(system, result: SimulationResult, h: float = 1e-7, mechanism=None) -> dict[str, np.ndarray]:
    """Tension (N) of every damper of ``system``'s description at every row of ``result``.

    ``T = c v + c2 v |v|`` with ``v = dl/dt`` (see :mod:`mechcont.mechanism.elements.damper`): the
    length ``l`` between the damper's drawn end points, its rate by a central difference along the
    row's velocity (error ``O(h^2)``, relative ~1e-14 at the default ``h``). ``mechanism``: the description's
    mechanism when already at hand (a model loaded from the cache makes it on first use, seconds for a large
    one, and a copy made with other values before that makes it again).
    """
    tension = DamperTension(system, result.coordinates, h, mechanism)
    names = tension.names
    out = {n: np.zeros(len(result)) for n in names}
    for i in range(len(result)):
        for n, v in tension(result.values[i], result.qdot[i]).items():
            out[n][i] = v
    return out


class DamperTension:
    """The dampers' tensions (N) at one state: ``DamperTension(system, coordinates)(x, qdot)`` ->
    ``{damper: T}`` for a full row ``x`` and the velocities of ``coordinates`` (as :func:`damper_tensions`;
    ``names`` the dampers, empty when the description has none)."""

    def __init__(self, system, coordinates, h: float = 1e-7, mechanism=None) -> None:
        from ..equations import as_model

        mech: Any = as_model(system).mechanism if mechanism is None else mechanism
        self.dampers = list(getattr(mech, "dampers", ())) if system.scene is not None else []
        self.names = [d.name for d in self.dampers]
        self.system, self.mech, self.h = system, mech, h
        self.params = [v.name for v in system.variables if v.kind == "parameter"]
        self.q_index = np.array([system.index(c) for c in coordinates], dtype=int)
        self.coefficients: dict[tuple, list[tuple[float, float]]] = {}  # per parameter vector (they may vary in time)

    def _lengths(self, x) -> dict[str, float]:
        ends = {name: (a, b) for name, a, b in self.system.scene(x).dampers}
        return {n: float(np.linalg.norm(np.asarray(b) - np.asarray(a))) for n, (a, b) in ends.items()}

    def __call__(self, x: np.ndarray, qdot: np.ndarray) -> dict[str, float]:
        from ..mechanism import evaluate

        if not self.dampers:
            return {}
        p = {n: float(x[self.system.index(n)]) for n in self.params}
        key = tuple(p.values())
        if key not in self.coefficients:
            self.coefficients[key] = [(evaluate(self.mech.value(f"dampers.{d.name}.c"), p, f"dampers.{d.name}.c"),
                                       evaluate(self.mech.value(f"dampers.{d.name}.c2"), p, f"dampers.{d.name}.c2"))
                                      for d in self.dampers]
        xp, xm = np.array(x, float), np.array(x, float)
        xp[self.q_index] += self.h * qdot
        xm[self.q_index] -= self.h * qdot
        lp, lm = self._lengths(xp), self._lengths(xm)
        out = {}
        for d, (c, c2) in zip(self.dampers, self.coefficients[key]):
            v = (lp[d.name] - lm[d.name]) / (2 * self.h)
            out[d.name] = c * v + c2 * v * abs(v)
        return out
