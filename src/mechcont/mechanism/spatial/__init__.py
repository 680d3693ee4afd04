"""Spatial (3-D) mechanisms: describe bodies, joints and loads in space; equations generated.

A description file with ``[mechanism] dimension = 3`` (see ``docs/spatial-format.md``) or a
:class:`SpatialMechanism` built from objects gives, through ``.build(**overrides)``, the same
kind of :class:`~mechcont.equations.EquationSystem` as a planar description: coordinates
(frame origin and Euler parameters per body), joint reactions as named unknowns, exact
Jacobians, the mechanics for stability and time simulation, a 3-D drawing scene. Redundant
(over-constrained) closures are reported with their joints, and made determinate by a joint
``stiffness`` (see :mod:`.joints`).
"""

from ._description import (
    SpatialBody,
    SpatialCustomLoad,
    SpatialGravity,
    SpatialMechanism,
    SpatialMoment,
    spatial_coordinate_names,
)
from .joints import (
    JOINT_TYPES,
    Cylindrical,
    Inline,
    Prismatic3,
    Revolute3,
    SpatialJoint,
    Spherical,
    Universal,
    Weld3,
)

__all__ = ["SpatialMechanism", "SpatialBody", "SpatialGravity", "SpatialMoment", "SpatialCustomLoad",
           "SpatialJoint", "Spherical", "Revolute3", "Universal", "Inline", "Cylindrical", "Prismatic3", "Weld3",
           "JOINT_TYPES", "spatial_coordinate_names"]
