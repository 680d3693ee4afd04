"""Describe any planar mechanism; its static equations are generated, not hand-derived.

Describe bodies, points, joints, springs, dampers and loads (as objects or in a TOML file),
then :meth:`Mechanism.build` generates the equilibrium system with the joint reactions as
named unknowns (the paper's inter-link forces), exact Jacobians, the mechanics for
stability and dynamics, and a drawing scene::

    from mechcont.mechanism import load
    system = load("overcentre", LU=0.4)          # shipped description, or a path to a .toml
    system = load_description("my.toml").build_reduced(k=200.0)

:func:`assemble` gives a first equilibrium from approximate positions and held states;
:func:`check_report` says what was made of a description (``mechcont check``).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from .._lazy import lazy_exports

#: public name -> the module of this package that defines it; each is imported on first use
#: (PEP 562), so finding or listing description files imports no SymPy
_LAZY = {
    **dict.fromkeys(["Actuator"], "elements"),
    **dict.fromkeys(["DofReport", "assemble", "close_constraints", "dof_report"], "_assembly"),
    **dict.fromkeys(["CheckReport", "check_report"], "_check"),
    **dict.fromkeys(["Condition", "DownlockSpec"], "_conditions"),
    **dict.fromkeys(["Body", "CustomLoad", "Damper", "Drag", "Gravity", "Mechanism", "Moment", "Parameter", "PointForce",
                     "Polar", "Prismatic", "Revolute", "Slider", "Spring", "Weld", "coordinate_names"], "_description"),
    **dict.fromkeys(["load_description", "parse_description"], "_file"),
    **dict.fromkeys(["OdeSystem", "load_file", "parse_file"], "_ode_file"),
    **dict.fromkeys(["builtin_descriptions", "find_description", "read_description_bytes", "is_system_file"], "_paths"),
    # for the layers above: a compliant row's law, a parameter expression's value, the spatial row-switch test
    **dict.fromkeys(["compliant_constraints"], "_compliant"),
    **dict.fromkeys(["held_loop_error"], "_held_loop"),
    **dict.fromkeys(["evaluate"], "_expr"),
    **dict.fromkeys(["SWITCH_RATIO", "unit_rows"], "_dropped_rows"),
}

__all__ = [
    "load", "load_description", "parse_description", "builtin_descriptions", "find_description",
    "OdeSystem", "load_file", "parse_file", "is_system_file",
    "Mechanism", "Parameter", "Polar", "Body", "Revolute", "Slider", "Prismatic", "Weld", "Spring", "Damper",
    "Gravity", "PointForce", "Moment", "Drag", "CustomLoad", "Actuator", "Condition", "DownlockSpec",
    "coordinate_names",
    "assemble", "dof_report", "DofReport", "close_constraints", "check_report", "CheckReport",
    "read_description_bytes", "compliant_constraints", "held_loop_error", "evaluate", "SWITCH_RATIO", "unit_rows",
]

if TYPE_CHECKING:  # what the lazy names are, for type checkers and IDEs
    from ..equations import Model
    from ._assembly import DofReport, assemble, close_constraints, dof_report
    from ._check import CheckReport, check_report
    from ._compliant import compliant_constraints
    from ._conditions import Condition, DownlockSpec
    from ._description import (
        Body,
        CustomLoad,
        Damper,
        Drag,
        Gravity,
        Mechanism,
        Moment,
        Parameter,
        PointForce,
        Polar,
        Prismatic,
        Revolute,
        Slider,
        Spring,
        Weld,
        coordinate_names,
    )
    from ._dropped_rows import SWITCH_RATIO, unit_rows
    from ._expr import evaluate
    from ._file import load_description, parse_description
    from ._held_loop import held_loop_error
    from ._ode_file import OdeSystem, load_file, parse_file
    from ._paths import builtin_descriptions, find_description, is_system_file, read_description_bytes
    from .elements import Actuator


__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())


def load(name_or_path: str | Path, *, reduced: bool = False, **overrides: float) -> Model:
    """Load a description (a ``.toml`` path or a shipped stem) and build its equations.

    Parameters
    ----------
    name_or_path:
        Path to a description file, or the stem of a shipped one (:func:`builtin_descriptions`).
    reduced:
        Build the reduced form (tree coordinates and their reactions eliminated).
    **overrides:
        Parameter values (SI) replacing the file's defaults.

    Returns
    -------
    Model
        An equation system with ``mechanics``, ``scene``, ``potential_energy``, ``dof`` and the
        description's other facts as declared fields.
    """
    from ._file import load_description

    mech = load_description(name_or_path)
    return mech.build_reduced(**overrides) if reduced else mech.build(**overrides)
