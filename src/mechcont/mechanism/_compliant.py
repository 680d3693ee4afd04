"""The compliant constraint rows of a generated model (``Phi - lambda / k = 0``): which rows, which
reactions, which compliances; for ``check``'s report and the dynamics' assembly."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

    from ..equations import Model

__all__ = ["compliant_constraints"]


def compliant_constraints(system: Model, x: np.ndarray) -> list[tuple[int, str, float]]:
    """``(row, reaction, c)`` of each compliant constraint row ``Phi - lambda / k = 0``, found from the
    Jacobian (its own reaction enters with ``c = -1/k``); ``row`` indexes the system's equations."""
    reactions = list(system.reaction_names)
    if not reactions or system.mechanics is None:  # no reactions, or no coordinates to count the rows by
        return []
    nq = len(system.mechanics.coordinates)
    J = system.jacobian(x)
    # a dropped row's equation (spatial: ``<row>_dropped``) holds its reaction at zero: no spring
    dropped = {f"{d}_dropped" for d in system.dropped_constraints}
    return [(nq + i, r, float(J[nq + i, system.index(r)])) for i, r in enumerate(reactions)
            if J[nq + i, system.index(r)] != 0 and system.equation_names[nq + i] not in dropped]
