"""A force of fixed global direction at a point (planar and spatial): ``type = "force"``."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

from .._expr import Value
from .._plugin import Kinematics
from ._base import Load, Loads, check_at_point

if TYPE_CHECKING:
    from .._description import Mechanism

__all__ = ["PointForce"]


@dataclass(frozen=True)
class PointForce(Load[Kinematics]):
    """A force of fixed global direction at a point: ``magnitude * direction/|direction|`` (N).

    ``direction`` is a 2-vector or an angle (rad) in the plane, a 3-vector in space (required
    there). ``magnitude`` is typically a parameter name (``"F"``) so that the continuation can
    free it as an unknown. Conservative: it enters the potential as ``-F u . P``.
    """

    name: str
    at: str
    magnitude: Value
    direction: tuple[Value, ...] | Value = (0, 1)

    kind: ClassVar[str] = "force"
    SPACES: ClassVar[tuple[str, ...]] = ("plane", "space")
    KEYS: ClassVar[frozenset[str]] = frozenset({"at", "magnitude", "direction"})
    VECTORS: ClassVar[tuple[str, ...]] = ("direction",)
    FORCE_KEY: ClassVar[str | None] = "magnitude"
    #: In space an in-plane default direction means nothing: the file must give one.
    _REQUIRED: ClassVar[dict[str, tuple[str, ...]]] = {"plane": ("at", "magnitude"),
                                                       "space": ("at", "magnitude", "direction")}

    @classmethod
    def required(cls, space: str) -> tuple[str, ...]:
        """``at`` and ``magnitude``; in space also ``direction``."""
        return cls._REQUIRED[space]

    def check(self, mech: Mechanism) -> None:
        """Its point must be a body point."""
        check_at_point(self, self.at, mech)

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its magnitude and direction (components, or an angle in the plane)."""
        yield self.field("magnitude"), self.magnitude
        yield from mech.direction_values(self.field("direction"), self.direction)

    def vectors(self) -> list[str]:
        """A direction given as a vector must not be zero."""
        return [self.field("direction")] if isinstance(self.direction, (tuple, list)) else []

    def apply(self, kin: Kinematics, out: Loads) -> None:
        """Potential ``-F u . P``; drawn as its force vector at its point."""
        F = kin.mech.value(self.field("magnitude"))
        u = kin.direction(self.field("direction"), self.direction)
        P = kin.point(self.at)
        out.V -= F * u.dot(P)
        out.arrow(self.name, P, F * u)
