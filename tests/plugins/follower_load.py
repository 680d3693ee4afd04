"""A follower load as one module: ``[loads.NAME] type = "test_follower"`` (an extension written in a test only).

A force of magnitude ``magnitude`` (N) at the body point ``at`` along ``direction``, a vector fixed
in that body (it turns with the body: a follower force, not conservative), written once for both
spaces against the kinematics protocol: virtual work ``f . dP/dq`` with ``f = F kin.turn(at, d)``.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, ClassVar

import sympy as sp

from mechcont.mechanism._plugin import Kinematics
from mechcont.mechanism.loads import Load, Loads


@dataclass(frozen=True)
class FollowerForce(Load[Kinematics]):
    """Magnitude ``magnitude`` (N) at ``at`` along the body vector ``direction`` (normalised)."""

    name: str
    at: str
    magnitude: Any
    direction: Any

    kind: ClassVar[str] = "test_follower"
    SPACES: ClassVar[tuple[str, ...]] = ("plane", "space")
    KEYS: ClassVar[frozenset[str]] = frozenset({"at", "magnitude", "direction"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("at", "magnitude", "direction")
    VECTORS: ClassVar[tuple[str, ...]] = ("direction",)

    def check(self, mech: Any) -> None:
        """``at`` must be a point of the mechanism."""
        mech.point_ref(self.at, self.field("at"))

    def values(self, mech: Any) -> Iterator[tuple[str, Any]]:
        """Its magnitude and the direction's components."""
        yield self.field("magnitude"), self.magnitude
        yield from mech.vector_values(self.field("direction"), list(self.direction))

    def vectors(self) -> list[str]:
        """The direction must not be zero."""
        return [self.field("direction")]

    def apply(self, kin: Kinematics, out: Loads) -> None:
        """Virtual work of ``F A(at) d / |d|`` at ``at``; drawn at its point."""
        mech = kin.mech
        d = sp.Matrix([mech.value(self.field(f"direction.{c}")) for c in mech.AXES])
        force = mech.value(self.field("magnitude")) * kin.turn(self.at, d / sp.sqrt(d.dot(d)))
        P = kin.point(self.at)
        out.add(kin.force_work(P, force))
        out.arrow(self.name, P, force)
