"""The spatial part of a description file (``[mechanism] dimension = 3``).

Layout (besides the tables planar and spatial files share: ``[parameters]``, ``[springs]``,
``[dampers]``, ``[actuators]``, ``[conditions]``, ``[stops]``, ``[assembly]``; every number may be an
expression string in the parameter names)::

    [ground]            NAME = [x, y, z]
    [bodies.NAME]       mass, length (bar along the body's x axis), inertia = [Ixx, Iyy, Izz]
                        or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz], cg = [x, y, z], description,
                        points = {P = [x, y, z]}, initial = {x, y, z, rotation = [rx, ry, rz]}
    [joints.NAME]       type = "spherical" | "revolute" | "universal" | "inline" | "cylindrical"
                        | "prismatic" | "weld", a, b, axis = [x, y, z] (revolute, inline, cylindrical, prismatic),
                        axis_a, axis_b (universal), stiffness (N/m), rotational_stiffness (N m/rad)
    [gravity]           g, direction = [x, y, z] (default [0, 0, -1])
    [loads.NAME]        type = "force": at, magnitude, direction = [x, y, z]
                        type = "moment": body, magnitude, axis = [x, y, z]
                        type = "drag": body, rho, U, direction = [x, y, z], d, CD, start, end
                        type = "custom": at, fx, fy, fz, mx, my, mz (may use coordinates)

See :mod:`._description` for the conventions (design pose, coordinates).
"""

from __future__ import annotations

from collections.abc import Mapping

from ...errors import InputError
from .._tables import Reader, _only, _require, _table, _text
from ..loads import SpatialGravity
from ._description import SpatialBody, SpatialMechanism
from .joints import vector3 as _triple

__all__ = ["READER", "SPATIAL_KEYS"]

#: Keys of the other spatial tables, by key path (``NAME`` stands for a user's name).
SPATIAL_KEYS: dict[str, frozenset[str]] = {
    "bodies.NAME": frozenset({"mass", "length", "inertia", "cg", "points", "initial", "description"}),
    "bodies.NAME.initial": frozenset({"x", "y", "z", "rotation"}),
    "gravity": frozenset({"g", "direction"}),
}


def _body(name: str, spec: Mapping, f: str) -> SpatialBody:
    """A spatial ``[bodies.NAME]`` table."""
    _only(spec, SPATIAL_KEYS["bodies.NAME"], f)
    _require(spec, ["mass"], f)
    points = {pn: _triple(ps, f"{f}.points.{pn}") for pn, ps in _table(spec, "points", f + ".points").items()}
    initial = dict(_table(spec, "initial", f + ".initial"))
    _only(initial, SPATIAL_KEYS["bodies.NAME.initial"], f + ".initial")
    if "rotation" in initial:
        initial["rotation"] = _triple(initial["rotation"], f + ".initial.rotation")
    inertia = spec.get("inertia")
    if inertia is not None and (not isinstance(inertia, list) or len(inertia) not in (3, 6)):
        raise InputError(f + ".inertia", f"is [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (kg m^2), "
                                         f"got {inertia!r}")
    return SpatialBody(name, spec["mass"], spec.get("length"), None if inertia is None else tuple(inertia),
                       _triple(spec.get("cg", [0, 0, 0]), f + ".cg"), points, initial,
                       _text(spec.get("description", ""), f + ".description"))


def _gravity(table: Mapping) -> SpatialGravity:
    """The spatial ``[gravity]`` table."""
    _only(table, SPATIAL_KEYS["gravity"], "gravity")
    return SpatialGravity(table.get("g", "g"), _triple(table.get("direction", [0, 0, -1]), "gravity.direction"))


#: How the spatial tables are read (see :class:`~.._file.Reader`).
READER = Reader(SpatialMechanism, _triple, _triple, _body, _gravity)
