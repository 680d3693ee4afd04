"""Loads: one module per load type (see :mod:`._base` for the protocol), and gravity.

Every public module of this package is imported here, so a load class defined in a new module
registers its ``type`` in :data:`LOAD_TYPES` without any other file changing. The original
loads come first (the order of the types listed in error messages).
"""

from __future__ import annotations

import importlib
import pkgutil

from ._base import LOAD_TYPES, Load, Loads, load_keys
from .custom import CustomLoad, SpatialCustomLoad
from .drag import DRAG_SMOOTHING, Drag, SpatialDrag
from .force import PointForce
from .gravity import Gravity, SpatialGravity
from .moment import Moment, SpatialMoment

__all__ = ["LOAD_TYPES", "Load", "Loads", "load_keys", "PointForce", "Moment", "SpatialMoment", "Drag", "SpatialDrag",
           "CustomLoad", "SpatialCustomLoad", "Gravity", "SpatialGravity", "DRAG_SMOOTHING"]

for _info in pkgutil.iter_modules(__path__):
    if not _info.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_info.name}")
for _types in LOAD_TYPES.values():  # the historical order first, then the loads added since
    _types.first(("force", "moment", "drag", "custom"))
