"""Mechanism description files (TOML), validated, with errors that give line and key.

Layout (every number may be an expression string in the parameter names)::

    [mechanism]            name, description, dof (intended degrees of freedom, default 1),
                           redundant = "error" (default) | "drop" (over-constrained mechanisms)
    [parameters]           NAME = value  or  NAME = {value, unit, description, scale}
    [ground]               NAME = [x, y]
    [bodies.NAME]          mass, length (bar), inertia, cg = [x, y], description,
                           points = {P = [x, y] or {r, angle}}, initial = {x, y, theta}
    [joints.NAME]          type = "revolute" | "slider" | "prismatic" | "weld", a, b,
                           angle (slider line / weld offset), relative_angle (prismatic);
                           type = "pin_in_slot": pin, slot = [start, end] (see .joints)
    [springs.NAME]         a, b, k, free_length, preload
    [dampers.NAME]         a, b, c, c2 (tension c v + c2 v|v|, v = dl/dt)
    [gravity]              g, angle (default -pi/2)
    [loads.NAME]           type = "force": at, magnitude, direction ([x, y] or angle)
                           type = "moment": body, magnitude
                           type = "drag": body, rho, U, alpha, d, CD, start, end
                           type = "custom": at, fx, fy, moment (may use coordinates)
    [assembly]             hold = {COORDINATE = value}
    [actuators.NAME]       a, b, and either force (tension N, + pulls a and b together: a number
                           or an expression in the parameters) or length (m; a constraint whose
                           reaction T_NAME is the tension), description
    [conditions]           NAME = "expression in coordinates and parameters"  or
                           NAME = {type = "expression", expr, unit, target, description}
                                | {type = "collinear", points = [P1, P2, P3], target, description}
                                | {type = "distance", points = [P, Q], target, description}
                                | {type = "angle", bodies = [b1, b2], target, description}
                           (each adds the state NAME and the row cond_NAME: c(q, p) - NAME = 0;
                           see mechcont.mechanism._conditions for the sign conventions)
    [stops.NAME]           condition, min = LIMIT or max = LIMIT, description, restitution, contact
                           ("rigid" or "compliant" with stiffness, damping): a one-sided limit
                           of the condition; its contact reaction is the parameter R_NAME (>= 0,
                           default 0), see mechcont.mechanism._stops
    [mechanism] downlock = {condition = NAME, force = PARAMETER}: the condition held (at its
                           target) and the force solved for by ``mechcont downlock``/``design``

Point references are ``"<body>.<point>"`` or ``"ground.<point>"``.
"""

from __future__ import annotations

import re
import sys
import tomllib
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from ..errors import InputError, one_line
from ..units import LENGTH_UNITS, MASS_UNITS, UnitSystem
from ._bodies import PointSpec
from ._conditions import conditions_from_table, downlock_from_table
from ._description import Body, Gravity, Mechanism, Parameter, Polar
from ._locate import key_at, locate_error
from ._paths import MAX_TEXT, builtin_descriptions, find_description, read_description_bytes
from ._tables import Reader, _entries, _only, _require, _short, _table, _text
from .elements import ELEMENT_TYPES, Element

__all__ = ["load_description", "parse_description", "read_toml", "description_from_data",
           "builtin_descriptions", "find_description"]


