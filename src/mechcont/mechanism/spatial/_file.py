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
from typing import Any

from ...errors import InputError
from .._file import _entries, _only, _require, _table, _text, _typed, loads_from_table
from ..loads import SpatialGravity, load_keys
from ._description import SpatialBody, SpatialMechanism
from ._joints import JOINT_TYPES, joint_keys

__all__ = ["spatial_mechanism", "SPATIAL_KEYS", "SPATIAL_JOINTS", "SPATIAL_LOADS"]

#: ``type`` -> (class, keys) of ``[joints.NAME]`` in a spatial file.
SPATIAL_JOINTS = {kind: (cls, joint_keys(cls) - {"type"}) for kind, cls in JOINT_TYPES.items()}
#: ``type`` -> (class, keys) of ``[loads.NAME]`` in a spatial file.
SPATIAL_LOADS = load_keys("space")
#: Keys of the other spatial tables, by key path (``NAME`` stands for a user's name).
SPATIAL_KEYS: dict[str, frozenset[str]] = {
    "bodies.NAME": frozenset({"mass", "length", "inertia", "cg", "points", "initial", "description"}),
    "bodies.NAME.initial": frozenset({"x", "y", "z", "rotation"}),
    "gravity": frozenset({"g", "direction"}),
}


def _triple(v, field: str) -> tuple:
    if not isinstance(v, list) or len(v) != 3:
        raise InputError(field, f"must be a 3-vector [x, y, z], got {v!r}")
    return tuple(v)


def spatial_mechanism(data: Mapping, common: dict) -> SpatialMechanism:
    """Build a :class:`SpatialMechanism` from parsed TOML ``data`` and the shared ``common`` keywords."""
    ground = {k: _triple(v, f"ground.{k}") for k, v in _table(data, "ground", "ground").items()}
    bodies = []
    for bname, spec in _entries(data, "bodies"):
        f = f"bodies.{bname}"
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
        bodies.append(SpatialBody(bname, spec["mass"], spec.get("length"), None if inertia is None else tuple(inertia),
                                  _triple(spec.get("cg", [0, 0, 0]), f + ".cg"), points, initial,
                                  _text(spec.get("description", ""), f + ".description")))
    joints = []
    for jname, spec in _entries(data, "joints"):
        f = f"joints.{jname}"
        kind, _ = _typed(spec, f, "joints", SPATIAL_JOINTS)
        cls = SPATIAL_JOINTS[kind][0]
        _require(spec, ["a", "b"], f)
        kw: dict[str, Any] = {k: (_triple(v, f"{f}.{k}") if k in cls.VECTORS else v) for k, v in spec.items()
                              if k != "type"}
        joints.append(cls(jname, **kw))
    gravity = None
    if "gravity" in data:
        gtab = _table(data, "gravity", "gravity")
        _only(gtab, SPATIAL_KEYS["gravity"], "gravity")
        gravity = SpatialGravity(gtab.get("g", "g"), _triple(gtab.get("direction", [0, 0, -1]), "gravity.direction"))
    loads = loads_from_table(data, SPATIAL_LOADS, _triple, "space")
    return SpatialMechanism(bodies=bodies, joints=joints, ground=ground, loads=loads, gravity=gravity, **common)
