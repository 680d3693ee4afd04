"""Registers the loads of a stop's release (``SR``; ``NSF``, a release that is the snap) and a cusp (``CP``)
with the engine's point sensitivity.

:func:`mechcont.continuation._sensitivity.point_sensitivity` differentiates folds and ordinary points;
what a release or a cusp is belongs to this layer (stops, cusp conditions). Importing
:mod:`mechcont.analysis` registers them, cheaply: the handler imports its module on first use.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..continuation import SPECIAL_POINTS

if TYPE_CHECKING:
    from ..continuation import Sensitivity
    from ..equations import Model


def _release_or_cusp(system: Model, x: np.ndarray, params: Iterable[str], vary: str, label: str, info: dict[str, Any],
                     unknowns: Sequence[str] | None, values: Mapping[str, float] | None) -> Sensitivity:
    from .sensitivity import _switch_or_cusp

    return _switch_or_cusp(system, x, params, vary, label, info, unknowns, values)


SPECIAL_POINTS.setdefault("SR", _release_or_cusp)
SPECIAL_POINTS.setdefault("CP", _release_or_cusp)
SPECIAL_POINTS.setdefault("NSF", _release_or_cusp)
