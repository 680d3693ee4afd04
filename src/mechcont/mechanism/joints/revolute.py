"""The revolute joint (a pin): point ``a`` coincides with point ``b``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from ._base import ConstraintRow, Draw, PlanarJoint, point_rows

if TYPE_CHECKING:
    from .._kinematics import PlanarKinematics

__all__ = ["Revolute"]


@dataclass(frozen=True)
class Revolute(PlanarJoint):
    """A pin: point ``a`` coincides with point ``b``. Reactions ``R_<name>_x, R_<name>_y``:
    the force (N) that the body of ``a`` exerts on the body of ``b``."""

    name: str
    a: str
    b: str
    kind: ClassVar[str] = "revolute"
    COINCIDENT: ClassVar[bool] = True

    def rows(self, kin: PlanarKinematics) -> list[ConstraintRow]:
        return point_rows(self, kin)

    def draw(self, kin: PlanarKinematics, add: Draw) -> None:
        add("ground" if self.grounded() else "pin", self.name, [kin.point(self.b)])
