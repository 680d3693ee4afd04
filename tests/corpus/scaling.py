"""Rewrite a mechanism description in other units: lengths times ``L``, masses times ``M`` (seconds kept).

Every number of a description has a kind: a parameter its declared ``unit`` (read by
:func:`mechcont.units.dimension`), a plain number the key it stands under (``ground`` points and
``free_length`` are lengths, ``k`` a stiffness, a stop's ``min`` has its condition's unit, ...). A value of
dimension length^a mass^b time^c is multiplied by ``L^a M^b``; an expression string is left as it is (its
literals must be pure factors, as in ``"0.55*L"``). A number under a key this helper does not know is an
error, so a description it cannot rewrite is never rewritten wrongly. With ``labels``, each declared unit is
relabelled in the new units (``"m"`` -> ``"mm"``, ``"N"`` -> ``"g mm/s^2"``): labels never convert a value, so
the file is what a user working in those units would write; a scaling with named units (:data:`NAMES`) also
declares them (``[mechanism] units``), so the generated names' headers say them too.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from pathlib import Path

from mechcont.units import dimension

LENGTH, MASS, FORCE, MOMENT, NONE = (1, 0, 0), (0, 1, 0), (1, 1, -2), (2, 1, -2), (0, 0, 0)
#: the unit names of the scalings the tests use: (length factor, mass factor) -> (length label, mass label)
NAMES = {(1e3, 1e3): ("mm", "g"), (1e3, 1.0): ("mm", "kg"), (1e-3, 1.0): ("km", "kg"), (1e6, 1.0): ("um", "kg"),
         (1e3, 1e-3): ("mm", "t"),
         (1.0, 1.0): ("m", "kg")}


def factor(dim: tuple[int, int, int], L: float, M: float) -> float:
    """The factor by which a value of dimension ``dim`` (length, mass, time exponents) changes."""
    return L ** dim[0] * M ** dim[1]


def unit_factor(unit: str, L: float, M: float) -> float:
    """The factor of a value labelled ``unit`` (an SI label, as a table header or variable carries)."""
    dim = dimension(unit)
    assert dim is not None, f"cannot read the unit {unit!r}"
    return factor(dim, L, M)


def _label(unit: str, L: float, M: float) -> str:
    dim = dimension(unit)
    assert dim is not None, unit
    lname, mname = NAMES.get((L, M), ("m", "kg"))  # a unit without a name keeps the SI labels
    if dim == NONE:
        return unit
    num = [f"{n}^{e}" if e > 1 else n for n, e in ((lname, dim[0]), (mname, dim[1]), ("s", dim[2])) if e > 0]
    den = [f"{n}^{-e}" if e < -1 else n for n, e in ((lname, dim[0]), (mname, dim[1]), ("s", dim[2])) if e < 0]
    den += ["rad"] if "rad" in unit.replace("/", " ").split() else []
    return " ".join(num or ["1"]) + ("/" + " ".join(den) if den else "")


def _num(v, dim, L, M, where):
    if isinstance(v, bool):
        raise AssertionError(f"{where}: a boolean")
    if isinstance(v, int | float):
        return float(v) * factor(dim, L, M)
    if isinstance(v, str):
        return v  # an expression in parameters: follows them
    if isinstance(v, list):
        return [_num(x, dim, L, M, where) for x in v]
    raise AssertionError(f"{where}: cannot scale {v!r}")


def _point(v, L, M, where):
    if isinstance(v, Mapping):  # polar {r, angle}
        return {k: _num(x, LENGTH if k == "r" else NONE, L, M, f"{where}.{k}") for k, x in v.items()}
    return _num(v, LENGTH, L, M, where)


_BODY = {"length": LENGTH, "mass": MASS, "inertia": (2, 1, 0), "cg": LENGTH}
_SPRING = {"k": (0, 1, -2), "free_length": LENGTH, "preload": FORCE, "k_t": MOMENT}
_DAMPER = {"c": (0, 1, -1), "c2": (-1, 1, 0)}
_JOINT_NONE = {"angle", "axis", "type", "a", "b", "description", "normal", "direction"}
_LOAD = {"force": FORCE, "moment": MOMENT, "torque": MOMENT}


def _condition_dims(doc) -> dict[str, tuple[int, int, int]]:
    out = {}
    for name, c in doc.get("conditions", {}).items():
        kind = c.get("type")
        out[name] = (LENGTH if kind == "distance" else NONE if kind in ("angle", "collinear")
                     else dimension(c.get("unit", "")))
        assert out[name] is not None, f"conditions.{name}: unknown unit"
    return out


def _coordinate_dim(name: str, conditions) -> tuple[int, int, int]:
    if name in conditions:
        return conditions[name]
    if name.startswith("theta"):
        return NONE
    if name[:1] in "xyz":
        return LENGTH
    raise AssertionError(f"assembly: unknown coordinate {name}")


def scale_description(doc: Mapping, L: float, M: float, labels: bool = False) -> dict:
    """A copy of the parsed description ``doc`` with every value in lengths x ``L`` and masses x ``M``."""
    conditions = _condition_dims(doc)
    out: dict = {}
    for table, body in doc.items():
        if table == "mechanism" and labels and (L, M) in NAMES:  # declared, so the generated names say them
            out[table] = dict(body, units=dict(zip(("length", "mass"), NAMES[(L, M)])))
        elif table == "mechanism" or table == "conditions" and not any("target" in c for c in body.values()):
            out[table] = body
        elif table == "parameters":
            new = {}
            for name, p in body.items():
                if isinstance(p, Mapping):
                    f = unit_factor(p.get("unit", ""), L, M)
                    q = dict(p, value=p["value"] * f)
                    if "scale" in p:
                        q["scale"] = p["scale"] * f
                    if labels and "unit" in p:
                        q["unit"] = _label(p["unit"], L, M)
                    new[name] = q
                else:
                    assert isinstance(p, str), f"parameters.{name}: a plain number has no unit to scale it by"
                    new[name] = p
            out[table] = new
        elif table == "ground":
            out[table] = {k: _point(v, L, M, f"ground.{k}") for k, v in body.items()}
        elif table == "bodies":
            out[table] = {b: _body(v, L, M, f"bodies.{b}") for b, v in body.items()}
        elif table in ("springs", "dampers"):
            kinds = _SPRING if table == "springs" else _DAMPER
            out[table] = {e: {k: (_num(x, kinds[k], L, M, f"{table}.{e}.{k}") if k in kinds else _plain(x, f"{table}.{e}.{k}"))
                              for k, x in v.items()} for e, v in body.items()}
        elif table == "joints":
            out[table] = {j: {k: (x if k in _JOINT_NONE else _point(x, L, M, f"joints.{j}.{k}") if k in ("offset",)
                                  else _plain(x, f"joints.{j}.{k}")) for k, x in v.items()} for j, v in body.items()}
        elif table == "loads":
            out[table] = {n: _load(v, L, M, f"loads.{n}") for n, v in body.items()}
        elif table == "gravity":
            out[table] = {k: (_num(x, (1, 0, -2), L, M, "gravity.g") if k == "g" else x) for k, x in body.items()}
        elif table == "stops":
            out[table] = {s: _stop(v, conditions[v["condition"]], L, M, f"stops.{s}") for s, v in body.items()}
        elif table == "conditions":
            out[table] = {c: (dict(v, target=_num(v["target"], conditions[c], L, M, f"conditions.{c}.target"))
                              if "target" in v else v) for c, v in body.items()}
        elif table == "assembly":
            out[table] = {k: ({n: _num(x, _coordinate_dim(n, conditions), L, M, f"assembly.{k}.{n}") for n, x in v.items()}
                              if isinstance(v, Mapping) else v) for k, v in body.items()}
        else:
            raise AssertionError(f"[{table}]: this helper does not know its values")
    return out


def _plain(x, where):
    assert isinstance(x, str), f"{where}: a number this helper does not know how to scale"
    return x


def _body(v, L, M, where):
    out = {}
    for k, x in v.items():
        if k in _BODY:
            out[k] = _num(x, _BODY[k], L, M, f"{where}.{k}")
        elif k == "points":
            out[k] = {p: _point(y, L, M, f"{where}.points.{p}") for p, y in x.items()}
        elif k == "initial":
            out[k] = {c: _num(y, LENGTH if c in ("x", "y", "z") else NONE, L, M, f"{where}.initial.{c}")
                      for c, y in x.items()}
        else:
            out[k] = _plain(x, f"{where}.{k}")
    return out


def _load(v, L, M, where):
    dim = _LOAD.get(v.get("type", "force"))
    out = {}
    for k, x in v.items():
        if k == "magnitude":
            assert dim is not None, f"{where}: a {v.get('type')} load's magnitude"
            out[k] = _num(x, dim, L, M, f"{where}.magnitude")
        elif k in ("direction", "axis"):
            out[k] = x
        else:
            out[k] = _plain(x, f"{where}.{k}")
    return out


def _stop(v, dim, L, M, where):
    # a stiffness and damping are per unit of the condition: force (or moment) over the condition's unit
    push = MOMENT if dim == NONE else FORCE
    stiffness = (push[0] - dim[0], push[1] - dim[1], push[2] - dim[2])
    kinds = {"min": dim, "max": dim, "stiffness": stiffness, "damping": (stiffness[0], stiffness[1], stiffness[2] + 1)}
    return {k: (_num(x, kinds[k], L, M, f"{where}.{k}") if k in kinds else _plain(x, f"{where}.{k}")) for k, x in v.items()}


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int | float):
        return repr(float(v)) if isinstance(v, float) else str(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {_toml_value(x)}" for k, x in v.items()) + " }"
    raise AssertionError(f"cannot write {v!r}")


def _key(k: str) -> str:
    return k if k.replace("_", "").replace("-", "").isalnum() and k.isascii() else _toml_value(k)


def dump(doc: Mapping) -> str:
    """TOML text of a parsed description (each top-level table with its entries inline)."""
    lines = []
    for table, body in doc.items():
        lines.append(f"[{table}]")
        lines += [f"{_key(k)} = {_toml_value(v)}" for k, v in body.items()]
        lines.append("")
    return "\n".join(lines)


def write_scaled(src: Path, dest: Path, L: float, M: float, labels: bool = False) -> Path:
    """Write ``src`` rewritten with lengths x ``L`` and masses x ``M`` to ``dest``; returns ``dest``."""
    doc = tomllib.loads(Path(src).read_text())
    dest.write_text(dump(scale_description(doc, L, M, labels)))
    return dest
