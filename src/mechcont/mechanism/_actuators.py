"""Actuators: a two-force member between two points, driven by a force or by its length.

Sign convention: the actuator load is a **tension, positive** when it pulls its points
``a`` and ``b`` towards each other (negative: it pushes them apart, extending the
actuator). With ``l = |P_b - P_a|``:

* force mode (``force = F``, an expression in the parameters; a parameter name can be freed
  and solved for): the potential ``F l`` (J), i.e. the generalised force ``-F dl/dq``;
* length mode (``length = L``): the constraint row ``<NAME>_length: l - L = 0`` (m) whose
  reaction ``T_<NAME>`` (N) is the actuator tension. A length actuator removes one degree
  of freedom (declare ``dof`` accordingly); continuing in ``L`` drives the mechanism.

For a crank of angle ``theta`` under a moment ``M`` (counter-clockwise positive) the
virtual work gives ``F dl/dtheta = M`` in both modes.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from ..errors import InputError
from ._expr import Value

__all__ = ["Actuator", "actuator_length", "actuator_potential", "actuator_rows", "actuator_load",
           "actuators_from_table", "check_actuators", "ACTUATOR_KEYS"]

#: Keys of an ``[actuators.NAME]`` table.
ACTUATOR_KEYS = frozenset({"a", "b", "force", "length", "description"})


@dataclass(frozen=True)
class Actuator:
    """A straight actuator from point ``a`` to point ``b`` (see the module docstring).

    Exactly one of ``force`` (tension, N: a number or an expression in the parameters) and
    ``length`` (m, positive: a number or an expression in the parameters) is given.
    """

    name: str
    a: str
    b: str
    force: Value | None = None
    length: Value | None = None
    description: str = ""

    @property
    def mode(self) -> str:
        """``"force"`` or ``"length"``."""
        return "force" if self.force is not None else "length"


def check_actuators(mech) -> None:
    """Check each actuator's points and that it has exactly one of force and length."""
    for act in mech.actuators:
        f = f"actuators.{act.name}"
        if (act.force is None) == (act.length is None):
            raise InputError(f, "give exactly one of force (N, tension positive) and length (m)"
                             + (", not both" if act.force is not None else ""))
        mech.point_ref(act.a, f + ".a")
        mech.point_ref(act.b, f + ".b")
        if act.a == act.b:
            raise InputError(f + ".b", "an actuator needs two different points")
        if act.a.split(".")[0] == act.b.split(".")[0]:
            raise InputError(f + ".b", f"both ends are on {act.a.split('.')[0]!r}: an actuator joins two bodies "
                                       "(or a body and the ground)")


def actuator_length(kin, act: Actuator) -> sp.Expr:
    """``|P_b - P_a|`` (m) of ``act`` in the coordinates of ``kin``."""
    d = kin.point(act.b) - kin.point(act.a)
    return sp.sqrt(sum((c ** 2 for c in d), sp.S.Zero))


def actuator_potential(kin) -> sp.Expr:
    """Potential (J) of the force-mode actuators: ``sum F l`` (tension positive)."""
    V = sp.S.Zero
    for act in kin.mech.actuators:
        if act.mode == "force":
            V += kin.mech.value(f"actuators.{act.name}.force") * actuator_length(kin, act)
    return V


def actuator_rows(kin) -> list:
    """Constraint rows ``l - L`` (m) of the length-mode actuators, reactions ``T_<NAME>`` (N)."""
    from ._kinematics import ConstraintRow

    rows = []
    for act in kin.mech.actuators:
        if act.mode == "length":
            L = kin.mech.value(f"actuators.{act.name}.length")
            rows.append(ConstraintRow(act.name, f"{act.name}_length", f"T_{act.name}", "N",
                                      actuator_length(kin, act) - L))
    return rows


def actuator_load(mech, act: Actuator) -> sp.Expr:
    """The actuator tension (N) as an expression in the system's variables."""
    if act.mode == "force":
        return mech.value(f"actuators.{act.name}.force")
    return sp.Symbol(f"T_{act.name}", real=True)


def actuators_from_table(tab: Mapping, field: str = "actuators") -> list[Actuator]:
    """``[actuators.NAME]`` tables as parsed TOML -> :class:`Actuator` objects (keys checked)."""
    out = []
    for name, spec in tab.items():
        f = f"{field}.{name}"
        if not isinstance(spec, Mapping):
            raise InputError(f, "must be a table [actuators.NAME] with a, b and force or length")
        for k in spec:
            if k not in ACTUATOR_KEYS:
                raise InputError(f"{f}.{k}", f"unknown key; valid keys: {', '.join(sorted(ACTUATOR_KEYS))}")
        for k in ("a", "b"):
            if k not in spec:
                raise InputError(f"{f}.{k}", "is required (a point reference '<body>.<point>' or 'ground.<point>')")
        if "description" in spec and not isinstance(spec["description"], str):
            raise InputError(f + ".description", f"must be a string, got {spec['description']!r}")
        out.append(Actuator(name, spec["a"], spec["b"], spec.get("force"), spec.get("length"),
                            spec.get("description", "")))
    return out
