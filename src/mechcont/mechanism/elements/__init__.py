"""Force elements: one module per table (``[springs.NAME]``, ``[dampers.NAME]``, ``[actuators.NAME]``,
``[stops.NAME]``);
see :mod:`._base` for the protocol.

Every public module of this package is imported here, so an element class defined in a new module
registers its table in :data:`ELEMENT_TYPES` without any other file changing.
"""

from __future__ import annotations

import importlib
import pkgutil

from ._base import ELEMENT_TYPES, Element, TwoPointElement, element_rows
from .actuator import Actuator
from .damper import Damper, damper_tension
from .spring import Spring
from .stop import Stop

__all__ = ["ELEMENT_TYPES", "Element", "TwoPointElement", "element_rows", "Spring", "Damper", "Actuator",
           "Stop", "damper_tension"]

for _info in pkgutil.iter_modules(__path__):
    if not _info.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_info.name}")
