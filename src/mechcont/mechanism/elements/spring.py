"""Linear springs between two points (planar and spatial): ``[springs.NAME]``."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

from ...equations import Limit
from .._expr import Value
from .._plugin import Kinematics
from ._base import TwoPointElement

if TYPE_CHECKING:
    from .._description import Mechanism
    from ..loads import Loads

__all__ = ["Spring"]


@dataclass(frozen=True)
class Spring(TwoPointElement):
    """A linear spring between points ``a`` and ``b``: tension ``preload + k (l - free_length)``
    (N), potential ``preload*l + k/2 (l - free_length)^2`` (J). ``k`` > 0 (N/m),
    ``free_length`` > 0 (m)."""

    name: str
    a: str
    b: str
    k: Value
    free_length: Value
    preload: Value = 0

    table: ClassVar[str] = "springs"
    KEYS: ClassVar[frozenset[str]] = frozenset({"a", "b", "k", "free_length", "preload"})
    REQUIRED: ClassVar[tuple[str, ...]] = ("a", "b", "k", "free_length")
    LENGTH_KEYS: ClassVar[tuple[str, ...]] = ("free_length",)
    STIFFNESS_KEYS: ClassVar[tuple[str, ...]] = ("k",)
    DRAWN: ClassVar[str] = "spring"

    def values(self, mech: Mechanism) -> Iterator[tuple[str, Any]]:
        """Its stiffness, free length and preload."""
        yield self.field("k"), self.k
        yield self.field("free_length"), self.free_length
        yield self.field("preload"), self.preload

    def limits(self, kin: Kinematics, solve: bool) -> list[Limit]:
        """A positive free length; a positive stiffness in the file, zero allowed for an analysis
        (it disconnects the spring, as in the paper's Fig. 7, "no spring load")."""
        return [self.value_limit(kin, "k", not solve, "stiffness (N/m)"),
                self.value_limit(kin, "free_length", True, "free length (m)")]

    def apply(self, kin: Kinematics, out: Loads) -> None:
        """Potential ``preload*l + k/2 (l - free_length)^2`` (J)."""
        v = kin.mech.value
        k, l0, pre = v(self.field("k")), v(self.field("free_length")), v(self.field("preload"))
        length = kin.distance(self.a, self.b)
        out.V += pre * length + k / 2 * (length - l0) ** 2
