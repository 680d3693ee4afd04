"""The load protocol: one class per load type, registered by its TOML ``type`` for the kinematics it acts in.

A load acts on a mechanism described in the plane or in space (the registry key ``space`` of
the description class: ``"plane"`` or ``"space"``). A load class gives

* ``kind``: its ``type`` in a description file, ``SPACES``: the spaces it is registered for
  (setting ``kind`` registers the class in :data:`LOAD_TYPES`, the ``"loads"`` registries of
  :mod:`.._plugin`); ``KEYS``: its table's keys
  besides ``type``; :meth:`~Load.required`: the keys a file must give; ``VECTORS``: the keys
  given as vectors; ``COORDINATE_KEYS``: the keys whose expressions may use the coordinates;
  ``FORCE_KEY``: the key of a force magnitude (N) that sets the mechanism's typical force;
* :meth:`~Load.check`: its references, with one-line errors naming the key;
  :meth:`~Load.values`: every number or expression of it (key path, raw value);
* :meth:`~Load.limits`, :meth:`~Load.vectors`, :meth:`~Load.check_values`,
  :meth:`~Load.static_error`: the physical ranges of its values;
* :meth:`~Load.apply`: its potential or generalised forces and its arrows, written against a
  kinematics object (``kin.point``, ``kin.direction``, ``kin.force_work``, ...), added to a
  :class:`Loads`; :meth:`~Load.draw`: any other drawing primitive.

The class is a :class:`~.._plugin.PlugIn` of the family ``"loads"``: a load of both spaces is a
``Load[Kinematics]`` (written against the protocol), a load of one space a
``Load[PlanarKinematics]`` or ``Load[SpatialKinematics]``.

Adding a load type is adding one module to this package with one such class.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, TypeVar

import sympy as sp

from ...errors import InputError
from .._plugin import SPACES, Draw, Kinematics, PlugIn, Registry, registry

if TYPE_CHECKING:
    from .._description import Mechanism

__all__ = ["Load", "Loads", "LOAD_TYPES", "load_keys", "Draw"]

#: space (``"plane"``, ``"space"``) -> TOML ``type`` -> load class, in registration order.
LOAD_TYPES: dict[str, Registry] = {space: registry("loads", space) for space in SPACES}
K = TypeVar("K", bound=Kinematics)


@dataclass
class Loads:
    """Potential ``V`` (J), non-conservative generalised forces ``Q_nc`` (per coordinate) and
    the vectors to draw ``(kind, name, point expr, vector expr)`` (kind ``force`` or ``moment``)."""

    V: sp.Expr
    Q_nc: list[sp.Expr]
    arrows: list[tuple[str, str, sp.Matrix, sp.Matrix]]

    def add(self, Q: list) -> None:
        """Add the generalised forces ``Q`` (one per coordinate) to ``Q_nc``."""
        self.Q_nc = [a + b for a, b in zip(self.Q_nc, Q)]

    def arrow(self, name: str, at: sp.Matrix, vector: sp.Matrix, kind: str = "force") -> None:
        """Draw ``vector`` (N, or N m for a ``moment``) at the point ``at``."""
        self.arrows.append((kind, name, at, vector))


class Load(PlugIn[K]):
    """Base of the loads (see the module docstring for the protocol).

    Subclasses are frozen dataclasses whose first field is ``name``."""

    name: str
    FAMILY: ClassVar[str] = "loads"
    kind: ClassVar[str] = ""
    SPACES: ClassVar[tuple[str, ...]] = ("plane",)
    VECTORS: ClassVar[tuple[str, ...]] = ()
    COORDINATE_KEYS: ClassVar[tuple[str, ...]] = ()
    FORCE_KEY: ClassVar[str | None] = None

    @classmethod
    def required(cls, space: str) -> tuple[str, ...]:
        """The keys a ``[loads.NAME]`` table must give in a description of ``space``."""
        return cls.REQUIRED

    @classmethod
    def from_table(cls, name: str, spec: Mapping, field: str, vector: Callable[[Any, str], Any],
                   space: str) -> Load:
        """The load of a ``[loads.NAME]`` table ``spec`` (keys besides ``type``, already checked against
        ``KEYS``); ``vector(value, field)`` reads a vector of the description's space."""
        for k in cls.required(space):
            if k not in spec:
                raise InputError(f"{field}.{k}", "is required")
        kw = {k: (vector(v, f"{field}.{k}") if k in cls.VECTORS else v) for k, v in spec.items()}
        return cls(name, **kw)  # type: ignore[call-arg]

    def vectors(self) -> list[str]:
        """Key paths of the load's vectors that must not be zero (components ``.x``, ``.y`` (, ``.z``))."""
        return []

    def static_error(self) -> bool:
        """Whether the load has a defect that does not depend on the values (checked at a build)."""
        return False

    def apply(self, kin: K, out: Loads) -> None:
        """Add the load's potential, generalised forces and arrows in the coordinates of ``kin`` to ``out``."""
        raise NotImplementedError


def check_at_point(load: Load[Any], at: str, mech: Mechanism) -> None:
    """A load applied at the body point ``at`` (key ``at``)."""
    mech.point_ref(at, load.field("at"))
    if at.startswith("ground."):
        raise InputError(load.field("at"), "a load on the ground does nothing; apply it to a body point")


def check_on_body(load: Load[Any], body: str, mech: Mechanism, points: tuple[str, ...] = ()) -> None:
    """A load applied to ``body`` (key ``body``), naming the points ``points`` (keys) of it."""
    if body not in mech.body_map:
        raise InputError(load.field("body"), f"unknown body '{body}'; bodies: {', '.join(mech.body_map)}")
    for key in points:
        mech.point_ref(f"{body}.{getattr(load, key)}", load.field(key))


def load_keys(space: str) -> dict[str, tuple[type[Load[Any]], frozenset[str]]]:
    """``type`` -> (load class, the keys of its table besides ``type``), every load registered for ``space``."""
    return LOAD_TYPES[space].keyed()
