"""Resolve a model name or a description file to an equation system."""

from __future__ import annotations

import copy
from collections.abc import Callable
from pathlib import Path

from ..equations import EquationSystem
from ..errors import InputError

__all__ = ["BUILTIN_MODELS", "load_model", "model_names"]

_BUILT: dict[tuple, EquationSystem] = {}


def _overcentre(**kw):
    from .overcentre import build_overcentre

    return build_overcentre(**kw)


def _nose_gear(**kw):
    from .nose_gear import build_nose_gear

    return build_nose_gear(**kw)


def _dual_sidestay(**kw):
    from .dual_sidestay import build_dual_sidestay_kinematics

    system = build_dual_sidestay_kinematics()
    for name in kw:
        if name not in system.parameter_names:
            raise InputError(name, f"not a parameter of dual_sidestay_kinematics; valid: "
                                   f"{', '.join(system.parameter_names)}")
    if not kw:
        return copy.copy(system)
    new = system.with_values({k: float(v) for k, v in kw.items()})
    new.geometry = system.geometry
    return new


#: Hand-formulated reference models of the paper: name -> (builder, one-line description).
BUILTIN_MODELS: dict[str, tuple[Callable[..., EquationSystem], str]] = {
    "overcentre": (_overcentre, "overcentre mechanism, the paper's eq. 6 (6 states)"),
    "nose_gear": (_nose_gear, "planar nose landing gear, the paper's 25-equation form"),
    "dual_sidestay_kinematics": (_dual_sidestay, "dual-sidestay main gear retraction kinematics, 3-D (12 states)"),
}


def model_names() -> list[str]:
    """Names accepted by :func:`load_model`: built-in models, then shipped description files."""
    from ..mechanism import builtin_descriptions

    return [*BUILTIN_MODELS, *(f"{stem}.toml" for stem in builtin_descriptions())]


def load_model(name: str | Path, **overrides: float) -> EquationSystem:
    """The compiled equation system of a built-in model or a mechanism description.

    Parameters
    ----------
    name:
        A built-in model (``"overcentre"``, ``"nose_gear"``), a shipped description
        (``"fourbar.toml"`` or its stem ``"fourbar"``), or a path to a ``.toml`` file.
    **overrides:
        Parameter values (SI units) replacing the defaults.

    Raises
    ------
    InputError
        Unknown name or parameter, or an invalid description file.
    """
    key = str(name)
    if key in BUILTIN_MODELS:
        return BUILTIN_MODELS[key][0](**overrides)
    from ..mechanism import find_description, load

    path = find_description(key)
    if path is None:
        raise InputError("model", f"unknown model '{key}'; valid: {', '.join(model_names())} or a path to a .toml file")
    # generating and compiling equations costs ~0.5 s: keep one build per file version and
    # parameter set in this process, and hand out shallow copies (shared compiled code)
    stamp = (str(Path(path).resolve()), Path(path).stat().st_mtime_ns, tuple(sorted(overrides.items())))
    if stamp not in _BUILT:
        _BUILT[stamp] = load(key, **overrides)
    return copy.copy(_BUILT[stamp])