#: The top-level tables besides those of the force elements (:data:`~.elements.ELEMENT_TYPES`, read
#: at parse time: an element kind registered later is read too).
_OTHER_SECTIONS = {"mechanism", "parameters", "ground", "bodies", "joints", "gravity", "loads", "assembly", "conditions"}
#: The top-level tables of a description with the element kinds shipped with mechcont.
_SECTIONS = _OTHER_SECTIONS | set(ELEMENT_TYPES)
#: The keys accepted in each table other than ``[joints.NAME]``, ``[loads.NAME]``, ``[conditions.NAME]``
#: (whose keys, per ``type``, are their classes', in the registries of :mod:`._plugin`), by key path;
#: ``NAME`` stands for a user's name (the force elements' keys are those of their classes).
#: The parser checks against these sets and docs/mechanism-format.md is tested against them.
KEYS: dict[str, frozenset[str]] = {
    "mechanism": frozenset({"name", "description", "dimension", "dof", "redundant", "downlock", "units"}),
    "mechanism.downlock": frozenset({"condition", "force"}),
    "mechanism.units": frozenset({"length", "mass"}),
    "parameters.NAME": frozenset({"value", "unit", "description", "scale"}),
    "bodies.NAME": frozenset({"mass", "length", "inertia", "cg", "points", "initial", "description"}),
    "bodies.NAME.points.NAME": frozenset({"r", "angle"}),
    "gravity": frozenset({"g", "angle"}),
    "assembly": frozenset({"hold"}),
    **{f"{table}.NAME": cls.KEYS for table, cls in ELEMENT_TYPES.items()},
}


def load_description(name_or_path: str | Path) -> Mechanism[Any, Any]:
    """Read and validate a mechanism description file (or a shipped one by stem).

    Returns a :class:`Mechanism`; call ``.build(**overrides)`` for its equations.
    Raises :class:`InputError` (``file:line: key: what is wrong``) for a missing file,
    malformed TOML, unknown keys, wrong types and unknown references.
    """
    text, path = read_text(name_or_path)
    return parse_description(text, path.name)


def read_text(name_or_path: str | Path) -> tuple[str, Path]:
    """The text of a description file (or of a shipped one by stem) and its path. Raises :class:`InputError`
    for a missing file, one over the size limit or one that is not UTF-8."""
    path = find_description(name_or_path)
    if path is None:
        valid = ", ".join(builtin_descriptions())
        raise InputError(str(name_or_path), f"no such description file (.toml) or shipped description ({valid})")
    try:
        return read_description_bytes(path).decode("utf-8"), path
    except UnicodeDecodeError as exc:
        raise InputError(str(path), f"cannot read the file ({exc.__class__.__name__})") from None


#: Most entries of one table (``[parameters]``, ``[bodies]``, a body's points, ...), and of ``[parameters]``.
MAX_ENTRIES, MAX_PARAMETERS = 500, 2000
#: Longest array (a vector, a condition's points, a slot).
MAX_ARRAY = 100


def _check_sizes(v: object, field: str) -> None:
    """InputError naming the first table or array of the parsed ``v`` beyond its limit (decided before any
    work: a description of 100,000 parameters or points would take minutes to build)."""
    if isinstance(v, Mapping):
        limit = MAX_PARAMETERS if field == "parameters" else MAX_ENTRIES
        if len(v) > limit:
            raise InputError(field or "description", f"has {len(v)} entries; a description takes at most {limit} "
                                                     "in one table")
        for k, x in v.items():
            _check_sizes(x, f"{field}.{k}" if field else str(k))
    elif isinstance(v, list):
        if len(v) > MAX_ARRAY:
            raise InputError(field, f"is an array of {len(v)} values; at most {MAX_ARRAY} are allowed")
        for x in v:
            _check_sizes(x, field)


def parse_description(text: str, filename: str = "<string>") -> Mechanism[Any, Any]:
    """Parse description ``text`` (TOML); ``filename`` is used in error messages. Sizes are checked first:
    at most :data:`MAX_TEXT` characters, :data:`MAX_ENTRIES` entries in a table (:data:`MAX_PARAMETERS`
    parameters) and :data:`MAX_ARRAY` values in an array."""
    return description_from_data(read_toml(text, filename), text, filename)


