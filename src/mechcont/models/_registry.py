"""Resolve a model name or a description file to an equation system."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from ..equations import Model, Variable
from ..errors import InputError

if TYPE_CHECKING:
    from ..mechanism import Mechanism, OdeSystem

__all__ = ["BUILTIN_MODELS", "load_model", "model_at", "model_names", "describe_model", "ModelSummary"]

#: Descriptions read in this process, by (resolved path, text), at most ``_KEEP``.
_DESCRIPTIONS: dict[tuple[str, bytes], Mechanism | OdeSystem] = {}
_KEEP = 16


def _overcentre(**kw: float) -> Model:
    from .overcentre import build_overcentre

    return build_overcentre(**kw)


def _nose_gear(**kw: float) -> Model:
    from .nose_gear import build_nose_gear

    return build_nose_gear(**kw)


def _dual_sidestay(**kw: float) -> Model:
    from .dual_sidestay import build_dual_sidestay_kinematics

    system = build_dual_sidestay_kinematics()
    for name in kw:
        if name not in system.parameter_names:
            raise InputError(name, f"not a parameter of dual_sidestay_kinematics; valid: "
                                   f"{', '.join(system.parameter_names)}")
    return system.with_values({k: float(v) for k, v in kw.items()})


#: Hand-formulated reference models of the paper: name -> (builder, one-line description).
BUILTIN_MODELS: dict[str, tuple[Callable[..., Model], str]] = {
    "overcentre": (_overcentre, "overcentre mechanism, the paper's eq. 6 (6 states)"),
    "nose_gear": (_nose_gear, "planar nose landing gear, the paper's 25-equation form"),
    "dual_sidestay_kinematics": (_dual_sidestay, "dual-sidestay main gear retraction kinematics, 3-D (12 states)"),
}


def _overcentre_summary() -> tuple[str, list[Variable]]:
    from .overcentre import DEFAULTS, DESCRIPTION, _variables

    return DESCRIPTION, _variables(dict(DEFAULTS))


def _nose_gear_summary() -> tuple[str, list[Variable]]:
    from .nose_gear import DESCRIPTION, summary_variables

    return DESCRIPTION, summary_variables()


def _dual_sidestay_summary() -> tuple[str, list[Variable]]:
    from .dual_sidestay import DESCRIPTION, _variables
    from .dual_sidestay_geometry import DEFAULT_GEOMETRY

    return DESCRIPTION, _variables(DEFAULT_GEOMETRY)


#: What each built-in model declares, without generating its equations: (description, variables).
_SUMMARIES: dict[str, Callable[[], tuple[str, list[Variable]]]] = {
    "overcentre": _overcentre_summary,
    "nose_gear": _nose_gear_summary,
    "dual_sidestay_kinematics": _dual_sidestay_summary,
}


@dataclass(frozen=True)
class ModelSummary:
    """What a model declares: its description, equations, states and parameters (``mechcont models``).

    ``states`` holds ``(name, unit, description)``; ``parameters`` ``(name, default, unit,
    description)`` with the default in SI units.
    """

    name: str
    description: str
    n_equations: int
    states: tuple[tuple[str, str, str], ...]
    parameters: tuple[tuple[str, float, str, str], ...]


def describe_model(name: str | Path) -> ModelSummary:
    """What :func:`load_model` would give for ``name``, read from the registry or the description.

    Nothing is generated or compiled, except for a description whose variables only an assembly
    can tell (``redundant = "drop"``, or a spatial mechanism), which is built. Raises
    :class:`InputError` like :func:`load_model`.
    """
    key = str(name)
    if key in _SUMMARIES:
        description, variables = _SUMMARIES[key]()
        return _summary(key, description, [(v.name, v.kind, v.unit, v.description, v.value) for v in variables])
    from ..equations import stored
    from ..mechanism import find_description

    path = find_description(key)
    if path is None:
        raise InputError("model", f"unknown model '{key}'; valid: {', '.join(model_names())} or a path to a "
                                  f".toml file")
    text = _read(path)

    def describe() -> ModelSummary:
        from ..mechanism import load_file

        found = load_file(path).summary()
        if found is None:
            m = load_model(key)
            found = m.description, [(v.name, v.kind, v.unit, v.description, v.value) for v in m.variables]
        return _summary(key, *found)

    # kept in the disk cache, keyed by the file's name and full text (reading a description imports SymPy)
    return stored(lambda: ["description summary", key, path.name, text], describe,
                  valid=lambda obj: isinstance(obj, ModelSummary) and obj.name == key)


def _summary(key: str, description: str, rows: Sequence[tuple[str, str, str, str, float | None]]) -> ModelSummary:
    """A :class:`ModelSummary` from rows ``(name, kind, unit, description, value)`` (a state's value None; a
    parameter's is its default, nan if it had none)."""
    states = tuple((n, u, d) for n, kind, u, d, _ in rows if kind == "state")
    return ModelSummary(key, description, len(states), states,
                        tuple((n, float("nan") if v is None else float(v), u, d)
                              for n, kind, u, d, v in rows if kind == "parameter"))


def _read(path: Path) -> bytes:
    """The bytes of a description file (its key in the disk cache), or :class:`InputError`."""
    from ..mechanism import read_description_bytes

    return read_description_bytes(path)


def model_names() -> list[str]:
    """Names accepted by :func:`load_model`: built-in models, then shipped description files."""
    from ..mechanism import builtin_descriptions

    return [*BUILTIN_MODELS, *(f"{stem}.toml" for stem in builtin_descriptions())]


def _model_key(filename: str, text: bytes, values: Mapping[str, float]) -> list[str | bytes]:
    """The disk-cache key parts of a description's built model: its file name, full text and values."""
    return ["description model", filename, text, repr(sorted(values.items()))]


def model_from_text(text: str, filename: str) -> Model:
    """The model of a description given as TOML ``text`` (``filename``: the name its errors and model
    use, e.g. ``"gear.toml"``), at its default values.

    Like :func:`load_model` of a file, the built model is kept in the disk cache under the
    text, with the key a file of that name and text has: both share one entry.

    Raises
    ------
    InputError
        An invalid description.
    """

    def build() -> Model:
        from ..mechanism import parse_file

        return parse_file(text, filename).build()

    from ..equations import stored

    return stored(lambda: _model_key(filename, text.encode(), {}), build,
                  valid=lambda obj: isinstance(obj, Model))


def load_model(name: str | Path, **overrides: float) -> Model:
    """The model (a compiled equation system with its declared facts) of a built-in model or a description.

    Parameters
    ----------
    name:
        A built-in model (``"overcentre"``, ``"nose_gear"``), a shipped description
        (``"fourbar.toml"`` or its stem ``"fourbar"``), or a path to a ``.toml`` file: a mechanism
        description, or an ODE system (a ``[system]`` table, docs/ode-format.md) whose model has ``ode`` set.
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
    from ..equations import stored
    from ..mechanism import find_description

    path = find_description(key)
    if path is None:
        raise InputError("model", f"unknown model '{key}'; valid: {', '.join(model_names())} or a path to a .toml file")
    text = _read(path)
    values = {k: float(v) for k, v in overrides.items()}

    def build() -> Model:
        from ..mechanism import load_file

        # the description is parsed once per file text; its equations are generated and
        # compiled on its first build, and a build at other values reuses them (Mechanism.build);
        # a file with a [system] table is an ODE system (mechanism._ode_file)
        stamp = (str(Path(path).resolve()), text)
        mech = _DESCRIPTIONS.pop(stamp, None) or load_file(path)
        _DESCRIPTIONS[stamp] = mech  # most recently used last
        while len(_DESCRIPTIONS) > _KEEP:
            del _DESCRIPTIONS[next(iter(_DESCRIPTIONS))]
        return mech.build(**values)

    # the built model (structure and compiled code) is kept in the disk cache, keyed by the file's
    # name and full text and the values (an edited file never reuses an entry of its old text)
    return stored(lambda: _model_key(path.name, text, values), build,
                  valid=lambda obj: isinstance(obj, Model))


def model_at(name: str | Path, values: Mapping[str, float] | None = None, *, field: str = "--set") -> Model:
    """The model of ``name`` (as :func:`load_model`) at ``values`` (SI, rad): what every command does with ``--set``.

    ``values`` name parameters, or states whose value is then the guess the solves start from (as
    ``continue --set`` always accepted). They are checked as every option's values are
    (:func:`~mechcont.equations.check_values_at`: known names, finite, within the model's valid
    ranges; errors name ``field``). The model is then the description edited to the parameter values
    (its pose assembled there, its dropped redundant rows chosen there: what a file with those values
    gives), taken through :meth:`~mechcont.equations.Model.with_values`, so that everything written in
    parameters (a stop's limit, a condition's target, the downlock hold, element values, geometry) has
    its value at ``values``. Where the edited description would not build though the values are valid
    for an analysis (a spring of zero stiffness, a pose that does not assemble from the file's), it is
    the file's model with the values (its states then only a guess). Raises :class:`InputError`."""
    from ..equations import check_values_at

    base = load_model(name)
    if not values:
        return base
    check_values_at(base, values, field)
    params = {k: float(v) for k, v in values.items() if base.variable(k).kind == "parameter"}
    model = base
    if params:
        try:
            model = load_model(name, **params)
        except InputError:  # valid for an analysis, refused for a file (zero stiffness) or not assembled
            model = base
    return model.with_values({k: float(v) for k, v in values.items()})  # checked above, on the file's model
