"""Spatial joints: one module per joint type (see :mod:`._base` for the protocol).

Every public module of this package is imported here, so a joint class defined in a new module
registers its ``type`` in :data:`JOINT_TYPES` without any other file changing. The original joints
come first (the order of the types listed in error messages).
"""

from __future__ import annotations

import importlib
import pkgutil

from ._base import JOINT_TYPES, SpatialJoint, SpatialRow, joint_keys, vector3
from .cylindrical import Cylindrical
from .inline import Inline
from .prismatic import Prismatic3
from .revolute import Revolute3
from .spherical import Spherical
from .universal import Universal
from .weld import Weld3

__all__ = ["JOINT_TYPES", "SpatialJoint", "SpatialRow", "joint_keys", "vector3", "Spherical", "Revolute3",
           "Universal", "Inline", "Cylindrical", "Prismatic3", "Weld3"]

for _info in pkgutil.iter_modules(__path__):
    if not _info.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_info.name}")
JOINT_TYPES.first([cls.kind for cls in (Spherical, Revolute3, Universal, Inline, Cylindrical, Prismatic3, Weld3)])