def read_toml(text: str, filename: str) -> dict[str, Any]:
    """The parsed TOML of a description ``text`` (every string made printable), its sizes checked
    (:func:`parse_description`); :class:`InputError` with the file name and line otherwise."""
    if len(text) > MAX_TEXT:
        raise InputError(filename, f"is {len(text)} characters long; a description takes at most {MAX_TEXT}")
    try:
        data: dict[str, Any] = _printable(tomllib.loads(text))
    except (RecursionError, MemoryError):
        raise InputError(filename, "nested too deeply (arrays or inline tables inside each other); "
                                   "a description needs at most a few levels") from None
    except tomllib.TOMLDecodeError as exc:
        msg = str(exc)
        m = re.search(r"line (\d+)", msg)
        line = int(m.group(1)) if m else None
        key = key_at(text, line) if line else "?"
        raise InputError(f"{filename}:{line}: {key}", f"malformed TOML: {re.sub(r' [(]at .*[)]$', '', msg)}") from None
    except ValueError as exc:  # Python refuses to convert an integer of more than 4300 digits
        raise InputError(filename, f"a number the TOML reader refuses ({exc.args[0].split(';')[0]}); "
                                   "give numbers within the floating-point range") from None
    try:
        _check_sizes(data, "")
    except InputError as exc:
        raise locate_error((filename, text), exc) from None
    return data


def description_from_data(data: Mapping[str, Any], text: str, filename: str) -> Mechanism[Any, Any]:
    """The :class:`Mechanism` of the parsed TOML ``data`` (:func:`read_toml`) of ``text``."""
    if "system" in data:
        raise InputError(f"{filename}: system", "this file is an ODE system ([system] table), not a mechanism "
                                                "description; load it with mechcont.models.load_model")
    try:
        mech = _mechanism(data, filename)
    except InputError as exc:
        raise locate_error((filename, text), exc) from None
    mech.source = (filename, text)
    return mech


