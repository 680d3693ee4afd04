"""What to draw for the paper's overcentre (:mod:`mechcont.models.overcentre`) at a configuration.

Geometry (see that module's docstring): bar 1 runs from the ground pin at the origin to the
apex, bar 2 from its slider end on the ground line y = 0 to the apex; both are placed from
their centres of gravity ``(x_i, y_i)`` and angles ``theta_i`` as the equations define them,
so a vector that does not satisfy the constraints shows as a visibly broken mechanism
rather than being silently repaired. The spring joins the points at distances ``m`` and
``n`` from the centres of gravity towards the apex; ``F`` acts vertically at the apex.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..equations import EquationSystem, Scene

__all__ = ["overcentre_scene"]

_NAMES = ("x1", "y1", "theta1", "x2", "y2", "theta2", "L1", "L2", "m", "n", "F", "m1", "m2", "g")


def overcentre_scene(system: EquationSystem, *, weights: bool = False) -> Callable[[np.ndarray], Scene]:
    """A ``scene(x) -> Scene`` function for the overcentre ``system``.

    Parameters
    ----------
    system:
        An overcentre :class:`EquationSystem` (``build_overcentre``); the variable names
        ``x1, y1, theta1, x2, y2, theta2, L1, L2, m, n, F`` are looked up by name.
    weights:
        Also draw the bar weights ``m_i g`` (N, downward) at the centres of gravity.

    Returns
    -------
    callable
        ``scene(x)`` for a full variable vector ``x`` (ordered like ``system.names``; m, rad,
        N) giving bars ``"bar 1"``, ``"bar 2"``, the apex pin, the ground pin at the origin,
        the slider at bar 2's lower end on the rail y = 0 (direction +x), the spring and the
        force ``F`` (vector ``(0, F)`` at the apex).
    """
    return _OvercentreScene({name: system.index(name) for name in _NAMES}, weights)


@dataclass(frozen=True)
class _OvercentreScene:
    """``scene(x)`` of :func:`overcentre_scene`: the variables' positions ``idx`` by name (picklable)."""

    idx: dict[str, int]
    weights: bool = False

    def __call__(self, x: np.ndarray) -> Scene:
        """Drawing primitives at the full variable vector ``x`` (m, rad, N)."""
        v = {name: float(x[i]) for name, i in self.idx.items()}
        e1 = np.array([np.cos(v["theta1"]), np.sin(v["theta1"])])
        e2 = np.array([np.cos(v["theta2"]), np.sin(v["theta2"])])
        c1 = np.array([v["x1"], v["y1"]])
        c2 = np.array([v["x2"], v["y2"]])
        ground_end, apex1 = c1 - v["L1"] / 2 * e1, c1 + v["L1"] / 2 * e1
        slider_end, apex2 = c2 - v["L2"] / 2 * e2, c2 + v["L2"] / 2 * e2
        forces = [("F", apex1, np.array([0.0, v["F"]]))]
        if self.weights:
            forces += [("w1", c1, np.array([0.0, -v["m1"] * v["g"]])),
                       ("w2", c2, np.array([0.0, -v["m2"] * v["g"]]))]
        return Scene(
            bars=[("bar 1", np.array([ground_end, apex1])), ("bar 2", np.array([slider_end, apex2]))],
            pins=[apex1],
            grounds=[np.zeros(2)],
            sliders=[(slider_end, np.array([1.0, 0.0]))],
            springs=[("spring", c1 + v["m"] * e1, c2 + v["n"] * e2)],
            forces=forces,
        )
