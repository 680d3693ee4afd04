"""The load protocol: one class per load type, registered by its TOML ``type`` for the kinematics it acts in.

A load acts on a mechanism described in the plane or in space (the registry key ``space`` of
the description class: ``"plane"`` or ``"space"``). A load class gives

* ``kind``: its ``type`` in a description file, ``SPACES``: the spaces it is registered for
  (setting ``kind`` registers the class in :data:`LOAD_TYPES`); ``KEYS``: its table's keys
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

Adding a load type is adding one module to this package with one such class.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from ...errors import InputError

if TYPE_CHECKING:
    from .._description import Mechanism

__all__ = ["Load", "Loads", "LOAD_TYPES", "load_keys"]

#: space (``"plane"``, ``"space"``) -> TOML ``type`` -> load class, in registration order.
LOAD_TYPES: dict[str, dict[str, type[Load]]] = {"plane": {}, "space": {}}
#: ``add(kind, name, points)``: one drawing primitive (see the scene functions).
Draw = Callable[[str, str, list[sp.Matrix]], None]


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


class Load:
    """Base of the loads (see the module docstring for the protocol).

    Subclasses are frozen dataclasses whose first field is ``name``."""

    name: str
    kind: ClassVar[str] = ""
    SPACES: ClassVar[tuple[str, ...]] = ("plane",)
    KEYS: ClassVar[frozenset[str]] = frozenset()
    REQUIRED: ClassVar[tuple[str, ...]] = ()
    VECTORS: ClassVar[tuple[str, ...]] = ()
    COORDINATE_KEYS: ClassVar[tuple[str, ...]] = ()
    FORCE_KEY: ClassVar[str | None] = None

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        kind = cls.__dict__.get("kind")
        if kind:
            for space in cls.SPACES:
                known = LOAD_TYPES[space].get(kind)
                if known is not None and known.__qualname__ != cls.__qualname__:
                    raise TypeError(f"load type {kind!r} registered twice in {space} ({known.__name__}, {cls.__name__})")
                LOAD_TYPES[space][kind] = cls

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

    def field(self, key: str = "") -> str:
        """The key path of this load (or of its ``key``)."""
        return f"loads.{self.name}" + (f".{key}" if key else "")

    def check(self, mech: Mechanism) -> None:
        """Check the references against ``mech`` (a one-line InputError naming the key)."""

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Every (key path, raw value) of the load that is a number or an expression."""
        return iter(())

    def limits(self) -> list[tuple[str, bool, str]]:
        """``(key path, strict, what)``: values that must be positive (strict) or non-negative."""
        return []

    def vectors(self) -> list[str]:
        """Key paths of the load's vectors that must not be zero (components ``.x``, ``.y`` (, ``.z``))."""
        return []

    def static_error(self) -> bool:
        """Whether the load has a defect that does not depend on the values (checked at a build)."""
        return False

    def check_values(self, mech: Mechanism, values: Mapping[str, float]) -> None:
        """Reject values impossible for this load at the parameter ``values`` (one-line InputError)."""

    def apply(self, kin, out: Loads) -> None:
        """Add the load's potential, generalised forces and arrows in the coordinates of ``kin`` to ``out``."""
        raise NotImplementedError

    def draw(self, kin, add: Draw, pinned: Mapping[str, str]) -> None:
        """Add drawing primitives besides its arrows (``pinned``: body -> its point pinned to the ground)."""


def check_at_point(load: Load, at: str, mech: Mechanism) -> None:
    """A load applied at the body point ``at`` (key ``at``)."""
    mech.point_ref(at, load.field("at"))
    if at.startswith("ground."):
        raise InputError(load.field("at"), "a load on the ground does nothing; apply it to a body point")


def check_on_body(load: Load, body: str, mech: Mechanism, points: tuple[str, ...] = ()) -> None:
    """A load applied to ``body`` (key ``body``), naming the points ``points`` (keys) of it."""
    if body not in mech.body_map:
        raise InputError(load.field("body"), f"unknown body '{body}'; bodies: {', '.join(mech.body_map)}")
    for key in points:
        mech.point_ref(f"{body}.{getattr(load, key)}", load.field(key))


def load_keys(space: str) -> dict[str, tuple[type[Load], frozenset[str]]]:
    """``type`` -> (load class, the keys of its table besides ``type``), every load registered for ``space``."""
    return {kind: (cls, cls.KEYS) for kind, cls in LOAD_TYPES[space].items()}
