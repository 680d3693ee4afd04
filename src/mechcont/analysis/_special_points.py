"""Registers the loads of a stop's release (``SR``; ``NSF``, a release that is the snap) and a cusp (``CP``)
with the engine's point sensitivity.

:func:`mechcont.continuation._sensitivity.point_sensitivity` differentiates folds and ordinary points;
what a release or a cusp is belongs to this layer (stops, cusp conditions). Importing
:mod:`mechcont.analysis` registers them, cheaply: the handler imports its module on first use.
"""

from __future__ import annotations

from ..continuation import SPECIAL_POINTS


def _release_or_cusp(*args):
    from .sensitivity import _switch_or_cusp

    return _switch_or_cusp(*args)


SPECIAL_POINTS.setdefault("SR", _release_or_cusp)
SPECIAL_POINTS.setdefault("CP", _release_or_cusp)
SPECIAL_POINTS.setdefault("NSF", _release_or_cusp)