# -- building objects from the parsed tables ---------------------------------------------------
def _printable(v: Any) -> Any:
    """``v`` (parsed TOML) with every string's line breaks, escape sequences and other control
    characters escaped (:func:`~mechcont.errors.one_line`): text from a description is printed to
    terminals and written to tables, where it must not forge lines or drive the terminal."""
    if isinstance(v, str):
        return one_line(v)
    if isinstance(v, dict):
        return {k: _printable(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_printable(x) for x in v]
    return v


def _pair(v: Any, field: str) -> tuple[Any, ...]:
    if not isinstance(v, list) or len(v) != 2:
        raise InputError(field, f"must be a pair [x, y], got {v!r}")
    return tuple(v)


def _direction(v: Any, field: str) -> Any:
    """A planar vector ``[x, y]``, or an angle (rad) where a direction may be one."""
    return _pair(v, field) if isinstance(v, list) else v


def _parameters(data: Mapping[str, Any], section: str = "parameters") -> list[Parameter]:
    """The ``[parameters]`` table (or another ``section`` of that form, an ODE file's ``[states]``):
    ``NAME = value`` or ``NAME = {value, unit, description, scale}``."""
    params = []
    for pname, spec in _table(data, section, section).items():
        f = f"{section}.{pname}"
        if isinstance(spec, Mapping):
            _only(spec, KEYS["parameters.NAME"], f)
            _require(spec, ["value"], f)
            val = spec["value"]
            unit, desc, scale = spec.get("unit", ""), spec.get("description", ""), spec.get("scale")
            _text(unit, f + ".unit")
            _text(desc, f + ".description")
        else:
            val, unit, desc, scale = spec, "", "", None
        where = f + ".value" if isinstance(spec, Mapping) else f
        if isinstance(val, bool) or not isinstance(val, (int, float)):
            raise InputError(where, f"must be a number, got {_short(val)}")
        if not (abs(val) <= sys.float_info.max):  # inf, nan, or an integer beyond the float range
            raise InputError(where, f"must be a finite number within +-{sys.float_info.max:.4g}, got {_short(val)}")
        if scale is not None and (isinstance(scale, bool) or not isinstance(scale, (int, float))
                                  or not 0 < scale <= sys.float_info.max):
            raise InputError(f + ".scale", f"must be a finite positive number, got {_short(scale)}")
        params.append(Parameter(pname, float(val), unit, desc, scale))
    return params


def _force_elements(data: Mapping[str, Any]) -> dict[str, list[Element]]:
    """The tables of every registered force element (:data:`~.elements.ELEMENT_TYPES`), each entry
    read by its class, as the keyword arguments of a description (``springs=[...]``, ...; the kinds
    without a field of their own in ``elements``)."""
    out: dict[str, list[Element]] = {}
    for table, cls in ELEMENT_TYPES.items():
        items = [cls.from_table(name, spec, f"{table}.{name}") for name, spec in _entries(data, table)]
        out.setdefault(table if table in Mechanism.ELEMENT_FIELDS else "elements", []).extend(items)
    return out


def _common(data: Mapping[str, Any], head: Mapping[str, Any], filename: str) -> dict[str, Any]:
    """The keyword arguments both planar and spatial mechanisms take from a file."""
    assembly = _table(data, "assembly", "assembly")
    _only(assembly, KEYS["assembly"], "assembly")
    return dict(
        **_force_elements(data),
        name=_text(head.get("name", one_line(Path(filename).stem.replace("-", "_"))), "mechanism.name"),
        parameters=_parameters(data), dof=head.get("dof", 1),
        hold=dict(_table(assembly, "hold", "assembly.hold")),
        description=_text(head.get("description", ""), "mechanism.description"),
        redundant=head.get("redundant", "error"),
        conditions=conditions_from_table(_table(data, "conditions", "conditions")),
        downlock=downlock_from_table(head["downlock"]) if "downlock" in head else None,
        units=_units(_table(head, "units", "mechanism.units")))


def _units(table: Mapping[str, Any]) -> UnitSystem:
    """The ``[mechanism] units = { length = "mm", mass = "g" }`` table: the units the file's numbers are in
    (each key optional, SI by default)."""
    _only(table, KEYS["mechanism.units"], "mechanism.units")
    out = {}
    for key, valid in (("length", LENGTH_UNITS), ("mass", MASS_UNITS)):
        if key in table:
            if table[key] not in valid:
                raise InputError(f"mechanism.units.{key}", f"must be one of {', '.join(map(repr, valid))}, "
                                                            f"got {table[key]!r}")
            out[key] = table[key]
    return UnitSystem(**out)


def _mechanism(data: Mapping[str, Any], filename: str) -> Mechanism[Any, Any]:
    _only(data, _OTHER_SECTIONS | set(ELEMENT_TYPES), "")
    head = _table(data, "mechanism", "mechanism")
    _only(head, KEYS["mechanism"], "mechanism")
    dimension = head.get("dimension", 2)
    if isinstance(dimension, bool) or dimension not in _READERS:
        raise InputError("mechanism.dimension", f"must be 2 (planar, the default) or 3 (spatial), got {dimension!r}")
    return _READERS[dimension]().read(data, _common(data, head, filename))


def _body(name: str, spec: Mapping[str, Any], f: str) -> Body:
    """A planar ``[bodies.NAME]`` table."""
    _only(spec, KEYS["bodies.NAME"], f)
    _require(spec, ["mass"], f)
    points: dict[str, PointSpec] = {}
    for pn, ps in _table(spec, "points", f + ".points").items():
        if isinstance(ps, Mapping):
            _only(ps, KEYS["bodies.NAME.points.NAME"], f"{f}.points.{pn}")
            _require(ps, ["r", "angle"], f"{f}.points.{pn}")
            points[pn] = Polar(ps["r"], ps["angle"])
        else:
            points[pn] = _pair(ps, f"{f}.points.{pn}")
    initial = _table(spec, "initial", f + ".initial")
    return Body(name, spec["mass"], spec.get("length"), spec.get("inertia"), _pair(spec.get("cg", [0, 0]), f + ".cg"),
                points, dict(initial), _text(spec.get("description", ""), f + ".description"))


def _gravity(table: Mapping[str, Any]) -> Gravity:
    """The planar ``[gravity]`` table."""
    _only(table, KEYS["gravity"], "gravity")
    return Gravity(**table)


def _spatial_reader() -> Reader:
    from .spatial._file import READER
    return READER


#: ``[mechanism] dimension`` -> the reader of the rest of the file (the spatial one imported on first use).
_READERS: dict[int, Callable[[], Reader]] = {
    2: lambda: Reader(Mechanism, _pair, _direction, _body, _gravity), 3: _spatial_reader}
