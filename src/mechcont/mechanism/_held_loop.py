"""Why a planar description's model cannot be assembled with some coordinates held: the loop that cannot close."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..equations import MechanicalModel, Model
from ..errors import InputError
from ._description import Mechanism
from ._diagnose import least_squares_closure, loop_error
from ._kinematics import PlanarKinematics

__all__ = ["held_loop_error"]


def held_loop_error(system: Model, x: np.ndarray, hold: Sequence[str]) -> InputError | None:
    """Why the planar description's model ``system`` cannot be assembled with the coordinates ``hold`` at
    their values in ``x`` (its variable vector, the description's units): the loop that cannot close and
    by how much at best (:func:`loop_error`). None when the loops do close near ``x`` (least squares) or
    ``system`` is no planar description's full model (its rows are not the kinematics' own)."""
    mech, model = system.mechanism, system.mechanics
    if not isinstance(mech, Mechanism) or mech.normalisation_rows() or not isinstance(model, MechanicalModel):
        return None
    rows = PlanarKinematics(mech).constraints()
    by_name = {r.equation: r for r in rows}
    if model.constraint_names is not None:  # rows named: those kept (a redundant one dropped)
        if not all(n in by_name for n in model.constraint_names):
            return None
        rows = [by_name[n] for n in model.constraint_names]
    if len(rows) != np.size(model.phi(np.asarray(x, dtype=float))):
        return None
    free = np.array([c not in hold for c in model.coordinates])
    phi = model.phi(least_squares_closure(model, np.asarray(x, dtype=float), free))
    lengths = [s for c, s in zip(model.coordinates, system.scales()[model.q_index]) if not c.startswith("theta")]
    if phi.size == 0 or np.max(np.abs(phi)) <= 1e-9 * max(lengths, default=1.0):
        return None
    names = list(system.names)
    return loop_error(mech, rows, phi, {h: f"{x[names.index(h)]:.6g}" for h in hold})
