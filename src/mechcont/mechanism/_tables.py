"""The tables of a description file as read by both spaces: checked tables, keys and plug-in types, and the
:class:`Reader` of the tables that differ in the plane and in space."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..errors import InputError
from ._plugin import Registry, registry

if TYPE_CHECKING:
    from ._description import Mechanism
    from .loads import Load

__all__ = ["Reader", "loads_from_table"]


def _table(data: Mapping[str, Any], key: str, field: str) -> Mapping[str, Any]:
    v = data.get(key, {})
    if not isinstance(v, Mapping):
        raise InputError(field, f"must be a table ([{field}]), got {type(v).__name__}")
    return v


def _only(tab: Mapping[str, Any], allowed: set[str] | frozenset[str], field: str) -> None:
    for k in tab:
        if k not in allowed:
            raise InputError(f"{field}.{k}" if field else k, f"unknown key; valid keys: {', '.join(sorted(allowed))}")


def _entries(data: Mapping[str, Any], section: str) -> list[tuple[str, Mapping[str, Any]]]:
    """The ``[section.NAME]`` entries of ``section``, each checked to be a table."""
    out = []
    for name, spec in _table(data, section, section).items():
        if not isinstance(spec, Mapping):
            raise InputError(f"{section}.{name}", f"must be a table [{section}.{name}] of keys, "
                                                  f"got {type(spec).__name__} {_short(spec)}")
        out.append((name, spec))
    return out


def _short(v: object) -> str:
    text = repr(v)
    return text if len(text) <= 40 else text[:37] + "..."


def _typed(spec: object, field: str, table: str, plugins: Registry) -> Any:
    """The class of a ``[table.NAME]`` entry with a ``type`` from the registry ``plugins``, its keys checked."""
    if not isinstance(spec, Mapping):
        raise InputError(field, f"must be a table [{table}.NAME]")
    if "type" not in spec:
        others = f" (the table has {', '.join(spec)})" if spec else ""
        raise InputError(field + ".type", f"missing: give type = one of {', '.join(plugins)}{others}")
    kind = spec["type"]
    if not isinstance(kind, str) or kind not in plugins:
        raise InputError(field + ".type", f"must be one of {', '.join(plugins)}, got {kind!r}")
    cls = plugins[kind]
    _only(spec, cls.table_keys() | {"type"}, field)
    return cls


def _require(tab: Mapping[str, Any], keys: list[str], field: str) -> None:
    for k in keys:
        if k not in tab:
            raise InputError(f"{field}.{k}", "is required")


def _text(v: object, field: str) -> str:
    if not isinstance(v, str):
        raise InputError(field, f"must be a string, got {v!r}")
    return v


def loads_from_table(data: Mapping[str, Any], vector: Callable[[Any, str], Any], space: str) -> list[Load[Any]]:
    """The ``[loads.NAME]`` tables, each read by the class its ``type`` names in the loads registered
    for ``space`` (``vector(value, field)`` reads a vector of that space)."""
    out = []
    for lname, spec in _entries(data, "loads"):
        f = f"loads.{lname}"
        cls = _typed(spec, f, "loads", registry("loads", space))
        out.append(cls.from_table(lname, {k: v for k, v in spec.items() if k != "type"}, f, vector, space))
    return out


@dataclass(frozen=True)
class Reader:
    """How the tables that differ in the plane and in space are read: the description class and
    its ``space`` (the key of the joint and load registries, :func:`._plugin.registry`), a vector
    (``vector(value, field)``), a load's direction, a body (``body(name, spec, field)``) and gravity
    (``gravity(table)``)."""

    mechanism: type[Mechanism[Any, Any]]
    vector: Callable[[Any, str], Any]
    direction: Callable[[Any, str], Any]
    body: Callable[[str, Mapping[str, Any], str], Any]
    gravity: Callable[[Mapping[str, Any]], Any]

    def read(self, data: Mapping[str, Any], common: dict[str, Any]) -> Mechanism[Any, Any]:
        """The mechanism of the parsed TOML ``data`` with the ``common`` keywords (:func:`_common`)."""
        ground = {k: self.vector(v, f"ground.{k}") for k, v in _table(data, "ground", "ground").items()}
        bodies = [self.body(name, spec, f"bodies.{name}") for name, spec in _entries(data, "bodies")]
        space = self.mechanism.space
        joints = []
        for jname, spec in _entries(data, "joints"):
            f = f"joints.{jname}"
            cls = _typed(spec, f, "joints", registry("joints", space))
            joints.append(cls.from_table(jname, {k: v for k, v in spec.items() if k != "type"}, f))
        gravity = self.gravity(_table(data, "gravity", "gravity")) if "gravity" in data else None
        loads = loads_from_table(data, self.direction, space)
        return self.mechanism(bodies=bodies, joints=joints, ground=ground, loads=loads, gravity=gravity, **common)
