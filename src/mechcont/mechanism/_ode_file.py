"""ODE and algebraic systems described in TOML (``[system]`` files), for users coming from AUTO-07p.

Layout (see docs/ode-format.md)::

    [system]        name, description
    [parameters]    NAME = value  or  NAME = {value, unit, description, scale}   (as in mechanism files)
    [states]        NAME = initial value  or  NAME = {value, unit, description, scale}
    [rates]         NAME = "expression": du/dt of the state NAME (AUTO's IPS = 1), one per state
    [equations]     NAME = "residual": 0 = g(u, p), one per state (AUTO's IPS = 0), instead of [rates]

Expressions are read by the whitelist parser of descriptions (:mod:`._expr`), never evaluated as
code. A file with a ``[system]`` table is an ODE system; any other is a mechanism description:
:func:`parse_file` and :func:`load_file` read either.
"""

from __future__ import annotations

import keyword
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError, one_line
from ._elements import Parameter
from ._expr import FUNCTIONS, symbol, to_expr
from ._file import _parameters, description_from_data, read_text, read_toml
from ._locate import locate_error
from ._tables import _only, _table, _text

if TYPE_CHECKING:
    import sympy as sp

    from ..equations import Model
    from ._description import Mechanism

__all__ = ["OdeSystem", "parse_file", "load_file", "KEYS"]

#: The tables of an ODE file and the keys of ``[system]``.
KEYS: dict[str, frozenset[str]] = {
    "": frozenset({"system", "parameters", "states", "rates", "equations"}),
    "system": frozenset({"name", "description"}),
}


@dataclass(frozen=True)
class OdeSystem:
    """An ODE ``du/dt = f(u, p)`` (or, ``algebraic``, ``0 = g(u, p)``) read from a ``[system]`` file.

    ``states`` and ``parameters`` hold name, value (the initial state; the parameter's default, SI),
    unit, description and scale; ``rates`` one SymPy expression per state, in the states' order.
    """

    name: str
    description: str
    states: tuple[Parameter, ...]
    parameters: tuple[Parameter, ...]
    rates: tuple[sp.Expr, ...]
    algebraic: bool
    source: tuple[str, str] | None = None

    def build(self, **values: float) -> Model:
        """The :class:`~mechcont.equations.Model` (``ode`` set) with the parameters at ``values`` (SI),
        the file's values otherwise. Raises :class:`InputError` for a name that is not a parameter."""
        from ..equations import ode_model

        known = {p.name for p in self.parameters}
        for name in values:
            if name not in known:
                raise InputError(name, f"not a parameter of {self.name}; valid: {', '.join(sorted(known)) or 'none'}")
        params = [replace(p, value=float(values.get(p.name, p.value))) for p in self.parameters]
        named = (*self.states, *params)
        model = ode_model(self.name, {s.name: s.value for s in self.states}, {p.name: p.value for p in params},
                          dict(zip((s.name for s in self.states), self.rates)),
                          units={v.name: v.unit for v in named}, algebraic=self.algebraic,
                          description=self.description)
        given = {v.name: v for v in named}
        variables = [replace(v, description=given[v.name].description,
                             scale=given[v.name].scale or v.scale) for v in model.variables]
        return model.evolve(variables=variables)

    def summary(self) -> tuple[str, list[tuple[str, str, str, str, float | None]]]:
        """``(description, rows)``, a row ``(name, kind, unit, description, value)`` per state and
        parameter (as :meth:`Mechanism.summary <mechcont.mechanism.Mechanism.summary>`)."""
        rows: list[tuple[str, str, str, str, float | None]] = [
            (s.name, "state", s.unit, s.description, s.value) for s in self.states]
        rows += [(p.name, "parameter", p.unit, p.description, p.value) for p in self.parameters]
        return self.description, rows


def load_file(name_or_path: str | Path) -> Mechanism | OdeSystem:
    """Read a description file (or a shipped one by stem): an :class:`OdeSystem` when it has a
    ``[system]`` table, a mechanism description otherwise. Raises :class:`InputError`."""
    text, path = read_text(name_or_path)
    return parse_file(text, path.name)


def parse_file(text: str, filename: str = "<string>") -> Mechanism | OdeSystem:
    """Parse TOML ``text`` (``filename`` for messages): an :class:`OdeSystem` when it has a
    ``[system]`` table, else a mechanism description (:func:`~._file.parse_description`)."""
    data = read_toml(text, filename)
    if "system" not in data:
        return description_from_data(data, text, filename)
    try:
        system = _system(data, filename)
    except InputError as exc:
        raise locate_error((filename, text), exc) from None
    return replace(system, source=(filename, text))


def _name(name: str, field: str) -> str:
    """``name`` if it can stand in an expression: an identifier, not a keyword, a function or a constant."""
    if not name.isidentifier() or not name.isascii():
        raise InputError(field, "a name must be ASCII letters, digits and underscores, not starting with a digit")
    if keyword.iskeyword(name) or name in FUNCTIONS:
        raise InputError(field, f"'{name}' is a reserved word or a function of the expressions; choose another name")
    return name


def _system(data: Mapping, filename: str) -> OdeSystem:
    _only(data, KEYS[""], "")
    head = _table(data, "system", "system")
    _only(head, KEYS["system"], "system")
    name = _text(head.get("name", one_line(Path(filename).stem.replace("-", "_"))), "system.name")
    if not name.strip():
        raise InputError("system.name", "must not be empty")
    description = _text(head.get("description", ""), "system.description")
    params = _parameters(data, "parameters")
    states = _parameters(data, "states")
    if not states:
        raise InputError("states", "give at least one state: NAME = initial value under [states]")
    for p in params:
        _name(p.name, f"parameters.{p.name}")
    for s in states:
        _name(s.name, f"states.{s.name}")
        if any(p.name == s.name for p in params):
            raise InputError(f"states.{s.name}", "is also a parameter; give each name once")
    if "rates" in data and "equations" in data:
        raise InputError("equations", "give either [rates] (an ODE, du/dt) or [equations] (algebraic, 0 = g), not both")
    if "rates" not in data and "equations" not in data:
        raise InputError("rates", "missing: give [rates] (NAME = \"du/dt\" per state) or [equations] "
                                  "(NAME = \"residual\" per state)")
    algebraic = "equations" in data
    section = "equations" if algebraic else "rates"
    table = _table(data, section, section)
    state_names = [s.name for s in states]
    for key in table:
        if key not in state_names:
            raise InputError(f"{section}.{key}", f"is not a state; the states are {', '.join(state_names)} "
                                                 "(one entry per state, named after it)")
    known = {n: symbol(n) for n in (*state_names, *(p.name for p in params))}
    rates = []
    for n in state_names:
        if n not in table:
            what = f"d{n}/dt" if not algebraic else "a residual"
            raise InputError(f"{section}.{n}", f"missing: give {what} for the state {n} ({n} = \"expression\")")
        rates.append(to_expr(table[n], f"{section}.{n}", known, "[parameters] or [states]"))
    return OdeSystem(name, description, tuple(states), tuple(params), tuple(rates), algebraic)
