"""Planar joints: one module per joint type (see :mod:`._base` for the protocol).

Every public module of this package is imported here, so a joint class defined in a new
module registers its ``type`` in :data:`JOINT_TYPES` without any other file changing. The
four original joints come first (the order of the types listed in error messages).
"""

from __future__ import annotations

import importlib
import pkgutil

from ._base import JOINT_TYPES, ConstraintRow, PlanarJoint
from .prismatic import Prismatic
from .revolute import Revolute
from .slider import Slider
from .weld import Weld

__all__ = ["JOINT_TYPES", "ConstraintRow", "PlanarJoint", "Revolute", "Slider", "Prismatic", "Weld", "joint_keys"]

for _info in pkgutil.iter_modules(__path__):
    if not _info.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_info.name}")
# the historical order first, then the joints added since (alphabetically by module)
JOINT_TYPES.first([cls.kind for cls in (Revolute, Slider, Prismatic, Weld)])


def joint_keys() -> dict[str, tuple[type[PlanarJoint], frozenset[str]]]:
    """``type`` -> (joint class, the keys of its table besides ``type``), every registered joint."""
    return JOINT_TYPES.keyed()
